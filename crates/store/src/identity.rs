//! What the store says a job, a prep or a sweep is: the identities the scheduler's ledger
//! checks every record against ([`JobIdentity`], [`PrepIdentity`]), the sweep's uid that
//! stamps its Slurm run directories, and how many jobs each point has.

use std::time::{SystemTime, UNIX_EPOCH};

use rusqlite::{params, OptionalExtension};

use cellsweep_stats::{Axes, Others};

use crate::database::Store;
use crate::encoding::seed_from_sql;
use crate::error::Result;
use crate::lifecycle::JobState;

/// What the store says a job is: the ledger checks every record that claims it against this.
#[derive(Debug, Clone, PartialEq)]
pub struct JobIdentity {
    pub sweep_id: i64,
    pub solver_version: String,
    pub seed: u64,
    pub prep_id: i64,
    pub state: JobState,
    /// JSON of the point's solver configuration.
    pub config: String,
    /// The prep's verdict, once it is done.
    pub prep_verdict: Option<cellsweep_stats::PrepVerdict>,
}

/// What the store says a prep is.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepIdentity {
    pub seed: u64,
    pub solver_version: String,
    pub state: JobState,
    /// JSON of the prep's configuration (parameters and protocol).
    pub config: String,
    /// Whether jobs of the given sweep start from it.
    pub used_by_sweep: bool,
}

impl Store {
    /// The identity of job `id`, if it exists.
    pub fn job_identity(&self, id: i64) -> Result<Option<JobIdentity>> {
        // Cached statements: `collect` asks this for every record it takes in.
        Ok(self
            .conn
            .prepare_cached(
                "SELECT p.sweep_id, j.solver_version, j.seed, j.prep_id, j.state, p.params,
                        CASE WHEN pr.state = ?2 THEN pr.verdict END
                 FROM jobs j JOIN points p ON p.id = j.point_id JOIN preps pr ON pr.id = j.prep_id
                 WHERE j.id = ?1",
            )?
            .query_row(params![id, JobState::Done], |r| {
                Ok(JobIdentity {
                    sweep_id: r.get(0)?,
                    solver_version: r.get(1)?,
                    seed: seed_from_sql(r.get(2)?),
                    prep_id: r.get(3)?,
                    state: r.get(4)?,
                    config: r.get(5)?,
                    prep_verdict: crate::kinds::maybe_verdict_at(r, 6)?,
                })
            })
            .optional()?)
    }

    /// The identity of prep `id` as seen from sweep `sweep_id`, if it exists.
    pub fn prep_identity(&self, id: i64, sweep_id: i64) -> Result<Option<PrepIdentity>> {
        Ok(self
            .conn
            .prepare_cached(
                "SELECT seed, solver_version, state, config, EXISTS (
                     SELECT 1 FROM jobs j JOIN points p ON p.id = j.point_id
                     WHERE j.prep_id = preps.id AND p.sweep_id = ?2)
                 FROM preps WHERE id = ?1",
            )?
            .query_row(params![id, sweep_id], |r| {
                Ok(PrepIdentity {
                    seed: seed_from_sql(r.get(0)?),
                    solver_version: r.get(1)?,
                    state: r.get(2)?,
                    config: r.get(3)?,
                    used_by_sweep: r.get(4)?,
                })
            })
            .optional()?)
    }

    /// The canonical JSON definition of a registered sweep.
    pub fn sweep_spec(&self, sweep_id: i64) -> Result<String> {
        Ok(self
            .conn
            .query_row("SELECT spec FROM sweeps WHERE id = ?1", [sweep_id], |r| {
                r.get(0)
            })?)
    }

    /// The sweep file a registered sweep was last run from, as given (None when unknown, as
    /// for an imported sweep).
    pub fn sweep_source(&self, sweep_id: i64) -> Result<Option<String>> {
        Ok(self
            .conn
            .query_row("SELECT source FROM sweeps WHERE id = ?1", [sweep_id], |r| {
                r.get(0)
            })?)
    }

    /// SQLite's count of commits by other connections (`PRAGMA data_version`): it changes
    /// exactly when someone else wrote the file since this connection last asked, so a reader
    /// that polls knows without a query over the data whether anything is new.
    pub fn data_version(&self) -> Result<i64> {
        Ok(self
            .conn
            .query_row("PRAGMA data_version", [], |r| r.get(0))?)
    }

    /// Jobs registered per point of a sweep under `version`, and how many of them are still
    /// open (pending or running), by point index.
    pub fn jobs_per_point(&self, sweep_id: i64, version: &str) -> Result<Vec<PointJobs>> {
        // Planned jobs (schema 5) are counted pending in `point_progress` but have no row yet.
        let mut q = self.conn.prepare(match self.has_progress() {
            true => {
                "SELECT p.idx, COALESCE(pp.pending + pp.running + pp.done + pp.failed, 0),
                        COALESCE(pp.pending + pp.running, 0)
                 FROM points p
                 LEFT JOIN point_progress pp ON pp.point_id = p.id AND pp.solver_version = ?2
                 WHERE p.sweep_id = ?1 ORDER BY p.idx"
            }
            false => {
                "SELECT p.idx, COUNT(j.id),
                        COUNT(CASE WHEN j.state IN ('pending', 'running') THEN 1 END)
                 FROM points p
                 LEFT JOIN jobs j ON j.point_id = p.id AND j.solver_version = ?2
                 WHERE p.sweep_id = ?1 GROUP BY p.id ORDER BY p.idx"
            }
        })?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, i64>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (idx, n, open) = row?;
            let idx = idx as usize;
            if out.len() <= idx {
                out.resize(idx + 1, PointJobs::default());
            }
            out[idx] = PointJobs {
                jobs: n as u32,
                open: open as u32,
            };
        }
        Ok(out)
    }

    /// The axes of every point of a sweep, by point index (its grid's, then those its
    /// refinement added): the paper's four as stored, and the others read by `others_of` out
    /// of the point's configuration JSON.
    pub fn point_axes(
        &self,
        sweep_id: i64,
        others_of: &dyn Fn(&str) -> Others,
    ) -> Result<Vec<Axes>> {
        let mut q = self.conn.prepare(
            "SELECT alpha, beta, L, sigma, params FROM points WHERE sweep_id = ?1 ORDER BY idx",
        )?;
        let rows = q.query_map([sweep_id], |r| {
            Ok(Axes {
                alpha: r.get(0)?,
                beta: r.get(1)?,
                L: r.get(2)?,
                sigma: r.get(3)?,
                others: others_of(&r.get::<_, String>(4)?),
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }
}

/// One point's jobs under a solver version.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PointJobs {
    /// Registered.
    pub jobs: u32,
    /// Pending or running.
    pub open: u32,
}

impl Store {
    /// The sweep's uid, a random identity that names its Slurm run directories: created on
    /// first use unless `create` is false (then `None` for a sweep that has none yet).
    pub fn sweep_uid(&mut self, sweep_id: i64, create: bool) -> Result<Option<String>> {
        let key = format!("sweep_uid:{sweep_id}");
        let found: Option<String> = self
            .conn
            .query_row("SELECT value FROM meta WHERE key = ?1", [&key], |r| {
                r.get(0)
            })
            .optional()?;
        if found.is_some() || !create {
            return Ok(found);
        }
        // Unique enough for a stamp: the time to the nanosecond, the process, the store's path.
        let nanos = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let seed = format!(
            "{nanos} {} {} {sweep_id}",
            std::process::id(),
            self.path().display()
        );
        let uid = format!(
            "{:016x}{:016x}",
            crate::digest::fnv1a(seed.as_bytes()),
            crate::digest::fnv1a(format!("{seed} second half").as_bytes())
        );
        self.conn.execute(
            "INSERT INTO meta (key, value) VALUES (?1, ?2)",
            params![key, uid],
        )?;
        Ok(Some(uid))
    }
}
