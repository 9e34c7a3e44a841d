//! A store's status at one moment, one model for every reader: `cellsweep status` (text and
//! JSON) and the live page of `cellsweep serve` render the same [`SweepView`]s, gathered here
//! through one read-only connection: progress, outcomes, speed and ETA, each point's adaptive
//! standing, a refined sweep's columns, box-limited points, failures with the command that
//! retries them, and the engine's queue (Slurm arrays and their tasks' states).

use std::collections::BTreeMap;
use std::path::Path;

use cellsweep_scheduler::engine;
use cellsweep_scheduler::ledger::ColumnStanding;
use cellsweep_scheduler::slurm::shell_quote;
use cellsweep_scheduler::{Ledger, RunError};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::RefineRule;
use cellsweep_store::{Failure, SlurmArray, Store, StoreError, SweepStatus};
use serde::Serialize;

use crate::load;
use crate::Results;

pub mod refinement;
pub mod text;

/// Why a store's status could not be read: one line naming the sweep where it is one's.
#[derive(Debug, thiserror::Error)]
pub enum StatusError {
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("sweep {sweep:?}: {source}")]
    Ledger {
        sweep: String,
        #[source]
        source: RunError,
    },
}

/// Why a part of a [`SweepView`] is not there (the queue did not answer, the results are not
/// read or are too many to redraw live), in the words every reader shows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unavailable(pub String);

impl std::fmt::Display for Unavailable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// One sweep under one solver version, as every reader shows it.
#[derive(Debug, Clone, Serialize)]
pub struct SweepView {
    /// Progress, outcomes, speed and ETA.
    pub status: SweepStatus,
    /// Whether the jobs are the current solver's (only those run).
    pub current: bool,
    /// Nothing pending or running, and no point open for another adaptive round.
    pub finished: bool,
    /// A writer holds the store now (a run, a watching submit): else jobs marked running were
    /// left by a run that died.
    pub live: bool,
    /// Points by adaptive standing (open, settled, sign, exhausted, verdict).
    pub standings: Option<BTreeMap<&'static str, usize>>,
    /// Points registered, and of them those refinement added between the grid's betas.
    pub points: usize,
    pub refined_points: Option<usize>,
    /// A refined sweep's rule and each column's standing.
    #[serde(skip)]
    pub refinement: Option<(RefineRule, Vec<ColumnStanding>)>,
    /// Its box-limited points (SPEC 4.5).
    pub box_limited: Vec<String>,
    pub failures: Vec<Failure>,
    /// The command that puts the failures back to pending and runs them.
    pub retry: Option<String>,
    pub arrays: Vec<SlurmArray>,
    /// States of the arrays' tasks in Slurm's queue, or why squeue gave no answer.
    pub queue: Result<Vec<(String, usize)>, Unavailable>,
    /// The sweep's results, where they are read (the current solver's, at most `max_points`
    /// points): what the live page draws.
    #[serde(skip)]
    pub results: Result<Results, Unavailable>,
}

/// Every sweep of `store` (opened read-only at `path`) under each solver version it has jobs
/// of; `results` kept for sweeps of at most `max_points` points.
pub fn gather(
    store: &Store,
    path: &Path,
    max_points: usize,
) -> Result<Vec<SweepView>, StatusError> {
    let live = cellsweep_scheduler::StoreLock::is_held(path);
    store
        .status()?
        .into_iter()
        .map(|s| sweep_view(store, path, s, live, max_points))
        .collect()
}

fn sweep_view(
    store: &Store,
    path: &Path,
    status: SweepStatus,
    live: bool,
    max_points: usize,
) -> Result<SweepView, StatusError> {
    let sweep = status.sweep.clone();
    let ledger_err = |source| StatusError::Ledger {
        sweep: sweep.clone(),
        source,
    };
    let id = store.sweep_id(&status.sweep)?;
    let current = status.solver_version == SOLVER_VERSION;
    let ledger = Ledger::load(store, id, &status.solver_version).map_err(ledger_err)?;
    let standings = match current {
        true => ledger.standing_counts(store).map_err(ledger_err)?,
        false => None,
    };
    let points = ledger.points(store).map_err(ledger_err)?;
    let refined_points = ledger.sweep.refine.map(|_| {
        let grid = &ledger.sweep.grid.beta;
        points.iter().filter(|p| !grid.contains(&p.beta)).count()
    });
    let refinement = match (current, ledger.sweep.refine) {
        (true, Some(rule)) => Some((
            rule,
            ledger.refine_standing(store, &rule).map_err(ledger_err)?,
        )),
        _ => None,
    };
    let failures = store.failures(id, &status.solver_version)?;
    let retry = (!failures.is_empty()).then(|| retry_command(store, id, path));
    let arrays = store.arrays_of(id, &status.solver_version)?;
    let queue = engine::queue_states(store, id, &status.sweep, &status.solver_version)
        .map_err(|e| Unavailable(e.to_string()));
    let open = standings
        .as_ref()
        .and_then(|s| s.get("open"))
        .copied()
        .unwrap_or(0);
    let j = &status.jobs;
    let finished = j.pending == 0 && j.running == 0 && open == 0;
    // Read once: for the box-limited flags (every size) and for what the page draws.
    let loaded = current.then(|| load::from_store(path, Some(&status.sweep)));
    let box_limited = match &loaded {
        Some(Ok(r)) => r.box_limited_points(),
        _ => Vec::new(),
    };
    let results = match loaded {
        None => Err("only the current solver version's results are read".to_string()),
        Some(_) if points.len() > max_points => Err(format!(
            "{} points: too many to redraw live (cellsweep plot --db {} draws them)",
            points.len(),
            path.display()
        )),
        Some(r) => r.map_err(|e| format!("sweep {sweep:?}: {e}")),
    }
    .map_err(Unavailable);
    Ok(SweepView {
        live,
        current,
        finished,
        standings,
        points: points.len(),
        refined_points,
        refinement,
        box_limited,
        failures,
        retry,
        arrays,
        queue,
        results,
        status,
    })
}

/// `cellsweep run FILE --db DB --retry-failed`, quoted for a POSIX shell.
fn retry_command(store: &Store, sweep_id: i64, db: &Path) -> String {
    let file = store
        .sweep_source(sweep_id)
        .ok()
        .flatten()
        .filter(|s| !s.is_empty());
    format!(
        "cellsweep run {} --db {} --retry-failed",
        file.map_or("SWEEP.toml".to_string(), |f| shell_quote(&f)),
        shell_quote(&db.display().to_string())
    )
}
