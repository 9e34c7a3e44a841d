//! `cellsweep reset`: put chosen points of a sweep back to pending (their results deleted), so
//! that the next run computes them again with the same seeds.

use anyhow::{bail, Context};
use cellsweep_scheduler::StoreLock;
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::{Axes, Condition, SelectError, Selector};
use cellsweep_store::{PointRef, Store};

use crate::cli::ResetArgs;

/// The paper's axes; a sweep may have others (R0, E0, ...), which a selector may name too.
const KEYS: [&str; 4] = ["alpha", "beta", "L", "sigma"];

/// A selector of points and the words that name it in errors (`--point ...`, `FILE: row 3`).
#[derive(Debug)]
struct Chosen {
    text: String,
    selector: Selector,
}

impl Chosen {
    /// A selector over the axes `axes` of the sweep (an unknown name is refused, never
    /// ignored: ignoring it would put back every value of that axis).
    fn new(
        text: String,
        selector: Result<Selector, SelectError>,
        axes: &[String],
    ) -> anyhow::Result<Chosen> {
        let axes: Vec<&str> = axes.iter().map(String::as_str).collect();
        match selector.and_then(|s| s.check_axes(&axes, "the sweep").map(|_| s)) {
            Ok(selector) => Ok(Chosen { text, selector }),
            Err(e) => bail!("{text}: {e}"),
        }
    }

    fn matches(&self, p: &PointRef) -> bool {
        let names: Vec<&str> = self
            .selector
            .conditions
            .iter()
            .map(|c| c.name.as_str())
            .filter(|k| !KEYS.contains(k))
            .collect();
        let mut axes = Axes::new(p.alpha, p.beta, p.L, p.sigma);
        axes.others = cellsweep_store::point_others(&p.config, &names);
        self.selector.matches(|name| axes.value(name))
    }
}

/// `--point alpha=0.1,beta=46` (any axis of the sweep).
fn parse_point(text: &str, axes: &[String]) -> anyhow::Result<Chosen> {
    Chosen::new(format!("--point {text}"), Selector::parse(text), axes)
}

/// `--points FILE.csv`: one selector per row; every column must name an axis of the sweep.
fn read_points(path: &std::path::Path, axes: &[String]) -> anyhow::Result<Vec<Chosen>> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {file}"))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .with_context(|| format!("{file}: unreadable header"))?
        .clone();
    let columns: Vec<(usize, &str)> = header.iter().enumerate().collect();
    if let Some((_, h)) = columns.iter().find(|(_, h)| !axes.iter().any(|a| a == h)) {
        bail!(
            "{file}: column {h:?} is not an axis of the sweep (its axes: {})",
            axes.join(", ")
        );
    }
    let mut out = Vec::new();
    for (i, row) in reader.records().enumerate() {
        let row = row.with_context(|| format!("{file}: row {}", i + 1))?;
        let conditions = columns
            .iter()
            .map(|&(c, key)| Condition::new(key, row.get(c).unwrap_or("")))
            .collect::<Result<Vec<_>, _>>();
        out.push(Chosen::new(
            format!("{file}: row {}", i + 1),
            conditions.and_then(Selector::of),
            axes,
        )?);
    }
    if out.is_empty() {
        bail!("{file}: no points listed");
    }
    Ok(out)
}

pub fn run(args: ResetArgs) -> anyhow::Result<()> {
    if args.point.is_empty() && args.points.is_none() && !args.breakups {
        bail!("say what to put back: --point alpha=0.1,beta=46, --points FILE.csv or --breakups");
    }
    let db = &args.db.db;
    // The sweep and its axes, read before anything is locked or written: a selector that does
    // not fit the sweep is refused with the store as it was.
    let (name, axes) = {
        let store = Store::open_read(db)?;
        let name = store.choose_sweep(args.sweep.as_deref())?;
        let id = store.sweep_id(&name)?;
        let sweep = cellsweep_scheduler::Sweep::stored(&store, id)
            .map_err(|e| anyhow::anyhow!("{}: {e}", db.display()))?;
        let mut axes: Vec<String> = KEYS.iter().map(|k| k.to_string()).collect();
        axes.extend(sweep.grid.others.iter().map(|a| a.name.clone()));
        (name, axes)
    };
    let mut selectors: Vec<Chosen> = args
        .point
        .iter()
        .map(|p| parse_point(p, &axes))
        .collect::<anyhow::Result<_>>()?;
    if let Some(path) = &args.points {
        selectors.extend(read_points(path, &axes)?);
    }
    // No run may be live while its jobs are put back (a dry run only reads).
    let _lock = if args.dry_run {
        None
    } else {
        Some(StoreLock::acquire(db)?)
    };
    let mut store = if args.dry_run {
        Store::open_read(db)?
    } else {
        Store::open(db)?
    };
    let sweep_id = store.sweep_id(&name)?;
    let points = store.sweep_points(sweep_id)?;
    let mut chosen: Vec<i64> = Vec::new();
    if selectors.is_empty() {
        // --breakups alone: every point of the sweep.
        chosen.extend(points.iter().map(|p| p.id));
    }
    for s in &selectors {
        let hits: Vec<i64> = points
            .iter()
            .filter(|p| s.matches(p))
            .map(|p| p.id)
            .collect();
        if hits.is_empty() {
            bail!("{}: no point of sweep {name:?} matches", s.text);
        }
        chosen.extend(hits);
    }
    chosen.sort_unstable();
    chosen.dedup();
    if args.breakups {
        return reset_breakups(&mut store, &name, db, &chosen, args.dry_run);
    }
    if args.dry_run {
        let jobs = store.jobs_of_points(&chosen, SOLVER_VERSION)?;
        println!(
            "would put back {jobs} jobs at {} points of {name:?} in {} (dry run: nothing changed)",
            chosen.len(),
            db.display()
        );
        return Ok(());
    }
    store.check_integrity()?;
    let r = store.reset_points(SOLVER_VERSION, &chosen)?;
    println!(
        "put back {} jobs at {} points of {name:?} in {} ({} results deleted); \
         `cellsweep run` of the sweep computes them again",
        r.jobs,
        r.points,
        db.display(),
        r.results
    );
    Ok(())
}

/// `--breakups`: what a change of the breakup rule can change at the chosen points, and only
/// that. A dry run rolls the change back after counting it.
fn reset_breakups(
    store: &mut Store,
    name: &str,
    db: &std::path::Path,
    chosen: &[i64],
    dry_run: bool,
) -> anyhow::Result<()> {
    if dry_run {
        let r = store.count_breakups(SOLVER_VERSION, chosen)?;
        println!(
            "would put back {} jobs at {} points of {name:?} in {} ({} results, {} preps to \
             compute again; dry run: nothing changed)",
            r.jobs,
            r.points,
            db.display(),
            r.results,
            r.preps
        );
        return Ok(());
    }
    store.check_integrity()?;
    let r = store.reset_breakups(SOLVER_VERSION, chosen)?;
    println!(
        "put back {} jobs at {} points of {name:?} in {} ({} results deleted, {} preps to \
         compute again): every stored breakup; `cellsweep run` of the sweep computes them again",
        r.jobs,
        r.points,
        db.display(),
        r.results,
        r.preps
    );
    Ok(())
}
