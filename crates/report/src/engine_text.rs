//! What `cellsweep run`, `submit` and `collect` say about a sweep's session on an engine:
//! what registration did ([`announcement`], [`submit_opening`]), each engine [`Event`]
//! ([`event`]), how the session ended ([`nothing_to_run`], [`submit_ending`],
//! [`failed_for_good`]) and an adaptive sweep's standing after a run ([`adaptive_standing`]).

use std::fmt::Write;
use std::path::Path;

use cellsweep_scheduler::engine::{Event, Finish};
use cellsweep_scheduler::Sweep;
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::{NewSweep, Registration, Store, StoreError};

use crate::text::counted;
use crate::Results;

/// What registration did, and the sweep's shape, in a few lines (`run`).
pub fn announcement(sweep: &Sweep, new: &NewSweep, reg: &Registration, db: &Path) -> String {
    let n_jobs: usize = new.points.iter().map(|p| p.jobs.len()).sum();
    let mut out = String::new();
    if let Some(old) = &reg.archived_as {
        let _ = writeln!(
            out,
            "the previous sweep {:?} keeps its results as {old:?}",
            sweep.name
        );
    }
    for (version, n) in &reg.other_versions {
        let _ = writeln!(
            out,
            "note: the store holds {n} results of {:?} from {version}; this run is {SOLVER_VERSION}, \
             and the two stay apart",
            sweep.name
        );
    }
    let verb = if reg.created {
        "registered"
    } else if reg.grown_from.is_some() {
        "grew"
    } else {
        "resuming"
    };
    let (points, replicates) = (
        counted(new.points.len(), "point"),
        counted(sweep.replicates as usize, "replicate"),
    );
    let shape = match sweep.adaptive {
        Some(_) => format!(
            "{points} x up to {replicates} (adaptive), {} in the first round",
            counted(n_jobs, "job")
        ),
        None => format!("{points} x {replicates} = {}", counted(n_jobs, "job")),
    };
    let _ = writeln!(
        out,
        "{verb} sweep {:?}: {shape}, {}, in {}",
        sweep.name,
        counted(new.preps.len(), "prep"),
        db.display()
    );
    if let Some(a) = &sweep.adaptive {
        let _ = writeln!(
            out,
            "  adaptive: {} replicates per point first, then {} more per round until the point's \
             label is settled at error {:?} (or its sign, away from the crossing), at most {}",
            a.min_replicates, a.batch, a.error, a.max_replicates
        );
    }
    if let Some(r) = &sweep.refine {
        let _ = writeln!(
            out,
            "  refine: once a column's points are finished, up to {} beta values per round on \
             multiples of {} inside its 95% interval of beta*, until the interval is at most {} \
             wide (at most {} values per column)",
            r.per_round, r.step, r.width, r.max_new_per_column
        );
    }
    if let Some(from) = reg.grown_from {
        let _ = writeln!(
            out,
            "  from {from} replicates per point: the results already stored are kept, and only the \
             new replicates run (a replicate's seed depends on its index, not on the count)"
        );
    }
    out
}

/// What registration did, where it did something to say (`submit`: a sweep grown).
pub fn submit_opening(sweep: &Sweep, reg: &Registration) -> Option<String> {
    reg.grown_from.map(|from| {
        format!(
            "sweep {:?} grew from {from} to {} replicates per point; the results already stored \
             are kept",
            sweep.name, sweep.replicates
        )
    })
}

/// A sweep with nothing left to run: how far it is, and the way to its failed jobs.
pub fn nothing_to_run(store: &Store, name: &str) -> Result<Option<String>, StoreError> {
    let Some(s) = store.sweep_status(name, SOLVER_VERSION)? else {
        return Ok(None);
    };
    let failed = match s.jobs.failed {
        0 => String::new(),
        n => format!(" ({n} failed: `cellsweep run --retry-failed` runs them again)"),
    };
    Ok(Some(format!(
        "{} of {} jobs done{failed}, nothing to run",
        s.jobs.done,
        s.jobs.total()
    )))
}

/// The error line of a session whose jobs failed after their retries, with the way out
/// (`command`: run or submit).
pub fn failed_for_good(failed: u64, name: &str, command: &str) -> String {
    format!(
        "{failed} jobs of {name:?} failed after retries; `cellsweep status --failed` lists them \
         with their errors, `cellsweep {command} --retry-failed` runs them again"
    )
}

/// What `submit` says once the engine is done with it (None: interrupted).
pub fn submit_ending(finish: Finish, sweep: &Sweep, db: &Path) -> Option<String> {
    let rounds = sweep.adaptive.is_some() || sweep.refine.is_some();
    match finish {
        Finish::Done { failed, .. } if failed > 0 => Some(format!(
            "nothing to submit: every job of {:?} has a result or failed for good",
            sweep.name
        )),
        Finish::Done { .. } => Some(format!(
            "nothing to submit: every job of {:?} has a result{}",
            sweep.name,
            match (sweep.adaptive.is_some(), sweep.refine.is_some()) {
                (_, true) =>
                    ", every point is settled and every column refined as far as its rule goes",
                (true, false) => " and every point is settled or at its budget",
                (false, false) => "",
            }
        )),
        Finish::Sent => Some(format!(
            "when they are done: cellsweep collect --db {}{}",
            db.display(),
            match rounds {
                true => ", then submit again for the next round (or submit --watch)",
                false => "",
            }
        )),
        Finish::Interrupted => None,
    }
}

/// An event's words: warnings (for stderr) and lines (for stdout).
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Said {
    pub warnings: Vec<String>,
    pub lines: Vec<String>,
}

/// What an engine's event tells the user, for sweep `name` (`max_attempts`: the attempts a
/// job has).
pub fn event(e: &Event<'_>, name: &str, max_attempts: u32) -> Said {
    let mut said = Said::default();
    match e {
        Event::FoundAgain { arrays } => said.lines.push(format!(
            "found again {arrays} array(s) of {name:?} that a stop had left recorded without their \
             Slurm id"
        )),
        Event::Collected { dir, collected: c } => {
            said.warnings.extend(c.problems.iter().cloned());
            said.lines.push(format!(
                "collected {name:?} from {dir}: {} preps and {} results new, {} already in the \
                 store, {} failed attempts recorded",
                c.preps, c.results, c.already, c.failures
            ));
            if c.planned > 0 {
                said.lines.push(format!(
                    "  planned the next round: {} more jobs (adaptive replicates, refined points)",
                    c.planned
                ));
            }
        }
        Event::EndedWithoutResult { kind: k } => said.lines.push(format!(
            "  {} {} ended without a result ({}): a failed attempt each; {}: {}",
            k.count,
            if k.count == 1 {
                "job or prep"
            } else {
                "jobs or preps"
            },
            k.kind,
            if k.count == 1 {
                "the reason"
            } else {
                "the first"
            },
            k.example
        )),
        Event::OutOfAttempts { count, .. } => said.lines.push(format!(
            "{count} preps and jobs are out of attempts ({max_attempts}) or need a prep that is: \
             failed for good"
        )),
        Event::Submitted(sub) => {
            said.lines.push(format!(
                "submitted {name:?}: {} preps in {} array tasks, {} collisions in {} array tasks \
                 ({} per task); run directory {}",
                sub.preps,
                sub.prep_tasks,
                sub.jobs,
                sub.collide_tasks,
                sub.jobs_per_task,
                sub.sub_dir.display()
            ));
            for (kind, id) in &sub.slurm_ids {
                said.lines.push(format!("  {kind}: Slurm job {id}"));
            }
        }
        Event::Retrying {
            error,
            wait,
            failures,
            give_up_after,
        } => said.warnings.push(format!(
            "{error}; trying again in {wait:.1} s (failure {failures}; the watch gives up after \
             {give_up_after} s of failures)"
        )),
    }
    said
}

/// An adaptive sweep's points by standing, and the replicates run of its budget of
/// `replicates` per point (None for a sweep that is not adaptive).
pub fn adaptive_standing(loaded: &Results, replicates: u32) -> Option<String> {
    let st = loaded.standings.as_ref()?;
    let mut by: std::collections::BTreeMap<&str, usize> = Default::default();
    for a in st {
        *by.entry(a.standing.as_str()).or_default() += 1;
    }
    let ran: u64 = loaded.counts.iter().map(|c| c.total()).sum();
    let budget = st.len() as u64 * replicates as u64;
    let by: Vec<String> = by.iter().map(|(k, n)| format!("{n} {k}")).collect();
    Some(format!(
        "adaptive: {}; {ran} of {budget} replicates run ({:.0}%)",
        by.join(", "),
        100.0 * ran as f64 / budget.max(1) as f64
    ))
}
