//! The finished replicates of a sweep, read for the statistics (`cellsweep_stats`).

use cellsweep_stats::{Others, Replicate};
use rusqlite::params;

use crate::database::Store;
use crate::encoding::seed_from_sql;
use crate::error::Result;

impl Store {
    /// Every finished replicate of a sweep under `version`, in grid and replicate order.
    /// `others_of` reads a point's other axes (its sweep's, beyond the paper's four) out of
    /// the point's configuration JSON; it is called once per point.
    pub fn replicates(
        &self,
        sweep_id: i64,
        version: &str,
        others_of: &dyn Fn(&str) -> Others,
    ) -> Result<Vec<Replicate>> {
        let mut points = self
            .conn
            .prepare("SELECT idx, params FROM points WHERE sweep_id = ?1 ORDER BY idx")?;
        let mut others: Vec<Others> = Vec::new();
        for row in points.query_map([sweep_id], |r| {
            Ok((r.get::<_, i64>(0)?, r.get::<_, String>(1)?))
        })? {
            let (idx, config) = row?;
            let idx = idx as usize;
            if others.len() <= idx {
                others.resize(idx + 1, Others::default());
            }
            others[idx] = others_of(&config);
        }
        let mut q = self.conn.prepare(
            "SELECT p.alpha, p.beta, p.L, p.sigma, j.replicate, j.seed, pr.seed,
                    r.verdict, r.outcome, r.decision_time, p.idx
             FROM results r JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
             JOIN preps pr ON pr.id = j.prep_id
             WHERE p.sweep_id = ?1 AND r.solver_version = ?2
             ORDER BY p.idx, j.replicate",
        )?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok((
                (r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?),
                (r.get::<_, i64>(5)?, r.get::<_, i64>(6)?),
                (
                    crate::kinds::verdict_at(r, 7)?,
                    crate::kinds::outcome_at(r, 8)?,
                    r.get(9)?,
                ),
                r.get::<_, i64>(10)?,
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let ((alpha, beta, l, sigma, replicate), (seed, prep_seed), (verdict, outcome, t), idx) =
                row?;
            // An `ok` result without an outcome: the schema's CHECKs admit none.
            let Some(end) = crate::kinds::end_of(verdict, outcome) else {
                continue;
            };
            out.push(Replicate {
                alpha,
                beta,
                L: l,
                sigma,
                others: others.get(idx as usize).cloned().unwrap_or_default(),
                point: idx as u32,
                replicate,
                seed: seed_from_sql(seed),
                prep_seed: seed_from_sql(prep_seed),
                end,
                decision_time: t,
            });
        }
        Ok(out)
    }

    /// The solver versions a sweep has results under, oldest first.
    pub fn result_versions(&self, sweep_id: i64) -> Result<Vec<String>> {
        let mut q = self.conn.prepare(
            "SELECT r.solver_version FROM results r JOIN jobs j ON j.id = r.job_id
             JOIN points p ON p.id = j.point_id WHERE p.sweep_id = ?1
             GROUP BY r.solver_version ORDER BY MIN(r.finished_at)",
        )?;
        let rows = q.query_map([sweep_id], |r| r.get(0))?;
        Ok(rows.collect::<rusqlite::Result<Vec<String>>>()?)
    }
}
