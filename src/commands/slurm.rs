//! `cellsweep submit --backend slurm` and `cellsweep collect`.

use anyhow::{bail, Context};
use cellsweep_scheduler::slurm::{self, SubmitOptions};
use cellsweep_scheduler::{plan, plan_in, SlurmError, StoreLock, Sweep};
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_store::{NewSweep, Store};

use crate::cli::{CollectArgs, SubmitArgs};

/// Take stock of a sweep's Slurm run (queue, run directories, arrays that ended) and say
/// what it found; the queue's answer, or why there is none.
fn take_stock(
    store: &mut Store,
    sweep_id: i64,
    name: &str,
) -> anyhow::Result<Result<slurm::Queue, slurm::QueueError>> {
    let stock = slurm::take_stock(store, sweep_id, name, SOLVER_VERSION)?;
    if stock.found_again > 0 {
        println!(
            "found again {} array(s) of {name:?} that a stop had left recorded without their Slurm id",
            stock.found_again
        );
    }
    for (d, c) in &stock.collected {
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
    for k in &stock.ended.failures {
        println!(
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
        );
    }
    Ok(stock.queue)
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
    let new = if args.replace {
        new
    } else {
        plan_in(&sweep, &args.sweep.display().to_string(), &store)?
    };
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
    // With --watch, a queue or an sbatch that fails is waited out: tried again after a wait
    // that doubles (from --poll, at most 5 minutes) until it has failed for --give-up-after.
    let mut trouble: Option<(std::time::Instant, u32)> = None;
    loop {
        let wait = match submit_round(&args, &mut store, reg.sweep_id, &sweep, &opts) {
            Ok(Some(code)) => return Ok(code),
            Ok(None) => {
                trouble = None;
                args.poll
            }
            Err(e) if args.watch && transient(&e) => {
                let (since, n) = trouble.get_or_insert((std::time::Instant::now(), 0));
                *n += 1;
                let failing = since.elapsed().as_secs_f64();
                if failing >= args.give_up_after {
                    bail!(
                        "{e}; it has failed for {failing:.0} s (--give-up-after {}), so the watch stops; nothing was sent for jobs that may still be queued: run submit --watch again when Slurm answers",
                        args.give_up_after
                    );
                }
                let wait = (args.poll * 2f64.powi(*n as i32 - 1))
                    .min(300f64.max(args.poll))
                    .min(args.give_up_after - failing);
                eprintln!(
                    "warning: {e}; trying again in {wait:.1} s (failure {n}; the watch gives up after {} s of failures)",
                    args.give_up_after
                );
                wait
            }
            Err(e) => return Err(e),
        };
        std::thread::sleep(std::time::Duration::from_secs_f64(wait.max(0.0)));
    }
}

/// Whether an error of a submit round is Slurm not answering now (the queue, or sbatch), which
/// a watch waits out.
fn transient(e: &anyhow::Error) -> bool {
    matches!(
        e.downcast_ref::<SlurmError>(),
        Some(SlurmError::Queue(_) | SlurmError::Sbatch { .. })
    ) || e.downcast_ref::<slurm::QueueError>().is_some()
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
    // The queue is asked before the run directory is read (slurm::take_stock), so a task that
    // ends between the two is still counted as running and collected next time. Without an
    // answer from the queue nothing is sent: jobs still queued would look lost.
    let queue = take_stock(store, sweep_id, &sweep.name)?;
    let queue = queue.map_err(|e| {
        if args.watch {
            anyhow::Error::new(e)
        } else {
            anyhow::anyhow!("{e}: it is unknown whether earlier arrays of {:?} still run, so nothing was sent; submit again when squeue answers (or use --watch, which waits)", sweep.name)
        }
    })?;
    let ids: Vec<String> = store
        .open_arrays_of(sweep_id, SOLVER_VERSION)?
        .into_iter()
        .filter_map(|a| a.slurm_job_id)
        .collect();
    let ids: Vec<&str> = ids.iter().map(String::as_str).collect();
    let active: usize = queue.states_of(&ids).iter().map(|(_, n)| n).sum();
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
        if let Err(e) = take_stock(&mut store, id, &name)? {
            eprintln!(
                "warning: {e}: tasks that ended without results are examined once squeue answers"
            );
        }
    }
    Ok(())
}
