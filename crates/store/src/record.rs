//! The one write path of results, shared by both engines and by import: a checked prep or
//! collision record (see the scheduler's ledger) finishes its prep or job, each write one
//! transaction; writing the same record again changes nothing.

use rusqlite::{params, Connection};

use crate::database::Store;
use crate::encoding::{bytes_to_f64s, f64s_to_bytes, now};
use crate::error::Result;
use crate::kinds::{outcome_name, verdict_at};
use crate::lifecycle::JobState::{Done, Failed, Pending, Running};
use cellsweep_stats::{End, PrepVerdict};

/// A finished prep, as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepRecord {
    pub verdict: PrepVerdict,
    pub verdict_time: Option<f64>,
    pub free_speed: Option<f64>,
    pub nx: usize,
    pub ny: usize,
    pub phi: Vec<f64>,
    pub p: Vec<f64>,
    /// JSON summaries of the relaxed and prepped cell.
    pub summary: String,
    pub wall_s: f64,
}

/// A finished collision, as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct ResultRecord {
    pub verdict: PrepVerdict,
    /// The collision's outcome (an [`End`] that is a collision), none where the prep's verdict
    /// decided the replicate.
    pub outcome: Option<End>,
    pub contact_time: Option<f64>,
    pub decision_time: Option<f64>,
    pub free_speed: Option<f64>,
    pub threshold_speed: Option<f64>,
    pub attachment: Option<[String; 2]>,
    pub collision_steps: u64,
    /// Why a cell broke up (outcome `breakup` only).
    pub breakup_reason: Option<String>,
    pub wall_s: f64,
    /// JSON of the classifier settings.
    pub classifier: String,
    /// JSON of the whole trajectory result.
    pub record: String,
}

impl Store {
    /// A checked collision result: a job that is not yet done becomes done with it, in one
    /// transaction; a job already done is left alone. Returns whether it was new.
    pub fn record_result(&mut self, job_id: i64, version: &str, r: &ResultRecord) -> Result<bool> {
        let tx = self.write()?;
        let t = now();
        let n = tx
            .prepare_cached(
                "UPDATE jobs SET state = ?4, finished_at = ?2, error = NULL
                 WHERE id = ?1 AND state IN (?5, ?6, ?7) AND solver_version = ?3",
            )?
            .execute(params![job_id, t, version, Done, Pending, Running, Failed])?;
        if n == 0 {
            return Ok(false);
        }
        insert_result(&tx, job_id, version, r, t)?;
        tx.commit()?;
        Ok(true)
    }

    /// A checked prep: a prep that is not yet done becomes done with its fields, in one
    /// guarded UPDATE; a prep already done is left alone. Returns whether it was new.
    pub fn record_prep(&mut self, prep_id: i64, r: &PrepRecord) -> Result<bool> {
        let n = self.conn.execute(
            "UPDATE preps SET state = ?12, error = NULL, verdict = ?2, verdict_time = ?3,
                 free_speed = ?4, nx = ?5, ny = ?6, phi = ?7, p = ?8, summary = ?9, wall_s = ?10,
                 finished_at = ?11
             WHERE id = ?1 AND state IN (?13, ?14, ?15)",
            params![
                prep_id,
                r.verdict.as_str(),
                r.verdict_time,
                r.free_speed,
                r.nx as i64,
                r.ny as i64,
                f64s_to_bytes(&r.phi),
                f64s_to_bytes(&r.p),
                r.summary,
                r.wall_s,
                now(),
                Done,
                Pending,
                Running,
                Failed
            ],
        )?;
        Ok(n == 1)
    }

    /// The stored fields of a finished prep.
    pub fn load_prep(&self, prep_id: i64) -> Result<PrepRecord> {
        Ok(self.conn.query_row(
            "SELECT verdict, verdict_time, free_speed, nx, ny, phi, p, summary, wall_s
             FROM preps WHERE id = ?1 AND state = ?2",
            params![prep_id, Done],
            |r| {
                Ok(PrepRecord {
                    verdict: verdict_at(r, 0)?,
                    verdict_time: r.get(1)?,
                    free_speed: r.get(2)?,
                    nx: r.get::<_, i64>(3)? as usize,
                    ny: r.get::<_, i64>(4)? as usize,
                    phi: bytes_to_f64s(&r.get::<_, Vec<u8>>(5)?),
                    p: bytes_to_f64s(&r.get::<_, Vec<u8>>(6)?),
                    summary: r.get(7)?,
                    wall_s: r.get(8)?,
                })
            },
        )?)
    }

    /// A prep whose verdict is not `ok` decides its pending jobs of `sweep_id` without a
    /// collision: each gets a result carrying the verdict, in one transaction. Returns how many.
    pub fn settle_jobs_of_prep(
        &mut self,
        sweep_id: i64,
        prep_id: i64,
        version: &str,
        r: &ResultRecord,
    ) -> Result<usize> {
        let tx = self.write()?;
        crate::plans::materialize_prep(&tx, sweep_id, prep_id, version)?;
        let ids: Vec<i64> = {
            let mut q = tx.prepare(
                "SELECT j.id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.prep_id = ?2 AND j.solver_version = ?3 AND j.state = ?4",
            )?;
            let rows = q.query_map(params![sweep_id, prep_id, version, Pending], |r| r.get(0))?;
            rows.collect::<rusqlite::Result<Vec<_>>>()?
        };
        let t = now();
        for &id in &ids {
            tx.prepare_cached("UPDATE jobs SET state = ?3, finished_at = ?2 WHERE id = ?1")?
                .execute(params![id, t, Done])?;
            insert_result(&tx, id, version, r, t)?;
        }
        tx.commit()?;
        Ok(ids.len())
    }
}

fn insert_result(
    tx: &Connection,
    job_id: i64,
    version: &str,
    r: &ResultRecord,
    t: f64,
) -> Result<()> {
    let (a1, a2) = match &r.attachment {
        Some([a, b]) => (Some(a.as_str()), Some(b.as_str())),
        None => (None, None),
    };
    // Cached: one statement for every result a run or a `collect` commits.
    tx.prepare_cached(
        "INSERT INTO results (job_id, solver_version, verdict, outcome, contact_time, decision_time,
             free_speed, threshold_speed, attachment_1, attachment_2, collision_steps, wall_s,
             classifier, record, finished_at, breakup_reason)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)",
    )?
    .execute(params![
            job_id,
            version,
            r.verdict.as_str(),
            outcome_name(r.outcome),
            r.contact_time,
            r.decision_time,
            r.free_speed,
            r.threshold_speed,
            a1,
            a2,
            r.collision_steps as i64,
            r.wall_s,
            r.classifier,
            r.record,
            t,
            r.breakup_reason
        ],
    )?;
    Ok(())
}
