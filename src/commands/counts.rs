//! Loading outcome counts from a store or from a counts CSV file.

use std::path::Path;

use anyhow::{bail, Context};
use cellsweep_scheduler::Ledger;
use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_store::{Assessment, Counts, Label, Scales, Store};

use crate::cli::CountsSource;

/// Counts of every point, and the scales (R0, d) of the model they came from.
pub struct Loaded {
    pub name: String,
    pub counts: Vec<Counts>,
    pub scales: Scales,
    /// An adaptive sweep's standing of each point, beside `counts`.
    pub standings: Option<Vec<Assessment>>,
}

pub fn load(src: &CountsSource) -> anyhow::Result<Loaded> {
    match &src.counts {
        Some(path) => Ok(Loaded {
            name: path.display().to_string(),
            counts: read_csv(path)?,
            scales: Scales::default(),
            standings: None,
        }),
        None => from_store(&src.db, src.sweep.as_deref()),
    }
}

pub fn from_store(db: &Path, sweep: Option<&str>) -> anyhow::Result<Loaded> {
    let store = Store::open(db)?;
    let names = store.sweep_names()?;
    let name = match sweep {
        Some(n) => n.to_string(),
        None => match names.as_slice() {
            [one] => one.clone(),
            [] => bail!("no sweeps in {}", db.display()),
            many => bail!(
                "{} holds several sweeps ({}); pass --sweep NAME",
                db.display(),
                many.join(", ")
            ),
        },
    };
    let id = store.sweep_id(&name)?;
    let points = store.point_counts(id, SOLVER_VERSION)?;
    // The scales of the sweep's model (R0 and d may be swept away from the paper's).
    let scales = points
        .first()
        .and_then(|p| store.point_params(p.point_id).ok())
        .and_then(|json| serde_json::from_str::<serde_json::Value>(&json).ok())
        .and_then(|v| serde_json::from_value::<Params>(v["params"].clone()).ok())
        .map_or_else(Scales::default, |p| Scales { R0: p.R0, d: p.d });
    let counts = points
        .into_iter()
        .map(|p| {
            let o = &p.outcomes;
            Counts {
                alpha: p.alpha,
                beta: p.beta,
                L: p.L,
                sigma: p.sigma,
                n_train: o.train as u64,
                n_walk: o.walk_past as u64,
                n_reversal: o.reversal as u64,
                n_undetermined: o.undetermined as u64,
                n_unstable: o.unstable as u64,
                n_breakup: o.breakup as u64,
                verdict: None,
                free_speed: p.free_speed,
            }
        })
        .collect();
    let standings = Ledger::load(&store, id, SOLVER_VERSION)?.assess(&store)?;
    Ok(Loaded {
        name,
        counts,
        scales,
        standings,
    })
}

/// Parse a counts CSV: a header naming the columns (any order, extra columns ignored).
pub fn read_csv(path: &Path) -> anyhow::Result<Vec<Counts>> {
    let file = path.display();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {file}"))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'));
    let Some((_, header)) = lines.next() else {
        bail!("{file}: empty file")
    };
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| cols.iter().position(|c| *c == name);
    let required = [
        "alpha",
        "beta",
        "L",
        "sigma",
        "n_train",
        "n_walk",
        "n_reversal",
        "n_undetermined",
    ];
    let mut idx = Vec::new();
    for r in required {
        idx.push(find(r).with_context(|| format!("{file}: line 1: missing column {r:?}"))?);
    }
    let (label_col, unstable_col, breakup_col, speed_col) = (
        find("label"),
        find("n_unstable"),
        find("n_breakup"),
        find("free_speed"),
    );
    let mut out = Vec::new();
    for (i, line) in lines {
        let n = i + 1;
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let cell = |c: usize| cells.get(c).copied().unwrap_or("");
        let num = |c: usize| -> anyhow::Result<f64> {
            cell(c)
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .with_context(|| {
                    format!(
                        "{file}: line {n}: {} = {:?} is not a number",
                        cols[c],
                        cell(c)
                    )
                })
        };
        let count = |c: usize| -> anyhow::Result<u64> {
            cell(c).parse::<u64>().with_context(|| {
                format!(
                    "{file}: line {n}: {} = {:?} is not a count",
                    cols[c],
                    cell(c)
                )
            })
        };
        let opt_count = |c: Option<usize>| -> anyhow::Result<u64> {
            c.filter(|&c| !cell(c).is_empty()).map_or(Ok(0), count)
        };
        let l = num(idx[2])?;
        if l.fract() != 0.0 || l < 0.0 {
            bail!("{file}: line {n}: L = {l} is not a whole number");
        }
        let verdict = match label_col.map(cell).unwrap_or("") {
            "" => None,
            s => match Label::parse(s) {
                Some(v @ (Label::Unstable | Label::Breakup)) => Some(v),
                Some(_) => None, // outcome labels are recomputed from the counts
                None => bail!("{file}: line {n}: unknown label {s:?}"),
            },
        };
        out.push(Counts {
            alpha: num(idx[0])?,
            beta: num(idx[1])?,
            L: l as u32,
            sigma: num(idx[3])?,
            n_train: count(idx[4])?,
            n_walk: count(idx[5])?,
            n_reversal: count(idx[6])?,
            n_undetermined: count(idx[7])?,
            n_unstable: opt_count(unstable_col)?,
            n_breakup: opt_count(breakup_col)?,
            verdict,
            free_speed: speed_col.and_then(|c| cell(c).parse().ok()),
        });
    }
    if out.is_empty() {
        bail!("{file}: no data rows");
    }
    Ok(out)
}
