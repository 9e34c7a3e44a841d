//! Where every shown number came from: per sweep, its source, solver, precision, budget and
//! cost.

use std::fmt::Write as _;

use super::escape;
use crate::analysis::Analysis;
use crate::Results;

pub(super) fn provenance_section(
    h: &mut String,
    all: &[Results],
    an: &Analysis<'_>,
    generated: &str,
) {
    let _ = write!(
        h,
        "<h2 id=\"provenance\">Provenance</h2>\n<p>Every replicate's seed derives from its \
         sweep's seed, its point and its index; the exports list each one. Core-hours are the \
         wall times recorded on the workers (collisions and preps, each prep once).</p>\n\
         <table>\n<tr><th>sweep</th><th>source</th><th>solver</th><th>seed</th>\
         <th>collisions</th><th>budget per point</th><th>replicates</th><th>collisions run</th>\
         <th>core-hours</th><th>shown</th></tr>\n"
    );
    for r in all {
        let shown = an
            .collection
            .unused
            .iter()
            .find(|(u, _)| std::ptr::eq(*u, r))
            .map_or("yes".to_string(), |(_, why)| format!("no: {why}"));
        match &r.provenance {
            Some(p) => {
                let budget = match &p.adaptive {
                    Some(a) => format!(
                        "adaptive, {} to {} in rounds of {}, error {}",
                        a.min_replicates, a.max_replicates, a.batch, a.error
                    ),
                    None => format!("{} fixed", p.replicates),
                };
                let budget = match (&p.refine, p.added_points) {
                    (Some(r), n) => format!(
                        "{budget}; refined to β* intervals {} wide on a step of {}: {n} β values added",
                        r.width, r.step
                    ),
                    (None, _) => budget,
                };
                let cost = p.total();
                let hours = core_hours(&cost);
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td><td>{}, {} τ<sub>0</sub></td>\
                     <td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td></tr>",
                    escape(&r.name),
                    escape(&p.source),
                    escape(&p.solver_versions.join(", ")),
                    p.seed,
                    escape(&p.precision),
                    p.collide_time,
                    escape(&budget),
                    cost.rows,
                    cost.collisions,
                    escape(&hours),
                    escape(&shown)
                );
            }
            None => {
                let _ = writeln!(
                    h,
                    "<tr><td>{}</td><td colspan=\"8\">a counts file: no provenance</td><td>{}</td></tr>",
                    escape(&r.name),
                    escape(&shown)
                );
            }
        }
    }
    let _ = writeln!(
        h,
        "</table>\n<p class=\"small\">Generated {} by cellsweep {}: <code>cellsweep report \
         --data DIR --out report.html</code> regenerates this page from the exports.</p>",
        escape(generated),
        env!("CARGO_PKG_VERSION")
    );
}

/// A cost's core-hours as the tables show them, with the rows that recorded no time.
pub(super) fn core_hours(cost: &crate::Cost) -> String {
    let ch = cost.core_hours();
    let ch = if ch >= 0.1 {
        format!("{ch:.2}")
    } else {
        format!("{ch:.4}")
    };
    if cost.untimed > 0 {
        format!(
            "{ch} (+ {} collisions imported without times)",
            cost.untimed
        )
    } else {
        ch
    }
}
