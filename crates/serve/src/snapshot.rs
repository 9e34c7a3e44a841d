//! What a store holds at one moment: every sweep's progress, standings, failures, Slurm arrays
//! and diagrams, gathered through one read-only connection.

use std::collections::BTreeMap;
use std::path::Path;

use cellsweep_report::{figures, load, Results};
use cellsweep_scheduler::slurm::shell_quote;
use cellsweep_scheduler::Ledger;
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::{Failure, SlurmArray, Store, SweepStatus};
use serde::Serialize;

/// Diagrams are drawn live only for sweeps of at most this many points: a figure of more
/// would be megabytes of SVG on every change (`cellsweep plot` draws any size).
pub const MAX_LIVE_POINTS: usize = 5_000;

/// One sweep under one solver version, as the page shows it.
#[derive(Debug, Clone, Serialize)]
pub struct SweepView {
    /// Progress, outcomes, speed and ETA: exactly `cellsweep status`'s numbers.
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
    /// Its box-limited points (SPEC 4.5), as `status` lists them.
    pub box_limited: Vec<String>,
    pub failures: Vec<Failure>,
    /// The command that puts the failures back to pending and runs them.
    pub retry: Option<String>,
    pub arrays: Vec<SlurmArray>,
    /// States of the arrays' tasks in Slurm's queue, or why squeue gave no answer.
    pub queue: Result<Vec<(String, usize)>, String>,
    /// The diagrams as inline SVG, or why they are not drawn.
    #[serde(skip)]
    pub diagrams: Result<Vec<String>, String>,
}

/// Every sweep of a store at one moment, or why there is none.
#[derive(Debug, Clone, Serialize)]
pub struct Snapshot {
    pub store: String,
    pub sweeps: Vec<SweepView>,
    /// Why there is nothing to show: no store at the path, or a store with no sweep.
    pub message: Option<String>,
    /// When it was gathered (Unix seconds).
    pub at: f64,
}

impl Snapshot {
    /// A page with nothing but a message (no store yet, or a file that is not a store).
    pub fn empty(path: &Path, message: String) -> Snapshot {
        Snapshot {
            store: path.display().to_string(),
            sweeps: Vec::new(),
            message: Some(message),
            at: cellsweep_store::now(),
        }
    }

    /// Everything `store` (opened read-only at `path`) holds now.
    pub fn gather(store: &Store, path: &Path) -> Result<Snapshot, String> {
        let all = store.status().map_err(|e| e.to_string())?;
        let names = store.sweep_names().map_err(|e| e.to_string())?;
        let mut sweeps = Vec::new();
        let live = cellsweep_scheduler::StoreLock::is_held(path);
        for status in all {
            let mut view = sweep_view(store, path, status)?;
            view.live = live;
            sweeps.push(view);
        }
        let message = match (names.is_empty(), sweeps.is_empty()) {
            (true, _) => Some(format!("{} holds no sweep yet", path.display())),
            (false, true) => Some(format!(
                "{} holds sweeps ({}) but no jobs yet",
                path.display(),
                names.join(", ")
            )),
            _ => None,
        };
        Ok(Snapshot {
            store: path.display().to_string(),
            sweeps,
            message,
            at: cellsweep_store::now(),
        })
    }

    /// Whether every sweep shown is finished (and there is at least one).
    pub fn finished(&self) -> bool {
        !self.sweeps.is_empty() && self.sweeps.iter().all(|s| s.finished)
    }
}

fn sweep_view(store: &Store, path: &Path, status: SweepStatus) -> Result<SweepView, String> {
    let e = |e: &dyn std::fmt::Display| format!("sweep {:?}: {e}", status.sweep);
    let id = store.sweep_id(&status.sweep).map_err(|x| e(&x))?;
    let current = status.solver_version == SOLVER_VERSION;
    let ledger = Ledger::load(store, id, &status.solver_version).map_err(|x| e(&x))?;
    let standings = match current {
        true => ledger.standing_counts(store).map_err(|x| e(&x))?,
        false => None,
    };
    let points = ledger.points(store).map_err(|x| e(&x))?;
    let refined_points = ledger.sweep.refine.map(|_| {
        let grid = &ledger.sweep.grid.beta;
        points.iter().filter(|p| !grid.contains(&p.beta)).count()
    });
    let failures = store
        .failures(id, &status.solver_version)
        .map_err(|x| e(&x))?;
    let retry = (!failures.is_empty()).then(|| retry_command(store, id, path));
    let arrays = store
        .arrays_of(id, &status.solver_version)
        .map_err(|x| e(&x))?;
    let queue =
        cellsweep_scheduler::slurm::queue_of(&status.sweep, &arrays).map_err(|e| e.to_string());
    let open = standings
        .as_ref()
        .and_then(|s| s.get("open"))
        .copied()
        .unwrap_or(0);
    let j = &status.jobs;
    let finished = j.pending == 0 && j.running == 0 && open == 0;
    let loaded = match (current, points.len()) {
        (false, _) => Err("only the current solver version's results are drawn".to_string()),
        (true, n) if n > MAX_LIVE_POINTS => Err(format!(
            "{n} points: too many to redraw live (cellsweep plot --db {} draws them)",
            path.display()
        )),
        (true, _) => load::from_store(path, Some(&status.sweep)).map_err(|x| e(&x)),
    };
    let box_limited = loaded
        .as_ref()
        .map(|r| r.box_limited_points())
        .unwrap_or_default();
    let diagrams = loaded.map(|r| draw(&r));
    Ok(SweepView {
        live: false,
        current,
        finished,
        standings,
        points: points.len(),
        refined_points,
        box_limited,
        failures,
        retry,
        arrays,
        queue,
        diagrams,
        status,
    })
}

/// Every diagram of `results` as SVG (the report's four-panel figure, paper's line drawn).
fn draw(results: &Results) -> Vec<String> {
    figures::diagrams(&results.counts)
        .iter()
        .map(|k| figures::diagram_of(results, k, None).to_svg())
        .collect()
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
