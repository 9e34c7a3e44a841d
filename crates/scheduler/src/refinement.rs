//! A sweep file's `[refine]` table read into its rule (SPEC section 6, "Refinement").
//!
//! Which points a refined sweep may then hold is [`crate::Sweep::points_with`]; where the
//! values go is decided by [`cellsweep_stats::refine`]; when, by the ledger's rounds.

use cellsweep_stats::RefineRule;

use crate::limits::MAX_AXIS_POINTS;
use crate::sweep_file::{RefineFile, Whole};

/// The finest step of a refinement: added values are written with 9 decimals.
pub const MIN_STEP: f64 = 1e-6;

/// `[refine]` over its defaults (`axis = "beta"`, `width = 1.0`, `step = 0.5`,
/// `max_new_per_column = 6`, `per_round = 2`), checked against the grid's `betas` values; an
/// error is the dotted key and the problem.
pub(crate) fn rule(f: &RefineFile, grid_betas: &[f64]) -> Result<RefineRule, (String, String)> {
    let betas = grid_betas.len();
    let err = |key: &str, problem: String| (format!("refine.{key}"), problem);
    if let Some(axis) = f.axis.as_deref().filter(|a| *a != "beta") {
        return Err(err(
            "axis",
            format!("{axis:?}: only beta can be refined (the axis the crossing is read along)"),
        ));
    }
    let whole = |v: Option<Whole>, key: &str, default: u32| match v.map_or(default as i64, |w| w.0)
    {
        n if n < 1 => Err(err(key, format!("{n} must be at least 1"))),
        n if n as u64 > MAX_AXIS_POINTS as u64 => {
            Err(err(key, format!("{n} is more than {MAX_AXIS_POINTS}")))
        }
        n => Ok(n as u32),
    };
    let max_new = whole(f.max_new_per_column, "max_new_per_column", 6)?;
    let rule = RefineRule {
        width: f.width.map_or(1.0, |x| x.0),
        step: f.step.map_or(0.5, |x| x.0),
        max_new_per_column: max_new,
        per_round: whole(f.per_round, "per_round", 2.min(max_new))?,
    };
    if !(rule.width.is_finite() && rule.width > 0.0) {
        return Err(err("width", format!("{} must be a number > 0", rule.width)));
    }
    if !(rule.step.is_finite() && rule.step >= MIN_STEP) {
        return Err(err(
            "step",
            format!("{} must be a number of at least {MIN_STEP}", rule.step),
        ));
    }
    if rule.per_round > rule.max_new_per_column {
        return Err(err(
            "per_round",
            format!(
                "{} is more than max_new_per_column = {}",
                rule.per_round, rule.max_new_per_column
            ),
        ));
    }
    if betas < 3 {
        return Err((
            "grid.beta".into(),
            format!("{betas} values: a column needs at least 3 to have a crossing to refine"),
        ));
    }
    // A value on the step's lattice must fit strictly between two neighbouring grid values,
    // or refinement could never add one.
    let mut sorted = grid_betas.to_vec();
    sorted.sort_by(f64::total_cmp);
    let fits = sorted.windows(2).any(|w| {
        let (first, last) = (
            (w[0] / rule.step).floor() + 1.0,
            (w[1] / rule.step).ceil() - 1.0,
        );
        first <= last && first * rule.step > w[0] && first * rule.step < w[1]
    });
    if !fits {
        return Err(err(
            "step",
            format!(
                "{}: no multiple of it lies between two of the grid's beta values, so \
                 refinement could add none",
                rule.step
            ),
        ));
    }
    Ok(rule)
}
