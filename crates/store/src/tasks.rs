//! The work a run needs: the preps a sweep's jobs start from, and its pending jobs.

use std::sync::Arc;

use rusqlite::params;

use crate::database::Store;
use crate::encoding::seed_from_sql;
use crate::error::Result;
use crate::lifecycle::JobState;
use crate::progress::SWEEP_PREP_IDS;

/// A prep a run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepTask {
    pub id: i64,
    pub seed: u64,
    pub config: String,
    pub state: JobState,
    pub verdict: Option<cellsweep_stats::PrepVerdict>,
    pub attempts: u32,
}

/// A collision job a run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct JobTask {
    pub id: i64,
    pub point_id: i64,
    pub replicate: u32,
    pub seed: u64,
    pub prep_id: i64,
    pub attempts: u32,
    /// The point's solver configuration (JSON), one copy shared by all its jobs: a run of
    /// ten million jobs holds 96 thousand of these, not ten million.
    pub config: Arc<str>,
}

impl Store {
    /// The preps the sweep's jobs of `version` start from, in id order.
    pub fn preps_of(&self, sweep_id: i64, version: &str) -> Result<Vec<PrepTask>> {
        let k = self.preps_per_point(sweep_id)?;
        let mut q = self.conn.prepare(&format!(
            "SELECT id, seed, config, state, verdict, attempts FROM preps WHERE id IN (
                 {SWEEP_PREP_IDS}) ORDER BY id"
        ))?;
        let rows = q.query_map(params![sweep_id, version, k], |r| {
            Ok(PrepTask {
                id: r.get(0)?,
                seed: seed_from_sql(r.get(1)?),
                config: r.get(2)?,
                state: r.get(3)?,
                verdict: crate::kinds::maybe_verdict_at(r, 4)?,
                attempts: r.get(5)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// The sweep's pending jobs of `version` that are rows, in (point, replicate) order: those
    /// still planned (schema 5) are not listed until [`Store::materialize_next`] writes them.
    pub fn pending_jobs(&self, sweep_id: i64, version: &str) -> Result<Vec<JobTask>> {
        let mut q = self.conn.prepare(
            "SELECT j.id, j.point_id, j.replicate, j.seed, j.prep_id, j.attempts, p.params
             FROM jobs j JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = ?3
             ORDER BY p.idx, j.replicate",
        )?;
        let mut rows = q.query(params![sweep_id, version, JobState::Pending])?;
        let mut out = Vec::new();
        let mut config: Option<(i64, Arc<str>)> = None;
        while let Some(r) = rows.next()? {
            let point_id: i64 = r.get(1)?;
            // Rows come point by point: the configuration is read once per point.
            let shared = match &config {
                Some((p, c)) if *p == point_id => c.clone(),
                _ => {
                    let c: Arc<str> = Arc::from(r.get::<_, String>(6)?);
                    config = Some((point_id, c.clone()));
                    c
                }
            };
            out.push(JobTask {
                id: r.get(0)?,
                point_id,
                replicate: r.get(2)?,
                seed: seed_from_sql(r.get(3)?),
                prep_id: r.get(4)?,
                attempts: r.get(5)?,
                config: shared,
            });
        }
        Ok(out)
    }
}
