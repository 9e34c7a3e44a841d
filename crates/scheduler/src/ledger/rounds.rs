//! A sweep's rounds: an adaptive sweep's next replicates of the open points whose round is
//! complete, and a refined sweep's next beta values in the columns whose points are all
//! finished.

use std::collections::HashSet;

use cellsweep_solver::Params;
use cellsweep_stats::adaptive::kinds;
use cellsweep_stats::refine::{plan_round, ColumnNeed, ColumnRound};
use cellsweep_stats::{assess, Assessment, Axes, ColumnKey, Counts, PointEnds, RefineRule};
use cellsweep_store::{PointJobs, Store};

use super::Ledger;
use crate::error::RunError;
use crate::plan::plan_targets;

/// One column of a refined sweep as its next round sees it, over every finished replicate.
#[derive(Debug, Clone)]
pub struct ColumnStanding {
    pub round: ColumnRound,
    /// Some of its points have jobs open or an adaptive round owed: it gets no new values until
    /// they finish (its need is what it would be now).
    pub busy: bool,
    /// The values earlier rounds added to it.
    pub added: u32,
}

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
        let (have, targets) = self.targets(store, &ends)?;
        let added = match self.sweep.refine {
            Some(rule) => self.refinement(&self.columns(&rule, &axes, &ends, &have, &targets)),
            None => Vec::new(),
        };
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

    /// Where every column of the sweep stands under refinement rule `rule` (the sweep's own, or
    /// a sweep file's that would retune it): what `status` and `run --dry-run` show. Writes
    /// nothing.
    pub fn refine_standing(
        &self,
        store: &Store,
        rule: &RefineRule,
    ) -> Result<Vec<ColumnStanding>, RunError> {
        let axes = self.point_axes(store)?;
        let ends = self.point_ends(store)?;
        let (have, targets) = self.targets(store, &ends)?;
        Ok(self.columns(rule, &axes, &ends, &have, &targets))
    }

    /// Every point's jobs as registered, and the jobs it should have once the adaptive rule's
    /// next round of the points whose round is complete is added.
    fn targets(
        &self,
        store: &Store,
        ends: &[PointEnds],
    ) -> Result<(Vec<PointJobs>, Vec<u32>), RunError> {
        let mut have = store.jobs_per_point(self.sweep_id, &self.version)?;
        have.resize(ends.len(), PointJobs::default());
        let mut targets: Vec<u32> = have.iter().map(|h| h.jobs).collect();
        if let Some(rule) = self.sweep.adaptive {
            let assessed = assess(ends, &rule, kinds(self.sweep.preps_per_point));
            for (t, a) in targets.iter_mut().zip(&assessed) {
                *t = a.next_round.map_or(*t, |n| n.max(*t));
            }
        }
        Ok((have, targets))
    }

    /// Every column's next round under `rule`, and whether its points are all finished (no job
    /// open, no adaptive round owed).
    fn columns(
        &self,
        rule: &RefineRule,
        axes: &[Axes],
        ends: &[PointEnds],
        have: &[PointJobs],
        targets: &[u32],
    ) -> Vec<ColumnStanding> {
        let busy: HashSet<ColumnKey> = (0..axes.len())
            .filter(|&i| have[i].open > 0 || targets[i] > have[i].jobs)
            .map(|i| axes[i].column())
            .collect();
        let counts: Vec<Counts> = ends.iter().map(|e| e.counts(u32::MAX)).collect();
        let grid_beta = &self.sweep.grid.beta;
        let added_to = |key: &ColumnKey| {
            axes.iter()
                .filter(|a| a.column() == *key && !grid_beta.contains(&a.beta))
                .count() as u32
        };
        plan_round(&counts, rule, &added_to)
            .into_iter()
            .map(|round| {
                let key = round.key();
                ColumnStanding {
                    busy: busy.contains(&key),
                    added: added_to(&key),
                    round,
                }
            })
            .collect()
    }

    /// A refined sweep's next points: in every column whose points are all finished, the
    /// values [`cellsweep_stats::refine`] asks for.
    fn refinement(&self, columns: &[ColumnStanding]) -> Vec<Axes> {
        let mut out = Vec::new();
        for c in columns.iter().filter(|c| !c.busy) {
            if let ColumnNeed::Add(values) = &c.round.need {
                for &beta in values {
                    let a = Axes {
                        alpha: c.round.alpha,
                        beta,
                        L: c.round.L,
                        sigma: c.round.sigma,
                        others: c.round.others.clone(),
                    };
                    // (The values lie inside a crossing's interval, itself inside the
                    // column's sampled betas, or on an extension's ladder up to extend_to,
                    // on the step lattice: always admitted.)
                    if self.sweep.refused_addition(&a).is_none() {
                        out.push(a);
                    }
                }
            }
        }
        out
    }
}
