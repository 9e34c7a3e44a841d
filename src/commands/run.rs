//! `cellsweep run`: register a sweep and run (or resume) it with local worker processes.

use std::path::Path;
use std::time::Duration;

use anyhow::{bail, Context};
use cellsweep_scheduler::{
    plan, plan_in, run_sweep, Ending, Ledger, RunOptions, StoreLock, Sweep, WorkerCommand,
};
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
    // One writer per store: a second run (or submit, collect, import) is refused here.
    let _lock = StoreLock::acquire(&args.db.db)?;
    let mut store = Store::open_or_create(&args.db.db)?;
    store.check_integrity()?;
    if !args.force {
        refuse_while_on_slurm(&store, &sweep.name)?;
    }
    let source = args.sweep.display().to_string();
    let new = if args.replace {
        plan(&sweep, &source)
    } else {
        plan_in(&sweep, &source, &store)?
    };
    let reg = store.register(&new, args.replace)?;
    announce(&sweep, &new, &reg, &args.db.db);

    if args.retry_failed {
        let n = store.retry_failed(reg.sweep_id, SOLVER_VERSION)?;
        println!("retrying {n} failed jobs and preps");
    }
    // A finished sweep (an adaptive one with no round to add): say so and run nothing.
    if !reg.created && reg.grown_from.is_none() {
        if let Some(failed) = finished_already(&mut store, reg.sweep_id, &sweep.name)? {
            summarize(&args, &store, reg.sweep_id, &sweep, false)?;
            return Ok(failed_exit(failed, &sweep.name, "run"));
        }
    }
    let opts = run_options(&args, &sweep, workers)?;
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")?;
    let mut bar = SweepBar::new();
    crate::on_broken_pipe(crate::OnBrokenPipe::Fail);
    let report = runtime.block_on(run_sweep(
        &mut store,
        reg.sweep_id,
        SOLVER_VERSION,
        opts,
        &mut bar,
    ));
    bar.finish();
    // The jobs are settled: from here a closed pipe may end the process quietly.
    crate::on_broken_pipe(crate::OnBrokenPipe::Die);
    let report = report.with_context(|| format!("the run on {} stopped", args.db.db.display()))?;

    summarize(
        &args,
        &store,
        reg.sweep_id,
        &sweep,
        report.ending == Ending::Interrupted,
    )?;
    Ok(match report.ending {
        Ending::Interrupted => 130,
        Ending::Finished => failed_exit(report.progress.failed, &sweep.name, "run"),
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

/// A local run of a sweep whose Slurm arrays are still queued would compute their jobs a second
/// time: refused (as where squeue cannot tell), unless `--force`.
fn refuse_while_on_slurm(store: &Store, name: &str) -> anyhow::Result<()> {
    let Ok(id) = store.sweep_id(name) else {
        return Ok(());
    };
    let arrays = store.open_arrays_of(id, SOLVER_VERSION)?;
    if arrays.is_empty() {
        return Ok(());
    }
    let labels: Vec<String> = arrays.iter().map(|a| a.label()).collect();
    match cellsweep_scheduler::slurm::queue_of(name, &arrays) {
        Ok(states) if states.is_empty() => Ok(()),
        Ok(states) => {
            let n: usize = states.iter().map(|(_, n)| n).sum();
            bail!("{n} array tasks of {name:?} are still queued or running on Slurm (arrays {}): a local run would compute their jobs again; wait for them (cellsweep submit --watch, or collect), scancel them, or pass --force", labels.join(", "))
        }
        Err(e) => bail!("{name:?} has Slurm arrays not yet seen to end ({}) and {e}, so whether they still run is unknown; run where squeue answers, or pass --force", labels.join(", ")),
    }
}

/// For a sweep that is already registered: the number of failed jobs if it has nothing left
/// to run (after planning any adaptive round it is owed), else None.
fn finished_already(store: &mut Store, sweep_id: i64, name: &str) -> anyhow::Result<Option<u64>> {
    Ledger::load(store, sweep_id, SOLVER_VERSION)?.plan_rounds(store)?;
    let st = store
        .status()?
        .into_iter()
        .find(|s| s.sweep == name && s.solver_version == SOLVER_VERSION);
    let Some(s) =
        st.filter(|s| s.jobs.pending + s.jobs.running == 0 && s.preps_done == s.preps_total)
    else {
        return Ok(None);
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
    Ok(Some(s.jobs.failed as u64))
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
    println!("{}", text::LEGEND);
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
