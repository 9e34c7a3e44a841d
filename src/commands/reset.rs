//! `cellsweep reset`: put chosen points of a sweep back to pending (their results deleted), so
//! that the next run computes them again with the same seeds.

use anyhow::{bail, Context};
use cellsweep_scheduler::StoreLock;
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::{PointRef, Store};

use crate::cli::ResetArgs;

/// The swept parameters a selector may name, as they are spelled in sweep files.
const KEYS: [&str; 4] = ["alpha", "beta", "L", "sigma"];

/// Points chosen by some of their parameters: `(key index, value)` pairs, all of which must hold.
#[derive(Debug)]
struct Selector {
    text: String,
    terms: Vec<(usize, f64)>,
}

impl Selector {
    fn new(text: String, pairs: Vec<(&str, &str)>) -> anyhow::Result<Selector> {
        let mut terms = Vec::new();
        for (key, value) in pairs {
            let Some(k) = KEYS.iter().position(|&x| x == key.trim()) else {
                bail!("{text}: {key:?} is not a swept parameter (one of alpha, beta, L, sigma)");
            };
            if terms.iter().any(|&(t, _)| t == k) {
                bail!("{text}: {key} is given twice");
            }
            let v: f64 = value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .with_context(|| format!("{text}: {key} = {value:?} is not a finite number"))?;
            terms.push((k, v));
        }
        if terms.is_empty() {
            bail!("{text}: names no parameter (write e.g. alpha=0.1,beta=46)");
        }
        Ok(Selector { text, terms })
    }

    fn matches(&self, p: &PointRef) -> bool {
        let values = [p.alpha, p.beta, f64::from(p.L), p.sigma];
        self.terms
            .iter()
            .all(|&(k, v)| (values[k] - v).abs() <= 1e-9 * v.abs().max(1.0))
    }
}

/// `--point alpha=0.1,beta=46`.
fn parse_point(text: &str) -> anyhow::Result<Selector> {
    let label = format!("--point {text}");
    let mut pairs = Vec::new();
    for term in text.split(',').filter(|t| !t.trim().is_empty()) {
        let Some((k, v)) = term.split_once('=') else {
            bail!("{label}: {term:?} is not KEY=VALUE");
        };
        pairs.push((k, v));
    }
    Selector::new(label, pairs)
}

/// `--points FILE.csv`: one selector per row, from the columns named alpha, beta, L, sigma.
fn read_points(path: &std::path::Path) -> anyhow::Result<Vec<Selector>> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {file}"))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .with_context(|| format!("{file}: unreadable header"))?
        .clone();
    let columns: Vec<(usize, &str)> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| KEYS.contains(h))
        .collect();
    if columns.is_empty() {
        bail!("{file}: the header names none of alpha, beta, L, sigma");
    }
    let mut out = Vec::new();
    for (i, row) in reader.records().enumerate() {
        let row = row.with_context(|| format!("{file}: row {}", i + 1))?;
        let pairs = columns
            .iter()
            .map(|&(c, key)| (key, row.get(c).unwrap_or("")))
            .collect();
        out.push(Selector::new(format!("{file}: row {}", i + 1), pairs)?);
    }
    if out.is_empty() {
        bail!("{file}: no points listed");
    }
    Ok(out)
}

pub fn run(args: ResetArgs) -> anyhow::Result<()> {
    let mut selectors: Vec<Selector> = args
        .point
        .iter()
        .map(|p| parse_point(p))
        .collect::<anyhow::Result<_>>()?;
    if let Some(path) = &args.points {
        selectors.extend(read_points(path)?);
    }
    if selectors.is_empty() {
        bail!("say which points to put back: --point alpha=0.1,beta=46 or --points FILE.csv");
    }
    let db = &args.db.db;
    // A store that is not there (or not ours) is named before any lock file is made beside it.
    drop(Store::open_read(db)?);
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
    let name = store.choose_sweep(args.sweep.as_deref())?;
    let sweep_id = store.sweep_id(&name)?;
    let points = store.sweep_points(sweep_id)?;
    let mut chosen: Vec<i64> = Vec::new();
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
