//! The guarded transitions of the job lifecycle ([`crate::lifecycle`]) other than finishing:
//! claiming, failing an attempt, recovering what a killed run left `running`, and retrying
//! what failed for good. Each is one UPDATE that applies only from the expected state.

use rusqlite::{params, OptionalExtension};

use crate::database::Store;
use crate::encoding::now;
use crate::error::{Result, StoreError};
use crate::lifecycle::JobState::{self, Failed, Pending, Running};

impl Store {
    /// Put a sweep's failed jobs and preps back to pending, each with `max_attempts` attempts
    /// anew (their errors are kept until they run again). The count of failed attempts goes
    /// on growing, so a failure recorded before the retry is never counted again. Returns how
    /// many.
    pub fn retry_failed(&mut self, sweep_id: i64, version: &str) -> Result<usize> {
        let tx = self.write()?;
        let preps = tx.execute(
            "UPDATE preps SET state = ?3, attempts_at_retry = attempts
             WHERE state = ?4 AND solver_version = ?2 AND id IN (
                 SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1)",
            params![sweep_id, version, Pending, Failed],
        )?;
        let jobs = tx.execute(
            "UPDATE jobs SET state = ?3, attempts_at_retry = attempts
             WHERE state = ?4 AND solver_version = ?2
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![sweep_id, version, Pending, Failed],
        )?;
        tx.commit()?;
        Ok(preps + jobs)
    }

    /// Put the sweep's `running` preps and jobs of `version` back to `pending`: a coordinator that
    /// was killed or interrupted did not finish them. Returns how many were recovered.
    pub fn recover_running(&mut self, sweep_id: i64, version: &str) -> Result<usize> {
        let tx = self.write()?;
        let jobs = tx.execute(
            "UPDATE jobs SET state = ?3, started_at = NULL
             WHERE state = ?4 AND solver_version = ?2
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![sweep_id, version, Pending, Running],
        )?;
        let preps = tx.execute(
            "UPDATE preps SET state = ?3
             WHERE state = ?4 AND solver_version = ?2 AND id IN (
                 SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1)",
            params![sweep_id, version, Pending, Running],
        )?;
        tx.commit()?;
        Ok(jobs + preps)
    }

    /// pending -> running for a job.
    pub fn claim_job(&mut self, id: i64) -> Result<()> {
        let n = self.conn.execute(
            "UPDATE jobs SET state = ?3, started_at = ?2 WHERE id = ?1 AND state = ?4",
            params![id, now(), Running, Pending],
        )?;
        self.expect_one(n, "job", id, Pending, "jobs")
    }

    /// pending -> running for a prep.
    pub fn claim_prep(&mut self, id: i64) -> Result<()> {
        let n = self.conn.execute(
            "UPDATE preps SET state = ?2 WHERE id = ?1 AND state = ?3",
            params![id, Running, Pending],
        )?;
        self.expect_one(n, "prep", id, Pending, "preps")
    }

    pub(crate) fn expect_one(
        &self,
        n: usize,
        what: &'static str,
        id: i64,
        expected: JobState,
        table: &str,
    ) -> Result<()> {
        if n == 1 {
            return Ok(());
        }
        let found: Option<String> = self
            .conn
            .query_row(
                &format!("SELECT state FROM {table} WHERE id = ?1"),
                [id],
                |r| r.get(0),
            )
            .optional()?;
        Err(StoreError::BadTransition {
            what,
            id,
            found: found.unwrap_or_else(|| "missing".into()),
            expected: expected.as_str(),
        })
    }

    /// Record failed attempt number `attempt` of a job (one guarded UPDATE): back to pending,
    /// or failed for good once `max_attempts` attempts have failed since its latest retry
    /// (`None`: the limit is not known here, and [`Store::give_up_exhausted`] applies it later).
    /// Returns the new state, or `None` when that attempt is already recorded or the job is no
    /// longer open (done, or failed for good): a record read twice counts once.
    pub fn fail_job(
        &mut self,
        id: i64,
        attempt: u32,
        error: &str,
        max_attempts: Option<u32>,
    ) -> Result<Option<JobState>> {
        self.fail("jobs", id, attempt, error, max_attempts)
    }

    /// Record a failed attempt of a prep (see [`Store::fail_job`]).
    pub fn fail_prep(
        &mut self,
        id: i64,
        attempt: u32,
        error: &str,
        max_attempts: Option<u32>,
    ) -> Result<Option<JobState>> {
        self.fail("preps", id, attempt, error, max_attempts)
    }

    fn fail(
        &mut self,
        table: &str,
        id: i64,
        attempt: u32,
        error: &str,
        max_attempts: Option<u32>,
    ) -> Result<Option<JobState>> {
        // Attempt n is the one made after n - 1 failed: the local engine's task is `running`,
        // a Slurm task stays `pending` until its record is collected.
        let n = self.conn.execute(
            &format!(
                "UPDATE {table} SET attempts = attempts + 1, error = ?2,
                     state = CASE WHEN ?3 IS NOT NULL AND attempts + 1 - attempts_at_retry >= ?3
                                  THEN ?5 ELSE ?6 END
                 WHERE id = ?1 AND state IN (?6, ?7) AND attempts = ?4 - 1"
            ),
            params![id, error, max_attempts, attempt, Failed, Pending, Running],
        )?;
        if n == 0 {
            return Ok(None);
        }
        let state: JobState = self.conn.query_row(
            &format!("SELECT state FROM {table} WHERE id = ?1"),
            [id],
            |r| r.get(0),
        )?;
        Ok(Some(state))
    }

    /// Fail for good the sweep's pending preps and jobs of `version` that have failed
    /// `max_attempts` attempts since their latest retry (recorded where the limit was not
    /// known: a Slurm collect). Returns how many preps and jobs.
    pub fn give_up_exhausted(
        &mut self,
        sweep_id: i64,
        version: &str,
        max_attempts: u32,
    ) -> Result<usize> {
        let tx = self.write()?;
        let preps = tx.execute(
            "UPDATE preps SET state = ?4
             WHERE state = ?5 AND attempts - attempts_at_retry >= ?3
               AND solver_version = ?2 AND id IN (
                 SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1)",
            params![sweep_id, version, max_attempts, Failed, Pending],
        )?;
        let jobs = tx.execute(
            "UPDATE jobs SET state = ?4
             WHERE state = ?5 AND attempts - attempts_at_retry >= ?3
               AND solver_version = ?2
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![sweep_id, version, max_attempts, Failed, Pending],
        )?;
        tx.commit()?;
        Ok(preps + jobs)
    }

    /// Mark the sweep's pending jobs of a failed prep as failed (they cannot run).
    pub fn fail_jobs_of_prep(
        &mut self,
        sweep_id: i64,
        prep_id: i64,
        version: &str,
        error: &str,
    ) -> Result<usize> {
        let tx = self.write()?;
        crate::plans::materialize_prep(&tx, sweep_id, prep_id, version)?;
        let n = tx.execute(
            "UPDATE jobs SET state = ?5, error = ?4
             WHERE prep_id = ?2 AND solver_version = ?3 AND state = ?6
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![
                sweep_id,
                prep_id,
                version,
                format!("its prep failed: {error}"),
                Failed,
                Pending
            ],
        )?;
        tx.commit()?;
        Ok(n)
    }
}
