//! What the store keeps of Slurm runs: the job arrays submitted for a sweep.

use rusqlite::params;
use serde::{Deserialize, Serialize};

use crate::database::Store;
use crate::error::Result;

/// A submitted job array.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlurmArray {
    pub kind: String,
    pub slurm_job_id: String,
    pub run_dir: String,
    pub tasks: i64,
    pub jobs: i64,
    pub submitted_at: f64,
}

impl Store {
    /// Record a submitted array.
    pub fn record_array(&mut self, sweep_id: i64, version: &str, a: &SlurmArray) -> Result<()> {
        self.conn.execute(
            "INSERT INTO slurm_arrays (sweep_id, solver_version, kind, slurm_job_id, run_dir, tasks, jobs, submitted_at)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
            params![sweep_id, version, a.kind, a.slurm_job_id, a.run_dir, a.tasks, a.jobs, a.submitted_at],
        )?;
        Ok(())
    }

    /// The arrays submitted for a sweep, oldest first.
    pub fn arrays_of(&self, sweep_id: i64, version: &str) -> Result<Vec<SlurmArray>> {
        let mut q = self.conn.prepare(
            "SELECT kind, slurm_job_id, run_dir, tasks, jobs, submitted_at FROM slurm_arrays
             WHERE sweep_id = ?1 AND solver_version = ?2 ORDER BY id",
        )?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok(SlurmArray {
                kind: r.get(0)?,
                slurm_job_id: r.get(1)?,
                run_dir: r.get(2)?,
                tasks: r.get(3)?,
                jobs: r.get(4)?,
                submitted_at: r.get(5)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }
}
