//! `cellsweep submit --backend slurm` and `cellsweep collect`.

use anyhow::Context;
use cellsweep_report::engine_text;
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
    if let Some(line) = engine_text::submit_opening(&sweep, &session.registration) {
        println!("{line}");
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
    if let Some(line) = engine_text::submit_ending(finish, &sweep, &args.db.db) {
        println!("{line}");
    }
    Ok(match finish {
        Finish::Done { failed, .. } => super::run::failed_exit(failed, &sweep.name, "submit"),
        Finish::Sent => 0,
        Finish::Interrupted => 130,
    })
}

/// What the engine tells, as the user reads it.
fn print_event(e: &Event<'_>, name: &str, max_attempts: u32) {
    let said = engine_text::event(e, name, max_attempts);
    for w in said.warnings {
        eprintln!("warning: {w}");
    }
    for line in said.lines {
        println!("{line}");
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
