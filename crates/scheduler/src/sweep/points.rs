//! A sweep's points: its grid's, and those its refinement may add.
//!
//! An added point is an ordinary point of its sweep: its parameters are a grid column's
//! (alpha, L, sigma and every fixed parameter) with a beta between the grid's own, on the
//! refinement's step lattice, and its seeds derive from those parameters like any other
//! point's ([`crate::plan`]). So a refined sweep and a fixed sweep listing the same values run
//! the very same trajectories, whatever order the rounds came in.

use std::collections::{HashMap, HashSet};

use cellsweep_solver::Params;
use cellsweep_stats::Axes;
use cellsweep_store::{spec_change, SpecChange, Store, StoreError};

use super::Sweep;
use crate::error::{AddedPointError, RetuneError};

impl Sweep {
    /// Parameters of every grid point, ordered by the other axes (the first outermost), then
    /// L, sigma, alpha, beta.
    pub fn points(&self) -> Vec<Params> {
        let mut out = Vec::new();
        for others in self.other_values() {
            let base = self.with_others(&others);
            for &l in &self.grid.L {
                for &sigma in &self.grid.sigma {
                    for &alpha in &self.grid.alpha {
                        for &beta in &self.grid.beta {
                            out.push(Params {
                                alpha,
                                beta,
                                L: l,
                                sigma,
                                ..base.clone()
                            });
                        }
                    }
                }
            }
        }
        out
    }

    /// The parameters of the point at `axes` of this sweep (a grid point or an added one):
    /// its axes over the sweep's fixed parameters.
    pub fn point(&self, axes: &Axes) -> Params {
        Params {
            alpha: axes.alpha,
            beta: axes.beta,
            L: axes.L,
            sigma: axes.sigma,
            ..self.with_others(&axes.others)
        }
    }

    /// Most points refinement can add: every column's budget.
    pub fn max_added_points(&self) -> u64 {
        let g = &self.grid;
        let others: u64 = g.others.iter().map(|a| a.values.len() as u64).product();
        self.refine.map_or(0, |r| {
            (g.alpha.len() * g.L.len() * g.sigma.len()) as u64
                * others
                * r.max_new_per_column as u64
        })
    }

    /// Why the point at `axes`, not on the grid, cannot be a point this sweep's refinement
    /// added (None: it can be). It must lie in a column of the grid, with a beta inside the
    /// grid's range, on the step lattice, and not on the grid.
    pub fn refused_addition(&self, axes: &Axes) -> Option<String> {
        let g = &self.grid;
        let Some(rule) = self.refine else {
            return Some("the sweep has no [refine] to add it".into());
        };
        let names: Vec<&str> = g.others.iter().map(|a| a.name.as_str()).collect();
        let others_on_grid = axes.others.0.len() == g.others.len()
            && axes
                .others
                .0
                .iter()
                .zip(&g.others)
                .all(|((n, v), a)| *n == a.name && a.values.contains(v));
        if !(g.alpha.contains(&axes.alpha)
            && g.L.contains(&axes.L)
            && g.sigma.contains(&axes.sigma)
            && others_on_grid)
        {
            return Some(format!(
                "not a column of the grid{}",
                if names.is_empty() {
                    String::new()
                } else {
                    format!(" (with {})", names.join(", "))
                }
            ));
        }
        let beta = axes.beta;
        let (lo, hi) = g
            .beta
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        // An extension (SPEC section 6) reaches above the grid, up to extend_to.
        let top = rule.extend_to.map_or(hi, |to| to + 1e-9 * rule.step);
        if !(beta > lo && (beta < hi || (beta > hi && beta <= top))) {
            return Some(match rule.extend_to {
                Some(to) => {
                    format!("beta outside the grid's [{lo}, {hi}] and its extension to {to}")
                }
                None => format!("beta outside the grid's [{lo}, {hi}]"),
            });
        }
        let j = (beta / rule.step).round();
        if (beta - j * rule.step).abs() > 1e-6 * rule.step || snap(j * rule.step) != beta {
            return Some(format!("beta not on the refinement's step {}", rule.step));
        }
        if g.beta.contains(&beta) {
            return Some("a grid point".into());
        }
        None
    }

    /// Every point of the sweep that `found` names (repeats allowed): the grid's points in
    /// grid order, then the added points among `found` in their first order. An added point
    /// this sweep could not hold, or more added to one column than its budget, is an error
    /// naming the point.
    pub fn points_with(
        &self,
        found: impl IntoIterator<Item = Axes>,
    ) -> Result<Vec<Params>, AddedPointError> {
        let mut points = self.points();
        let mut seen: HashSet<_> = points.iter().map(|p| self.axes_of(p).key()).collect();
        let mut per_column: HashMap<_, u32> = Default::default();
        for axes in found {
            if !seen.insert(axes.key()) {
                continue;
            }
            if let Some(why) = self.refused_addition(&axes) {
                return Err(AddedPointError::NotOfSweep {
                    axes: axes.to_string(),
                    sweep: self.name.clone(),
                    why,
                });
            }
            let n = per_column.entry(axes.column()).or_default();
            *n += 1;
            let budget = self.refine.map_or(0, |r| r.max_new_per_column);
            if *n > budget {
                return Err(AddedPointError::OverBudget {
                    axes: axes.to_string(),
                    budget,
                });
            }
            points.push(self.point(&axes));
        }
        Ok(points)
    }
}

/// `v` without float noise beyond 9 decimals: the very number a sweep file listing it gives
/// (as `cellsweep_stats::refine` writes the values it adds).
fn snap(v: f64) -> f64 {
    format!("{v:.9}").parse().unwrap_or(v)
}

impl Sweep {
    /// The points of this definition in `store`: where the sweep of its name is stored and
    /// differs in its rules only (`replicates`, `[adaptive]`, `[refine]`), its grid's points
    /// and those earlier refinement rounds added there (so that growing `replicates` grows
    /// them too); None where there is nothing stored to hold (a new sweep, the very same
    /// definition, another sweep under the name, which registration refuses with the
    /// differences, or one without `[refine]`, whose dropping registration refuses). Refused
    /// where its `[refine]` could not have added what the rounds added (another step, a
    /// smaller budget): the store's own export would no longer import.
    pub fn stored_points(&self, store: &Store) -> Result<Option<Vec<Params>>, RetuneError> {
        let id = match store.sweep_id(&self.name) {
            Ok(id) => id,
            Err(StoreError::UnknownSweep(_)) => return Ok(None),
            Err(e) => return Err(e.into()),
        };
        let stored = store.sweep_spec(id)?;
        let rules_only = matches!(
            spec_change(&stored, &self.canonical_json()),
            SpecChange::Retuned | SpecChange::Grows { .. } | SpecChange::Shrinks { .. }
        );
        if !rules_only || self.refine.is_none() {
            return Ok(None);
        }
        let axes = store.point_axes(id, &|c| self.others_of_config(c))?;
        self.points_with(axes)
            .map(Some)
            .map_err(|why| RetuneError::Refused {
                name: self.name.clone(),
                why,
                stored: stored_refine(&stored),
            })
    }
}

/// The `[refine]` rule of a stored canonical definition, as `step 0.125, max_new_per_column 16`.
fn stored_refine(spec: &str) -> String {
    let v: serde_json::Value = serde_json::from_str(spec).unwrap_or_default();
    let r = &v["refine"];
    match (r["step"].as_f64(), r["max_new_per_column"].as_u64()) {
        (Some(step), Some(n)) => format!("step {step}, max_new_per_column {n}"),
        _ => "none".into(),
    }
}
