//! The line's sections: the fit of beta_crit with its intervals and the shift, and beta* per
//! column.

use std::fmt::Write as _;

use cellsweep_stats::{Column, Fit, NoFit};

use super::escape;
use crate::analysis::{Analysis, RESAMPLES};

pub(super) fn interval(v: f64, ci: [f64; 2], digits: usize) -> String {
    if ci[0].is_finite() {
        format!("{v:.digits$} [{:.digits$}, {:.digits$}]", ci[0], ci[1])
    } else {
        format!("{v:.digits$}")
    }
}

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

pub(super) fn fit_section(h: &mut String, an: &Analysis<'_>) {
    let _ = write!(
        h,
        "<h2 id=\"fit\">The transition line β<sub>crit</sub> = a α̃/L̃ + b</h2>\n\
         <p>Per α column of each diagram, β* is where n<sub>walk</sub> − n<sub>train</sub> \
         changes sign as β rises (linear interpolation); the line is fitted to the β* of every \
         spacing by least squares, with α̃ = 2π R<sub>0</sub> d α<sub>eff</sub> / ε<sub>0</sub> \
         and L̃ = L / R<sub>0</sub>. At σ = 0, α<sub>eff</sub> = α + 0.0134 (the paper's \
         shift), so a line that agrees with the paper's at both σ has the same a and b. \
         Intervals: 95% from {RESAMPLES} bootstrap resamples over replicates, each point \
         redrawn with its own n. They cover the sampling noise only: where the frequencies jump \
         between two β rows 4 apart, the interpolated crossing can sit up to 2 from the true one \
         without the bootstrap seeing it.</p>\n<table>\n<tr><th></th><th>a</th><th>b</th><th>R²</th>\
         <th>columns with a crossing</th><th>paper</th></tr>\n"
    );
    for (sigma, what, fit, paper) in [
        (5.0, "σ = 5, every L", &an.fit5, "a = 0.6, b = −12"),
        (0.0, "σ = 0, every L (shifted α)", &an.fit0, "the same line"),
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
    match &an.shift {
        Some(s) => {
            let _ = writeln!(
                h,
                "<p><b>The shift from σ = 5 to σ = 0</b>, measured without assuming it: the σ = 0 \
                 crossings fitted as the σ = 5 line (a = {:.3}, b = {:.1}, unshifted α) moved \
                 to smaller α by one δ for every L: <b>δ = {}</b> from {} columns at σ = 5 and \
                 {} at σ = 0, against the paper's {}.</p>",
                s.a,
                s.b,
                interval(s.delta, s.delta_ci, 4),
                s.columns_sigma5,
                s.columns_sigma0,
                s.paper_delta
            );
        }
        None => h.push_str(
            "<p><b>The shift from σ = 5 to σ = 0</b> needs crossings at both σ: not measured \
             yet.</p>\n",
        ),
    }
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
        "<h2 id=\"columns\">β* per column</h2>\n<p>With 95% bootstrap intervals (shown where at \
         least half the resamples have a crossing), beside the paper's line at that α.</p>\n",
    );
    if an.per_diagram.is_empty() {
        h.push_str("<p>No diagram yet.</p>\n");
        return;
    }
    for (key, cols, _) in &an.per_diagram {
        let Some(shown) = an.collection.diagram(key.L, key.sigma) else {
            continue;
        };
        let scales = shown.results.scales;
        let _ = write!(
            h,
            "<h3>{}</h3>\n<table>\n<tr><th>α</th>",
            escape(&key.title())
        );
        for c in cols {
            let _ = write!(h, "<th>{}</th>", c.alpha);
        }
        h.push_str("</tr>\n<tr><td>β* (data)</td>");
        for c in cols {
            let _ = write!(h, "<td class=\"num\">{}</td>", star_cell(c));
        }
        h.push_str("</tr>\n<tr><td>paper's line</td>");
        for c in cols {
            let b = scales.beta_on_line(
                cellsweep_stats::fit::PAPER_A,
                cellsweep_stats::fit::PAPER_B,
                c.alpha,
                c.L,
                c.sigma,
            );
            let _ = write!(h, "<td class=\"num\">{b:.1}</td>");
        }
        h.push_str("</tr>\n</table>\n");
    }
}
