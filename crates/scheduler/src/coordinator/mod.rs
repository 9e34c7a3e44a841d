//! The coordinator of a local run: takes a registered sweep's pending preps and jobs from the
//! store, dispatches them to worker processes (preps first; a point's collisions once its prep is
//! done), and commits each answer to the store in its own transaction as it arrives.
//!
//! Faults: a failed attempt (worker crash, timeout, solver error) sends the job back to `pending`
//! until `max_attempts` attempts have failed, then marks it `failed` with its error. Ctrl-C or
//! SIGTERM stops dispatching at once; jobs in flight get `grace` to finish (their results are
//! kept), then the workers are killed and their jobs put back to `pending`; a second signal
//! stops at once. A
//! coordinator killed outright leaves jobs `running`; the next run recovers them first.

use std::collections::{HashMap, VecDeque};
use std::time::Duration;

use cellsweep_stats::Tally;
use cellsweep_store::Store;
use tokio::sync::{mpsc, watch};
use tokio::task::JoinHandle;

use crate::error::RunError;
use crate::ledger::Ledger;
use crate::pool::{worker_task, Event, WorkerCommand};
use crate::reserve::Reserve;
use crate::wire::Response;

mod run;
mod signal;

use run::{Busy, Run, Worker};
use signal::Interrupts;

/// How to run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub workers: usize,
    pub job_timeout: Duration,
    pub max_attempts: u32,
    pub worker: WorkerCommand,
    /// After Ctrl-C or SIGTERM, how long jobs in flight may take to finish (their results are
    /// kept) before the workers are killed.
    pub grace: Duration,
}

/// A snapshot of a run's progress, for display.
#[derive(Debug, Clone, Default)]
pub struct Progress {
    pub jobs_done: u64,
    pub jobs_total: u64,
    pub preps_done: u64,
    pub preps_total: u64,
    pub outcomes: Tally,
    pub failed: u64,
    pub retries: u64,
    pub running: usize,
    /// Jobs per second over the latest window of this run's activity, by the estimator
    /// `status` uses (`cellsweep_stats::throughput`).
    pub jobs_per_s: Option<f64>,
    /// A refined sweep's points added between the grid's betas so far (None without
    /// `[refine]`).
    pub refined_points: Option<u64>,
}

/// Receives progress and notes from a run.
pub trait Reporter {
    fn progress(&mut self, progress: &Progress);
    fn note(&mut self, message: &str);
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// No dispatchable work is left.
    Finished,
    /// Stopped by Ctrl-C or SIGTERM; unfinished jobs are pending again.
    Interrupted,
}

#[derive(Debug, Clone)]
pub struct RunReport {
    pub ending: Ending,
    pub progress: Progress,
}

/// Run the pending work of sweep `sweep_id` for solver `version` to completion (or interruption).
pub async fn run_sweep(
    store: &mut Store,
    sweep_id: i64,
    version: &str,
    opts: RunOptions,
    reporter: &mut dyn Reporter,
) -> Result<RunReport, RunError> {
    let mut reserve = Reserve::beside(store.path());
    let (ledger, opening) = Ledger::open(store, sweep_id, version, opts.max_attempts)?;
    if opening.recovered > 0 {
        reporter.note(&format!(
            "recovered {} interrupted jobs and preps; they run again",
            opening.recovered
        ));
    }
    let mut run = Run::new(store, ledger)?;
    reporter.progress(&run.progress);
    let work = run.prep_queue.len()
        + run.ready.len()
        + run.waiting.values().map(|v| v.len()).sum::<usize>();
    let (cancel, cancelled) = watch::channel(false);
    let (mut workers, handles, mut events) = if work > 0 {
        start_workers(opts.workers.max(1).min(work), &opts, &cancelled)
    } else {
        (HashMap::new(), Vec::new(), mpsc::unbounded_channel().1)
    };
    let driven = drive(&mut run, &mut workers, &mut events, &opts, reporter).await;
    // Stop the workers: cancelling kills the processes of unfinished calls at once, and closing
    // their request channels ends their tasks; then whatever was running goes back to pending.
    let _ = cancel.send(true);
    drop(workers);
    for h in handles {
        let _ = h.await;
    }
    let requeued = match run.store.recover_running(sweep_id, version) {
        Ok(n) => n,
        // A full disk: give back the reserved room, and try once more.
        Err(_) if reserve.release() => run.store.recover_running(sweep_id, version)?,
        Err(e) => return Err(e.into()),
    };
    let ending = driven?;
    if ending == Ending::Interrupted {
        reporter.note(&format!(
            "interrupted: {requeued} running jobs put back to pending; run again to resume"
        ));
    }
    run.progress.running = 0;
    Ok(RunReport {
        ending,
        progress: run.progress,
    })
}

type Workers = HashMap<usize, Worker>;

/// `n` worker processes, each behind its task, and the channel of their events.
fn start_workers(
    n: usize,
    opts: &RunOptions,
    cancelled: &watch::Receiver<bool>,
) -> (Workers, Vec<JoinHandle<()>>, mpsc::UnboundedReceiver<Event>) {
    let (event_tx, events) = mpsc::unbounded_channel();
    let mut workers = HashMap::new();
    let mut handles = Vec::new();
    for i in 0..n {
        let (tx, rx) = mpsc::channel(1);
        handles.push(tokio::spawn(worker_task(
            i,
            opts.worker.clone(),
            opts.job_timeout,
            rx,
            event_tx.clone(),
            cancelled.clone(),
        )));
        workers.insert(
            i,
            Worker {
                requests: tx,
                preps: VecDeque::new(),
                busy: None,
            },
        );
    }
    (workers, handles, events)
}

/// What woke the dispatcher.
enum Wake {
    Event(Option<Event>),
    Signal,
    GraceOver,
}

/// Dispatch and take answers until no work is left, the workers are gone, or a signal stops
/// the run (after a second signal, or the grace period, at once).
async fn drive(
    run: &mut Run<'_>,
    workers: &mut Workers,
    events: &mut mpsc::UnboundedReceiver<Event>,
    opts: &RunOptions,
    reporter: &mut dyn Reporter,
) -> Result<Ending, RunError> {
    let mut interrupts = Interrupts::listen();
    // After the first signal: no more dispatch; in-flight jobs may finish until this deadline.
    let mut grace_until: Option<tokio::time::Instant> = None;
    let mut ending = Ending::Finished;
    loop {
        if grace_until.is_none() {
            dispatch(run, workers).await?;
        }
        run.progress.running = workers.values().filter(|w| w.busy.is_some()).count();
        reporter.progress(&run.progress);
        if run.progress.running == 0 {
            return Ok(ending);
        }
        let grace = async {
            match grace_until {
                Some(t) => tokio::time::sleep_until(t).await,
                None => std::future::pending().await,
            }
        };
        let wake = tokio::select! {
            ev = events.recv() => Wake::Event(ev),
            _ = interrupts.next() => Wake::Signal,
            _ = grace => Wake::GraceOver,
        };
        match wake {
            Wake::Event(None) => return Ok(ending),
            Wake::Event(Some(ev)) => on_event(run, workers, ev, opts, reporter)?,
            Wake::Signal => {
                ending = Ending::Interrupted;
                if grace_until.is_some() {
                    reporter.note("second signal: stopping at once");
                    return Ok(ending);
                }
                grace_until = Some(tokio::time::Instant::now() + opts.grace);
                // The listener has been on since the run began: a second signal sent once the
                // note is out is never missed.
                reporter.note(&format!(
                    "interrupted: no new jobs; waiting up to {} s for the {} in flight to finish \
                     (Ctrl-C again to stop at once)",
                    opts.grace.as_secs_f64(),
                    run.progress.running
                ));
            }
            Wake::GraceOver => {
                reporter.note("grace period over: stopping the workers");
                return Ok(ending);
            }
        }
    }
}

/// Give every idle worker something to do, in worker order, while there is work.
async fn dispatch(run: &mut Run<'_>, workers: &mut Workers) -> Result<(), RunError> {
    let mut ids: Vec<usize> = workers.keys().copied().collect();
    ids.sort_unstable();
    for id in ids {
        let Some(w) = workers.get_mut(&id) else {
            continue;
        };
        if w.busy.is_some() {
            continue;
        }
        let Some(req) = run.next_request(w)? else {
            return Ok(());
        };
        if w.requests.send(req).await.is_err() {
            // The worker task is gone; its Dead event explains why.
            if let Some(busy) = w.busy.take() {
                run.on_failure(busy, "worker process is gone")?;
            }
        }
    }
    Ok(())
}

/// One event of a worker: its answer, a lost call (crash, timeout), or its end.
fn on_event(
    run: &mut Run<'_>,
    workers: &mut Workers,
    ev: Event,
    opts: &RunOptions,
    reporter: &mut dyn Reporter,
) -> Result<(), RunError> {
    match ev {
        Event::Reply { worker, response } => {
            let Some(w) = workers.get_mut(&worker) else {
                return Ok(());
            };
            // A prep the worker failed to compute or to take is not in its cache: the next
            // job of it sends it again.
            let unsure = match (&w.busy, &response) {
                (Some(Busy::Prep(p)), r) if !matches!(r, Response::Prep { .. }) => Some(p.id),
                (Some(Busy::Job(j)), Response::Failed { .. }) => Some(j.prep_id),
                _ => None,
            };
            if let Some(id) = unsure {
                w.preps.retain(|(k, _)| *k != id);
            }
            if let Some(busy) = w.busy.take() {
                run.on_reply(busy, response)?;
            }
        }
        Event::Lost { worker, error } => {
            reporter.note(&format!("worker {worker}: {error}"));
            if let Some(w) = workers.get_mut(&worker) {
                w.preps.clear();
                if let Some(busy) = w.busy.take() {
                    run.on_failure(busy, &error.to_string())?;
                }
            }
        }
        Event::Dead { worker, error } => {
            reporter.note(&format!("worker {worker} is gone: {error}"));
            if let Some(mut w) = workers.remove(&worker) {
                if let Some(busy) = w.busy.take() {
                    run.on_failure(busy, &error)?;
                }
            }
            if workers.is_empty() {
                return Err(RunError::Spawn {
                    exe: opts.worker.exe.display().to_string(),
                    source: std::io::Error::other(error),
                });
            }
        }
    }
    Ok(())
}
