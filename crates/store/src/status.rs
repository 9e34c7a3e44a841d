//! Read-side queries: progress of sweeps and outcome counts per point.

use cellsweep_stats::throughput::{self, WINDOW_S};
use rusqlite::params;
use serde::{Deserialize, Serialize};

use crate::database::Store;
use crate::error::Result;
use cellsweep_stats::End;

/// Jobs of one sweep and solver version, by state.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StateCounts {
    pub pending: i64,
    pub running: i64,
    pub done: i64,
    pub failed: i64,
}

impl StateCounts {
    pub fn total(&self) -> i64 {
        self.pending + self.running + self.done + self.failed
    }
}

/// Results by label: the four outcomes, and jobs decided by a prep verdict.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct OutcomeCounts {
    pub train: i64,
    pub walk_past: i64,
    pub reversal: i64,
    pub undetermined: i64,
    pub unstable: i64,
    pub breakup: i64,
    /// Collisions in which a cell broke up (SPEC section 5).
    #[serde(default)]
    pub collision_breakup: i64,
}

impl OutcomeCounts {
    fn add(&mut self, verdict: &str, outcome: Option<&str>, n: i64) {
        // The schema admits no other pair; anything else would be a broken prep, counted so.
        let slot = match End::of(verdict, outcome).unwrap_or(End::Breakup) {
            End::Train => &mut self.train,
            End::WalkPast => &mut self.walk_past,
            End::Reversal => &mut self.reversal,
            End::Undetermined => &mut self.undetermined,
            End::Unstable => &mut self.unstable,
            End::Breakup => &mut self.breakup,
            End::CollisionBreakup => &mut self.collision_breakup,
        };
        *slot += n;
    }
}

/// Progress of one sweep under one solver version.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepStatus {
    pub sweep: String,
    pub solver_version: String,
    pub jobs: StateCounts,
    pub outcomes: OutcomeCounts,
    pub preps_done: i64,
    pub preps_total: i64,
    /// Jobs finished per second over the latest ten minutes of activity.
    pub jobs_per_s: Option<f64>,
    /// Seconds to finish the remaining jobs at that rate.
    pub eta_s: Option<f64>,
    /// When the latest job finished (Unix seconds).
    pub last_finished: Option<f64>,
}

/// Outcome counts of one grid point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct PointCounts {
    pub point_id: i64,
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    pub outcomes: OutcomeCounts,
    pub jobs: StateCounts,
    /// Mean free speed of the point's prepped cells.
    pub free_speed: Option<f64>,
}

impl Store {
    /// Names of the registered sweeps, oldest first.
    pub fn sweep_names(&self) -> Result<Vec<String>> {
        let mut q = self.conn.prepare("SELECT name FROM sweeps ORDER BY id")?;
        let rows = q.query_map([], |r| r.get(0))?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// Progress of every sweep under every solver version it has jobs for.
    pub fn status(&self) -> Result<Vec<SweepStatus>> {
        let mut out = Vec::new();
        let mut pairs = self.conn.prepare(
            "SELECT DISTINCT s.id, s.name, j.solver_version FROM sweeps s
             JOIN points p ON p.sweep_id = s.id JOIN jobs j ON j.point_id = p.id
             ORDER BY s.id, j.solver_version",
        )?;
        let pairs: Vec<(i64, String, String)> = pairs
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?
            .collect::<rusqlite::Result<_>>()?;
        for (sweep_id, name, version) in pairs {
            let jobs = self.state_counts(sweep_id, &version, None)?;
            let outcomes = self.outcome_counts(sweep_id, &version, None)?;
            let (preps_done, preps_total): (i64, i64) = self.conn.query_row(
                "SELECT COALESCE(SUM(state = 'done'), 0), COUNT(*) FROM preps WHERE id IN (
                     SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                     WHERE p.sweep_id = ?1 AND j.solver_version = ?2)",
                params![sweep_id, version],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )?;
            let last: Option<f64> = self.conn.query_row(
                "SELECT MAX(j.finished_at) FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = 'done'",
                params![sweep_id, version],
                |r| r.get(0),
            )?;
            let jobs_per_s = match last {
                Some(last) => {
                    let mut q = self.conn.prepare_cached(
                        "SELECT j.started_at, j.finished_at FROM jobs j JOIN points p ON p.id = j.point_id
                         WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = 'done'
                           AND j.finished_at >= ?3 AND j.started_at IS NOT NULL",
                    )?;
                    let spans: Vec<(f64, f64)> = q
                        .query_map(params![sweep_id, version, last - WINDOW_S], |r| {
                            Ok((r.get(0)?, r.get(1)?))
                        })?
                        .collect::<rusqlite::Result<_>>()?;
                    throughput::jobs_per_s(&spans)
                }
                None => None,
            };
            let remaining = (jobs.pending + jobs.running) as f64;
            out.push(SweepStatus {
                sweep: name,
                solver_version: version,
                eta_s: throughput::eta_s(remaining, jobs_per_s),
                jobs,
                outcomes,
                preps_done,
                preps_total,
                jobs_per_s,
                last_finished: last,
            });
        }
        Ok(out)
    }

    fn state_counts(
        &self,
        sweep_id: i64,
        version: &str,
        point: Option<i64>,
    ) -> Result<StateCounts> {
        let mut q = self.conn.prepare_cached(
            "SELECT j.state, COUNT(*) FROM jobs j JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND (?3 IS NULL OR p.id = ?3)
             GROUP BY j.state",
        )?;
        let mut c = StateCounts::default();
        let rows = q.query_map(params![sweep_id, version, point], |r| {
            Ok((r.get::<_, String>(0)?, r.get::<_, i64>(1)?))
        })?;
        for row in rows {
            let (state, n) = row?;
            match state.as_str() {
                "pending" => c.pending = n,
                "running" => c.running = n,
                "done" => c.done = n,
                _ => c.failed = n,
            }
        }
        Ok(c)
    }

    fn outcome_counts(
        &self,
        sweep_id: i64,
        version: &str,
        point: Option<i64>,
    ) -> Result<OutcomeCounts> {
        let mut q = self.conn.prepare_cached(
            "SELECT r.verdict, r.outcome, COUNT(*) FROM results r
             JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND r.solver_version = ?2 AND (?3 IS NULL OR p.id = ?3)
             GROUP BY r.verdict, r.outcome",
        )?;
        let mut c = OutcomeCounts::default();
        let rows = q.query_map(params![sweep_id, version, point], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, Option<String>>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })?;
        for row in rows {
            let (verdict, outcome, n) = row?;
            c.add(&verdict, outcome.as_deref(), n);
        }
        Ok(c)
    }

    /// Outcome counts of every point of a sweep under `version`, in grid order.
    pub fn point_counts(&self, sweep_id: i64, version: &str) -> Result<Vec<PointCounts>> {
        let mut q = self.conn.prepare(
            "SELECT id, alpha, beta, L, sigma FROM points WHERE sweep_id = ?1 ORDER BY idx",
        )?;
        let points: Vec<(i64, f64, f64, u32, f64)> = q
            .query_map([sweep_id], |r| {
                Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?))
            })?
            .collect::<rusqlite::Result<_>>()?;
        let mut speed = self.conn.prepare_cached(
            "SELECT AVG(free_speed) FROM preps WHERE state = 'done' AND id IN (
                 SELECT prep_id FROM jobs WHERE point_id = ?1 AND solver_version = ?2)",
        )?;
        let mut out = Vec::with_capacity(points.len());
        for (id, alpha, beta, l, sigma) in points {
            out.push(PointCounts {
                point_id: id,
                alpha,
                beta,
                L: l,
                sigma,
                outcomes: self.outcome_counts(sweep_id, version, Some(id))?,
                jobs: self.state_counts(sweep_id, version, Some(id))?,
                free_speed: speed.query_row(params![id, version], |r| r.get(0))?,
            });
        }
        Ok(out)
    }
}

impl Store {
    /// The stored solver configuration (JSON) of a point.
    pub fn point_params(&self, point_id: i64) -> Result<String> {
        Ok(self
            .conn
            .query_row("SELECT params FROM points WHERE id = ?1", [point_id], |r| {
                r.get(0)
            })?)
    }
}

/// A job or prep that failed for good, with its error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Failure {
    /// `job` or `prep`.
    pub kind: String,
    pub id: i64,
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    /// The replicate (jobs only).
    pub replicate: Option<u32>,
    pub attempts: u32,
    pub error: String,
}

impl Store {
    /// The failed jobs and preps of a sweep under `version`, preps first.
    pub fn failures(&self, sweep_id: i64, version: &str) -> Result<Vec<Failure>> {
        let mut q = self.conn.prepare(
            "SELECT 'prep', pr.id, MIN(p.alpha), MIN(p.beta), MIN(p.L), MIN(p.sigma), NULL,
                    pr.attempts, COALESCE(pr.error, '')
             FROM preps pr JOIN jobs j ON j.prep_id = pr.id JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND pr.state = 'failed'
             GROUP BY pr.id
             UNION ALL
             SELECT 'job', j.id, p.alpha, p.beta, p.L, p.sigma, j.replicate, j.attempts,
                    COALESCE(j.error, '')
             FROM jobs j JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = 'failed'",
        )?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok(Failure {
                kind: r.get(0)?,
                id: r.get(1)?,
                alpha: r.get(2)?,
                beta: r.get(3)?,
                L: r.get(4)?,
                sigma: r.get(5)?,
                replicate: r.get(6)?,
                attempts: r.get(7)?,
                error: r.get(8)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// Put a sweep's failed jobs and preps back to pending, each with `max_attempts` attempts
    /// anew (their errors are kept until they run again). The count of failed attempts goes
    /// on growing, so a failure recorded before the retry is never counted again. Returns how
    /// many.
    pub fn retry_failed(&mut self, sweep_id: i64, version: &str) -> Result<usize> {
        let tx = self.write()?;
        let preps = tx.execute(
            "UPDATE preps SET state = 'pending', attempts_at_retry = attempts
             WHERE state = 'failed' AND solver_version = ?2 AND id IN (
                 SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1)",
            params![sweep_id, version],
        )?;
        let jobs = tx.execute(
            "UPDATE jobs SET state = 'pending', attempts_at_retry = attempts
             WHERE state = 'failed' AND solver_version = ?2
               AND point_id IN (SELECT id FROM points WHERE sweep_id = ?1)",
            params![sweep_id, version],
        )?;
        tx.commit()?;
        Ok(preps + jobs)
    }
}

/// What this store measured of the solver: mean seconds per prep and per collision (of
/// `version`, on whatever lattices its sweeps used), with how many each mean is over.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeasuredCost {
    pub prep_s: Option<f64>,
    pub preps: i64,
    pub collision_s: Option<f64>,
    pub collisions: i64,
}

impl Store {
    pub fn measured_cost(&self, version: &str) -> Result<MeasuredCost> {
        let (prep_s, preps) = self.conn.query_row(
            "SELECT AVG(wall_s), COUNT(*) FROM preps
             WHERE state = 'done' AND solver_version = ?1 AND wall_s > 0",
            [version],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )?;
        let (collision_s, collisions) = self.conn.query_row(
            "SELECT AVG(wall_s), COUNT(*) FROM results
             WHERE solver_version = ?1 AND collision_steps > 0 AND wall_s > 0",
            [version],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )?;
        Ok(MeasuredCost {
            prep_s,
            preps,
            collision_s,
            collisions,
        })
    }
}
