//! Refinement in parameter space (SPEC section 6, "Refinement"): where a column's beta* is not
//! yet known to the width asked, which new beta values a round adds.
//!
//! The information a point at beta carries about the crossing of a logistic column is
//! k^2 m p (1 - p) (the Fisher information of beta* at p = sigma(k (beta - beta*))): largest
//! where p = 1/2, that is at beta* itself, and falling off on either side. So a round adds the
//! values on the `step` lattice nearest to the current beta*, inside its 95% interval, that the
//! column does not hold yet: nearest first, up to `per_round` of them, and never past the
//! column's budget of `max_new` added values. The grid's own values are never removed, and a
//! value is added once.
//!
//! A column is narrow enough when its interval is at most `width` wide *and* it has collided
//! within `width` of beta* on both sides. The interval rests on the logistic curve; where all
//! the points near the crossing lie on one side of it (a steep column whose next row is 4
//! away), the curve's slope alone carries it across the gap, and the round adds values on the
//! empty side.

use serde::{Deserialize, Serialize};

use crate::axes::{ColumnKey, Others};
use crate::column_model::{fit_column, ColumnModel, NoModelCrossing};
use crate::counts::Counts;
use crate::fit::{columns, tallies, Scales};

/// One column's next round.
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)]
pub struct ColumnRound {
    pub L: u32,
    pub sigma: f64,
    pub alpha: f64,
    /// The sweep's other axes in this column.
    pub others: Others,
    /// The width of its crossing's 95% interval, where it has one.
    pub width: Option<f64>,
    pub need: ColumnNeed,
}

impl ColumnRound {
    /// The column's identity, as [`crate::Counts::column`] gives it.
    pub fn key(&self) -> ColumnKey {
        crate::axes::column_key(self.alpha, self.L, self.sigma, &self.others)
    }
}

/// A sweep's refinement rule (its `[refine]` table).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RefineRule {
    /// Stop once the 95% interval of beta* is at most this wide.
    pub width: f64,
    /// New values lie on multiples of this step.
    pub step: f64,
    /// At most this many values added to one column, over all rounds.
    pub max_new_per_column: u32,
    /// At most this many values added to one column in one round.
    pub per_round: u32,
    /// Beyond the grid (SPEC section 6: an open column, in a separately named sweep): values
    /// above the grid's last beta may be added up to this one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extend_to: Option<f64>,
    /// The spacing of the values an extension adds above a column's last one (by default the
    /// grid's last spacing, so that beta 10..50 step 4 goes on 54, 58, 62).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extend_step: Option<f64>,
}

/// What a column needs next.
#[derive(Debug, Clone, PartialEq)]
pub enum ColumnNeed {
    /// Its interval is at most `width` wide, with collided points within `width` of beta* on
    /// both sides: done.
    Narrow { width: f64 },
    /// New beta values for the next round, nearest the crossing first.
    Add(Vec<f64>),
    /// Wider than asked, but its budget of added values is spent.
    Budget { width: f64 },
    /// Wider than asked, but every value on the step lattice inside its interval is present:
    /// only more replicates (or a finer step) can narrow it.
    Lattice { width: f64 },
    /// No crossing to refine (the model's reason): refinement adds values only inside a
    /// crossing's interval, or beyond the grid in an extension.
    NoCrossing(String),
}

/// Whether a column without a crossing is open at its top, so that values above it may find
/// one: its interval reaches its last beta, or training dominates everywhere it was sampled
/// (walk-past grows with beta: its crossing lies above).
fn open_above(why: &NoModelCrossing) -> bool {
    matches!(
        why,
        NoModelCrossing::Open { side: "last", .. } | NoModelCrossing::TrainEverywhere
    )
}

impl RefineRule {
    /// The values an extension adds to a column open at its top: the next `per_round` values
    /// of the ladder above its highest beta (`extend_step` apart, at most `extend_to`, within
    /// the budget). None where the rule has no extension, the column is not open at its top,
    /// or the ladder or the budget is spent.
    fn extension(&self, why: &NoModelCrossing, present: &[f64], added: u32) -> Option<Vec<f64>> {
        let (to, spacing) = (self.extend_to?, self.extend_step?);
        if !open_above(why) || added >= self.max_new_per_column {
            return None;
        }
        let room = (self.max_new_per_column - added).min(self.per_round);
        let top = present.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let next: Vec<f64> = (1..=room)
            .map(|j| snap(top + f64::from(j) * spacing))
            .take_while(|&b| b <= to + 1e-9 * spacing)
            .collect();
        (!next.is_empty()).then_some(next)
    }

    /// The next round of one column: its model (or why it has none), the beta values it holds
    /// (the grid's and those added before), those of them with a walk-past or training end,
    /// and how many values earlier rounds added.
    pub fn need(
        &self,
        model: &Result<ColumnModel, NoModelCrossing>,
        present: &[f64],
        sampled: &[f64],
        added: u32,
    ) -> ColumnNeed {
        let m = match model {
            Ok(m) => m,
            Err(why) => {
                return match self.extension(why, present, added) {
                    Some(next) => ColumnNeed::Add(next),
                    None => ColumnNeed::NoCrossing(why.to_string()),
                }
            }
        };
        let width = m.ci[1] - m.ci[0];
        let near = |lo: f64, hi: f64| sampled.iter().any(|&b| b >= lo && b <= hi);
        let (below, above) = (
            near(m.beta_star - self.width, m.beta_star),
            near(m.beta_star, m.beta_star + self.width),
        );
        if width <= self.width && below && above {
            return ColumnNeed::Narrow { width };
        }
        if added >= self.max_new_per_column {
            return ColumnNeed::Budget { width };
        }
        let room = (self.max_new_per_column - added).min(self.per_round) as usize;
        let held = |b: f64| {
            present
                .iter()
                .any(|&p| (p - b).abs() <= 1e-9 * self.step.max(1.0))
        };
        // The lattice values strictly inside the interval, nearest beta* first.
        let (first, last) = (
            (m.ci[0] / self.step).floor() as i64 + 1,
            (m.ci[1] / self.step).ceil() as i64 - 1,
        );
        let mut candidates: Vec<f64> = (first..=last)
            .map(|j| snap(j as f64 * self.step))
            .filter(|&b| b > m.ci[0] && b < m.ci[1] && !held(b))
            .collect();
        // A column narrow enough but for a side with no collided point near beta* takes values
        // on that side only.
        if width <= self.width {
            candidates.retain(|&b| (b < m.beta_star && !below) || (b > m.beta_star && !above));
        }
        candidates.sort_by(|a, b| {
            (a - m.beta_star)
                .abs()
                .total_cmp(&(b - m.beta_star).abs())
                .then(a.total_cmp(b))
        });
        candidates.truncate(room);
        if candidates.is_empty() {
            return ColumnNeed::Lattice { width };
        }
        candidates.sort_by(f64::total_cmp);
        ColumnNeed::Add(candidates)
    }
}

/// The next round of every column of `counts` (every axis but beta); `added` says how many values
/// earlier rounds added to a column.
pub fn plan_round(
    counts: &[Counts],
    rule: &RefineRule,
    added: &dyn Fn(&ColumnKey) -> u32,
) -> Vec<ColumnRound> {
    columns(counts, &Scales::default(), &|_| 0)
        .into_iter()
        .map(|c| {
            let column: Vec<&Counts> = counts.iter().filter(|p| p.column() == c.key()).collect();
            let present: Vec<f64> = column.iter().map(|p| p.beta).collect();
            let sampled: Vec<f64> = column
                .iter()
                .filter(|p| p.n_walk() + p.n_train() > 0)
                .map(|p| p.beta)
                .collect();
            let model = fit_column(&tallies(counts, &c));
            ColumnRound {
                L: c.L,
                sigma: c.sigma,
                alpha: c.alpha,
                width: model.as_ref().ok().map(|m| m.ci[1] - m.ci[0]),
                need: rule.need(&model, &present, &sampled, added(&c.key())),
                others: c.others,
            }
        })
        .collect()
}

/// j x step without its float noise (0.1 x 3 = 0.30000000000000004 becomes 0.3), so that a
/// value added by refinement is the very number a sweep file listing it would give.
fn snap(v: f64) -> f64 {
    format!("{v:.9}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::end::End;

    fn model(star: f64, lo: f64, hi: f64) -> Result<ColumnModel, NoModelCrossing> {
        Ok(ColumnModel {
            beta_star: star,
            ci: [lo, hi],
            slope: 0.3,
            points: 8,
            deviance: 4.0,
            df: 6,
            fit_p: Some(0.7),
            dispersion: 1.0,
            cut_at: None,
        })
    }

    const RULE: RefineRule = RefineRule {
        width: 1.0,
        step: 0.5,
        max_new_per_column: 6,
        per_round: 2,
        extend_to: None,
        extend_step: None,
    };

    #[test]
    fn a_round_adds_the_values_nearest_the_crossing_inside_its_interval() {
        let grid = [10.0, 14.0, 18.0, 22.0, 26.0];
        // beta* = 17.3 in [16.2, 18.6]: 17.5 and 17.0 are nearest; 18.0 is on the grid.
        let need = RULE.need(&model(17.3, 16.2, 18.6), &grid, &grid, 0);
        assert_eq!(need, ColumnNeed::Add(vec![17.0, 17.5]));
        // With those present, the next two nearest.
        let held = [10.0, 14.0, 17.0, 17.5, 18.0, 22.0, 26.0];
        let need = RULE.need(&model(17.3, 16.4, 18.4), &held, &held, 2);
        assert_eq!(need, ColumnNeed::Add(vec![16.5]));
    }

    #[test]
    fn an_extension_climbs_the_ladder_above_a_column_open_at_its_top() {
        let rule = RefineRule {
            extend_to: Some(62.0),
            extend_step: Some(4.0),
            ..RULE
        };
        let grid = [42.0, 46.0, 50.0];
        let open: Result<ColumnModel, NoModelCrossing> = Err(NoModelCrossing::Open {
            side: "last",
            beta: 50.0,
        });
        assert_eq!(
            rule.need(&open, &grid, &grid, 0),
            ColumnNeed::Add(vec![54.0, 58.0])
        );
        // Training everywhere: its crossing lies above too.
        let train: Result<ColumnModel, NoModelCrossing> = Err(NoModelCrossing::TrainEverywhere);
        let held = [42.0, 46.0, 50.0, 54.0, 58.0];
        assert_eq!(
            rule.need(&train, &held, &held, 2),
            ColumnNeed::Add(vec![62.0])
        );
        // Not past extend_to, not past the budget, and never below the grid or without one.
        let top = [42.0, 46.0, 50.0, 54.0, 58.0, 62.0];
        assert!(matches!(
            rule.need(&open, &top, &top, 3),
            ColumnNeed::NoCrossing(_)
        ));
        assert!(matches!(
            rule.need(&open, &grid, &grid, 6),
            ColumnNeed::NoCrossing(_)
        ));
        let first: Result<ColumnModel, NoModelCrossing> = Err(NoModelCrossing::Open {
            side: "first",
            beta: 42.0,
        });
        assert!(matches!(
            rule.need(&first, &grid, &grid, 0),
            ColumnNeed::NoCrossing(_)
        ));
        assert!(matches!(
            RULE.need(&open, &grid, &grid, 0),
            ColumnNeed::NoCrossing(_)
        ));
        // A bounded crossing is refined as any other, inside its interval.
        assert_eq!(
            rule.need(&model(52.3, 51.2, 53.6), &held, &held, 2),
            ColumnNeed::Add(vec![52.0, 52.5])
        );
    }

    #[test]
    fn a_column_stops_when_narrow_out_of_budget_or_out_of_lattice() {
        let grid = [10.0, 14.0, 14.5, 15.5, 18.0];
        assert_eq!(
            RULE.need(&model(15.0, 14.6, 15.5), &grid, &grid, 0),
            ColumnNeed::Narrow { width: 15.5 - 14.6 }
        );
        assert!(matches!(
            RULE.need(&model(15.0, 13.0, 17.0), &grid, &grid, 6),
            ColumnNeed::Budget { .. }
        ));
        // Only one slot left: one value.
        assert_eq!(
            RULE.need(&model(15.0, 13.0, 17.0), &grid, &grid, 5),
            ColumnNeed::Add(vec![15.0])
        );
        let all = [14.0, 14.5, 15.0, 15.5, 16.0];
        assert!(matches!(
            RULE.need(&model(15.0, 14.2, 15.8), &all, &all, 3),
            ColumnNeed::Lattice { .. }
        ));
        let none: Result<ColumnModel, NoModelCrossing> = Err(NoModelCrossing::TrainEverywhere);
        assert!(matches!(
            RULE.need(&none, &grid, &grid, 0),
            ColumnNeed::NoCrossing(_)
        ));
    }

    #[test]
    fn a_narrow_column_with_no_collisions_near_one_side_of_its_crossing_gets_values_there() {
        // Training at 26, walk-past from 29.75: the curve's slope alone puts beta* at 29.56 in
        // [28.84, 29.69], with nothing collided within 1.0 below it.
        let held = [22.0, 26.0, 29.75, 29.875, 30.0, 34.0];
        let steep = model(29.56, 28.84, 29.69);
        let rule = RefineRule {
            step: 0.125,
            ..RULE
        };
        assert_eq!(
            rule.need(&steep, &held, &held, 2),
            ColumnNeed::Add(vec![29.375, 29.5])
        );
        // A point whose collisions all broke up says nothing: 29.5 held but not sampled.
        let held = [22.0, 26.0, 29.5, 29.75, 29.875, 30.0];
        let sampled = [22.0, 26.0, 29.75, 29.875, 30.0];
        assert_eq!(
            rule.need(&steep, &held, &sampled, 2),
            ColumnNeed::Add(vec![29.25, 29.375])
        );
        // With a collided point below, within 1.0: narrow enough.
        let held = [22.0, 26.0, 29.0, 29.75, 29.875, 30.0];
        assert!(matches!(
            rule.need(&steep, &held, &held, 3),
            ColumnNeed::Narrow { .. }
        ));
        // Wider than asked: nearest beta* first, whichever side (the rounds that narrow it
        // fill in around it).
        let wide = model(29.3, 28.2, 29.69);
        let held = [26.0, 29.5, 29.625, 30.0];
        assert_eq!(
            rule.need(&wide, &held, &held, 2),
            ColumnNeed::Add(vec![29.25, 29.375])
        );
    }

    #[test]
    fn a_round_is_planned_per_column() {
        // Walk-past rises through one half between beta = 18 and 22 at alpha = 0.1; alpha = 0.2
        // trains everywhere.
        let point = |alpha: f64, beta: f64, walk: u64| Counts {
            tally: [(End::WalkPast, walk), (End::Train, 96 - walk)]
                .into_iter()
                .collect(),
            ..Counts::none(alpha, beta, 90, 5.0)
        };
        let mut counts = Vec::new();
        for (beta, walk) in [
            (10.0, 2),
            (14.0, 10),
            (18.0, 35),
            (22.0, 62),
            (26.0, 88),
            (30.0, 95),
        ] {
            counts.push(point(0.1, beta, walk));
            counts.push(point(0.2, beta, 0));
        }
        let plan = plan_round(&counts, &RULE, &|_| 0);
        assert_eq!(plan.len(), 2);
        let ColumnNeed::Add(v) = &plan[0].need else {
            panic!("{plan:?}");
        };
        assert!(
            v.len() == 2 && v.iter().all(|b| *b > 18.0 && *b < 22.0),
            "{v:?}"
        );
        assert!(
            matches!(plan[1].need, ColumnNeed::NoCrossing(_)),
            "{plan:?}"
        );
    }

    #[test]
    fn added_values_are_the_numbers_a_sweep_file_would_list() {
        let rule = RefineRule { step: 0.1, ..RULE };
        let ColumnNeed::Add(v) = rule.need(&model(0.3, 0.05, 1.25), &[], &[], 0) else {
            panic!("a round was owed");
        };
        assert_eq!(v, vec![0.2, 0.3]);
    }
}
