//! What `cellsweep run --dry-run` says: what a sweep is, what the store already holds of it,
//! and what running it now would cost, writing nothing ([`text`]).

use std::fmt::Write;
use std::path::Path;

use cellsweep_scheduler::cost::{unit_costs, CostBasis, UnitCosts};
use cellsweep_scheduler::{plan, Ledger, RunError, Sweep};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::{NewSweep, Store, StoreError};

use crate::text::counted;

/// Why a dry run could not read the store.
#[derive(Debug, thiserror::Error)]
pub enum DryRunError {
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error(transparent)]
    Ledger(#[from] RunError),
}

fn hours(s: f64) -> String {
    if s < 3600.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// The dry run of `sweep` (read from `source`) against the store at `db` (which need not
/// exist), with `workers` workers.
pub fn text(
    sweep: &Sweep,
    source: &Path,
    db: &Path,
    workers: usize,
) -> Result<String, DryRunError> {
    let new = plan(sweep, &source.display().to_string());
    let first: usize = new.points.iter().map(|p| p.jobs.len()).sum();
    let mut out = format!("dry run of {:?} (nothing is written):\n", sweep.name);
    shape(&mut out, sweep, &new);
    let store = match db.exists() {
        true => Some(Store::open_read(db)?),
        false => None,
    };
    let (jobs_left, preps_left) = match &store {
        Some(store) => left_in_store(&mut out, store, sweep, db)?,
        None => {
            let _ = writeln!(
                out,
                "  {} does not exist: it would be created",
                db.display()
            );
            None
        }
    }
    .unwrap_or((first as i64, new.preps.len() as i64));
    let measured = match &store {
        Some(s) => Some(s.measured_cost(SOLVER_VERSION)?),
        None => None,
    };
    let UnitCosts {
        prep_s,
        collision_s,
        basis,
    } = unit_costs(sweep, measured);
    let how = basis_words(&basis);
    let total = preps_left.max(0) as f64 * prep_s + jobs_left.max(0) as f64 * collision_s;
    let _ = writeln!(
        out,
        "  cost: {prep_s:.1} s per prep, {collision_s:.1} s per collision ({how})"
    );
    let _ = writeln!(
        out,
        "  to run now: {} and {}{}: {:.2} core-hours, about {} on {}",
        counted(preps_left.max(0) as usize, "prep"),
        counted(jobs_left.max(0) as usize, "collision"),
        if sweep.adaptive.is_some() {
            " (the first round; later rounds follow)"
        } else {
            ""
        },
        total / 3600.0,
        hours(total / workers.max(1) as f64),
        counted(workers, "worker")
    );
    if let Some(store) = &store {
        refine_now(&mut out, sweep, store, prep_s, collision_s)?;
    }
    Ok(out)
}

/// The sweep's points, replicates, jobs and preps, and its adaptive and refinement rules,
/// written to `out`.
fn shape(out: &mut String, sweep: &Sweep, new: &NewSweep) {
    let points = new.points.len();
    let first: usize = new.points.iter().map(|p| p.jobs.len()).sum();
    let budget = points * sweep.replicates as usize;
    let _ = match &sweep.adaptive {
        Some(a) => writeln!(
            out,
            "  {points} points, {} preps; adaptive: {} replicates per point first, {} more per \
             round until settled (error {:?}), at most {}: {first} jobs in the first round, at most \
             {budget}",
            new.preps.len(),
            a.min_replicates,
            a.batch,
            a.error,
            a.max_replicates
        ),
        None => writeln!(
            out,
            "  {} x {} = {}, {}",
            counted(points, "point"),
            counted(sweep.replicates as usize, "replicate"),
            counted(budget, "job"),
            counted(new.preps.len(), "prep")
        ),
    };
    if let Some(r) = &sweep.refine {
        let most = sweep.max_added_points();
        let _ = writeln!(
            out,
            "  refine: up to {} beta values per column ({most} points, at most {} more jobs and \
             {most} more preps), added in rounds of {} once a column is finished, until its \
             interval of beta* is at most {} wide",
            r.max_new_per_column,
            most * sweep.replicates as u64,
            r.per_round,
            r.width
        );
        if let (Some(to), Some(spacing)) = (r.extend_to, r.extend_step) {
            let _ = writeln!(
                out,
                "  extension: a column open at its top (no crossing below the grid's last beta) \
                 takes values {spacing} apart above it, up to beta {to}"
            );
        }
    }
}

/// Where the store's columns stand under the sweep's refinement rule, and what its next round
/// would add and cost, written to `out` (nothing for a sweep without one, or not registered).
fn refine_now(
    out: &mut String,
    sweep: &Sweep,
    store: &Store,
    prep_s: f64,
    collision_s: f64,
) -> Result<(), DryRunError> {
    let (Some(rule), Ok(id)) = (&sweep.refine, store.sweep_id(&sweep.name)) else {
        return Ok(());
    };
    let ledger = Ledger::load(store, id, SOLVER_VERSION)?;
    let columns = ledger.refine_standing(store, rule)?;
    let (lines, next) = crate::status::refinement::lines(&columns, rule, "    ");
    let _ = writeln!(out, "  refine now: {}", lines.join("\n"));
    let jobs = next.values as f64 * f64::from(sweep.initial_replicates());
    let cost = next.values as f64 * prep_s + jobs * collision_s;
    let _ = writeln!(
        out,
        "  the next round of refinement: {} new points, {jobs} collisions in their first \
         round and {} preps: {:.2} core-hours (their adaptive rounds follow)",
        next.values,
        next.values,
        cost / 3600.0
    );
    for column in &next.list {
        let _ = writeln!(out, "    {column}");
    }
    Ok(())
}

/// What the store holds of the sweep, written to `out`: the jobs and preps left to run, or
/// None if it is not registered there.
fn left_in_store(
    out: &mut String,
    store: &Store,
    sweep: &Sweep,
    db: &Path,
) -> Result<Option<(i64, i64)>, StoreError> {
    let Some(s) = store.sweep_status(&sweep.name, SOLVER_VERSION)? else {
        let _ = writeln!(out, "  not registered in {} yet", db.display());
        return Ok(None);
    };
    let _ = writeln!(
        out,
        "  in {}: {} done, {} pending, {} running, {} failed; {} of {} done",
        db.display(),
        counted(s.jobs.done as usize, "job"),
        s.jobs.pending,
        s.jobs.running,
        s.jobs.failed,
        s.preps_done,
        counted(s.preps_total as usize, "prep")
    );
    Ok(Some((
        s.jobs.pending + s.jobs.running,
        s.preps_total - s.preps_done,
    )))
}

/// How the unit costs were found, in words.
fn basis_words(basis: &CostBasis) -> String {
    match *basis {
        CostBasis::Measured { preps, collisions } => format!(
            "as measured in this store over {} and {}",
            counted(preps as usize, "prep"),
            counted(collisions as usize, "collision")
        ),
        CostBasis::Timed {
            step_s,
            collision_step_s,
        } => format!(
            "from a single-cell step of {:.2} ms measured here (f64){}; a collision at most \
             (per-cell windows and early stopping make most far cheaper)",
            step_s * 1e3,
            collision_step_s.map_or(String::new(), |c| format!(
                ", {:.2} ms in the collision's f32",
                c * 1e3
            ))
        ),
    }
}
