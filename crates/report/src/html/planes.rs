//! The section of diagrams on other axes: one subsection per plane a shown sweep asks for.

use std::fmt::Write as _;

use cellsweep_plot::phase::diagram_figure;

use super::escape;
use crate::analysis::Analysis;

pub(super) fn planes_section(h: &mut String, an: &Analysis<'_>) {
    if an.planes.is_empty() {
        return;
    }
    h.push_str(
        "<h2 id=\"planes\">Other planes</h2>\n<p>Diagrams on axes other than (α, β), as the \
         sweeps below ask for them (<code>[report] planes</code> in a sweep file). Each is \
         drawn from every diagram shown in this report, so a sweep's points stand beside the \
         others' where the diagram's fixed values agree; only diagrams holding a point of an \
         asking sweep are drawn. α̃/L̃ is each point's own, at its R<sub>0</sub> and d, with \
         the adhesion shift.</p>\n",
    );
    for a in &an.planes {
        let _ = write!(
            h,
            "<h3>{}</h3>\n<p class=\"small\">Asked for by {}.</p>\n",
            escape(&a.title()),
            escape(&a.asked_by.join(", "))
        );
        match &a.drawn {
            Err(why) => {
                let _ = writeln!(h, "<p>Not drawn: {}.</p>", escape(&why.to_string()));
            }
            Ok(d) if d.is_empty() => {
                h.push_str("<p>Not drawn: no point of the asking sweeps is shown.</p>\n")
            }
            Ok(drawn) => {
                for (_, d) in drawn {
                    let svg = diagram_figure(d).to_svg();
                    let _ = writeln!(
                        h,
                        "<figure>{svg}<figcaption>{}</figcaption></figure>",
                        escape(&d.title)
                    );
                }
            }
        }
    }
}
