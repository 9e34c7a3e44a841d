//! Putting chosen points of a sweep back to pending ([`Store::reset_points`]): after a fix that
//! changes how some collisions end (the collision breakup check of SPEC section 5, say), the
//! points it touches run again with the very same seeds, and the rest of the sweep keeps its
//! results. [`PointRef`] names a point by its swept parameters.

use rusqlite::params;
use serde::Serialize;

use crate::database::Store;
use crate::error::Result;

/// A registered point: its row id and the four swept parameters.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct PointRef {
    pub id: i64,
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    /// The point's configuration as stored (JSON), where its other axes' values are.
    pub config: String,
}

/// What [`Store::reset_points`] changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Reset {
    /// Points asked for.
    pub points: usize,
    /// Jobs put back to pending (done, failed, or left running by a killed run).
    pub jobs: usize,
    /// Results deleted with them.
    pub results: usize,
}

impl Store {
    /// Every point of a sweep, in grid order.
    pub fn sweep_points(&self, sweep_id: i64) -> Result<Vec<PointRef>> {
        let mut q = self.conn.prepare(
            "SELECT id, alpha, beta, L, sigma, params FROM points WHERE sweep_id = ?1 ORDER BY idx",
        )?;
        let rows = q.query_map([sweep_id], |r| {
            Ok(PointRef {
                id: r.get(0)?,
                alpha: r.get(1)?,
                beta: r.get(2)?,
                L: r.get(3)?,
                sigma: r.get(4)?,
                config: r.get(5)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// How many jobs of `version` at these points [`Store::reset_points`] would put back.
    pub fn jobs_of_points(&self, point_ids: &[i64], version: &str) -> Result<usize> {
        let mut n = 0usize;
        for &point in point_ids {
            n += self.conn.query_row(
                "SELECT COUNT(*) FROM jobs
                 WHERE point_id = ?1 AND solver_version = ?2 AND state != 'pending'",
                params![point, version],
                |r| r.get::<_, i64>(0),
            )? as usize;
        }
        Ok(n)
    }

    /// Put every job of `version` at these points back to `pending` with its error cleared and
    /// its attempts anew (the count goes on, as for a retry), deleting the results of those that were done; one transaction, so either all of
    /// them go back or none. Preps are kept: a prep decides its jobs again when the run starts.
    /// The caller holds the writer lock (no run is live), so a `running` job is one a killed
    /// run left behind; a Slurm array in flight may still deliver a record for a job put back,
    /// which is the very trajectory the rerun would compute (same seed, same solver).
    pub fn reset_points(&mut self, version: &str, point_ids: &[i64]) -> Result<Reset> {
        let tx = self.write()?;
        let mut out = Reset {
            points: point_ids.len(),
            ..Reset::default()
        };
        for &point in point_ids {
            out.results += tx.execute(
                "DELETE FROM results WHERE job_id IN (
                     SELECT id FROM jobs WHERE point_id = ?1 AND solver_version = ?2)",
                params![point, version],
            )?;
            out.jobs += tx.execute(
                "UPDATE jobs SET state = 'pending', attempts_at_retry = attempts, error = NULL,
                     started_at = NULL, finished_at = NULL
                 WHERE point_id = ?1 AND solver_version = ?2 AND state != 'pending'",
                params![point, version],
            )?;
        }
        tx.commit()?;
        Ok(out)
    }
}
