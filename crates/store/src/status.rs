//! Read-side queries: progress of sweeps and outcome counts per point.

use cellsweep_stats::throughput::{self, WINDOW_S};
use rusqlite::params;
use serde::{Deserialize, Serialize};

use crate::database::Store;
use crate::error::Result;
use crate::kinds::{end_of, outcome_at, verdict_at};
use crate::lifecycle::JobState::{Done, Failed};
use cellsweep_stats::{End, Tally};

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

/// The end of `n` stored results with the verdict and outcome in columns `at` and `at + 1`
/// of `r`, added to `tally`. A name that is neither is an error; the schema admits no `ok`
/// result without an outcome, which would be a broken prep, counted so.
fn add_stored(tally: &mut Tally, r: &rusqlite::Row, at: usize, n: i64) -> rusqlite::Result<()> {
    let (verdict, outcome) = (verdict_at(r, at)?, outcome_at(r, at + 1)?);
    tally.add(
        end_of(verdict, outcome).unwrap_or(End::Breakup),
        n.max(0) as u64,
    );
    Ok(())
}

/// Progress of one sweep under one solver version.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepStatus {
    pub sweep: String,
    pub solver_version: String,
    pub jobs: StateCounts,
    pub outcomes: Tally,
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
    pub outcomes: Tally,
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
        let mut pairs = self.conn.prepare(match self.has_progress() {
            true => {
                "SELECT DISTINCT s.id, s.name, pp.solver_version FROM sweeps s
                 JOIN points p ON p.sweep_id = s.id JOIN point_progress pp ON pp.point_id = p.id
                 WHERE pp.pending + pp.running + pp.done + pp.failed > 0
                 ORDER BY s.id, pp.solver_version"
            }
            false => {
                "SELECT DISTINCT s.id, s.name, j.solver_version FROM sweeps s
                 JOIN points p ON p.sweep_id = s.id JOIN jobs j ON j.point_id = p.id
                 ORDER BY s.id, j.solver_version"
            }
        })?;
        let pairs: Vec<(i64, String, String)> = pairs
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?
            .collect::<rusqlite::Result<_>>()?;
        for (sweep_id, name, version) in pairs {
            out.push(self.status_of(sweep_id, name, version)?);
        }
        Ok(out)
    }

    /// Progress of one sweep under solver `version`, or None where it has no job of that
    /// version (or is not registered).
    pub fn sweep_status(&self, name: &str, version: &str) -> Result<Option<SweepStatus>> {
        Ok(self
            .status()?
            .into_iter()
            .find(|s| s.sweep == name && s.solver_version == version))
    }

    fn status_of(&self, sweep_id: i64, name: String, version: String) -> Result<SweepStatus> {
        let jobs = self.state_counts(sweep_id, &version, None)?;
        let outcomes = self.outcome_counts(sweep_id, &version, None)?;
        let (preps_done, preps_total) = self.prep_counts(sweep_id, &version)?;
        let last = self.last_finished(sweep_id, &version)?;
        let jobs_per_s = match last {
            Some(last) => {
                throughput::jobs_per_s(&self.recent_spans(sweep_id, &version, last - WINDOW_S)?)
            }
            None => None,
        };
        let remaining = (jobs.pending + jobs.running) as f64;
        Ok(SweepStatus {
            sweep: name,
            solver_version: version,
            eta_s: throughput::eta_s(remaining, jobs_per_s),
            jobs,
            outcomes,
            preps_done,
            preps_total,
            jobs_per_s,
            last_finished: last,
        })
    }

    fn state_counts(
        &self,
        sweep_id: i64,
        version: &str,
        point: Option<i64>,
    ) -> Result<StateCounts> {
        if self.has_progress() {
            return Ok(self
                .conn
                .prepare_cached(
                    "SELECT COALESCE(SUM(pp.pending), 0), COALESCE(SUM(pp.running), 0),
                        COALESCE(SUM(pp.done), 0), COALESCE(SUM(pp.failed), 0)
                 FROM point_progress pp JOIN points p ON p.id = pp.point_id
                 WHERE p.sweep_id = ?1 AND pp.solver_version = ?2 AND (?3 IS NULL OR p.id = ?3)",
                )?
                .query_row(params![sweep_id, version, point], |r| {
                    Ok(StateCounts {
                        pending: r.get(0)?,
                        running: r.get(1)?,
                        done: r.get(2)?,
                        failed: r.get(3)?,
                    })
                })?);
        }
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

    fn outcome_counts(&self, sweep_id: i64, version: &str, point: Option<i64>) -> Result<Tally> {
        let mut q = self.conn.prepare_cached(match self.has_progress() {
            true => {
                "SELECT po.verdict, NULLIF(po.outcome, ''), SUM(po.n) FROM point_outcomes po
                 JOIN points p ON p.id = po.point_id
                 WHERE p.sweep_id = ?1 AND po.solver_version = ?2 AND (?3 IS NULL OR p.id = ?3)
                 GROUP BY po.verdict, po.outcome HAVING SUM(po.n) > 0"
            }
            false => {
                "SELECT r.verdict, r.outcome, COUNT(*) FROM results r
                 JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND r.solver_version = ?2 AND (?3 IS NULL OR p.id = ?3)
                 GROUP BY r.verdict, r.outcome"
            }
        })?;
        let mut c = Tally::default();
        let mut rows = q.query(params![sweep_id, version, point])?;
        while let Some(r) = rows.next()? {
            add_stored(&mut c, r, 0, r.get(2)?)?;
        }
        Ok(c)
    }

    /// Outcome counts of every point of a sweep under `version`, in grid order: one grouped
    /// pass over the results, one over the jobs' states and one over the preps, whatever the
    /// number of points (a query per point was quadratic at ten million jobs).
    pub fn point_counts(&self, sweep_id: i64, version: &str) -> Result<Vec<PointCounts>> {
        let mut q = self.conn.prepare(
            "SELECT id, alpha, beta, L, sigma FROM points WHERE sweep_id = ?1 ORDER BY idx",
        )?;
        let mut out: Vec<PointCounts> = q
            .query_map([sweep_id], |r| {
                Ok(PointCounts {
                    point_id: r.get(0)?,
                    alpha: r.get(1)?,
                    beta: r.get(2)?,
                    L: r.get(3)?,
                    sigma: r.get(4)?,
                    outcomes: Tally::default(),
                    jobs: StateCounts::default(),
                    free_speed: None,
                })
            })?
            .collect::<rusqlite::Result<_>>()?;
        let at: std::collections::HashMap<i64, usize> = out
            .iter()
            .enumerate()
            .map(|(i, p)| (p.point_id, i))
            .collect();
        let mut q = self.conn.prepare(match self.has_progress() {
            true => {
                "SELECT po.point_id, po.verdict, NULLIF(po.outcome, ''), po.n
                 FROM point_outcomes po JOIN points p ON p.id = po.point_id
                 WHERE p.sweep_id = ?1 AND po.solver_version = ?2 AND po.n > 0"
            }
            false => {
                "SELECT j.point_id, r.verdict, r.outcome, COUNT(*) FROM results r
                 JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND r.solver_version = ?2
                 GROUP BY j.point_id, r.verdict, r.outcome"
            }
        })?;
        let mut rows = q.query(params![sweep_id, version])?;
        while let Some(r) = rows.next()? {
            if let Some(&i) = at.get(&r.get::<_, i64>(0)?) {
                add_stored(&mut out[i].outcomes, r, 1, r.get(3)?)?;
            }
        }
        for (point, jobs) in self.point_states(sweep_id, version)? {
            if let Some(&i) = at.get(&point) {
                out[i].jobs = jobs;
            }
        }
        let k = self.preps_per_point(sweep_id)?;
        let mut q = self.conn.prepare(
            "SELECT p.id, AVG(pr.free_speed) FROM points p JOIN jobs j ON j.point_id = p.id
             JOIN preps pr ON pr.id = j.prep_id
             WHERE p.sweep_id = ?1 AND j.replicate < ?3 AND j.solver_version = ?2
               AND pr.state = ?4 GROUP BY p.id",
        )?;
        let mut rows = q.query(params![sweep_id, version, k, Done])?;
        while let Some(r) = rows.next()? {
            if let Some(&i) = at.get(&r.get::<_, i64>(0)?) {
                out[i].free_speed = r.get(1)?;
            }
        }
        Ok(out)
    }

    /// Each point's jobs by state (points without jobs left out).
    fn point_states(&self, sweep_id: i64, version: &str) -> Result<Vec<(i64, StateCounts)>> {
        let sql = match self.has_progress() {
            true => {
                "SELECT pp.point_id, pp.pending, pp.running, pp.done, pp.failed
                 FROM point_progress pp JOIN points p ON p.id = pp.point_id
                 WHERE p.sweep_id = ?1 AND pp.solver_version = ?2"
            }
            false => {
                "SELECT j.point_id, SUM(j.state = 'pending'), SUM(j.state = 'running'),
                        SUM(j.state = 'done'), SUM(j.state = 'failed')
                 FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.solver_version = ?2 GROUP BY j.point_id"
            }
        };
        let mut q = self.conn.prepare(sql)?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok((
                r.get(0)?,
                StateCounts {
                    pending: r.get(1)?,
                    running: r.get(2)?,
                    done: r.get(3)?,
                    failed: r.get(4)?,
                },
            ))
        })?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
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
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND pr.state = ?3
             GROUP BY pr.id
             UNION ALL
             SELECT 'job', j.id, p.alpha, p.beta, p.L, p.sigma, j.replicate, j.attempts,
                    COALESCE(j.error, '')
             FROM jobs j JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = ?3",
        )?;
        let rows = q.query_map(params![sweep_id, version, Failed], |r| {
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
             WHERE state = ?2 AND solver_version = ?1 AND wall_s > 0",
            params![version, Done],
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
