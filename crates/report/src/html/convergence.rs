//! The convergence section ("Is it converged?"): each shown column's beta* against the same
//! column in variants of the numerics (a halved dt, a wider box, a finer lattice, ...), read
//! by the column model on both sides ([`cellsweep_stats::compare_columns`]; SPEC section 6,
//! docs/convergence.md).

use std::fmt::Write as _;

use cellsweep_stats::{compare_columns, Side, Verdict};

use super::escape;
use crate::analysis::Analysis;
use crate::Results;

/// "18.21 [17.60, 18.83]", or why there is no crossing.
fn side(s: &Side) -> String {
    match (s.beta_star, s.ci) {
        (Some(b), Some([lo, hi])) => format!("{b:.2} [{lo:.2}, {hi:.2}]"),
        _ => format!(
            "none ({})",
            escape(s.skipped.as_deref().unwrap_or("no crossing"))
        ),
    }
}

pub(super) fn convergence_section(h: &mut String, an: &Analysis<'_>, variants: &[Results]) {
    h.push_str(
        "<h2 id=\"converged\">Is it converged?</h2>\n<p>Each variant is a sweep that differs \
         from a shown diagram in how a trajectory is computed (its name says how: \
         <code>dt-half</code> halves the time step with t<sub>sample</sub> kept, \
         <code>wide</code> widens the pair lattice to 600, <code>k2</code> halves the lattice \
         spacing). For every column both hold: β* on each side with its 95% interval, the \
         difference variant − shown with its interval, and a verdict: <i>agrees</i> (the \
         interval holds 0), <i>moves</i> (it does not) or <i>open</i> (a side has no \
         crossing yet). <code>cellsweep converge</code> prints the same table.</p>\n",
    );
    let mut rows = String::new();
    for v in variants {
        for shown in &an.collection.diagrams {
            let base = shown.results;
            let same_diagram = v
                .counts
                .iter()
                .any(|c| base.counts.iter().any(|b| b.L == c.L && b.sigma == c.sigma));
            if !same_diagram || base.name == v.name {
                continue;
            }
            for c in compare_columns(&base.counts, &base.scales, &v.counts, &v.scales) {
                let diff = match (c.difference, c.difference_ci) {
                    (Some(d), Some([lo, hi])) => format!("{d:+.2} [{lo:+.2}, {hi:+.2}]"),
                    _ => "–".into(),
                };
                let class = match c.verdict {
                    Verdict::Agrees => "reproduced",
                    Verdict::Moves => "not",
                    Verdict::Open => "nodata",
                };
                let _ = writeln!(
                    rows,
                    "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                     <td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{} / {}\
                     </td><td><span class=\"verdict {class}\">{}</span></td></tr>",
                    escape(&v.name),
                    escape(&base.name),
                    c.L,
                    c.sigma,
                    c.alpha,
                    format_args!("{} → {}", side(&c.baseline), side(&c.variant)),
                    c.baseline.collisions,
                    c.variant.collisions,
                    format_args!("{diff} {}", c.verdict.as_str()),
                );
            }
        }
    }
    if rows.is_empty() {
        h.push_str(
            "<p>No variant is loaded: <code>cellsweep report --data data/paper --variants \
             data/convergence</code> compares the committed ones.</p>\n",
        );
        return;
    }
    let _ = write!(
        h,
        "<table>\n<tr><th>variant</th><th>shown</th><th>L</th><th>σ</th><th>α</th>\
         <th>β*: shown → variant</th><th>collisions</th><th>difference, verdict</th></tr>\n\
         {rows}</table>\n"
    );
}
