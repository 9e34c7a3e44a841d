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

use std::collections::{HashMap, HashSet, VecDeque};
use std::time::Duration;

use cellsweep_solver::{Outcome, Verdict};
use cellsweep_stats::throughput;
use cellsweep_store::{JobState, JobTask, OutcomeCounts, PrepTask, Store};
use tokio::sync::mpsc;

use crate::error::RunError;
use crate::ledger::{Failure, Ledger, Settlement, TaskRef};
use crate::pool::{worker_task, Event, WorkerCommand};
use crate::reserve::Reserve;
use crate::wire::{PrepPayload, Request, Response};
use crate::worker::remember;

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
    pub outcomes: OutcomeCounts,
    pub failed: u64,
    pub retries: u64,
    pub running: usize,
    /// Jobs per second over the latest window of this run's activity, by the estimator
    /// `status` uses (`cellsweep_stats::throughput`).
    pub jobs_per_s: Option<f64>,
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

enum Busy {
    Prep(PrepTask),
    Job(JobTask),
}

struct Worker {
    requests: mpsc::Sender<Request>,
    /// The preps its process holds: a copy of its cache, kept by the worker's own rule.
    preps: VecDeque<(i64, ())>,
    busy: Option<Busy>,
}

/// A malformed prep in transit or in the store.
fn count(outcomes: &mut OutcomeCounts, verdict: &str, outcome: Option<Outcome>, n: i64) {
    let slot = match (verdict, outcome) {
        (_, Some(Outcome::Train)) => &mut outcomes.train,
        (_, Some(Outcome::WalkPast)) => &mut outcomes.walk_past,
        (_, Some(Outcome::Reversal)) => &mut outcomes.reversal,
        (_, Some(Outcome::Undetermined)) => &mut outcomes.undetermined,
        (_, Some(Outcome::Breakup)) => &mut outcomes.collision_breakup,
        ("unstable", None) => &mut outcomes.unstable,
        _ => &mut outcomes.breakup,
    };
    *slot += n;
}

struct Run<'a> {
    store: &'a mut Store,
    ledger: Ledger,
    prep_queue: VecDeque<PrepTask>,
    waiting: HashMap<i64, VecDeque<JobTask>>,
    ready: VecDeque<JobTask>,
    /// Every job this run has queued, so that a new round's jobs are queued once.
    queued: HashSet<i64>,
    /// Preps known to be decided `ok` (their jobs go straight to `ready`).
    ok_preps: HashSet<i64>,
    payloads: HashMap<i64, PrepPayload>,
    prep_seeds: HashMap<i64, u64>,
    progress: Progress,
    /// (started, finished) of the jobs this run finished in the latest window.
    spans: Vec<(f64, f64)>,
}

impl<'a> Run<'a> {
    /// A run of the ledger's sweep: the preps still to compute queued first, then the jobs.
    fn new(store: &'a mut Store, ledger: Ledger) -> Result<Self, RunError> {
        let preps = store.preps_of(ledger.sweep_id, &ledger.version)?;
        let mut run = Run {
            store,
            ledger,
            prep_queue: VecDeque::new(),
            waiting: HashMap::new(),
            ready: VecDeque::new(),
            queued: HashSet::new(),
            ok_preps: HashSet::new(),
            payloads: HashMap::new(),
            prep_seeds: preps.iter().map(|p| (p.id, p.seed)).collect(),
            progress: Progress::default(),
            spans: Vec::new(),
        };
        run.refresh_totals()?;
        run.progress.preps_total = preps.len() as u64;
        for prep in preps {
            match prep.state {
                JobState::Done | JobState::Failed => {
                    run.progress.preps_done += 1;
                    if prep.verdict.as_deref() == Some("ok") {
                        run.ok_preps.insert(prep.id);
                    }
                }
                _ => run.prep_queue.push_back(prep),
            }
        }
        run.queue_pending()?;
        Ok(run)
    }

    /// Totals and counts from the store (at the start, and when a round adds jobs).
    fn refresh_totals(&mut self) -> Result<(), RunError> {
        let name = self.ledger.sweep.name.clone();
        if let Some(s) = self
            .store
            .status()?
            .into_iter()
            .find(|s| s.solver_version == self.ledger.version && s.sweep == name)
        {
            self.progress.jobs_total = s.jobs.total() as u64;
            self.progress.jobs_done = s.jobs.done as u64;
            self.progress.failed = s.jobs.failed as u64;
            self.progress.outcomes = s.outcomes.clone();
        }
        Ok(())
    }

    /// Queue the sweep's pending jobs this run has not queued yet.
    fn queue_pending(&mut self) -> Result<(), RunError> {
        for job in self
            .store
            .pending_jobs(self.ledger.sweep_id, &self.ledger.version)?
        {
            if !self.queued.insert(job.id) {
                continue;
            }
            if self.ok_preps.contains(&job.prep_id) {
                self.ready.push_back(job);
            } else {
                self.waiting.entry(job.prep_id).or_default().push_back(job);
            }
        }
        Ok(())
    }

    /// An adaptive sweep's next rounds, once a point's round is complete.
    fn plan_rounds(&mut self) -> Result<(), RunError> {
        if self.ledger.plan_rounds(self.store)? > 0 {
            self.refresh_totals()?;
            self.queue_pending()?;
        }
        Ok(())
    }

    fn payload(&mut self, prep_id: i64) -> Result<PrepPayload, RunError> {
        if let Some(p) = self.payloads.get(&prep_id) {
            return Ok(p.clone());
        }
        let seed = self.prep_seeds.get(&prep_id).copied().unwrap_or_default();
        let payload = PrepPayload::from_record(self.store.load_prep(prep_id)?, seed)?;
        self.payloads.insert(prep_id, payload.clone());
        Ok(payload)
    }

    /// The next request for `worker`, claimed in the store.
    fn next_request(&mut self, worker: &mut Worker) -> Result<Option<Request>, RunError> {
        if let Some(prep) = self.prep_queue.pop_front() {
            self.store.claim_prep(prep.id)?;
            let req = Request::prep(&prep)?;
            // The worker keeps the prep it computes (the mirror is mended if it fails).
            remember(&mut worker.preps, prep.id, ());
            worker.busy = Some(Busy::Prep(prep));
            return Ok(Some(req));
        }
        if let Some(job) = self.ready.pop_front() {
            self.store.claim_job(job.id)?;
            let prep = if worker.preps.iter().any(|(id, _)| *id == job.prep_id) {
                None
            } else {
                let payload = self.payload(job.prep_id)?;
                remember(&mut worker.preps, job.prep_id, ());
                Some(Box::new(payload))
            };
            let req = Request::collide(&job, prep)?;
            worker.busy = Some(Busy::Job(job));
            return Ok(Some(req));
        }
        Ok(None)
    }

    /// A prep is decided: release its jobs (`ok`), or count the jobs its verdict settled.
    fn prep_decided(&mut self, prep_id: i64, verdict: Verdict, settled: usize) {
        let jobs = self.waiting.remove(&prep_id).unwrap_or_default();
        if verdict == Verdict::Ok {
            self.ok_preps.insert(prep_id);
            self.ready.extend(jobs);
        } else {
            self.progress.jobs_done += settled as u64;
            count(
                &mut self.progress.outcomes,
                verdict.as_str(),
                None,
                settled as i64,
            );
        }
    }

    fn on_reply(&mut self, busy: Busy, response: Response) -> Result<(), RunError> {
        match (busy, response) {
            (
                Busy::Prep(task),
                Response::Prep {
                    task: id,
                    prep,
                    wall_s,
                },
            ) if id == task.id => {
                let s = self
                    .ledger
                    .settle_prep(self.store, task.id, &prep, wall_s)?;
                if let Settlement::Refused(why) = &s.settlement {
                    return self.on_failure(Busy::Prep(task), why);
                }
                self.progress.preps_done += 1;
                let verdict = prep.verdict;
                self.payloads.insert(task.id, *prep);
                self.prep_decided(task.id, verdict, s.jobs_settled);
                self.plan_rounds()?;
            }
            (
                Busy::Job(task),
                Response::Collide {
                    task: id,
                    result,
                    wall_s,
                },
            ) if id == task.id => {
                match self
                    .ledger
                    .settle_job(self.store, task.id, &result, wall_s)?
                {
                    Settlement::Refused(why) => return self.on_failure(Busy::Job(task), &why),
                    Settlement::Already => {}
                    Settlement::New => {
                        self.progress.jobs_done += 1;
                        let t = cellsweep_store::now();
                        self.spans.push((t - wall_s, t));
                        self.spans.retain(|s| s.1 >= t - throughput::WINDOW_S);
                        self.progress.jobs_per_s = throughput::jobs_per_s(&self.spans);
                        count(
                            &mut self.progress.outcomes,
                            result.verdict.as_str(),
                            result.outcome,
                            1,
                        );
                        self.plan_rounds()?;
                    }
                }
            }
            (busy, Response::Failed { error, .. }) => self.on_failure(busy, &error)?,
            (busy, other) => self.on_failure(
                busy,
                &format!(
                    "worker answered with the wrong result: {}",
                    serde_json::to_string(&other).unwrap_or_default()
                ),
            )?,
        }
        Ok(())
    }

    /// A failed attempt, recorded by the ledger: queued again, or counted as failed.
    fn on_failure(&mut self, busy: Busy, error: &str) -> Result<(), RunError> {
        let (task, attempt) = match &busy {
            Busy::Prep(p) => (TaskRef::Prep(p.id), p.attempts + 1),
            Busy::Job(j) => (TaskRef::Job(j.id), j.attempts + 1),
        };
        match (self.ledger.fail(self.store, task, attempt, error)?, busy) {
            (Failure::Retry, Busy::Prep(mut p)) => {
                self.progress.retries += 1;
                p.attempts += 1;
                self.prep_queue.push_front(p);
            }
            (Failure::Retry, Busy::Job(mut j)) => {
                self.progress.retries += 1;
                j.attempts += 1;
                self.ready.push_front(j);
            }
            (Failure::GaveUp { jobs }, Busy::Prep(p)) => {
                self.progress.preps_done += 1;
                self.progress.failed += jobs as u64;
                self.waiting.remove(&p.id);
            }
            (Failure::GaveUp { jobs }, Busy::Job(_)) => self.progress.failed += jobs as u64,
            // (A task this run claimed is open and its prep is ready: not reached.)
            (Failure::Already | Failure::PrepNotReady, _) => {}
        }
        Ok(())
    }
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
    let n_workers = opts.workers.max(1).min(work.max(1));
    let (event_tx, mut events) = mpsc::unbounded_channel();
    let (cancel, cancelled) = tokio::sync::watch::channel(false);
    let mut workers: HashMap<usize, Worker> = HashMap::new();
    let mut handles = Vec::new();
    if work > 0 {
        for i in 0..n_workers {
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
    }
    drop(event_tx);

    let mut interrupt = Box::pin(interrupted());
    let mut ending = Ending::Finished;
    let mut fatal: Option<RunError> = None;
    // After the first signal: no more dispatch; in-flight jobs may finish until this deadline.
    let mut grace_until: Option<tokio::time::Instant> = None;
    loop {
        // Give every idle worker something to do (unless stopping).
        let mut ids: Vec<usize> = workers.keys().copied().collect();
        ids.sort_unstable();
        for id in ids.into_iter().filter(|_| grace_until.is_none()) {
            let Some(w) = workers.get_mut(&id) else {
                continue;
            };
            if w.busy.is_some() {
                continue;
            }
            match run.next_request(w) {
                Ok(Some(req)) => {
                    if w.requests.send(req).await.is_err() {
                        // The worker task is gone; its Dead event explains why.
                        if let Some(busy) = w.busy.take() {
                            if let Err(e) = run.on_failure(busy, "worker process is gone") {
                                fatal = Some(e);
                                break;
                            }
                        }
                    }
                }
                Ok(None) => break,
                Err(e) => {
                    fatal = Some(e);
                    break;
                }
            }
        }
        if fatal.is_some() {
            break;
        }
        run.progress.running = workers.values().filter(|w| w.busy.is_some()).count();
        reporter.progress(&run.progress);
        if run.progress.running == 0 {
            break;
        }
        let grace = async {
            match grace_until {
                Some(t) => tokio::time::sleep_until(t).await,
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            ev = events.recv() => match ev {
                Some(Event::Reply { worker, response }) => {
                    if let Some(w) = workers.get_mut(&worker) {
                        // A prep the worker failed to compute or to take is not in its cache:
                        // the next job of it sends it again.
                        let unsure = match (&w.busy, &response) {
                            (Some(Busy::Prep(p)), r) if !matches!(r, Response::Prep { .. }) => Some(p.id),
                            (Some(Busy::Job(j)), Response::Failed { .. }) => Some(j.prep_id),
                            _ => None,
                        };
                        if let Some(id) = unsure {
                            w.preps.retain(|(k, _)| *k != id);
                        }
                        if let Some(busy) = w.busy.take() {
                            if let Err(e) = run.on_reply(busy, response) { fatal = Some(e); break; }
                        }
                    }
                }
                Some(Event::Lost { worker, error }) => {
                    reporter.note(&format!("worker {worker}: {error}"));
                    if let Some(w) = workers.get_mut(&worker) {
                        w.preps.clear();
                        if let Some(busy) = w.busy.take() {
                            if let Err(e) = run.on_failure(busy, &error.to_string()) { fatal = Some(e); break; }
                        }
                    }
                }
                Some(Event::Dead { worker, error }) => {
                    reporter.note(&format!("worker {worker} is gone: {error}"));
                    if let Some(mut w) = workers.remove(&worker) {
                        if let Some(busy) = w.busy.take() {
                            if let Err(e) = run.on_failure(busy, &error) { fatal = Some(e); break; }
                        }
                    }
                    if workers.is_empty() {
                        fatal = Some(RunError::Spawn {
                            exe: opts.worker.exe.display().to_string(),
                            source: std::io::Error::other(error),
                        });
                        break;
                    }
                }
                None => break,
            },
            _ = &mut interrupt => {
                ending = Ending::Interrupted;
                if grace_until.is_some() {
                    reporter.note("second signal: stopping at once");
                    break;
                }
                reporter.note(&format!(
                    "interrupted: no new jobs; waiting up to {} s for the {} in flight to finish \
                     (Ctrl-C again to stop at once)",
                    opts.grace.as_secs_f64(),
                    run.progress.running
                ));
                grace_until = Some(tokio::time::Instant::now() + opts.grace);
                interrupt = Box::pin(interrupted());
            }
            _ = grace => {
                reporter.note("grace period over: stopping the workers");
                break;
            }
        }
    }
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
    if ending == Ending::Interrupted {
        reporter.note(&format!(
            "interrupted: {requeued} running jobs put back to pending; run again to resume"
        ));
    }
    if let Some(e) = fatal {
        return Err(e);
    }
    run.progress.running = 0;
    Ok(RunReport {
        ending,
        progress: run.progress,
    })
}

/// Resolves on Ctrl-C or SIGTERM.
async fn interrupted() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{signal, SignalKind};
        let mut term = match signal(SignalKind::terminate()) {
            Ok(s) => s,
            Err(_) => return std::future::pending().await,
        };
        tokio::select! {
            _ = tokio::signal::ctrl_c() => {}
            _ = term.recv() => {}
        }
    }
    #[cfg(not(unix))]
    {
        let _ = tokio::signal::ctrl_c().await;
    }
}
