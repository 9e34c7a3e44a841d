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
        extend_to: None,
        extend_step: None,
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
    extension(f, &sorted, rule)
}

/// `extend_to` and `extend_step` (SPEC section 6: an open column may be extended beyond the
/// grid, in a separately named sweep): above the grid's last beta, with a ladder (by default
/// the grid's last spacing) whose every value lies on the refinement's step.
fn extension(
    f: &RefineFile,
    sorted: &[f64],
    mut rule: RefineRule,
) -> Result<RefineRule, (String, String)> {
    let err = |key: &str, problem: String| (format!("refine.{key}"), problem);
    let Some(to) = f.extend_to.map(|x| x.0) else {
        if f.extend_step.is_some() {
            return Err(err("extend_step", "given without extend_to".into()));
        }
        return Ok(rule);
    };
    let (top, below) = (sorted[sorted.len() - 1], sorted[sorted.len() - 2]);
    if !(to.is_finite() && to > top) {
        return Err(err(
            "extend_to",
            format!("{to} must be a number above the grid's last beta ({top})"),
        ));
    }
    let spacing = f.extend_step.map_or(top - below, |x| x.0);
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(err(
            "extend_step",
            format!("{spacing} must be a number > 0"),
        ));
    }
    let rungs = ((to - top) / spacing).floor() as u64;
    if rungs == 0 || rungs > MAX_AXIS_POINTS as u64 {
        return Err(err(
            "extend_to",
            format!(
                "{to}: {rungs} values {spacing} apart above the grid's {top} (at least 1, at \
                 most {MAX_AXIS_POINTS})"
            ),
        ));
    }
    let on_step = |b: f64| ((b / rule.step) - (b / rule.step).round()).abs() <= 1e-6;
    // A multiple of the step, so that a rung above any value refinement added stays on it too.
    if !on_step(spacing) {
        return Err(err(
            "extend_step",
            format!(
                "{spacing} is not a multiple of the refinement's step {}",
                rule.step
            ),
        ));
    }
    if let Some(b) = (1..=rungs)
        .map(|j| top + j as f64 * spacing)
        .find(|&b| !on_step(b))
    {
        return Err(err(
            "extend_step",
            format!(
                "{spacing}: the extension's value {b} is not on the refinement's step {}",
                rule.step
            ),
        ));
    }
    rule.extend_to = Some(to);
    rule.extend_step = Some(spacing);
    Ok(rule)
}
