//! The shift from sigma = 5 to sigma = 0 in the line's section: one delta for every column
//! (with the columns' scatter about the three-number model), then each column's own delta and
//! the test of one for all.

use std::fmt::Write as _;

use cellsweep_stats::{ColumnShifts, Fit, NoFit, Shift};

use super::interval;
use crate::analysis::Analysis;

pub(super) fn shift_section(h: &mut String, an: &Analysis<'_>) {
    match (&an.shift, &an.shift_interpolated) {
        (Some(s), interpolated) => {
            let beside = interpolated.as_ref().map_or(String::new(), |i| {
                format!(
                    " (by interpolation: δ = {})",
                    interval(i.delta, i.delta_ci, 4)
                )
            });
            let _ = writeln!(
                h,
                "<p><b>The shift from σ = 5 to σ = 0</b>, measured without assuming it: the σ = 0 \
                 crossings fitted as the σ = 5 line (a = {:.3}, b = {:.1}, unshifted α) moved \
                 to smaller α by one δ for every L: <b>δ = {}</b> from {} columns at σ = 5 and \
                 {} at σ = 0{beside}, against the paper's {}.</p>",
                s.a,
                s.b,
                interval(s.delta, s.delta_ci, 4),
                s.columns_sigma5,
                s.columns_sigma0,
                s.paper_delta
            );
            scatter_note(h, &an.line_sigma5, s);
            if let Some(each) = &s.per_column {
                column_shifts_note(h, each);
            }
        }
        (None, _) => h.push_str(
            "<p><b>The shift from σ = 5 to σ = 0</b> needs crossings at both σ: not measured \
             yet.</p>\n",
        ),
    }
}

/// How far the columns lie off the σ = 5 line and off the three-number model, in units of
/// their own intervals (Birge's ratios): where well above 1, the line's straightness, not the
/// columns' precision, sets the intervals of a, b and δ.
fn scatter_note(h: &mut String, line_sigma5: &Result<Fit, NoFit>, s: &Shift) {
    let (
        Ok(Fit {
            scatter: Some(r5), ..
        }),
        Some(rd),
    ) = (line_sigma5, s.scatter)
    else {
        return;
    };
    let _ = writeln!(
        h,
        "<p>The σ = 5 columns scatter about their line {r5:.2} times as far as their 95% \
         intervals allow, and all the columns about the three-number model (a, b, δ) {rd:.2} \
         times (Birge's ratio; the intervals of a, b and δ are widened by it where it is above \
         1). {}</p>",
        if r5.max(rd) > 1.5 {
            "Well above 1 means the crossings lie off one straight line in α̃/L̃ (and one \
             shift) by more than they are uncertain: narrower columns would raise the ratio \
             rather than narrow the line or δ; only more columns, or a model that is not a \
             straight line, would."
        } else {
            "Near 1, the columns' own intervals set those of the line and δ."
        }
    );
}

/// Each column's own shift (its sigma = 0 and sigma = 5 crossings, which share their prepped
/// cells) and whether one delta fits them all.
fn column_shifts_note(h: &mut String, each: &ColumnShifts) {
    let verdict = if each.p < 0.01 {
        "one δ for every column is rejected: the shift depends on the column, and the δ above \
         is an average over the columns measured, not a constant of the model"
    } else {
        "one δ for every column is consistent with them"
    };
    let _ = writeln!(
        h,
        "<p><b>Column by column</b>, each σ = 0 crossing against the σ = 5 crossing of the same \
         L and α (the two share their prepped cells, so they differ by adhesion alone): δ_c = \
         (β*₀ − β*₅) / (a dx/dα). About their weighted mean {} the {} columns give χ² = {:.1} \
         on {} degrees of freedom (p = {}): {verdict}.</p>",
        interval(each.mean, each.mean_ci, 4),
        each.columns.len(),
        each.chi2,
        each.df,
        p_text(each.p),
    );
    h.push_str(
        "<table>\n<tr><th>L</th><th>α</th><th>β* σ = 5</th><th>β* σ = 0</th>\
         <th>δ_c [95%]</th></tr>\n",
    );
    for c in &each.columns {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td class=\"num\">{:.2}</td><td class=\"num\">{:.2}</td>\
             <td class=\"num\">{}</td></tr>",
            c.L,
            c.alpha,
            c.beta_star_sigma5,
            c.beta_star_sigma0,
            interval(c.delta, c.delta_ci, 4)
        );
    }
    h.push_str("</table>\n");
}

/// A p-value as text: scientific below 0.001.
fn p_text(p: f64) -> String {
    if p < 1e-3 {
        format!("{p:.1e}")
    } else {
        format!("{p:.3}")
    }
}
