//! Putting chosen points of a sweep back to pending ([`Store::reset_points`]): after a fix that
//! changes how some collisions end (the collision breakup check of SPEC section 5, say), the
//! points it touches run again with the very same seeds, and the rest of the sweep keeps its
//! results. [`PointRef`] names a point by its swept parameters.

use rusqlite::params;
use serde::Serialize;

use crate::database::Store;
use crate::error::Result;
use crate::lifecycle::JobState::Pending;

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
    /// Preps put back to be computed again ([`Store::reset_breakups`] only).
    pub preps: usize,
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
                 WHERE point_id = ?1 AND solver_version = ?2 AND state != ?3",
                params![point, version, Pending],
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
                "UPDATE jobs SET state = ?3, attempts_at_retry = attempts, error = NULL,
                     started_at = NULL, finished_at = NULL
                 WHERE point_id = ?1 AND solver_version = ?2 AND state != ?3",
                params![point, version, Pending],
            )?;
        }
        tx.commit()?;
        Ok(out)
    }

    /// What [`Store::reset_breakups`] would put back at these points, changing nothing.
    pub fn count_breakups(&self, version: &str, point_ids: &[i64]) -> Result<Reset> {
        let t = breakup_targets(&self.conn, version, point_ids)?;
        let mut out = Reset {
            points: t.points,
            preps: t.preps.len(),
            ..Reset::default()
        };
        for &job in &t.jobs {
            let (has_result, not_pending): (i64, i64) = self.conn.query_row(
                "SELECT (SELECT COUNT(*) FROM results WHERE job_id = ?1),
                        (SELECT COUNT(*) FROM jobs WHERE id = ?1 AND state != ?2)",
                params![job, Pending],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )?;
            out.results += has_result as usize;
            out.jobs += not_pending as usize;
        }
        Ok(out)
    }

    /// Put back what a change of the breakup rule (SPEC section 5) can change, and nothing
    /// else, at these points of `version`: every job whose result is a collision that broke
    /// up, and every prep whose verdict is `breakup` with all the jobs that start from it (in
    /// any sweep of the store: a prep is shared). One transaction; the caller holds the
    /// writer lock. The next run computes them again with the same seeds.
    pub fn reset_breakups(&mut self, version: &str, point_ids: &[i64]) -> Result<Reset> {
        let tx = self.write()?;
        let t = breakup_targets(&tx, version, point_ids)?;
        let mut out = Reset {
            points: t.points,
            ..Reset::default()
        };
        for &prep in &t.preps {
            out.preps += tx.execute(
                "UPDATE preps SET state = ?2, attempts_at_retry = attempts, error = NULL,
                     verdict = NULL, verdict_time = NULL, free_speed = NULL, nx = NULL, ny = NULL,
                     phi = NULL, p = NULL, summary = NULL, wall_s = NULL, finished_at = NULL
                 WHERE id = ?1",
                params![prep, Pending],
            )?;
        }
        for &job in &t.jobs {
            out.results += tx.execute("DELETE FROM results WHERE job_id = ?1", [job])?;
            out.jobs += tx.execute(
                "UPDATE jobs SET state = ?2, attempts_at_retry = attempts, error = NULL,
                     started_at = NULL, finished_at = NULL
                 WHERE id = ?1 AND state != ?2",
                params![job, Pending],
            )?;
        }
        tx.commit()?;
        Ok(out)
    }
}

/// The jobs and preps a change of the breakup rule can change at these points.
struct BreakupTargets {
    /// Jobs to put back: collisions that broke up, and every job of a prep that broke up.
    jobs: Vec<i64>,
    /// Preps whose verdict is `breakup`.
    preps: Vec<i64>,
    /// Points with a stored breakup.
    points: usize,
}

fn breakup_targets(
    conn: &rusqlite::Connection,
    version: &str,
    point_ids: &[i64],
) -> Result<BreakupTargets> {
    let mut preps: Vec<i64> = Vec::new();
    let mut jobs: Vec<i64> = Vec::new();
    let mut points = 0;
    let mut broke = conn.prepare(
        "SELECT j.id, j.prep_id, r.verdict FROM jobs j JOIN results r ON r.job_id = j.id
         WHERE j.point_id = ?1 AND j.solver_version = ?2
           AND (r.outcome = 'breakup' OR (r.verdict = 'breakup' AND r.outcome IS NULL))",
    )?;
    for &point in point_ids {
        let rows = broke.query_map(params![point, version], |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, i64>(1)?,
                r.get::<_, String>(2)?,
            ))
        })?;
        let before = (jobs.len(), preps.len());
        for row in rows {
            let (job, prep, verdict) = row?;
            match verdict.as_str() {
                "breakup" => preps.push(prep),
                _ => jobs.push(job),
            }
        }
        if (jobs.len(), preps.len()) != before {
            points += 1;
        }
    }
    preps.sort_unstable();
    preps.dedup();
    let mut of_prep = conn.prepare("SELECT id FROM jobs WHERE prep_id = ?1")?;
    for &prep in &preps {
        for id in of_prep.query_map([prep], |r| r.get::<_, i64>(0))? {
            jobs.push(id?);
        }
    }
    jobs.sort_unstable();
    jobs.dedup();
    Ok(BreakupTargets {
        jobs,
        preps,
        points,
    })
}
