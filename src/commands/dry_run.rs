//! `cellsweep run --dry-run`: what a sweep is and what it would cost, writing nothing.

use std::path::Path;
use std::time::Instant;

use cellsweep_report::text::counted;
use cellsweep_scheduler::{plan, Sweep};
use cellsweep_solver::prep::{initial_circle, kick};
use cellsweep_solver::resolution::to_lattice;
use cellsweep_solver::{Cell, Fibers, Lattice, Params, Precision, Real, SOLVER_VERSION};
use cellsweep_store::{MeasuredCost, Store};

/// Seconds per single-cell step on the first point's lattice, from a short measurement here,
/// and the mean over the points of their lattice's sites over the first's (lattices that
/// follow R0 differ from point to point).
/// Seconds per single-cell step measured here: in f64 (the prep's precision) and in the
/// collision's precision (f32 steps are faster), and the sweep's mean lattice size relative to
/// its first point's.
fn single_step_s(sweep: &Sweep) -> (f64, f64, f64) {
    let points = sweep.points();
    let params = &points[0];
    let sites = |p| {
        let [nx, ny] = sweep.protocol_for(p).single_lattice;
        (nx * ny) as f64
    };
    let scale = points.iter().map(|p| sites(p) / sites(params)).sum::<f64>() / points.len() as f64;
    // Measured on the lattice the solver runs: a finer one (resolution k) has k^2 the sites.
    let (params, protocol) = &to_lattice(params, &sweep.protocol_for(params));
    let [nx, ny] = protocol.single_lattice;
    let lat = Lattice::new(nx, ny);
    let fibers = Fibers::at_resolution(params, ny, protocol.resolution);
    let mut cell = Cell::new(&lat, &fibers, initial_circle(&lat, params), lat.zeros());
    kick(&lat, &mut cell);
    let f64_step = best_step_s(&mut cell, &lat, &fibers, params);
    let collision_step = match protocol.precision {
        Precision::F64 => f64_step,
        Precision::F32 => best_step_s(
            &mut cell.convert::<f32>(&lat, &fibers),
            &lat,
            &fibers,
            params,
        ),
    };
    (f64_step, collision_step, scale)
}

/// The fastest of 4 timings of 20 steps of `cell`, per step.
fn best_step_s<T: Real>(
    cell: &mut Cell<T>,
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..4 {
        let t = Instant::now();
        for _ in 0..20 {
            cell.step(lat, fibers, params, [0.05, -0.03], true, false);
        }
        best = best.min(t.elapsed().as_secs_f64() / 20.0);
    }
    best
}

fn hours(s: f64) -> String {
    if s < 3600.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

pub fn run(sweep: &Sweep, source: &Path, db: &Path, workers: usize) -> anyhow::Result<()> {
    let new = plan(sweep, &source.display().to_string());
    let points = new.points.len();
    let first: usize = new.points.iter().map(|p| p.jobs.len()).sum();
    let budget = points * sweep.replicates as usize;
    println!("dry run of {:?} (nothing is written):", sweep.name);
    match &sweep.adaptive {
        Some(a) => println!(
            "  {points} points, {} preps; adaptive: {} replicates per point first, {} more per \
             round until settled (error {:?}), at most {}: {first} jobs in the first round, at most \
             {budget}",
            new.preps.len(),
            a.min_replicates,
            a.batch,
            a.error,
            a.max_replicates
        ),
        None => println!(
            "  {} x {} = {}, {}",
            counted(points, "point"),
            counted(sweep.replicates as usize, "replicate"),
            counted(budget, "job"),
            counted(new.preps.len(), "prep")
        ),
    }
    if let Some(r) = &sweep.refine {
        let most = sweep.max_added_points();
        println!(
            "  refine: up to {} beta values per column ({most} points, at most {} more jobs and \
             {most} more preps), added in rounds of {} once a column is finished, until its \
             interval of beta* is at most {} wide",
            r.max_new_per_column,
            most * sweep.replicates as u64,
            r.per_round,
            r.width
        );
        if let (Some(to), Some(spacing)) = (r.extend_to, r.extend_step) {
            println!(
                "  extension: a column open at its top (no crossing below the grid's last beta) \
                 takes values {spacing} apart above it, up to beta {to}"
            );
        }
    }
    let store = if db.exists() {
        Some(Store::open_read(db)?)
    } else {
        None
    };
    let (jobs_left, preps_left) = match &store {
        Some(store) => left_in_store(store, sweep, db)?,
        None => {
            println!("  {} does not exist: it would be created", db.display());
            None
        }
    }
    .unwrap_or((first as i64, new.preps.len() as i64));
    let measured = match &store {
        Some(s) => Some(s.measured_cost(SOLVER_VERSION)?),
        None => None,
    };
    let (prep_s, collision_s, how) = unit_costs(sweep, measured);
    let total = preps_left.max(0) as f64 * prep_s + jobs_left.max(0) as f64 * collision_s;
    println!("  cost: {prep_s:.1} s per prep, {collision_s:.1} s per collision ({how})");
    println!(
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
    if let (Some(rule), Some(store)) = (&sweep.refine, &store) {
        if let Ok(id) = store.sweep_id(&sweep.name) {
            let ledger = cellsweep_scheduler::Ledger::load(store, id, SOLVER_VERSION)?;
            let columns = ledger.refine_standing(store, rule)?;
            let (lines, next) = cellsweep_report::status::refinement::lines(&columns, rule, "    ");
            println!("  refine now: {}", lines.join("\n"));
            let jobs = next.values as f64 * f64::from(sweep.initial_replicates());
            let cost = next.values as f64 * prep_s + jobs * collision_s;
            println!(
                "  the next round of refinement: {} new points, {jobs} collisions in their first \
                 round and {} preps: {:.2} core-hours (their adaptive rounds follow)",
                next.values,
                next.values,
                cost / 3600.0
            );
            for column in &next.list {
                println!("    {column}");
            }
        }
    }
    Ok(())
}

/// What the store holds of the sweep, printed: the jobs and preps left to run, or None if it
/// is not registered there.
fn left_in_store(store: &Store, sweep: &Sweep, db: &Path) -> anyhow::Result<Option<(i64, i64)>> {
    let Some(s) = store
        .status()?
        .into_iter()
        .find(|s| s.sweep == sweep.name && s.solver_version == SOLVER_VERSION)
    else {
        println!("  not registered in {} yet", db.display());
        return Ok(None);
    };
    println!(
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

/// Seconds per prep and per collision, and how they were found: measured in the store where it
/// has both, else from a single-cell step timed here (a collision at its longest).
fn unit_costs(sweep: &Sweep, measured: Option<MeasuredCost>) -> (f64, f64, String) {
    let first = &sweep.points()[0];
    // Steps of the lattice the solver runs (dt / k^2 on a finer one).
    let (params, p) = &to_lattice(first, &sweep.protocol_for(first));
    let steps = |t: f64| (t / params.dt).round();
    match measured {
        Some(m) if m.prep_s.is_some() && m.collision_s.is_some() => (
            m.prep_s.unwrap_or(0.0),
            m.collision_s.unwrap_or(0.0),
            format!(
                "as measured in this store over {} and {}",
                counted(m.preps as usize, "prep"),
                counted(m.collisions as usize, "collision")
            ),
        ),
        _ => {
            let (step, collision_step, scale) = single_step_s(sweep);
            let (step, collision_step) = (step * scale, collision_step * scale);
            let sites = |l: [usize; 2]| (l[0] * l[1]) as f64;
            let ratio = 2.0 * sites(p.pair_lattice) / sites(p.single_lattice);
            let precision = match p.precision {
                Precision::F64 => String::new(),
                Precision::F32 => {
                    format!(", {:.2} ms in the collision's f32", collision_step * 1e3)
                }
            };
            (
                step * (steps(p.relax_time) + steps(p.free_time)),
                collision_step * ratio * steps(p.collide_time),
                format!(
                    "from a single-cell step of {:.2} ms measured here (f64){precision}; a \
                     collision at most (per-cell windows and early stopping make most far cheaper)",
                    step * 1e3
                ),
            )
        }
    }
}
