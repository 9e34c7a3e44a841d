//! Jobs planned, not yet written (schema 5, [`crate::schema::PLANS`]): registration keeps a
//! row of `jobs` only for each point's first replicates, one per prep, and the seeds of the
//! rest in the point's plan; [`Store::materialize_next`] and the writes that need a prep's
//! jobs turn a point's planned tail into pending rows, all of it at once. A planned job is
//! `pending` in every count from registration on.

use rusqlite::{params, Connection, OptionalExtension};

use crate::database::Store;
use crate::encoding::seed_to_sql;
use crate::error::{Result, StoreError};

/// One replicate of a point to register: its index, its seed and which of the point's preps it
/// starts from (an index into `NewSweep::preps`).
#[derive(Debug, Clone, Copy)]
pub struct NewJob {
    pub replicate: u32,
    pub seed: u64,
    /// Index into [`NewSweep::preps`].
    pub prep: usize,
}

/// A point's plan under one solver version.
struct Plan {
    id: i64,
    planned: u32,
    materialized: u32,
    /// Replicate r starts from the prep of replicate r mod `cycle`.
    cycle: u32,
    /// Seeds of replicates `materialized..planned`, 8 bytes each, little-endian.
    seeds: Vec<u8>,
}

fn plan_of(conn: &Connection, point_id: i64, version: &str) -> Result<Option<Plan>> {
    Ok(conn
        .prepare_cached(
            "SELECT id, planned, materialized, cycle, seeds FROM point_plans
             WHERE point_id = ?1 AND solver_version = ?2",
        )?
        .query_row(params![point_id, version], |r| {
            Ok(Plan {
                id: r.get(0)?,
                planned: r.get(1)?,
                materialized: r.get(2)?,
                cycle: r.get(3)?,
                seeds: r.get(4)?,
            })
        })
        .optional()?)
}

/// Plan the jobs of one point (replicates `0..n` in order, replicate r from the prep of
/// replicate r mod `cycle`, as `plan_targets` gives them) that its plan does not hold yet:
/// replicates below `cycle` become rows of `jobs`, the rest seeds in the plan. `prep_ids[i]`
/// is the row id of `NewSweep::preps[i]`. Returns how many jobs are new (all pending).
pub(crate) fn plan_point_jobs(
    conn: &Connection,
    point_id: i64,
    version: &str,
    cycle: u32,
    jobs: &[NewJob],
    prep_ids: &[i64],
) -> Result<usize> {
    let cycle = cycle.max(1);
    for (r, job) in jobs.iter().enumerate() {
        let slot = &jobs[r % cycle as usize];
        if job.replicate as usize != r || job.prep != slot.prep {
            return Err(StoreError::Unplannable {
                point_id,
                why: format!(
                    "job {r} is replicate {} from prep {}, not replicate {r} from the prep of \
                     replicate {}",
                    job.replicate,
                    job.prep,
                    r % cycle as usize
                ),
            });
        }
    }
    let target = jobs.len() as u32;
    let plan = plan_of(conn, point_id, version)?;
    let (planned, materialized) = plan
        .as_ref()
        .map_or((0, 0), |p| (p.planned, p.materialized));
    if target <= planned {
        return Ok(0);
    }
    // The rows a plan keeps: one per prep slot (below `cycle`), written now.
    let rows_to = target.min(cycle).max(materialized);
    if materialized < rows_to && materialized < planned {
        // (A tail exists only beyond `cycle` rows, so this cannot happen.)
        return Err(StoreError::Unplannable {
            point_id,
            why: "its plan has a tail before one row per prep".into(),
        });
    }
    let mut insert = conn.prepare_cached(
        "INSERT OR IGNORE INTO jobs (point_id, replicate, solver_version, prep_id, seed, state)
         VALUES (?1, ?2, ?3, ?4, ?5, 'pending')",
    )?;
    for job in &jobs[materialized as usize..rows_to as usize] {
        insert.execute(params![
            point_id,
            job.replicate,
            version,
            prep_ids[job.prep],
            seed_to_sql(job.seed)
        ])?;
    }
    let mut seeds = plan.as_ref().map_or(Vec::new(), |p| p.seeds.clone());
    for job in &jobs[planned.max(rows_to) as usize..] {
        seeds.extend_from_slice(&job.seed.to_le_bytes());
    }
    match plan {
        Some(p) => conn
            .prepare_cached(
                "UPDATE point_plans SET planned = ?2, materialized = ?3, cycle = ?4, seeds = ?5
                 WHERE id = ?1",
            )?
            .execute(params![p.id, target, rows_to, cycle, seeds])?,
        None => conn
            .prepare_cached(
                "INSERT INTO point_plans (point_id, solver_version, planned, materialized, cycle,
                                          seeds)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6)",
            )?
            .execute(params![point_id, version, target, rows_to, cycle, seeds])?,
    };
    Ok((target - planned) as usize)
}

/// Write the planned tail of a point's jobs as pending rows (their counts do not change: a
/// planned job is pending already). Returns how many rows were written.
fn materialize_point(conn: &Connection, point_id: i64, version: &str) -> Result<usize> {
    let Some(plan) = plan_of(conn, point_id, version)? else {
        return Ok(0);
    };
    if plan.planned <= plan.materialized {
        return Ok(0);
    }
    let mut preps = vec![0i64; plan.cycle as usize];
    {
        let mut q = conn.prepare_cached(
            "SELECT replicate, prep_id FROM jobs
             WHERE point_id = ?1 AND solver_version = ?2 AND replicate < ?3",
        )?;
        let mut rows = q.query(params![point_id, version, plan.cycle])?;
        while let Some(r) = rows.next()? {
            let replicate: u32 = r.get(0)?;
            preps[replicate as usize] = r.get(1)?;
        }
    }
    let mut insert = conn.prepare_cached(
        "INSERT OR IGNORE INTO jobs (point_id, replicate, solver_version, prep_id, seed, state)
         VALUES (?1, ?2, ?3, ?4, ?5, 'pending')",
    )?;
    for (i, bytes) in plan.seeds.chunks_exact(8).enumerate() {
        let replicate = plan.materialized + i as u32;
        // chunks_exact(8) gives slices of 8 bytes only.
        let seed = u64::from_le_bytes(bytes.try_into().expect("8 bytes"));
        let prep = preps[(replicate % plan.cycle) as usize];
        insert.execute(params![
            point_id,
            replicate,
            version,
            prep,
            seed_to_sql(seed)
        ])?;
    }
    conn.prepare_cached(
        "UPDATE point_plans SET materialized = planned, seeds = X'' WHERE id = ?1",
    )?
    .execute([plan.id])?;
    Ok((plan.planned - plan.materialized) as usize)
}

/// Write the planned jobs of every point of sweep ?1 under ?2 whose jobs start from prep ?3
/// (each such point has a row of that prep: one per prep slot).
pub(crate) fn materialize_prep(
    conn: &Connection,
    sweep_id: i64,
    prep_id: i64,
    version: &str,
) -> Result<usize> {
    let points: Vec<i64> = conn
        .prepare_cached(
            "SELECT DISTINCT j.point_id FROM jobs j
             JOIN point_plans pl ON pl.point_id = j.point_id AND pl.solver_version = j.solver_version
             JOIN points p ON p.id = j.point_id
             WHERE j.prep_id = ?2 AND j.solver_version = ?3 AND p.sweep_id = ?1
               AND pl.planned > pl.materialized",
        )?
        .query_map(params![sweep_id, prep_id, version], |r| r.get(0))?
        .collect::<rusqlite::Result<_>>()?;
    let mut n = 0;
    for point in points {
        n += materialize_point(conn, point, version)?;
    }
    Ok(n)
}

impl Store {
    /// How many of the sweep's jobs under `version` are planned and not rows yet.
    pub fn planned_jobs(&self, sweep_id: i64, version: &str) -> Result<usize> {
        if self.schema < crate::schema::PLANS_SCHEMA {
            return Ok(0);
        }
        Ok(self.conn.query_row(
            "SELECT COALESCE(SUM(pl.planned - pl.materialized), 0)
             FROM point_plans pl INDEXED BY point_plans_open JOIN points p ON p.id = pl.point_id
             WHERE pl.planned > pl.materialized AND pl.solver_version = ?2 AND p.sweep_id = ?1",
            params![sweep_id, version],
            |r| r.get::<_, i64>(0),
        )? as usize)
    }

    /// Write the planned jobs of the sweep's next points (in point order) as pending rows,
    /// until at least `at_least` are written or none is left planned: what a run does before it
    /// dispatches them (a few points ahead), and a Slurm submission or an import for all of
    /// them. Returns how many were written; 0 when nothing is planned any more.
    pub fn materialize_next(
        &mut self,
        sweep_id: i64,
        version: &str,
        at_least: usize,
    ) -> Result<usize> {
        if self.schema < crate::schema::PLANS_SCHEMA {
            return Ok(0);
        }
        let tx = self.write()?;
        let mut n = 0;
        'points: loop {
            let points: Vec<i64> = tx
                .prepare_cached(
                    "SELECT pl.point_id FROM point_plans pl INDEXED BY point_plans_open
                     JOIN points p ON p.id = pl.point_id
                     WHERE pl.planned > pl.materialized AND pl.solver_version = ?2
                       AND p.sweep_id = ?1
                     ORDER BY pl.point_id LIMIT 64",
                )?
                .query_map(params![sweep_id, version], |r| r.get(0))?
                .collect::<rusqlite::Result<_>>()?;
            if points.is_empty() {
                break;
            }
            for point in points {
                n += materialize_point(&tx, point, version)?;
                if n >= at_least {
                    break 'points;
                }
            }
        }
        tx.commit()?;
        Ok(n)
    }
}
