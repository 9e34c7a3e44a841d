//! `cellsweep submit --backend slurm` and `cellsweep collect`.

use anyhow::Context;
use cellsweep_scheduler::engine::{
    drive, DriveOptions, EngineError, Event, Finish, Session, SessionOptions, SlurmArrays, Target,
};
use cellsweep_scheduler::slurm::{self, ArrayKind, SubmitOptions};
use cellsweep_scheduler::{plan, StoreLock, Sweep};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::Store;

use crate::cli::{CollectArgs, SubmitArgs};

pub fn submit(args: SubmitArgs) -> anyhow::Result<i32> {
    let sweep = Sweep::load(&args.sweep)?;
    let opts = submit_options(&args, &sweep)?;
    if args.dry_run {
        show_dry_run(&args, &sweep, &opts)?;
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
            refuse_if_elsewhere: false,
        },
    )?;
    if let Some(from) = session.registration.grown_from {
        println!(
            "sweep {:?} grew from {from} to {} replicates per point; the results already stored are kept",
            sweep.name, sweep.replicates
        );
    }
    if let Some(n) = session.retried {
        println!("retrying {n} failed jobs and preps");
    }
    let target = Target {
        sweep_id: session.registration.sweep_id,
        name: &sweep.name,
        version: SOLVER_VERSION,
    };
    let max_attempts = opts.max_attempts;
    let finish = drive(
        &mut SlurmArrays { opts },
        &mut session.store,
        target,
        DriveOptions {
            watch: args.watch,
            poll: args.poll,
            give_up_after: args.give_up_after,
        },
        &mut |e| print_event(&e, &sweep.name, max_attempts),
    )?;
    Ok(match finish {
        Finish::Done { failed, .. } if failed > 0 => {
            println!(
                "nothing to submit: every job of {:?} has a result or failed for good",
                sweep.name
            );
            super::run::failed_exit(failed, &sweep.name, "submit")
        }
        Finish::Done { .. } => {
            println!(
                "nothing to submit: every job of {:?} has a result{}",
                sweep.name,
                match (sweep.adaptive.is_some(), sweep.refine.is_some()) {
                    (_, true) =>
                        ", every point is settled and every column refined as far as its rule goes",
                    (true, false) => " and every point is settled or at its budget",
                    (false, false) => "",
                }
            );
            0
        }
        Finish::Sent => {
            println!(
                "when they are done: cellsweep collect --db {}{}",
                args.db.db.display(),
                if sweep.adaptive.is_some() || sweep.refine.is_some() {
                    ", then submit again for the next round (or submit --watch)"
                } else {
                    ""
                }
            );
            0
        }
        Finish::Interrupted => 130,
    })
}

/// What the Slurm engine tells, as the user reads it.
fn print_event(e: &Event<'_>, name: &str, max_attempts: u32) {
    match e {
        Event::FoundAgain { arrays } => println!(
            "found again {arrays} array(s) of {name:?} that a stop had left recorded without their Slurm id"
        ),
        Event::Collected { dir, collected: c } => {
            for p in &c.problems {
                eprintln!("warning: {p}");
            }
            println!(
                "collected {name:?} from {dir}: {} preps and {} results new, {} already in the store, {} failed attempts recorded",
                c.preps, c.results, c.already, c.failures
            );
            if c.planned > 0 {
                println!(
                    "  planned the next round: {} more jobs (adaptive replicates, refined points)",
                    c.planned
                );
            }
        }
        Event::EndedWithoutResult { kind: k } => println!(
            "  {} {} ended without a result ({}): a failed attempt each; {}: {}",
            k.count,
            if k.count == 1 { "job or prep" } else { "jobs or preps" },
            k.kind,
            if k.count == 1 { "the reason" } else { "the first" },
            k.example
        ),
        Event::OutOfAttempts { count, .. } => println!(
            "{count} preps and jobs are out of attempts ({max_attempts}) or need a prep that is: failed for good"
        ),
        Event::Submitted(sub) => {
            println!(
                "submitted {name:?}: {} preps in {} array tasks, {} collisions in {} array tasks ({} per task); run directory {}",
                sub.preps, sub.prep_tasks, sub.jobs, sub.collide_tasks, sub.jobs_per_task, sub.sub_dir.display()
            );
            for (kind, id) in &sub.slurm_ids {
                println!("  {kind}: Slurm job {id}");
            }
        }
        Event::Retrying {
            error,
            wait,
            failures,
            give_up_after,
        } => eprintln!(
            "warning: {error}; trying again in {wait:.1} s (failure {failures}; the watch gives up after {give_up_after} s of failures)"
        ),
    }
}

/// The submission's options from the flags (the sweep file's `[run]` for attempts), checked;
/// the run directory made absolute, since the array tasks run elsewhere.
fn submit_options(args: &SubmitArgs, sweep: &Sweep) -> anyhow::Result<SubmitOptions> {
    let run_dir = args
        .run_dir
        .clone()
        .unwrap_or_else(|| std::path::PathBuf::from("cellsweep-runs").join(&sweep.name));
    let run_dir = if run_dir.is_absolute() {
        run_dir
    } else {
        std::env::current_dir()?.join(run_dir)
    };
    let opts = SubmitOptions {
        run_dir,
        partition: args.partition.clone(),
        account: args.account.clone(),
        time: args.time.clone(),
        jobs_per_task: args.jobs_per_task as usize,
        max_running: args.max_array.map(|n| n as usize),
        sbatch_args: args.sbatch_args.clone(),
        exe: std::env::current_exe().context("cannot find the cellsweep executable")?,
        max_attempts: args.max_attempts.unwrap_or(sweep.run.max_attempts),
        dry_run: args.dry_run,
    };
    opts.validate()?;
    Ok(opts)
}

/// `submit --dry-run`: the scripts that would be submitted now, changing nothing.
fn show_dry_run(args: &SubmitArgs, sweep: &Sweep, opts: &SubmitOptions) -> anyhow::Result<()> {
    if !args.db.db.exists() {
        let new = plan(sweep, &args.sweep.display().to_string());
        // Nothing to read: show the scripts of a fresh sweep without creating a store.
        let jobs: usize = new.points.iter().map(|p| p.jobs.len()).sum();
        let sub = opts.run_dir.join("sub-0000");
        println!(
            "{}",
            slurm::script(opts, &sub, ArrayKind::Prep, new.preps.len(), &sweep.name)
        );
        println!(
            "{}",
            slurm::script(
                opts,
                &sub,
                ArrayKind::Collide,
                jobs.div_ceil(opts.jobs_per_task),
                &sweep.name
            )
        );
        return Ok(());
    }
    // Read only: what would be submitted now, from the store as it is.
    let mut store = Store::open(&args.db.db)?;
    let Ok(id) = store.sweep_id(&sweep.name) else {
        println!(
            "sweep {:?} is not registered in {}: it would be registered first",
            sweep.name,
            args.db.db.display()
        );
        return Ok(());
    };
    let sub = slurm::submit(&mut store, id, &sweep.name, SOLVER_VERSION, opts)?;
    for (_, text) in &sub.scripts {
        println!("{text}");
    }
    Ok(())
}

pub fn collect(args: CollectArgs) -> anyhow::Result<()> {
    let mut store = Store::open(&args.db.db)?;
    let _lock = StoreLock::acquire(&args.db.db)?;
    store.check_integrity()?;
    let names = match &args.sweep {
        Some(n) => vec![n.clone()],
        None => store.sweep_names()?,
    };
    for name in names {
        let target = Target {
            sweep_id: store.sweep_id(&name)?,
            name: &name,
            version: SOLVER_VERSION,
        };
        match SlurmArrays::collect(&mut store, target, &mut |e| print_event(&e, &name, 0)) {
            Ok(_) => {}
            Err(EngineError::Queue(e)) => eprintln!(
                "warning: {e}: tasks that ended without results are examined once squeue answers"
            ),
            Err(e) => return Err(e.into()),
        }
    }
    Ok(())
}
