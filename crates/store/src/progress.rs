//! How far a sweep has come, read cheaply: from `point_progress` (kept by triggers since
//! schema 4, [`crate::schema::PROGRESS`]) where the store has it, else by counting `jobs` (an
//! older store opened read-only as it is).

use rusqlite::{params, OptionalExtension};

use crate::database::Store;
use crate::error::Result;
use crate::schema::PROGRESS_SCHEMA;

/// The ids of the preps that sweep ?1's jobs of version ?2 start from, given ?3 preps per
/// point. Replicate r of a point starts from the point's prep r mod k (round-robin, SPEC
/// section 4) and replicates are registered in index order, so the jobs of replicates 0..k
/// reach every prep the point's jobs use: k index seeks per point, not a scan of every job.
pub(crate) const SWEEP_PREP_IDS: &str =
    "SELECT j.prep_id FROM points p JOIN jobs j ON j.point_id = p.id
     WHERE p.sweep_id = ?1 AND j.replicate < ?3 AND j.solver_version = ?2";

impl Store {
    /// Whether the file keeps `point_progress` and the index of finished jobs by time.
    pub(crate) fn has_progress(&self) -> bool {
        self.schema >= PROGRESS_SCHEMA
    }

    /// How many preps each point of the sweep has (the sweep's `preps_per_point`, 1 if its
    /// definition does not say).
    pub(crate) fn preps_per_point(&self, sweep_id: i64) -> Result<i64> {
        let spec: String =
            self.conn
                .query_row("SELECT spec FROM sweeps WHERE id = ?1", [sweep_id], |r| {
                    r.get(0)
                })?;
        Ok(serde_json::from_str::<serde_json::Value>(&spec)
            .ok()
            .and_then(|v| v.get("preps_per_point").and_then(|k| k.as_i64()))
            .unwrap_or(1)
            .max(1))
    }

    /// The sweep's preps under `version`: (done, all).
    pub(crate) fn prep_counts(&self, sweep_id: i64, version: &str) -> Result<(i64, i64)> {
        let k = self.preps_per_point(sweep_id)?;
        let sql = format!(
            "SELECT COALESCE(SUM(state = 'done'), 0), COUNT(*) FROM preps WHERE id IN ({SWEEP_PREP_IDS})"
        );
        Ok(self
            .conn
            .prepare_cached(&sql)?
            .query_row(params![sweep_id, version, k], |r| {
                Ok((r.get(0)?, r.get(1)?))
            })?)
    }

    /// When the sweep's latest job finished (Unix seconds), if any has.
    pub(crate) fn last_finished(&self, sweep_id: i64, version: &str) -> Result<Option<f64>> {
        let sql = match self.has_progress() {
            true => {
                "SELECT MAX(pp.last_finished) FROM point_progress pp
                 JOIN points p ON p.id = pp.point_id
                 WHERE p.sweep_id = ?1 AND pp.solver_version = ?2"
            }
            false => {
                "SELECT MAX(j.finished_at) FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = 'done'"
            }
        };
        Ok(self
            .conn
            .query_row(sql, params![sweep_id, version], |r| r.get(0))
            .optional()?
            .flatten())
    }

    /// (started, finished) of the sweep's jobs that finished at or after `since`: the spans
    /// the speed is measured over (`cellsweep_stats::throughput`).
    pub(crate) fn recent_spans(
        &self,
        sweep_id: i64,
        version: &str,
        since: f64,
    ) -> Result<Vec<(f64, f64)>> {
        // Through the partial index of finished jobs by time where there is one: the window
        // holds minutes of work, not the sweep's millions of jobs.
        let sql = match self.has_progress() {
            true => {
                "SELECT j.started_at, j.finished_at FROM jobs j INDEXED BY jobs_done_by_finish
                 JOIN points p ON p.id = j.point_id
                 WHERE j.state = 'done' AND j.finished_at >= ?3 AND p.sweep_id = ?1
                   AND j.solver_version = ?2 AND j.started_at IS NOT NULL"
            }
            false => {
                "SELECT j.started_at, j.finished_at FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = 'done'
                   AND j.finished_at >= ?3 AND j.started_at IS NOT NULL"
            }
        };
        let mut q = self.conn.prepare_cached(sql)?;
        let spans = q
            .query_map(params![sweep_id, version, since], |r| {
                Ok((r.get(0)?, r.get(1)?))
            })?
            .collect::<rusqlite::Result<_>>()?;
        Ok(spans)
    }
}
