//! The diagrams' sections: each diagram's figures with a summary, and the checks beside them.

use std::fmt::Write as _;

use cellsweep_stats::{End, Standing};

use super::escape;
use crate::analysis::Analysis;
use crate::collection::{DiagramKey, Shown, PAPER_DIAGRAMS};
use crate::figures::{diagram_of, speed_of};

/// The sweep file that makes diagram `key` in this repository.
pub(super) fn sweep_file(key: &DiagramKey) -> String {
    format!("sweeps/adaptive/L{}-sigma{}.toml", key.L, key.sigma)
}

/// n per point and the adaptive standings of a shown diagram, in words.
pub(super) fn diagram_summary(s: &Shown<'_>) -> String {
    let (rows, collisions) = s.replicates();
    let ns: Vec<u64> = s.counts().map(|c| c.total()).collect();
    let (lo, hi) = (
        ns.iter().copied().min().unwrap_or(0),
        ns.iter().copied().max().unwrap_or(0),
    );
    let mut out = format!(
        "{} points, {rows} replicates ({collisions} collisions), {lo} to {hi} per point",
        s.points.len()
    );
    if let Some(st) = &s.results.standings {
        let count = |w: Standing| s.points.iter().filter(|&&i| st[i].standing == w).count();
        out += &format!(
            "; adaptive: {} settled on their label, {} on their sign away from the crossing, {} \
             decided by their prep, {} at the full budget, {} still open",
            count(Standing::Settled),
            count(Standing::Sign),
            count(Standing::Verdict),
            count(Standing::Exhausted),
            count(Standing::Open)
        );
    }
    // SPEC section 5: collisions in which a cell broke up are artefacts of the lattice, counted
    // and named where they are.
    let broke: Vec<String> = s
        .counts()
        .filter(|c| c.tally[End::CollisionBreakup] > 0)
        .map(|c| {
            format!(
                "{}/{} at (α {}, β {})",
                c.tally[End::CollisionBreakup],
                c.total(),
                c.alpha,
                c.beta
            )
        })
        .collect();
    if !broke.is_empty() {
        let n: u64 = s.counts().map(|c| c.tally[End::CollisionBreakup]).sum();
        out += &format!(
            "; {n} collisions broke up (a cell split during the collision, SPEC section 5): {}",
            broke.join(", ")
        );
    }
    // SPEC 4.5: box-limited points, counted and named.
    let boxed: Vec<String> = s
        .counts()
        .filter(|c| c.box_limited)
        .map(|c| format!("(α {}, β {})", c.alpha, c.beta))
        .collect();
    if !boxed.is_empty() {
        out += &format!(
            "; {} box-limited points (a prepped cell longer than 0.65 of its box: the outcome \
             depends on the pair lattice, SPEC 4.5): {}",
            boxed.len(),
            boxed.join(", ")
        );
    }
    let shed: u64 = s.counts().map(|c| c.sheddings).sum();
    if shed > 0 {
        out += &format!(
            "; {shed} drops shed in its collisions (second pieces under 5% of a cell or \
             passing: counted, not a breakup, SPEC 5)"
        );
    }
    out
}

pub(super) fn diagrams_section(h: &mut String, an: &Analysis<'_>) {
    h.push_str(
        "<h2 id=\"diagrams\">The six diagrams</h2>\n<p>Panels as in the paper: (a) the label of \
         each point by SPEC section 6 (dominant at 55%, coexistence, or the prep's verdict), \
         (b)–(d) the frequencies of training, walk-past and reversal. The number beside each \
         mark is its n (a + marks an adaptive point still taking rounds); hovering a point \
         shows its counts and intervals. Dashed: the paper's line (black) and the line fitted \
         over every spacing at that σ (orange).</p>\n",
    );
    for key in PAPER_DIAGRAMS {
        let fig_name = key.paper_figure().unwrap_or("");
        let _ = writeln!(
            h,
            "<h3 id=\"L{}-sigma{}\">{} (paper {fig_name})</h3>",
            key.L,
            key.sigma,
            escape(&key.title())
        );
        let Some(s) = an.collection.diagram(key.L, key.sigma) else {
            let _ = writeln!(
                h,
                "<p>Not run yet: <code>cellsweep run {}</code>.</p>",
                sweep_file(&key)
            );
            continue;
        };
        let fit = if key.sigma == 5.0 {
            an.line_sigma5.as_ref().ok()
        } else {
            an.line_sigma0.as_ref().ok()
        };
        let svg = diagram_of(s.results, &key, fit).to_svg();
        let _ = writeln!(
            h,
            "<figure>{svg}<figcaption>{} (sweep {})</figcaption></figure>",
            escape(&diagram_summary(s)),
            escape(&s.results.name)
        );
    }
    for s in an
        .collection
        .diagrams
        .iter()
        .filter(|s| !PAPER_DIAGRAMS.contains(&s.key))
    {
        let svg = diagram_of(s.results, &s.key, None).to_svg();
        let _ = writeln!(
            h,
            "<h3>{} (not one of the paper's)</h3>\n<figure>{svg}<figcaption>{} (sweep {})\
             </figcaption></figure>",
            escape(&s.key.title()),
            escape(&diagram_summary(s)),
            escape(&s.results.name)
        );
    }
}

pub(super) fn checks_section(h: &mut String, an: &Analysis<'_>) {
    h.push_str("<h2 id=\"checks\">Speed and spindle</h2>\n");
    match an.collection.speed {
        Some(r) => {
            let _ = writeln!(
                h,
                "<figure>{}<figcaption>The paper's Fig. A4: free speed of the prepped cells \
                 against β (sweep {}).</figcaption></figure>",
                speed_of(r).to_svg(),
                escape(&r.name)
            );
        }
        None => h.push_str(
            "<p>The speed figure is not run yet: <code>cellsweep run \
             sweeps/check-speed-alpha0.20.toml</code>.</p>\n",
        ),
    }
    match an.collection.spindle {
        Some(r) => {
            h.push_str("<table>\n<tr><th>one fiber: α, β, σ</th><th>n</th>");
            for e in End::ALL.into_iter().filter(|e| e.always_shown()) {
                let _ = write!(h, "<th>{}</th>", e.words());
            }
            h.push_str("</tr>\n");
            for c in &r.counts {
                let _ = write!(
                    h,
                    "<tr><td>{}, {}, {}</td><td class=\"num\">{}</td>",
                    c.alpha,
                    c.beta,
                    c.sigma,
                    c.total()
                );
                for e in End::ALL.into_iter().filter(|e| e.always_shown()) {
                    let _ = write!(h, "<td class=\"num\">{}</td>", c.tally[e]);
                }
                h.push_str("</tr>\n");
            }
            h.push_str("</table>\n");
        }
        None => h.push_str(
            "<p>The spindle check is not run yet: <code>cellsweep run \
             sweeps/check-spindle.toml</code>.</p>\n",
        ),
    }
}
