//! `cellsweep submit --backend slurm` and `cellsweep collect`.

use anyhow::{bail, Context};
use cellsweep_scheduler::slurm::{self, SubmitOptions};
use cellsweep_scheduler::{plan, StoreLock, Sweep};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::{NewSweep, Store};

use crate::cli::{CollectArgs, SubmitArgs};

fn collect_sweep(store: &mut Store, sweep_id: i64, name: &str) -> anyhow::Result<()> {
    let mut dirs: Vec<String> = store
        .arrays_of(sweep_id, SOLVER_VERSION)?
        .into_iter()
        .map(|a| a.run_dir)
        .collect();
    dirs.sort();
    dirs.dedup();
    for d in dirs {
        let c = slurm::collect(store, sweep_id, SOLVER_VERSION, std::path::Path::new(&d))?;
        for p in &c.problems {
            eprintln!("warning: {p}");
        }
        println!(
            "collected {name:?} from {d}: {} preps and {} results new, {} already in the store, {} failed attempts recorded",
            c.preps, c.results, c.already, c.failures
        );

        if c.planned > 0 {
            println!(
                "  planned the next round: {} more jobs (adaptive replicates, refined points)",
                c.planned
            );
        }
    }
    Ok(())
}

pub fn submit(args: SubmitArgs) -> anyhow::Result<i32> {
    let sweep = Sweep::load(&args.sweep)?;
    let new = plan(&sweep, &args.sweep.display().to_string());
    let opts = submit_options(&args, &sweep)?;
    if args.dry_run {
        show_dry_run(&args, &sweep, &new, &opts)?;
        return Ok(0);
    }
    let _lock = StoreLock::acquire(&args.db.db)?;
    let mut store = Store::open_or_create(&args.db.db)?;
    store.check_integrity()?;
    let reg = store.register(&new, args.replace)?;
    if let Some(from) = reg.grown_from {
        println!(
            "sweep {:?} grew from {from} to {} replicates per point; the results already stored are kept",
            sweep.name, sweep.replicates
        );
    }
    if args.retry_failed {
        let n = store.retry_failed(reg.sweep_id, SOLVER_VERSION)?;
        println!("retrying {n} failed jobs and preps");
    }
    loop {
        if let Some(code) = submit_round(&args, &mut store, reg.sweep_id, &sweep, &opts)? {
            return Ok(code);
        }
        std::thread::sleep(std::time::Duration::from_secs_f64(args.poll));
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
fn show_dry_run(
    args: &SubmitArgs,
    sweep: &Sweep,
    new: &NewSweep,
    opts: &SubmitOptions,
) -> anyhow::Result<()> {
    if !args.db.db.exists() {
        // Nothing to read: show the scripts of a fresh sweep without creating a store.
        let jobs: usize = new.points.iter().map(|p| p.jobs.len()).sum();
        let sub = opts.run_dir.join("sub-0000");
        println!(
            "{}",
            slurm::script(opts, &sub, "prep", new.preps.len(), &sweep.name)
        );
        println!(
            "{}",
            slurm::script(
                opts,
                &sub,
                "collide",
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

/// One round of `submit`: take in what finished, then submit what is owed. Some exit code
/// when there is nothing more to do (or, without `--watch`, once submitted); None to wait.
fn submit_round(
    args: &SubmitArgs,
    store: &mut Store,
    sweep_id: i64,
    sweep: &Sweep,
    opts: &SubmitOptions,
) -> anyhow::Result<Option<i32>> {
    // Ask the queue first, then take in what finished (an adaptive sweep's next round is
    // planned from it), and wait while earlier arrays still run. In this order a task that ends
    // between the two steps is still counted as running, so its results are collected next
    // time; the other order could read its result file before the task wrote it, then see the
    // array gone from the queue and send the job again.
    let ids: Vec<String> = store
        .arrays_of(sweep_id, SOLVER_VERSION)?
        .into_iter()
        .map(|a| a.slurm_job_id)
        .collect();
    let states = slurm::queue_states(&ids);
    collect_sweep(store, sweep_id, &sweep.name)?;
    // Without an answer from the queue, jobs still running would look lost and be sent again.
    let Some(states) = states else {
        if args.watch {
            eprintln!("warning: squeue could not be run; waiting to see whether earlier arrays of {:?} still run", sweep.name);
            return Ok(None);
        }
        bail!("squeue could not be run, so it is unknown whether earlier arrays of {:?} still run; submit again where squeue works", sweep.name);
    };
    let active: usize = states.iter().map(|(_, n)| n).sum();
    if active > 0 {
        if !args.watch {
            bail!("{active} array tasks of {:?} are still queued or running (squeue); wait for them or scancel them, then submit again", sweep.name);
        }
        return Ok(None);
    }
    let sub = slurm::submit(store, sweep_id, &sweep.name, SOLVER_VERSION, opts)?;
    if sub.opening.failed > 0 {
        println!(
            "{} preps and jobs are out of attempts ({}) or need a prep that is: failed for good",
            sub.opening.failed, opts.max_attempts
        );
    }
    if sub.scripts.is_empty() {
        let failed = failed_jobs(store, &sweep.name)?;
        if failed > 0 {
            println!(
                "nothing to submit: every job of {:?} has a result or failed for good",
                sweep.name
            );
            return Ok(Some(super::run::failed_exit(failed, &sweep.name, "submit")));
        }
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
        return Ok(Some(0));
    }
    println!(
        "submitted {:?}: {} preps in {} array tasks, {} collisions in {} array tasks ({} per task); run directory {}",
        sweep.name, sub.preps, sub.prep_tasks, sub.jobs, sub.collide_tasks, sub.jobs_per_task, sub.sub_dir.display()
    );
    for (kind, id) in &sub.slurm_ids {
        println!("  {kind}: Slurm job {id}");
    }
    if !args.watch {
        println!(
            "when they are done: cellsweep collect --db {}{}",
            args.db.db.display(),
            if sweep.adaptive.is_some() || sweep.refine.is_some() {
                ", then submit again for the next round (or submit --watch)"
            } else {
                ""
            }
        );
        return Ok(Some(0));
    }
    Ok(None)
}

/// Jobs of the sweep failed for good (after their attempts).
fn failed_jobs(store: &Store, name: &str) -> anyhow::Result<u64> {
    Ok(store
        .status()?
        .into_iter()
        .find(|s| s.sweep == name && s.solver_version == SOLVER_VERSION)
        .map_or(0, |s| s.jobs.failed as u64))
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
        let id = store.sweep_id(&name)?;
        collect_sweep(&mut store, id, &name)?;
    }
    Ok(())
}
