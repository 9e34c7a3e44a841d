//! Slurm as the distributed engine: `submit` writes task files and sbatch scripts into a run
//! directory on the cluster's shared filesystem and submits two job arrays (preps, then
//! collisions with a dependency); array tasks run `cellsweep worker --slurm` on their slice and
//! append one JSON line per result to a file of their own; `collect` ingests those files into
//! the store, idempotently. Compute nodes never open the SQLite database.
//!
//! Run directory layout:
//! ```text
//! RUN_DIR/preps/<prep id>.json            prepped cells (written atomically: tmp + rename)
//! RUN_DIR/sub-<n>/tasks/<kind>/<task>.jsonl    requests of one array task
//! RUN_DIR/sub-<n>/results/<kind>-<task>.jsonl  one response per line, appended and flushed
//! RUN_DIR/sub-<n>/exits/<kind>-<task>.txt      why a task stopped before its last record
//! RUN_DIR/sub-<n>/{prep,collide}.sbatch, logs/
//! ```
//!
//! Each round of `submit` takes stock first ([`take_stock`]): it asks the queue ([`Queue`]; no
//! answer is never read as an empty queue), finds again arrays a kill left half-recorded,
//! collects the run directories, and gives the jobs of arrays that left the queue without a
//! result a failed attempt with the reason ([`settle_ended_arrays`]).

use std::path::{Path, PathBuf};

use cellsweep_store::{JobState, SlurmArray, Store};

use crate::error::SlurmError;
use crate::ledger::{Ledger, Opening};
use crate::run_dir::{claim_run_dir, io, write_atomic};
use crate::wire::{PrepPayload, Request};

mod array_task;
mod collect;
mod commands;
mod ended;
mod kind;
mod queue;

pub use crate::error::QueueError;
pub use array_task::serve_array_task;
pub use collect::{collect, read_responses, Collected};
use commands::sbatch;
pub use commands::{max_array_size, script, shell_quote};
pub use ended::{settle_ended_arrays, Ended, EndedKind};
pub use kind::ArrayKind;
pub use queue::{job_name, queue_of, Queue, QueuedTask};

/// How to submit.
#[derive(Debug, Clone)]
pub struct SubmitOptions {
    pub run_dir: PathBuf,
    pub partition: Option<String>,
    pub account: Option<String>,
    pub time: Option<String>,
    pub jobs_per_task: usize,
    /// Most array tasks running at once (`%N`).
    pub max_running: Option<usize>,
    pub sbatch_args: Vec<String>,
    /// The cellsweep executable the array tasks run (on the shared filesystem).
    pub exe: PathBuf,
    /// Failed attempts after which a task is failed for good (applied when submitting: a
    /// task out of attempts is not sent again).
    pub max_attempts: u32,
    pub dry_run: bool,
}

/// What a submission did.
#[derive(Debug, Clone, Default)]
pub struct Submission {
    /// What the ledger did before anything was sent.
    pub opening: Opening,
    pub sub_dir: PathBuf,
    pub prep_tasks: usize,
    pub preps: usize,
    pub collide_tasks: usize,
    pub jobs: usize,
    pub jobs_per_task: usize,
    pub scripts: Vec<(ArrayKind, String)>,
    pub slurm_ids: Vec<(ArrayKind, String)>,
}

fn write_tasks(dir: &Path, reqs: &[Request], per_task: usize) -> Result<usize, SlurmError> {
    std::fs::create_dir_all(dir).map_err(|e| io(e, dir))?;
    let mut n = 0;
    for (k, chunk) in reqs.chunks(per_task.max(1)).enumerate() {
        let mut text = String::new();
        for r in chunk {
            text += &serde_json::to_string(r)?;
            text.push('\n');
        }
        write_atomic(&dir.join(format!("{k}.jsonl")), text.as_bytes())?;
        n += 1;
    }
    Ok(n)
}

/// Submit the sweep's preps and jobs that have no result yet.
pub fn submit(
    store: &mut Store,
    sweep_id: i64,
    name: &str,
    version: &str,
    opts: &SubmitOptions,
) -> Result<Submission, SlurmError> {
    let preps_dir = opts.run_dir.join("preps");
    // (A dry run of a sweep never submitted has no uid yet: nothing to compare with.)
    if let Some(uid) = store.sweep_uid(sweep_id, !opts.dry_run)? {
        claim_run_dir(&opts.run_dir, &uid, opts.dry_run)?;
    }
    let mut opening = Opening::default();
    if !opts.dry_run {
        // The start every engine makes: work a killed local run left `running` is submitted
        // too, tasks out of attempts fail for good, decided preps settle their jobs, an
        // adaptive sweep plans its next round.
        opening = Ledger::open(store, sweep_id, version, opts.max_attempts)?.1;
    }
    // Every planned job becomes a row now: a task file names its jobs by id. A dry run writes
    // nothing, and counts the planned ones with the rows.
    let unwritten = if opts.dry_run {
        store.planned_jobs(sweep_id, version)?
    } else {
        store.materialize_next(sweep_id, version, usize::MAX)?;
        0
    };
    let (prep_reqs, job_reqs) = requests(store, sweep_id, version, &preps_dir, opts.dry_run)?;
    let jobs = job_reqs.len() + unwritten;
    let max_index = max_array_size().unwrap_or(1001).saturating_sub(1).max(1);
    let per_task = opts.jobs_per_task.max(1).max(jobs.div_ceil(max_index));
    let prep_per_task = 1usize.max(prep_reqs.len().div_ceil(max_index));
    let n = std::fs::read_dir(&opts.run_dir)
        .map(|d| d.count())
        .unwrap_or(0);
    let sub_dir = opts
        .run_dir
        .join(format!("sub-{n:04}-{}", std::process::id()));
    let mut sub = Submission {
        opening,
        sub_dir: sub_dir.clone(),
        jobs_per_task: per_task,
        preps: prep_reqs.len(),
        jobs,
        ..Default::default()
    };
    sub.prep_tasks = prep_reqs.len().div_ceil(prep_per_task);
    sub.collide_tasks = jobs.div_ceil(per_task);
    if sub.prep_tasks > 0 {
        sub.scripts.push((
            ArrayKind::Prep,
            script(opts, &sub_dir, ArrayKind::Prep, sub.prep_tasks, name),
        ));
    }
    if sub.collide_tasks > 0 {
        sub.scripts.push((
            ArrayKind::Collide,
            script(opts, &sub_dir, ArrayKind::Collide, sub.collide_tasks, name),
        ));
    }
    if opts.dry_run || sub.scripts.is_empty() {
        return Ok(sub);
    }
    write_submission(&sub, &prep_reqs, &job_reqs, prep_per_task, &preps_dir)?;
    send(store, sweep_id, version, opts, &mut sub)?;
    Ok(sub)
}

fn payload_from_store(store: &Store, prep_id: i64, seed: u64) -> Result<PrepPayload, SlurmError> {
    Ok(PrepPayload::from_record(store.load_prep(prep_id)?, seed)?)
}

/// The requests of a submission: every prep without a result, and the pending jobs whose prep
/// is not decided against them. The preps already done `ok` are written out for the collision
/// tasks (unless `dry_run`).
fn requests(
    store: &Store,
    sweep_id: i64,
    version: &str,
    preps_dir: &Path,
    dry_run: bool,
) -> Result<(Vec<Request>, Vec<Request>), SlurmError> {
    let preps = store.preps_of(sweep_id, version)?;
    let jobs = store.pending_jobs(sweep_id, version)?;
    let needed: std::collections::HashSet<i64> = jobs.iter().map(|j| j.prep_id).collect();
    // Preps decided earlier: a verdict that is not ok settled its jobs (the ledger, above);
    // ok preps are written out for the collision tasks, and written again where the file a
    // job of this submission needs is damaged (a task could not read it: its jobs failed an
    // attempt, and would fail every one after it).
    let mut prep_reqs = Vec::new();
    let mut blocked = std::collections::HashSet::new();
    for p in &preps {
        match (p.state, p.verdict) {
            (JobState::Done, Some(cellsweep_stats::PrepVerdict::Ok)) => {
                let path = preps_dir.join(format!("{}.json", p.id));
                let sound = path.exists()
                    && (!needed.contains(&p.id) || array_task::read_prep(&path).is_ok());
                if !sound && !dry_run {
                    std::fs::create_dir_all(preps_dir).map_err(|x| io(x, preps_dir))?;
                    let payload = payload_from_store(store, p.id, p.seed)?;
                    write_atomic(&path, serde_json::to_string(&payload)?.as_bytes())?;
                }
            }
            (JobState::Done | JobState::Failed, _) => {
                blocked.insert(p.id);
            }
            _ => prep_reqs.push(Request::prep(p)?),
        }
    }
    let job_reqs = jobs
        .iter()
        .filter(|j| !blocked.contains(&j.prep_id))
        .map(|j| Request::collide(j, None))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((prep_reqs, job_reqs))
}

/// The submission's directory: its logs and results folders and its task files.
fn write_submission(
    sub: &Submission,
    prep_reqs: &[Request],
    job_reqs: &[Request],
    prep_per_task: usize,
    preps_dir: &Path,
) -> Result<(), SlurmError> {
    let sub_dir = &sub.sub_dir;
    for d in ["logs", "results"] {
        std::fs::create_dir_all(sub_dir.join(d)).map_err(|x| io(x, sub_dir))?;
    }
    std::fs::create_dir_all(preps_dir).map_err(|x| io(x, preps_dir))?;
    write_tasks(&sub_dir.join("tasks/prep"), prep_reqs, prep_per_task)?;
    write_tasks(&sub_dir.join("tasks/collide"), job_reqs, sub.jobs_per_task)?;
    Ok(())
}

/// Submit the arrays of `sub` (the collisions after the preps), each recorded in the store
/// before sbatch runs and completed with its id after, so that a kill in between leaves a row
/// [`take_stock`] resolves, never an array the store does not know of. An array sbatch refuses
/// leaves no row, and a submission none of whose arrays was queued leaves no directory.
fn send(
    store: &mut Store,
    sweep_id: i64,
    version: &str,
    opts: &SubmitOptions,
    sub: &mut Submission,
) -> Result<(), SlurmError> {
    let mut previous: Option<String> = None;
    for (kind, text) in sub.scripts.clone() {
        let path = sub.sub_dir.join(format!("{kind}.sbatch"));
        write_atomic(&path, text.as_bytes())?;
        let (tasks, count) = if kind == ArrayKind::Prep {
            (sub.prep_tasks, sub.preps)
        } else {
            (sub.collide_tasks, sub.jobs)
        };
        let row = store.begin_array(
            sweep_id,
            version,
            &SlurmArray {
                id: 0,
                kind: kind.to_string(),
                slurm_job_id: None,
                run_dir: opts.run_dir.display().to_string(),
                sub_dir: Some(sub.sub_dir.display().to_string()),
                tasks: tasks as i64,
                jobs: count as i64,
                submitted_at: cellsweep_store::now(),
                ended_at: None,
            },
        )?;
        let id = match sbatch(&path, previous.as_deref()) {
            Ok(id) => id,
            Err(e) => {
                store.forget_array(row)?;
                if sub.slurm_ids.is_empty() {
                    let _ = std::fs::remove_dir_all(&sub.sub_dir);
                }
                return Err(e);
            }
        };
        store.array_submitted(row, &id)?;
        sub.slurm_ids.push((kind, id.clone()));
        previous = Some(id);
    }
    Ok(())
}

/// What [`take_stock`] found and did.
#[derive(Debug, Clone)]
pub struct Stock {
    /// The queue's answer, or why there is none (then nothing was examined for failures, and
    /// nothing may be sent: jobs that look lost may still be queued).
    pub queue: Result<Queue, QueueError>,
    /// Arrays a kill left recorded without their id, found again in the queue by script.
    pub found_again: usize,
    /// Such arrays not in the queue: sbatch never took them, or they have ended.
    pub never_queued: usize,
    /// What each run directory gave, by directory.
    pub collected: Vec<(String, Collected)>,
    /// What the arrays that left the queue left undone.
    pub ended: Ended,
    /// Tasks of the sweep's arrays still queued or running.
    pub active: usize,
}

/// Take stock of a sweep's Slurm run: ask the queue (first, so that a task that ends while the
/// run directory is read is still counted as queued, and collected next time instead of sent
/// again), resolve arrays a kill left half-recorded, collect every run directory through the
/// ledger, and give each job an array left without a result a failed attempt with its reason.
pub fn take_stock(
    store: &mut Store,
    sweep_id: i64,
    name: &str,
    version: &str,
) -> Result<Stock, SlurmError> {
    let arrays = store.open_arrays_of(sweep_id, version)?;
    let queue = match arrays.is_empty() {
        true => Ok(Queue::default()),
        false => Queue::ask(name),
    };
    let mut stock = Stock {
        queue: Ok(Queue::default()),
        found_again: 0,
        never_queued: 0,
        collected: Vec::new(),
        ended: Ended::default(),
        active: 0,
    };
    if let Ok(q) = &queue {
        for a in arrays.iter().filter(|a| a.slurm_job_id.is_none()) {
            let script = a
                .sub_dir
                .as_ref()
                .map(|d| Path::new(d).join(format!("{}.sbatch", a.kind)));
            match script.and_then(|s| q.array_of_script(&s)) {
                Some(id) => {
                    store.array_submitted(a.id, &id)?;
                    stock.found_again += 1;
                }
                None => {
                    store.array_ended(a.id, cellsweep_store::now())?;
                    stock.never_queued += 1;
                }
            }
        }
    }
    let mut dirs: Vec<String> = store
        .arrays_of(sweep_id, version)?
        .into_iter()
        .map(|a| a.run_dir)
        .collect();
    dirs.sort();
    dirs.dedup();
    for d in dirs {
        let c = collect(store, sweep_id, version, Path::new(&d))?;
        stock.collected.push((d, c));
    }
    if let Ok(q) = &queue {
        let ledger = Ledger::load(store, sweep_id, version)?;
        stock.ended = settle_ended_arrays(&ledger, store, q)?;
        let open = store.open_arrays_of(sweep_id, version)?;
        let ids: Vec<&str> = open
            .iter()
            .filter_map(|a| a.slurm_job_id.as_deref())
            .collect();
        stock.active = q.states_of(&ids).iter().map(|(_, n)| n).sum();
    }
    stock.queue = queue;
    Ok(stock)
}
