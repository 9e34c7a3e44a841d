//! A sweep's rounds: an adaptive sweep's next replicates of the open points whose round is
//! complete, and a refined sweep's next beta values in the columns whose points are all
//! finished.

use std::collections::HashSet;

use cellsweep_solver::Params;
use cellsweep_stats::adaptive::kinds;
use cellsweep_stats::refine::{plan_round, ColumnNeed};
use cellsweep_stats::{assess, Assessment, Axes, ColumnKey, Counts, PointEnds};
use cellsweep_store::{PointJobs, Store};

use super::Ledger;
use crate::error::RunError;
use crate::plan::plan_targets;

impl Ledger {
    /// The axes of every point of the sweep by index, as the store holds them.
    pub fn point_axes(&self, store: &Store) -> Result<Vec<Axes>, RunError> {
        Ok(store.point_axes(self.sweep_id, &|c| self.sweep.others_of_config(c))?)
    }

    /// Every point of the sweep by index, as the store holds them: the grid's, then those its
    /// refinement added.
    pub fn points(&self, store: &Store) -> Result<Vec<Params>, RunError> {
        Ok(self
            .point_axes(store)?
            .iter()
            .map(|a| self.sweep.point(a))
            .collect())
    }

    /// Every point's finished replicates by index, in point order.
    pub fn point_ends(&self, store: &Store) -> Result<Vec<PointEnds>, RunError> {
        let (mut ends, _) = PointEnds::grid(self.point_axes(store)?);
        let no_others = |_: &str| Default::default();
        for r in store.replicates(self.sweep_id, &self.version, &no_others)? {
            // (One result per job, and a job per point and replicate: never twice.)
            if let Some(point) = ends.get_mut(r.point as usize) {
                point.record(r.replicate, r.end);
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

    /// How many points stand where (open, settled, sign, exhausted, verdict) under the
    /// adaptive rule: what `status` and the live page show (None for a fixed sweep).
    pub fn standing_counts(
        &self,
        store: &Store,
    ) -> Result<Option<std::collections::BTreeMap<&'static str, usize>>, RunError> {
        Ok(self.assess(store)?.map(|all| {
            let mut by = std::collections::BTreeMap::new();
            for a in all {
                *by.entry(a.standing.as_str()).or_default() += 1;
            }
            by
        }))
    }

    /// Add the next round of every open point whose round is complete (adaptive sweeps) and
    /// the next values of every finished column whose crossing is not yet narrow enough
    /// (refined sweeps), and settle new jobs whose prep is already decided. Returns how many
    /// jobs were added.
    pub fn plan_rounds(&self, store: &mut Store) -> Result<usize, RunError> {
        if self.sweep.adaptive.is_none() && self.sweep.refine.is_none() {
            return Ok(0);
        }
        let axes = self.point_axes(store)?;
        let ends = self.point_ends(store)?;
        let mut have = store.jobs_per_point(self.sweep_id, &self.version)?;
        have.resize(axes.len(), PointJobs::default());
        let mut targets: Vec<u32> = have.iter().map(|h| h.jobs).collect();
        if let Some(rule) = self.sweep.adaptive {
            let assessed = assess(&ends, &rule, kinds(self.sweep.preps_per_point));
            for (t, a) in targets.iter_mut().zip(&assessed) {
                *t = a.next_round.map_or(*t, |n| n.max(*t));
            }
        }
        let added = self.refinement(&axes, &ends, &have, &targets);
        let more: u32 = targets
            .iter()
            .zip(&have)
            .map(|(t, h)| t - h.jobs)
            .sum::<u32>()
            + added.len() as u32 * self.sweep.initial_replicates();
        if more == 0 {
            return Ok(0);
        }
        let first = self.sweep.initial_replicates();
        let points: Vec<Params> = axes
            .iter()
            .chain(&added)
            .map(|a| self.sweep.point(a))
            .collect();
        // The sweep is registered already: the source it was read from stays as stored.
        let target = |i: usize| targets.get(i).copied().unwrap_or(first);
        store.register(&plan_targets(&self.sweep, "", &points, &target), false)?;
        self.settle_decided(store)?;
        Ok(more as usize)
    }

    /// A refined sweep's next points: in every column whose points are all finished (no job
    /// open, no adaptive round owed), the values [`cellsweep_stats::refine`] asks for.
    fn refinement(
        &self,
        axes: &[Axes],
        ends: &[PointEnds],
        have: &[PointJobs],
        targets: &[u32],
    ) -> Vec<Axes> {
        let Some(rule) = self.sweep.refine else {
            return Vec::new();
        };
        let busy: HashSet<ColumnKey> = (0..axes.len())
            .filter(|&i| have[i].open > 0 || targets[i] > have[i].jobs)
            .map(|i| axes[i].column())
            .collect();
        let counts: Vec<Counts> = ends
            .iter()
            .zip(axes)
            .filter(|(_, a)| !busy.contains(&a.column()))
            .map(|(e, _)| e.counts(u32::MAX))
            .collect();
        let grid_beta = &self.sweep.grid.beta;
        let added_to = |key: &ColumnKey| {
            axes.iter()
                .filter(|a| a.column() == *key && !grid_beta.contains(&a.beta))
                .count() as u32
        };
        let mut out = Vec::new();
        for round in plan_round(&counts, &rule, &added_to) {
            if let ColumnNeed::Add(values) = round.need {
                for beta in values {
                    let a = Axes {
                        alpha: round.alpha,
                        beta,
                        L: round.L,
                        sigma: round.sigma,
                        others: round.others.clone(),
                    };
                    // (The values lie inside a crossing's interval, itself inside the
                    // column's sampled betas, on the step lattice: always admitted.)
                    if self.sweep.refused_addition(&a).is_none() {
                        out.push(a);
                    }
                }
            }
        }
        out
    }
}
