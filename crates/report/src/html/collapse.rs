//! The collapse section: is beta* one line in alpha~/L~ across every spacing, R0 and sigma shown?

use std::fmt::Write as _;

use super::escape;
use super::interval;
use crate::analysis::Analysis;
use crate::collapse::{collapse_of, groups};

pub(super) fn collapse_section(h: &mut String, an: &Analysis<'_>) {
    let groups = groups(&an.collapse_columns);
    let mut r0s: Vec<f64> = groups.iter().map(|g| g.R0).collect();
    r0s.sort_by(f64::total_cmp);
    r0s.dedup();
    let _ = write!(
        h,
        "<h2 id=\"collapse\">One line in α̃/L̃?</h2>\n<p>The paper's theory says β<sub>crit</sub> \
         depends on the parameters only through α̃/L̃ = 2π R<sub>0</sub><sup>2</sup> d \
         α<sub>eff</sub> / (ε<sub>0</sub> L). Below, every shown column's β* (the column \
         model's, with its 95% interval) at its own α̃/L̃, one series per (R<sub>0</sub>, L, σ), \
         {} series in all. ",
        groups.len()
    );
    match &an.collapse {
        Ok(f) => {
            let used = f.columns.iter().filter(|c| c.beta_ci.is_some()).count();
            let scatter = f.scatter.unwrap_or(1.0);
            let _ = write!(
                h,
                "The line through all {used} columns with a crossing: <b>a = {}, b = {}</b> \
                 (R² = {:.3}); they scatter about it {scatter:.2} times as far as their \
                 intervals allow (Birge's ratio: 1 is one line within the intervals; the \
                 line's intervals are widened by it). ",
                interval(f.a, f.a_ci, 3),
                interval(f.b, f.b_ci, 1),
                f.r2
            );
        }
        Err(no) => {
            let _ = write!(h, "No line yet: {}. ", escape(&no.reason));
        }
    }
    if r0s.len() < 2 {
        h.push_str(
            "Every column here has one R<sub>0</sub>: the test across cell sizes needs sweeps \
             at another R<sub>0</sub> (<code>sweeps/collapse/</code>, <code>docs/collapse.md</code>).",
        );
    }
    let svg = collapse_of(&an.collapse_columns, an.collapse.as_ref().ok()).to_svg();
    let _ = writeln!(
        h,
        "</p>\n<figure>{svg}<figcaption>β* against α̃/L̃; hover a column for its numbers.\
         </figcaption></figure>"
    );
}
