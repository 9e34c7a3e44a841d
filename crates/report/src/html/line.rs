//! The line's sections: the fit of beta_crit with its intervals (the shift follows it, in
//! `shift`), beta* per column, and the cost.

use std::fmt::Write as _;

use cellsweep_stats::{Column, Fit, NoFit};

use super::shift::shift_section;
use super::{escape, interval};
use crate::analysis::{Analysis, RESAMPLES};
use crate::Results;

pub(super) fn fit_row(h: &mut String, what: &str, fit: &Result<Fit, NoFit>, paper: &str) {
    match fit {
        Ok(f) => {
            let used = f.columns.iter().filter(|c| c.beta_star.is_some()).count();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                 <td class=\"num\">{:.3}</td><td class=\"num\">{used} of {}</td><td>{}</td></tr>",
                escape(what),
                interval(f.a, f.a_ci, 3),
                interval(f.b, f.b_ci, 1),
                f.r2,
                f.columns.len(),
                escape(paper)
            );
        }
        Err(no) => {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td colspan=\"5\">no line: {}</td></tr>",
                escape(what),
                escape(&no.reason)
            );
        }
    }
}

/// How the section's numbers are made, in words.
fn how_the_line_is_read() -> String {
    format!(
        "Per α column of each diagram, β* is where walk-past and training are equally \
         frequent. <b>Model</b> (primary): the fraction of walk-past among a point's walk-past \
         and training ends is fitted as a logistic curve in β over the whole column (binomial \
         maximum likelihood; every other end left out), β* is its \
         midpoint, and its 95% interval the profile likelihood's, widened by the dispersion \
         where the deviance shows lack of fit; a column gets a β* only when that interval is \
         closed inside the β it sampled. The line is fitted to the β* of every spacing by \
         least squares weighted by their intervals, its intervals from {RESAMPLES} draws of \
         every β* from its interval (widened by the columns' scatter about the line where it \
         exceeds their intervals). <b>Interpolation</b> (the paper's reading, beside): the \
         sign change of n<sub>walk</sub> − n<sub>train</sub> between grid rows, the line by \
         least squares, intervals by {RESAMPLES} bootstrap resamples over replicates; where \
         the frequencies change between two rows 4 apart, the interpolated crossing can sit up \
         to 2 from the true one without the bootstrap seeing it. α̃ = 2π R<sub>0</sub> d \
         α<sub>eff</sub> / ε<sub>0</sub>, L̃ = L / R<sub>0</sub>; at σ = 0, α<sub>eff</sub> = \
         α + 0.0134 (the paper's shift), so a line that agrees with the paper's at both σ has \
         the same a and b. The simulation behind the model's intervals is in \
         <code>docs/line.md</code>."
    )
}

pub(super) fn fit_section(h: &mut String, an: &Analysis<'_>) {
    let _ = write!(
        h,
        "<h2 id=\"fit\">The transition line β<sub>crit</sub> = a α̃/L̃ + b</h2>\n<p>{}</p>\n\
         <table>\n<tr><th></th><th>a</th><th>b</th><th>R²</th><th>columns with a crossing</th>\
         <th>paper</th></tr>\n",
        how_the_line_is_read()
    );
    for (sigma, what, fit, paper) in [
        (
            5.0,
            "σ = 5, every L: model",
            &an.line_sigma5,
            "a = 0.6, b = −12",
        ),
        (
            5.0,
            "σ = 5, every L: interpolation",
            &an.line_sigma5_interpolated,
            "a = 0.6, b = −12",
        ),
        (
            0.0,
            "σ = 0, every L (shifted α): model",
            &an.line_sigma0,
            "the same line",
        ),
        (
            0.0,
            "σ = 0, every L (shifted α): interpolation",
            &an.line_sigma0_interpolated,
            "the same line",
        ),
    ] {
        if an.collection.diagrams.iter().any(|s| s.key.sigma == sigma) {
            fit_row(h, what, fit, paper);
        } else {
            let _ = writeln!(
                h,
                "<tr><td>{what}</td><td colspan=\"5\">no diagram at this σ yet</td></tr>"
            );
        }
    }
    h.push_str("</table>\n");
    shift_section(h, an);
}

pub(super) fn star_cell(c: &Column) -> String {
    match (c.beta_star, c.beta_ci, c.skipped.as_deref()) {
        (Some(b), Some(ci), _) => interval(b, ci, 1),
        (Some(b), None, _) => format!("{b:.1}"),
        (None, _, Some(why)) => format!("<span class=\"small\">{}</span>", escape(why)),
        (None, _, None) => "–".into(),
    }
}

pub(super) fn columns_section(h: &mut String, an: &Analysis<'_>) {
    h.push_str(
        "<h2 id=\"columns\">β* per column</h2>\n<p>By the column model with its 95% \
         profile-likelihood interval (or why it gives none), by interpolation with its 95% \
         bootstrap interval (shown where at least half the resamples have a crossing), and the \
         paper's line at that α.</p>\n",
    );
    if an.per_diagram.is_empty() {
        h.push_str("<p>No diagram yet.</p>\n");
        return;
    }
    for (key, cols, _) in &an.per_diagram {
        if an.collection.shown(key).is_none() {
            continue;
        }
        let _ = write!(
            h,
            "<h3>{}</h3>\n<table>\n<tr><th>α</th>",
            escape(&key.title())
        );
        for c in cols {
            let _ = write!(h, "<th>{}</th>", c.alpha);
        }
        h.push_str("</tr>\n<tr><td>β* (model)</td>");
        for c in cols {
            let _ = write!(h, "<td class=\"num\">{}</td>", star_cell(c));
        }
        h.push_str("</tr>\n<tr><td>β* (interpolated)</td>");
        for c in cols {
            let cell = match (c.interpolated, c.interpolated_ci) {
                (Some(b), Some(ci)) => interval(b, ci, 1),
                (Some(b), None) => format!("{b:.1}"),
                (None, _) => "–".into(),
            };
            let _ = write!(h, "<td class=\"num\">{cell}</td>");
        }
        h.push_str("</tr>\n<tr><td>paper's line</td>");
        for c in cols {
            // c.x is alpha~/L~ at the column's own R0 and d.
            let b = cellsweep_stats::fit::PAPER_A * c.x + cellsweep_stats::fit::PAPER_B;
            let _ = write!(h, "<td class=\"num\">{b:.1}</td>");
        }
        h.push_str("</tr>\n</table>\n");
    }
}

/// How narrow the line's columns are, and what they cost against a fixed grid: one row per
/// shown result set (its diagrams' columns together), a total, and the paper's fixed run.
pub(super) fn cost_section(h: &mut String, an: &Analysis<'_>) {
    let mut sets: Vec<(&Results, Vec<&Column>, Vec<String>)> = Vec::new();
    for (s, (_, cols, _)) in an.collection.diagrams.iter().zip(&an.per_diagram) {
        match sets
            .iter_mut()
            .find(|(r, _, _)| std::ptr::eq(*r, s.results))
        {
            Some((_, c, titles)) => {
                c.extend(cols);
                titles.push(s.key.title());
            }
            None => sets.push((s.results, cols.iter().collect(), vec![s.key.title()])),
        }
    }
    if sets.is_empty() {
        return;
    }
    let _ = write!(
        h,
        "<h3 id=\"cost\">Precision and cost</h3>\n<p>Per result set: its columns with a model \
         crossing, how many have a 95% interval at most as wide as the sweep's refinement asks \
         (1.0 where it asks nothing; refinement also wants collided points within that width on \
         both sides of β*), and the replicates run at the grid's points (by the \
         adaptive rule) and at the β values refinement added, against a fixed run of the same \
         grid at the full budget (the paper's way: 96 replicates at each of 66 points per \
         diagram). Core-hours are the workers' recorded times, collisions and preps; a fixed \
         run's are estimated at this run's mean per replicate.</p>\n<table>\n<tr><th>diagrams</th><th>columns with a crossing</th>\
         <th>interval within the width</th><th>widest interval</th><th>fixed grid: replicates</th>\
         <th>grid (adaptive): replicates</th><th>refinement: β values, replicates</th>\
         <th>core-hours (grid + refinement)</th><th>fixed grid: core-hours, est.</th></tr>\n"
    );
    let (mut fixed, mut total, mut crossings, mut narrow) = (0u64, crate::Cost::default(), 0, 0);
    let mut fixed_hours = 0.0;
    for (r, cols, titles) in &sets {
        let width = r
            .provenance
            .as_ref()
            .and_then(|p| p.refine)
            .map_or(1.0, |rule| rule.width);
        let widths: Vec<f64> = cols
            .iter()
            .filter(|c| c.beta_star.is_some())
            .filter_map(|c| c.beta_ci.map(|ci| ci[1] - ci[0]))
            .collect();
        let fine = widths.iter().filter(|&&w| w <= width).count();
        crossings += widths.len();
        narrow += fine;
        let widest = widths
            .iter()
            .copied()
            .fold(None, |m: Option<f64>, w| Some(m.map_or(w, |m| m.max(w))))
            .map_or("–".into(), |w| format!("{w:.2}"));
        let Some(p) = &r.provenance else {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{fine} at ≤ {width}</td>\
                 <td class=\"num\">{widest}</td><td colspan=\"5\">a counts file: no costs</td></tr>",
                escape(&titles.join("; ")),
                widths.len()
            );
            continue;
        };
        let cost = p.total();
        let est = p.fixed_grid_replicates() as f64 * per_replicate_s(&cost) / 3600.0;
        fixed += p.fixed_grid_replicates();
        fixed_hours += est;
        total = total.plus(&cost);
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{fine} at ≤ {width}</td>\
             <td class=\"num\">{widest}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{}, {}</td><td class=\"num\">{}</td><td class=\"num\">{est:.1}</td></tr>",
            escape(&titles.join("; ")),
            widths.len(),
            p.fixed_grid_replicates(),
            p.grid.rows,
            p.added_points,
            p.added.rows,
            escape(&match p.added.rows {
                0 => super::provenance::core_hours(&p.grid),
                _ => format!(
                    "{} + {}",
                    super::provenance::core_hours(&p.grid),
                    super::provenance::core_hours(&p.added)
                ),
            }),
        );
    }
    let share = match fixed {
        0 => String::new(),
        f => format!(
            " ({:.0}% of the fixed grid's)",
            100.0 * total.rows as f64 / f as f64
        ),
    };
    let _ = writeln!(
        h,
        "<tr><td><b>all</b></td><td class=\"num\">{crossings}</td><td class=\"num\">{narrow} of {crossings}</td>\
         <td></td><td class=\"num\">{fixed}</td><td colspan=\"2\" class=\"num\">{} in all{}</td>\
         <td class=\"num\">{}</td><td class=\"num\">{fixed_hours:.1}</td></tr>\n</table>",
        total.rows,
        share,
        escape(&super::provenance::core_hours(&total)),
    );
}

/// Core-seconds per replicate over the rows that recorded their times (0 if none did).
fn per_replicate_s(cost: &crate::Cost) -> f64 {
    match cost.rows.saturating_sub(cost.untimed) {
        0 => 0.0,
        n => (cost.collision_s + cost.prep_s) / n as f64,
    }
}
