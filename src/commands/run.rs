//! `cellsweep run`: register a sweep and run (or resume) it with local worker processes.

use std::path::Path;
use std::time::Duration;

use anyhow::Context;
use cellsweep_scheduler::engine::{
    drive, DriveOptions, Finish, Local, Session, SessionOptions, Target,
};
use cellsweep_scheduler::{RunOptions, Sweep, WorkerCommand};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::Standing;
use cellsweep_store::{NewSweep, Registration, Store};

use cellsweep_report::text;
use cellsweep_report::text::counted;

use crate::cli::RunArgs;
use crate::progress::SweepBar;

pub fn run(args: RunArgs) -> anyhow::Result<i32> {
    let sweep = Sweep::load(&args.sweep)?;
    let workers = args.workers.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get()),
        usize::from,
    );
    if args.dry_run {
        super::dry_run::run(&sweep, &args.sweep, &args.db.db, workers)?;
        return Ok(0);
    }
    let mut session = Session::open(
        &args.db.db,
        &sweep,
        &args.sweep.display().to_string(),
        SOLVER_VERSION,
        SessionOptions {
            replace: args.replace,
            retry_failed: args.retry_failed,
            refuse_if_elsewhere: !args.force,
        },
    )?;
    announce(&sweep, &session.planned, &session.registration, &args.db.db);
    if let Some(n) = session.retried {
        println!("retrying {n} failed jobs and preps");
    }
    let target = Target {
        sweep_id: session.registration.sweep_id,
        name: &sweep.name,
        version: SOLVER_VERSION,
    };
    let mut bar = SweepBar::new();
    let mut local = Local::new(run_options(&args, &sweep, workers)?, &mut bar);
    crate::on_broken_pipe(crate::OnBrokenPipe::Fail);
    let finish = drive(
        &mut local,
        &mut session.store,
        target,
        DriveOptions {
            watch: false,
            poll: 0.0,
            give_up_after: 0.0,
        },
        &mut |_| {},
    );
    bar.finish();
    // The jobs are settled: from here a closed pipe may end the process quietly.
    crate::on_broken_pipe(crate::OnBrokenPipe::Die);
    let finish = finish.with_context(|| format!("the run on {} stopped", args.db.db.display()))?;
    if let Finish::Done { ran: false, .. } = finish {
        say_nothing_to_run(&session.store, target)?;
    }
    let interrupted = finish == Finish::Interrupted;
    summarize(&args, &session.store, target.sweep_id, &sweep, interrupted)?;
    Ok(match finish {
        Finish::Interrupted => 130,
        Finish::Done { failed, .. } => failed_exit(failed, &sweep.name, "run"),
        Finish::Sent => 0,
    })
}

/// What registration did, and the sweep's shape, in a few lines.
fn announce(sweep: &Sweep, new: &NewSweep, reg: &Registration, db: &Path) {
    let n_jobs: usize = new.points.iter().map(|p| p.jobs.len()).sum();
    if let Some(old) = &reg.archived_as {
        println!(
            "the previous sweep {:?} keeps its results as {old:?}",
            sweep.name
        );
    }
    for (version, n) in &reg.other_versions {
        println!(
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
    let shape = if sweep.adaptive.is_some() {
        format!(
            "{} x up to {} (adaptive), {} in the first round",
            counted(new.points.len(), "point"),
            counted(sweep.replicates as usize, "replicate"),
            counted(n_jobs, "job")
        )
    } else {
        format!(
            "{} x {} = {}",
            counted(new.points.len(), "point"),
            counted(sweep.replicates as usize, "replicate"),
            counted(n_jobs, "job")
        )
    };
    println!(
        "{verb} sweep {:?}: {shape}, {}, in {}",
        sweep.name,
        counted(new.preps.len(), "prep"),
        db.display()
    );
    if let Some(a) = &sweep.adaptive {
        println!(
            "  adaptive: {} replicates per point first, then {} more per round until the point's \
             label is settled at error {:?} (or its sign, away from the crossing), at most {}",
            a.min_replicates, a.batch, a.error, a.max_replicates
        );
    }
    if let Some(r) = &sweep.refine {
        println!(
            "  refine: once a column's points are finished, up to {} beta values per round on \
             multiples of {} inside its 95% interval of beta*, until the interval is at most {} \
             wide (at most {} values per column)",
            r.per_round, r.step, r.width, r.max_new_per_column
        );
    }
    if let Some(from) = reg.grown_from {
        println!(
            "  from {from} replicates per point: the results already stored are kept, and only the \
             new replicates run (a replicate's seed depends on its index, not on the count)"
        );
    }
}

/// A sweep with nothing left to run: how far it is, and the way to its failed jobs.
fn say_nothing_to_run(store: &Store, target: Target<'_>) -> anyhow::Result<()> {
    let Some(s) = store
        .status()?
        .into_iter()
        .find(|s| s.sweep == target.name && s.solver_version == target.version)
    else {
        return Ok(());
    };
    let failed = if s.jobs.failed > 0 {
        format!(
            " ({} failed: `cellsweep run --retry-failed` runs them again)",
            s.jobs.failed
        )
    } else {
        String::new()
    };
    println!(
        "{} of {} jobs done{failed}, nothing to run",
        s.jobs.done,
        s.jobs.total()
    );
    Ok(())
}

/// The local engine's options: the flags, else the sweep file's `[run]`.
fn run_options(args: &RunArgs, sweep: &Sweep, workers: usize) -> anyhow::Result<RunOptions> {
    Ok(RunOptions {
        workers,
        job_timeout: Duration::from_secs_f64(
            // Both checked to lie in (0, 30 days] by the flag's parser and the sweep file's.
            args.job_timeout.unwrap_or(sweep.run.job_timeout),
        ),
        max_attempts: args.max_attempts.unwrap_or(sweep.run.max_attempts),
        worker: WorkerCommand {
            exe: std::env::current_exe().context("cannot find the cellsweep executable")?,
            args: vec!["worker".into()],
        },
        grace: Duration::from_secs_f64(args.grace),
    })
}

/// Exit code of a finished run on either engine (`command`: run or submit): 1, with the way
/// out, if jobs failed after their retries.
pub(super) fn failed_exit(failed: u64, name: &str, command: &str) -> i32 {
    if failed == 0 {
        return 0;
    }
    eprintln!(
        "error: {failed} jobs of {name:?} failed after retries; `cellsweep status --failed` lists \
         them with their errors, `cellsweep {command} --retry-failed` runs them again"
    );
    1
}

/// After a run: the point counts, the diagram tables, the figures if asked (only for a
/// finished sweep), and an adaptive sweep's standing.
fn summarize(
    args: &RunArgs,
    store: &Store,
    sweep_id: i64,
    sweep: &Sweep,
    interrupted: bool,
) -> anyhow::Result<()> {
    let points = store.point_counts(sweep_id, SOLVER_VERSION)?;
    print!(
        "{}",
        text::point_counts_text(&points, &sweep.name, SOLVER_VERSION)
    );
    let loaded = cellsweep_report::load::from_store(&args.db.db, Some(&sweep.name))?;
    println!();
    print!("{}", text::grids_text(&loaded.counts));
    println!("{}", text::legend());
    let unfinished = interrupted
        || loaded
            .standings
            .as_ref()
            .is_some_and(|st| st.iter().any(|a| a.standing == Standing::Open));
    if let (Some(dir), true) = (&args.plot, unfinished) {
        println!(
            "the sweep is not finished: no figures written to {} (run again to finish it; \
             `cellsweep plot` draws what there is, with the replicates per point)",
            dir.display()
        );
    } else if let Some(dir) = &args.plot {
        for f in cellsweep_report::plot_files::write_plots(&loaded, dir)? {
            println!("wrote {}", f.display());
        }
    }
    if let Some(st) = &loaded.standings {
        let mut by: std::collections::BTreeMap<&str, usize> = Default::default();
        for a in st {
            *by.entry(a.standing.as_str()).or_default() += 1;
        }
        let ran: u64 = loaded.counts.iter().map(|c| c.total()).sum();
        let budget = st.len() as u64 * sweep.replicates as u64;
        println!(
            "adaptive: {}; {ran} of {budget} replicates run ({:.0}%)",
            by.iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(", "),
            100.0 * ran as f64 / budget.max(1) as f64
        );
    }
    Ok(())
}
