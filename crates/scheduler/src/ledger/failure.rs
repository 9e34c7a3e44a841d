//! Failed attempts, recorded the same way by both engines: the error and the attempt's number
//! are kept, and the task is pending again or, after the ledger's `max_attempts`, failed for
//! good (a prep failed for good fails the sweep's jobs that need it).

use cellsweep_store::{JobState, Store};

use super::Ledger;
use crate::error::RunError;

/// What an attempt was of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TaskRef {
    Prep(i64),
    Job(i64),
}

/// What a recorded failure did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// Pending again, for its next attempt.
    Retry,
    /// Failed for good; for a prep, `jobs` of the sweep failed with it.
    GaveUp { jobs: usize },
    /// Nothing changed: this attempt was recorded before (a record read twice), or the task
    /// is no longer open (done, or failed for good).
    Already,
    /// Nothing changed: a job whose prep has no result yet could not start, which is not an
    /// attempt of its own (a Slurm collide task runs whether or not its prep task succeeded).
    PrepNotReady,
}

impl Ledger {
    /// Record failed attempt number `attempt` of `task` (1 for the first), with its error.
    pub fn fail(
        &self,
        store: &mut Store,
        task: TaskRef,
        attempt: u32,
        error: &str,
    ) -> Result<Failure, RunError> {
        let max = self.max_attempts;
        let state = match task {
            TaskRef::Job(id) => {
                let ready = store
                    .job_identity(id)?
                    .is_some_and(|j| j.prep_verdict.is_some());
                if !ready {
                    return Ok(Failure::PrepNotReady);
                }
                store.fail_job(id, attempt, error, max)?
            }
            TaskRef::Prep(id) => store.fail_prep(id, attempt, error, max)?,
        };
        Ok(match (state, task) {
            (None, _) => Failure::Already,
            (Some(JobState::Failed), TaskRef::Prep(id)) => Failure::GaveUp {
                jobs: self.fail_jobs_of_prep(store, id, error)?,
            },
            (Some(JobState::Failed), TaskRef::Job(_)) => Failure::GaveUp { jobs: 1 },
            (Some(_), _) => Failure::Retry,
        })
    }

    /// The sweep's pending jobs of a prep that failed for good cannot run: they fail with it.
    fn fail_jobs_of_prep(
        &self,
        store: &mut Store,
        id: i64,
        error: &str,
    ) -> Result<usize, RunError> {
        Ok(store.fail_jobs_of_prep(self.sweep_id, id, &self.version, error)?)
    }

    /// Fail the pending jobs of every prep that failed for good earlier (jobs added since: a
    /// grown sweep, a new round). Returns how many.
    pub(super) fn fail_jobs_of_failed_preps(&self, store: &mut Store) -> Result<usize, RunError> {
        let mut n = 0;
        for p in store.preps_of(self.sweep_id, &self.version)? {
            if p.state == JobState::Failed {
                n += self.fail_jobs_of_prep(store, p.id, "failed in an earlier run")?;
            }
        }
        Ok(n)
    }
}
