//! The dispatcher's state of one local run: the queues of preps and jobs, what each worker
//! is busy with and which preps it holds, and what becomes of each answer (through the
//! ledger). [`super::run_sweep`] drives it with the workers' events.

use std::collections::{HashMap, HashSet, VecDeque};

use cellsweep_solver::{Outcome, Verdict};
use cellsweep_stats::throughput;
use cellsweep_stats::{End, Tally};
use cellsweep_store::{JobState, JobTask, PrepTask, Store};
use tokio::sync::mpsc;

use super::Progress;
use crate::error::RunError;
use crate::ledger::{Failure, Ledger, Settlement, TaskRef};
use crate::wire::{PrepPayload, Request, Response};
use crate::worker::remember;

/// Jobs a run keeps queued ahead of its workers (written as rows of the store just before).
const LOOKAHEAD: usize = 2048;

pub(super) enum Busy {
    Prep(PrepTask),
    Job(JobTask),
}

pub(super) struct Worker {
    pub(super) requests: mpsc::Sender<Request>,
    /// The preps its process holds: a copy of its cache, kept by the worker's own rule.
    pub(super) preps: VecDeque<(i64, ())>,
    pub(super) busy: Option<Busy>,
}

/// Count `n` replicates that ended so in the outcome counts of a run.
fn count(outcomes: &mut Tally, verdict: &str, outcome: Option<Outcome>, n: u64) {
    let end = End::of(verdict, outcome.map(Outcome::as_str)).unwrap_or(End::Breakup);
    outcomes.add(end, n);
}

pub(super) struct Run<'a> {
    pub(super) store: &'a mut Store,
    ledger: Ledger,
    pub(super) prep_queue: VecDeque<PrepTask>,
    pub(super) waiting: HashMap<i64, VecDeque<JobTask>>,
    pub(super) ready: VecDeque<JobTask>,
    /// The jobs this run has queued and not yet seen end, so that a new round's (or a top-up's)
    /// pending jobs are queued once; a job leaves it when it is done or failed for good, so it
    /// holds the jobs in flight and ahead, not the ten million of a whole run.
    queued: HashSet<i64>,
    /// Whether the store may still hold planned jobs of the sweep that are not rows yet (see
    /// [`Run::top_up`]).
    planned_left: bool,
    /// Preps known to be decided `ok` (their jobs go straight to `ready`).
    ok_preps: HashSet<i64>,
    /// The latest preps' fields, to send with a job to a worker that lacks its prep: a few,
    /// by the workers' own rule ([`remember`]), and read again from the store when gone (a
    /// sweep of ten thousand preps would otherwise hold gigabytes of fields here).
    payloads: VecDeque<(i64, PrepPayload)>,
    prep_seeds: HashMap<i64, u64>,
    pub(super) progress: Progress,
    /// (started, finished) of the jobs this run finished in the latest window.
    spans: Vec<(f64, f64)>,
}

impl<'a> Run<'a> {
    /// A run of the ledger's sweep: the preps still to compute queued first, then the jobs.
    pub(super) fn new(store: &'a mut Store, ledger: Ledger) -> Result<Self, RunError> {
        let mut run = Run {
            store,
            ledger,
            prep_queue: VecDeque::new(),
            waiting: HashMap::new(),
            ready: VecDeque::new(),
            queued: HashSet::new(),
            planned_left: true,
            ok_preps: HashSet::new(),
            payloads: VecDeque::new(),
            prep_seeds: HashMap::new(),
            progress: Progress::default(),
            spans: Vec::new(),
        };
        run.refresh_totals()?;
        run.queue_preps()?;
        run.queue_pending()?;
        run.top_up()?;
        Ok(run)
    }

    /// Keep about [`LOOKAHEAD`] jobs queued: the store keeps a sweep's jobs planned until a
    /// run is about to dispatch them (`Store::materialize_next`), so ten million registered
    /// jobs cost neither rows at registration nor memory here, only the next points' worth.
    fn top_up(&mut self) -> Result<(), RunError> {
        let queued = self.ready.len() + self.waiting.values().map(|v| v.len()).sum::<usize>();
        if !self.planned_left || queued >= LOOKAHEAD {
            return Ok(());
        }
        let written = self.store.materialize_next(
            self.ledger.sweep_id,
            &self.ledger.version,
            LOOKAHEAD - queued,
        )?;
        if written == 0 {
            self.planned_left = false;
        } else {
            self.queue_pending()?;
        }
        Ok(())
    }

    /// Queue the sweep's preps this run does not know yet (all of them at the start; then
    /// those of the points a refinement round adds): those still to compute, and those done
    /// counted as done.
    fn queue_preps(&mut self) -> Result<(), RunError> {
        for prep in self
            .store
            .preps_of(self.ledger.sweep_id, &self.ledger.version)?
        {
            if self.prep_seeds.insert(prep.id, prep.seed).is_some() {
                continue;
            }
            self.progress.preps_total += 1;
            match prep.state {
                JobState::Done | JobState::Failed => {
                    self.progress.preps_done += 1;
                    if prep.verdict == Some(cellsweep_stats::PrepVerdict::Ok) {
                        self.ok_preps.insert(prep.id);
                    }
                }
                _ => self.prep_queue.push_back(prep),
            }
        }
        Ok(())
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
            self.progress.outcomes = s.outcomes;
        }
        if self.ledger.sweep.refine.is_some() {
            let grid = &self.ledger.sweep.grid.beta;
            let added = self
                .ledger
                .point_axes(self.store)?
                .iter()
                .filter(|a| !grid.contains(&a.beta))
                .count();
            self.progress.refined_points = Some(added as u64);
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

    /// A sweep's next rounds (adaptive replicates, refined points), once a point's round or a
    /// column is complete.
    fn plan_rounds(&mut self) -> Result<(), RunError> {
        if self.ledger.plan_rounds(self.store)? > 0 {
            self.refresh_totals()?;
            self.queue_preps()?;
            self.queue_pending()?;
            self.planned_left = true;
            self.top_up()?;
        }
        Ok(())
    }

    fn payload(&mut self, prep_id: i64) -> Result<PrepPayload, RunError> {
        if let Some((_, p)) = self.payloads.iter().find(|(id, _)| *id == prep_id) {
            return Ok(p.clone());
        }
        let seed = self.prep_seeds.get(&prep_id).copied().unwrap_or_default();
        let payload = PrepPayload::from_record(self.store.load_prep(prep_id)?, seed)?;
        remember(&mut self.payloads, prep_id, payload.clone());
        Ok(payload)
    }

    /// The next request for `worker`, claimed in the store.
    pub(super) fn next_request(
        &mut self,
        worker: &mut Worker,
    ) -> Result<Option<Request>, RunError> {
        if let Some(prep) = self.prep_queue.pop_front() {
            self.store.claim_prep(prep.id)?;
            let req = Request::prep(&prep)?;
            // The worker keeps the prep it computes (the mirror is mended if it fails).
            remember(&mut worker.preps, prep.id, ());
            worker.busy = Some(Busy::Prep(prep));
            return Ok(Some(req));
        }
        if self.ready.len() < LOOKAHEAD / 2 {
            self.top_up()?;
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
            for j in &jobs {
                self.queued.remove(&j.id);
            }
            self.progress.jobs_done += settled as u64;
            count(
                &mut self.progress.outcomes,
                verdict.as_str(),
                None,
                settled as u64,
            );
        }
    }

    pub(super) fn on_reply(&mut self, busy: Busy, response: Response) -> Result<(), RunError> {
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
                if verdict == Verdict::Ok {
                    remember(&mut self.payloads, task.id, *prep);
                }
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
                    Settlement::Already => {
                        self.queued.remove(&task.id);
                    }
                    Settlement::New => {
                        self.queued.remove(&task.id);
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
    pub(super) fn on_failure(&mut self, busy: Busy, error: &str) -> Result<(), RunError> {
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
                for j in self.waiting.remove(&p.id).unwrap_or_default() {
                    self.queued.remove(&j.id);
                }
            }
            (Failure::GaveUp { jobs }, Busy::Job(j)) => {
                self.progress.failed += jobs as u64;
                self.queued.remove(&j.id);
            }
            // (A task this run claimed is open and its prep is ready: not reached.)
            (Failure::Already | Failure::PrepNotReady, _) => {}
        }
        Ok(())
    }
}
