//! How fast `collect` takes Slurm records into the store (issue 30's target: 50,000 a second).
//!
//!     cargo run --release -p cellsweep-scheduler --example bench_collect -- [RECORDS] [DIR]
//!
//! A run of a million collisions takes core-years, so the records are made, not run: a sweep of
//! RECORDS jobs (default 1,000,000) whose points differ only in sigma (one prep for all) is
//! registered in a fresh store under DIR (default: a new folder in /tmp); its prep is stored
//! with verdict `ok`; and every job gets the record a collide task would write for it (its own
//! parameters and both seeds; the outcome and times of a typical walk-past), in files of 1,000
//! records, as a Slurm array of 1,000-record tasks leaves them. `collect` then checks each one
//! against its job exactly as it checks a real one, and commits it. A second `collect` reads the
//! same files again and must add nothing. Prints records per second for both.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use cellsweep_scheduler::run_dir::claim_run_dir;
use cellsweep_scheduler::slurm::collect;
use cellsweep_scheduler::wire::Response;
use cellsweep_scheduler::{plan, Sweep};
use cellsweep_solver::{Attachment, Config, Outcome, Seeds, TrajectoryResult, Verdict};
use cellsweep_store::{PrepRecord, Store};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let records: usize = args.next().map_or(Ok(1_000_000), |a| a.parse())?;
    let dir = match args.next() {
        Some(d) => PathBuf::from(d),
        None => {
            std::env::temp_dir().join(format!("cellsweep-bench-collect.{}", std::process::id()))
        }
    };
    std::fs::create_dir_all(&dir)?;
    let db = dir.join("collect.sqlite");
    for f in ["", "-wal", "-shm"] {
        let _ = std::fs::remove_file(format!("{}{f}", db.display()));
    }
    let run_dir = dir.join("run");
    let _ = std::fs::remove_dir_all(&run_dir);

    // Points that differ only in sigma and g share their prep (SPEC section 6); an axis has
    // at most 1,000 values, so g takes 11 and sigma the rest.
    let sigmas = records.div_ceil(96 * 11).max(1);
    let points = sigmas * 11;
    let text = format!(
        "name = \"collect-bench\"\nseed = 1\nreplicates = 96\n[grid]\nalpha = [0.1]\n\
         beta = [22]\nL = [90]\nsigma = {{ from = 0, to = {}, step = 0.001 }}\n\
         g = {{ from = 1, to = 1.01, step = 0.001 }}\n[protocol]\nprecision = \"f32\"\n",
        (sigmas - 1) as f64 * 0.001
    );
    let sweep = Sweep::parse(&text, "collect-bench.toml")?;
    let mut store = Store::open_or_create(&db)?;
    let t = Instant::now();
    let reg = store.register(&plan(&sweep, &text), false)?;
    let version = cellsweep_solver::SOLVER_VERSION;
    let preps = store.preps_of(reg.sweep_id, version)?;
    for p in &preps {
        store.record_prep(
            p.id,
            &PrepRecord {
                verdict: cellsweep_stats::PrepVerdict::Ok,
                verdict_time: None,
                free_speed: Some(0.7),
                nx: 2,
                ny: 2,
                phi: vec![0.0; 4],
                p: vec![0.0; 4],
                summary: "{}".into(),
                wall_s: 60.0,
            },
        )?;
    }
    let prep_seed: std::collections::HashMap<i64, u64> =
        preps.iter().map(|p| (p.id, p.seed)).collect();
    store.materialize_next(reg.sweep_id, version, usize::MAX)?;
    let jobs = store.pending_jobs(reg.sweep_id, version)?;
    println!(
        "{} jobs at {} points registered in {:.1} s ({} prep)",
        jobs.len(),
        points,
        t.elapsed().as_secs_f64(),
        preps.len()
    );

    let uid = store.sweep_uid(reg.sweep_id, true)?.ok_or("no sweep uid")?;
    claim_run_dir(&run_dir, &uid, false)?;
    let results = run_dir.join("sub-0/results");
    std::fs::create_dir_all(&results)?;
    let t = Instant::now();
    let mut config: Option<(i64, Config)> = None;
    for (task, chunk) in jobs.chunks(1000).enumerate() {
        let mut out = std::io::BufWriter::new(std::fs::File::create(
            results.join(format!("collide-{task}.jsonl")),
        )?);
        for job in chunk {
            if config.as_ref().map(|c| c.0) != Some(job.point_id) {
                config = Some((job.point_id, serde_json::from_str(&job.config)?));
            }
            let result = TrajectoryResult {
                solver_version: version.to_string(),
                config: config.as_ref().unwrap().1.clone(),
                seeds: Seeds {
                    prep: prep_seed[&job.prep_id],
                    collision: job.seed,
                },
                verdict: Verdict::Ok,
                outcome: Some(Outcome::WalkPast),
                free_speed: Some(0.7),
                threshold_speed: Some(0.175),
                contact_time: Some(41.5),
                decision_time: Some(181.0),
                breakup_reason: None,
                sheddings: 0,
                attachment: Some([Attachment::Bottom, Attachment::Top]),
                collision_steps: 90_500,
                patch: None,
            };
            let line = serde_json::to_string(&Response::Collide {
                task: job.id,
                result: Box::new(result),
                wall_s: 61.0,
            })?;
            writeln!(out, "{line}")?;
        }
    }
    println!(
        "{} records written in {} files in {:.1} s",
        jobs.len(),
        jobs.len().div_ceil(1000),
        t.elapsed().as_secs_f64()
    );

    for pass in ["collect", "collect again (nothing new)"] {
        let t = Instant::now();
        let c = collect(&mut store, reg.sweep_id, version, &run_dir)?;
        let s = t.elapsed().as_secs_f64();
        if let Some(p) = c.problems.first() {
            return Err(format!("{} problems, the first: {p}", c.problems.len()).into());
        }
        println!(
            "{pass:<28} {s:8.2} s  {:>9.0} records/s  ({} new, {} already)",
            jobs.len() as f64 / s,
            c.results,
            c.already
        );
    }
    let st = store.status()?;
    let done = st.iter().map(|s| s.jobs.done).sum::<i64>();
    println!("store: {done} jobs done; {} kept", dir.display());
    Ok(())
}
