//! `cellsweep run`: register a sweep and run (or resume) it with local worker processes.

use std::time::Duration;

use anyhow::Context;
use cellsweep_scheduler::engine::{
    drive, DriveOptions, Finish, Local, Session, SessionOptions, Target,
};
use cellsweep_scheduler::{RunOptions, Sweep, WorkerCommand};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::Standing;
use cellsweep_store::Store;

use cellsweep_report::{engine_text, text};

use crate::cli::RunArgs;
use crate::progress::SweepBar;

pub fn run(args: RunArgs) -> anyhow::Result<i32> {
    let sweep = Sweep::load(&args.sweep)?;
    let workers = args.workers.map_or_else(
        || std::thread::available_parallelism().map_or(1, |n| n.get()),
        usize::from,
    );
    if args.dry_run {
        let text = cellsweep_report::dry_run::text(&sweep, &args.sweep, &args.db.db, workers)?;
        print!("{text}");
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
    print!(
        "{}",
        engine_text::announcement(&sweep, &session.planned, &session.registration, &args.db.db)
    );
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
        if let Some(line) = engine_text::nothing_to_run(&session.store, &sweep.name)? {
            println!("{line}");
        }
    }
    let interrupted = finish == Finish::Interrupted;
    summarize(&args, &session.store, target.sweep_id, &sweep, interrupted)?;
    Ok(match finish {
        Finish::Interrupted => 130,
        Finish::Done { failed, .. } => failed_exit(failed, &sweep.name, "run"),
        Finish::Sent => 0,
    })
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
        "error: {}",
        engine_text::failed_for_good(failed, name, command)
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
    if let Some(line) = engine_text::adaptive_standing(&loaded, sweep.replicates) {
        println!("{line}");
    }
    Ok(())
}
