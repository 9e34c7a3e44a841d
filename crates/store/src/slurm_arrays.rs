//! What the store keeps of Slurm runs: the job arrays of a sweep, each through three steps.
//!
//! An array is written before `sbatch` runs ([`Store::begin_array`], no job id yet: a kill
//! between the two leaves a row that says so, never an array the store does not know of),
//! completed with the id sbatch gives ([`Store::array_submitted`]) or removed where sbatch
//! refused it ([`Store::forget_array`]), and marked ended once it has left the queue and its
//! tasks were examined for jobs they left without a result ([`Store::array_ended`]).

use rusqlite::params;
use serde::{Deserialize, Serialize};

use crate::database::Store;
use crate::error::Result;

/// A job array of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlurmArray {
    /// The store's row (0 for an array not recorded yet).
    pub id: i64,
    pub kind: String,
    /// Slurm's job id; `None` while the array is being submitted (or where a kill came between
    /// sbatch and the store: the array is then found again in the queue by its script).
    pub slurm_job_id: Option<String>,
    pub run_dir: String,
    /// The submission's directory (task files, sbatch scripts, logs, results); `None` for
    /// arrays recorded by a store of layout 5 or older.
    pub sub_dir: Option<String>,
    pub tasks: i64,
    pub jobs: i64,
    pub submitted_at: f64,
    /// When the array was seen to have left the queue and its tasks were examined.
    pub ended_at: Option<f64>,
}

impl SlurmArray {
    /// The id, or `(submitting)` while it has none.
    pub fn label(&self) -> String {
        self.slurm_job_id
            .clone()
            .unwrap_or_else(|| "(submitting)".to_string())
    }
}

impl Store {
    /// Record an array about to be submitted (its `id`, `slurm_job_id` and `ended_at` are
    /// ignored); returns its row.
    pub fn begin_array(&mut self, sweep_id: i64, version: &str, a: &SlurmArray) -> Result<i64> {
        self.conn.execute(
            "INSERT INTO slurm_arrays (sweep_id, solver_version, kind, slurm_job_id, run_dir,
                                       sub_dir, tasks, jobs, submitted_at)
             VALUES (?1, ?2, ?3, NULL, ?4, ?5, ?6, ?7, ?8)",
            params![
                sweep_id,
                version,
                a.kind,
                a.run_dir,
                a.sub_dir,
                a.tasks,
                a.jobs,
                a.submitted_at
            ],
        )?;
        Ok(self.conn.last_insert_rowid())
    }

    /// The array of row `id` was accepted by Slurm as job `slurm_job_id`.
    pub fn array_submitted(&mut self, id: i64, slurm_job_id: &str) -> Result<()> {
        self.conn.execute(
            "UPDATE slurm_arrays SET slurm_job_id = ?2 WHERE id = ?1",
            params![id, slurm_job_id],
        )?;
        Ok(())
    }

    /// The array of row `id` was never queued (sbatch refused it): no trace of it is kept.
    pub fn forget_array(&mut self, id: i64) -> Result<()> {
        self.conn
            .execute("DELETE FROM slurm_arrays WHERE id = ?1", params![id])?;
        Ok(())
    }

    /// The array of row `id` has left the queue and its tasks were examined.
    pub fn array_ended(&mut self, id: i64, at: f64) -> Result<()> {
        self.conn.execute(
            "UPDATE slurm_arrays SET ended_at = ?2 WHERE id = ?1 AND ended_at IS NULL",
            params![id, at],
        )?;
        Ok(())
    }

    /// The arrays of a sweep, oldest first.
    pub fn arrays_of(&self, sweep_id: i64, version: &str) -> Result<Vec<SlurmArray>> {
        let columns = if self.schema >= crate::schema::ARRAYS_SCHEMA {
            "id, kind, slurm_job_id, run_dir, sub_dir, tasks, jobs, submitted_at, ended_at"
        } else {
            "id, kind, slurm_job_id, run_dir, NULL, tasks, jobs, submitted_at, NULL"
        };
        let mut q = self.conn.prepare(&format!(
            "SELECT {columns} FROM slurm_arrays
             WHERE sweep_id = ?1 AND solver_version = ?2 ORDER BY id"
        ))?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok(SlurmArray {
                id: r.get(0)?,
                kind: r.get(1)?,
                slurm_job_id: r.get(2)?,
                run_dir: r.get(3)?,
                sub_dir: r.get(4)?,
                tasks: r.get(5)?,
                jobs: r.get(6)?,
                submitted_at: r.get(7)?,
                ended_at: r.get(8)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// The arrays of a sweep not yet seen to have ended (queued, running, or being submitted).
    pub fn open_arrays_of(&self, sweep_id: i64, version: &str) -> Result<Vec<SlurmArray>> {
        Ok(self
            .arrays_of(sweep_id, version)?
            .into_iter()
            .filter(|a| a.ended_at.is_none())
            .collect())
    }

    /// Mean wall time of the sweep's collisions that finished (seconds), if any did.
    pub fn mean_collision_wall_s(&self, sweep_id: i64, version: &str) -> Result<Option<f64>> {
        Ok(self.conn.query_row(
            "SELECT AVG(r.wall_s) FROM results r JOIN jobs j ON j.id = r.job_id
             JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND r.solver_version = ?2 AND r.wall_s > 0",
            params![sweep_id, version],
            |r| r.get(0),
        )?)
    }
}
