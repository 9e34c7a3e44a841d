//! `cellsweep status`: progress of every sweep in the store (works while a sweep runs).

use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::{End, Tally};
use cellsweep_store::{Store, SweepStatus};
use serde_json::Value;

use crate::cli::StatusArgs;

/// The sweep's box-limited points (SPEC 4.5), read as `table` reads them; none where its
/// results cannot be read (another solver version's, say).
fn box_limited(db: &std::path::Path, sweep: &str) -> Vec<String> {
    cellsweep_report::load::from_store(db, Some(sweep))
        .map(|r| r.box_limited_points())
        .unwrap_or_default()
}
use cellsweep_stats::throughput::speed_line;

pub fn outcome_line(o: &Tally) -> String {
    o.line(End::words, " · ")
}

/// An adaptive sweep's points by standing (`None` for a fixed sweep, or another version).
fn standings(
    store: &Store,
    sweep: &str,
    version: &str,
) -> anyhow::Result<Option<std::collections::BTreeMap<&'static str, usize>>> {
    if version != SOLVER_VERSION {
        return Ok(None);
    }
    let id = store.sweep_id(sweep)?;
    Ok(cellsweep_scheduler::Ledger::load(store, id, version)?.standing_counts(store)?)
}

pub fn run(args: StatusArgs) -> anyhow::Result<()> {
    let store = Store::open_read(&args.db.db)?;
    let all = store.status()?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json_rows(
                &store,
                &args.db.db,
                &all,
                args.failed,
                cellsweep_scheduler::StoreLock::is_held(&args.db.db)
            )?)?
        );
        return Ok(());
    }
    if all.is_empty() {
        println!("no sweeps in {}", args.db.db.display());
    }
    let live = cellsweep_scheduler::StoreLock::is_held(&args.db.db);
    for s in &all {
        print_sweep(&store, &args.db.db, s, args.failed, live)?;
    }
    Ok(())
}

/// `status --json`: one object per sweep and solver version, with its adaptive standings,
/// failures (with `--failed`) and Slurm arrays where it has them.
fn json_rows(
    store: &Store,
    db: &std::path::Path,
    all: &[SweepStatus],
    failed: bool,
    live: bool,
) -> anyhow::Result<Vec<Value>> {
    let mut rows = Vec::new();
    for s in all {
        let mut v = serde_json::to_value(s)?;
        v["live"] = serde_json::json!(live);
        if s.solver_version == SOLVER_VERSION {
            v["box_limited"] = serde_json::json!(box_limited(db, &s.sweep));
        }
        let arrays = match store.sweep_id(&s.sweep) {
            Ok(id) => store.arrays_of(id, &s.solver_version)?,
            Err(_) => Vec::new(),
        };
        if let Some(by) = standings(store, &s.sweep, &s.solver_version)? {
            v["adaptive"] = serde_json::json!(by);
        }
        if failed {
            let id = store.sweep_id(&s.sweep)?;
            v["failures"] = serde_json::to_value(store.failures(id, &s.solver_version)?)?;
        }
        if !arrays.is_empty() {
            let queue = match cellsweep_scheduler::slurm::queue_of(&s.sweep, &arrays) {
                Ok(states) => serde_json::json!(states),
                Err(e) => serde_json::json!({ "unknown": e.to_string() }),
            };
            v["slurm"] = serde_json::json!({ "arrays": arrays, "queue": queue });
        }
        rows.push(v);
    }
    Ok(rows)
}

/// One sweep's status in a few lines.
/// `live`: whether a writer holds the store now (else jobs marked running were left by a run
/// that died, and no ETA is given).
fn print_sweep(
    store: &Store,
    db: &std::path::Path,
    s: &SweepStatus,
    failed: bool,
    live: bool,
) -> anyhow::Result<()> {
    let j = &s.jobs;
    let current = if s.solver_version == SOLVER_VERSION {
        ""
    } else {
        " (another solver version)"
    };
    println!("{} [{}{}]", s.sweep, s.solver_version, current);
    let running = if live || j.running == 0 {
        format!("{} running", j.running)
    } else {
        format!(
            "{} interrupted (no run holds the store: the next run takes them up again)",
            j.running
        )
    };
    println!(
        "  jobs     {} done / {} total · {} pending · {running} · {} failed",
        j.done,
        j.total(),
        j.pending,
        j.failed
    );
    println!("  preps    {} / {} done", s.preps_done, s.preps_total);
    println!("  outcomes {}", outcome_line(&s.outcomes));
    if let Some(by) = standings(store, &s.sweep, &s.solver_version)? {
        // Jobs of open points' later rounds are not registered yet: the total grows.
        println!(
            "  adaptive points {} (open points get more rounds: the job total grows)",
            by.iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(" · ")
        );
    }
    if s.solver_version == SOLVER_VERSION {
        print_refinement(store, &s.sweep)?;
        let boxed = box_limited(db, &s.sweep);
        if !boxed.is_empty() {
            println!(
                "  box      {} (SPEC 4.5: the prepped cell leaves its fronts under 0.35 Nx_s \
                 apart, so the outcome depends on the pair lattice): {}",
                cellsweep_report::text::counted(boxed.len(), "box-limited point"),
                boxed.join("; ")
            );
        }
    }
    if let Ok(id) = store.sweep_id(&s.sweep) {
        print_arrays(store, &s.sweep, id, &s.solver_version)?;
    }
    if failed {
        print_failures(store, &s.sweep, &s.solver_version)?;
    }
    if let Some(line) = speed_line(s.jobs_per_s, (j.pending + j.running) as f64) {
        match live {
            true => println!("  speed    {line}"),
            false if j.pending + j.running > 0 => {
                println!(
                    "  speed    stopped: no run holds the store (the last run's speed: {})",
                    line.split(" · ETA").next().unwrap_or(&line)
                )
            }
            false => println!("  speed    {line}"),
        }
    }
    Ok(())
}

/// A refined sweep's columns: how many are narrow enough, the widest, the next round.
fn print_refinement(store: &Store, sweep: &str) -> anyhow::Result<()> {
    let ledger = cellsweep_scheduler::Ledger::load(store, store.sweep_id(sweep)?, SOLVER_VERSION)?;
    let Some(rule) = ledger.sweep.refine else {
        return Ok(());
    };
    let columns = ledger.refine_standing(store, &rule)?;
    let (lines, _) = super::refine_lines::lines(&columns, &rule, "           ");
    println!("  refine   {}", lines.join("\n"));
    Ok(())
}

/// The sweep's Slurm arrays and the states of their tasks in the queue.
fn print_arrays(store: &Store, sweep: &str, id: i64, version: &str) -> anyhow::Result<()> {
    let arrays = store.arrays_of(id, version)?;
    if !arrays.is_empty() {
        let queue = match cellsweep_scheduler::slurm::queue_of(sweep, &arrays) {
            Err(e) => format!("the queue could not be asked ({e})"),
            Ok(st) if st.is_empty() => "none queued or running".to_string(),
            Ok(st) => st
                .iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(", "),
        };
        let labels: Vec<String> = arrays.iter().map(|a| a.label()).collect();
        println!("  slurm    arrays {} · tasks: {queue}", labels.join(", "));
    }
    Ok(())
}

/// Each failed job and prep with its attempts and error.
fn print_failures(store: &Store, sweep: &str, version: &str) -> anyhow::Result<()> {
    let id = store.sweep_id(sweep)?;
    for f in store.failures(id, version)? {
        println!(
            "  failed   {} {} at alpha = {}, beta = {}, L = {}, sigma = {}{} after {} attempts: {}",
            f.kind,
            f.id,
            f.alpha,
            f.beta,
            f.L,
            f.sigma,
            f.replicate
                .map_or(String::new(), |r| format!(", replicate {r}")),
            f.attempts,
            f.error
        );
    }
    Ok(())
}
