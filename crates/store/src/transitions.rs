//! The guarded transitions of the job lifecycle ([`crate::lifecycle`]) other than finishing:
//! claiming, failing an attempt, and recovering what a killed run left `running`. Each is one
//! UPDATE that applies only from the expected state.

use rusqlite::{params, OptionalExtension};

use crate::error::{Result, StoreError};
use crate::lifecycle::JobState;
use crate::store::{now, Store};

impl Store {
    /// Put the sweep's `running` preps and jobs of `version` back to `pending`: a coordinator that
    /// was killed or interrupted did not finish them. Returns how many were recovered.
    pub fn recover_running(&mut self, sweep_id: i64, version: &str) -> Result<usize> {
        let tx = self.write()?;
        let jobs = tx.execute(
            "UPDATE jobs SET state = 'pending', started_at = NULL
             WHERE state = 'running' AND solver_version = ?2
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![sweep_id, version],
        )?;
        let preps = tx.execute(
            "UPDATE preps SET state = 'pending'
             WHERE state = 'running' AND solver_version = ?2 AND id IN (
                 SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1)",
            params![sweep_id, version],
        )?;
        tx.commit()?;
        Ok(jobs + preps)
    }

    /// pending -> running for a job.
    pub fn claim_job(&mut self, id: i64) -> Result<()> {
        let n = self.conn.execute(
            "UPDATE jobs SET state = 'running', started_at = ?2 WHERE id = ?1 AND state = 'pending'",
            params![id, now()],
        )?;
        self.expect_one(n, "job", id, "pending", "jobs")
    }

    /// pending -> running for a prep.
    pub fn claim_prep(&mut self, id: i64) -> Result<()> {
        let n = self.conn.execute(
            "UPDATE preps SET state = 'running' WHERE id = ?1 AND state = 'pending'",
            params![id],
        )?;
        self.expect_one(n, "prep", id, "pending", "preps")
    }

    pub(crate) fn expect_one(
        &self,
        n: usize,
        what: &'static str,
        id: i64,
        expected: &'static str,
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
            expected,
        })
    }

    /// A failed attempt of a running job: back to pending, or failed for good once `max_attempts`
    /// attempts have failed. Returns the new state.
    pub fn fail_job(&mut self, id: i64, error: &str, max_attempts: u32) -> Result<JobState> {
        self.fail("jobs", "job", id, error, max_attempts)
    }

    /// A failed attempt of a running prep (see [`Store::fail_job`]).
    pub fn fail_prep(&mut self, id: i64, error: &str, max_attempts: u32) -> Result<JobState> {
        self.fail("preps", "prep", id, error, max_attempts)
    }

    fn fail(
        &mut self,
        table: &str,
        what: &'static str,
        id: i64,
        error: &str,
        max_attempts: u32,
    ) -> Result<JobState> {
        let n = self.conn.execute(
            &format!(
                "UPDATE {table} SET attempts = attempts + 1, error = ?2,
                     state = CASE WHEN attempts + 1 >= ?3 THEN 'failed' ELSE 'pending' END
                 WHERE id = ?1 AND state = 'running'"
            ),
            params![id, error, max_attempts],
        )?;
        self.expect_one(n, what, id, "running", table)?;
        let s: String = self.conn.query_row(
            &format!("SELECT state FROM {table} WHERE id = ?1"),
            [id],
            |r| r.get(0),
        )?;
        Ok(JobState::parse(&s).unwrap_or(JobState::Failed))
    }

    /// Mark the sweep's pending jobs of a failed prep as failed (they cannot run).
    pub fn fail_jobs_of_prep(
        &mut self,
        sweep_id: i64,
        prep_id: i64,
        version: &str,
        error: &str,
    ) -> Result<usize> {
        Ok(self.conn.execute(
            "UPDATE jobs SET state = 'failed', error = ?4
             WHERE prep_id = ?2 AND solver_version = ?3 AND state = 'pending'
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![
                sweep_id,
                prep_id,
                version,
                format!("its prep failed: {error}")
            ],
        )?)
    }
}
