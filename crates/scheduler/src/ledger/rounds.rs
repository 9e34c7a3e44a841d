//! An adaptive sweep's rounds: where each point stands, and the next replicates of the open
//! points whose round is complete.

use cellsweep_stats::adaptive::kinds;
use cellsweep_stats::{assess, Assessment, PointEnds};
use cellsweep_store::Store;

use super::Ledger;
use crate::error::RunError;
use crate::plan::plan_targets;

impl Ledger {
    /// Every point's finished replicates by index, in grid order.
    pub fn point_ends(&self, store: &Store) -> Result<Vec<PointEnds>, RunError> {
        let (mut ends, index) = PointEnds::grid(
            self.sweep
                .points()
                .iter()
                .map(|p| (p.alpha, p.beta, p.L, p.sigma)),
        );
        for r in store.replicates(self.sweep_id, &self.version)? {
            // (One result per job, and a job per point and replicate: never twice.)
            if let Some(i) = index.of(r.alpha, r.beta, r.L, r.sigma) {
                ends[i].record(r.replicate, r.end);
            }
        }
        Ok(ends)
    }

    /// Where every point stands under the sweep's adaptive rule (None for a fixed sweep).
    pub fn assess(&self, store: &Store) -> Result<Option<Vec<Assessment>>, RunError> {
        let Some(rule) = self.sweep.adaptive else {
            return Ok(None);
        };
        let ends = self.point_ends(store)?;
        Ok(Some(assess(
            &ends,
            &rule,
            kinds(self.sweep.preps_per_point),
        )))
    }

    /// Add the next round of every open point whose round is complete (adaptive sweeps), and
    /// settle new jobs whose prep is already decided. Returns how many jobs were added.
    pub fn plan_rounds(&self, store: &mut Store) -> Result<usize, RunError> {
        let Some(assessed) = self.assess(store)? else {
            return Ok(0);
        };
        let have = store.jobs_per_point(self.sweep_id, &self.version)?;
        let targets: Vec<u32> = assessed
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let h = have.get(i).copied().unwrap_or(0);
                a.next_round.map_or(h, |n| n.max(h))
            })
            .collect();
        let added: u32 = targets
            .iter()
            .enumerate()
            .map(|(i, &t)| t - have.get(i).copied().unwrap_or(0))
            .sum();
        if added == 0 {
            return Ok(0);
        }
        // The sweep is registered already: the source it was read from stays as stored.
        let new = plan_targets(&self.sweep, "", &|i| targets[i]);
        store.register(&new, false)?;
        self.settle_decided(store)?;
        Ok(added as usize)
    }
}
