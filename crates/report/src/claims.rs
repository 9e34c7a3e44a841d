//! The paper's qualitative claims (results section, captions, discussion), each checked
//! against the data by a stated rule and given a [`Verdict`]. A claim whose diagrams have not
//! been run gets [`Verdict::NoData`], never a guess.

use cellsweep_store::{wilson, Column, Counts, Label};

use crate::analysis::Analysis;
use crate::collection::Shown;
use crate::figures::mean_and_error;

/// How a claim fares against the data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Reproduced,
    Partly,
    Not,
    /// The data it needs has not been run.
    NoData,
}

impl Verdict {
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::Not => "not reproduced",
            Verdict::NoData => "no data yet",
        }
    }
}

/// One claim of the paper and what the data say.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// Where in the paper.
    pub source: &'static str,
    /// The paper's words.
    pub quote: &'static str,
    /// The rule the verdict follows.
    pub rule: &'static str,
    /// The numbers from the data (or what is missing).
    pub evidence: String,
    pub verdict: Verdict,
}

fn collided(c: &Counts) -> u64 {
    c.n_train + c.n_walk + c.n_reversal + c.n_undetermined
}

fn pct(k: u64, n: u64) -> String {
    if n == 0 {
        return "–".into();
    }
    let w = wilson(k, n);
    format!(
        "{:.1}% [{:.1}, {:.1}]",
        100.0 * w.value,
        100.0 * w.low,
        100.0 * w.high
    )
}

/// Points of a diagram carrying `label`.
fn with_label<'s>(s: &'s Shown<'_>, label: Label) -> Vec<&'s Counts> {
    s.counts().filter(|c| c.label() == Some(label)).collect()
}

/// Outcome sums of the collided points of a diagram: (train, walk, reversal, collisions).
fn sums<'c>(points: impl Iterator<Item = &'c Counts>) -> (u64, u64, u64, u64) {
    points.filter(|c| c.collided()).fold((0, 0, 0, 0), |a, c| {
        (
            a.0 + c.n_train,
            a.1 + c.n_walk,
            a.2 + c.n_reversal,
            a.3 + collided(c),
        )
    })
}

/// Points at the same (alpha, beta) in two diagrams, both collided.
fn matched<'x>(a: &'x Shown<'_>, b: &'x Shown<'_>) -> Vec<(&'x Counts, &'x Counts)> {
    a.counts()
        .filter(|c| c.collided())
        .filter_map(|c| {
            b.counts()
                .find(|d| d.alpha == c.alpha && d.beta == c.beta && d.collided())
                .map(|d| (c, d))
        })
        .collect()
}

/// beta* of a column as an ordered value: training everywhere is above any crossing (+inf),
/// walk-past everywhere below (-inf); None where the column says nothing.
fn star_rank(c: &Column) -> Option<f64> {
    match (c.beta_star, c.skipped.as_deref()) {
        (Some(b), _) => Some(b),
        (None, Some(why)) if why.starts_with("training") => Some(f64::INFINITY),
        (None, Some(why)) if why.starts_with("walk-past") => Some(f64::NEG_INFINITY),
        _ => None,
    }
}

fn star_text(v: f64) -> String {
    if v == f64::INFINITY {
        "none (training throughout)".into()
    } else if v == f64::NEG_INFINITY {
        "none (walk-past throughout)".into()
    } else {
        format!("{v:.1}")
    }
}

/// Columns of two diagrams by alpha: (alpha, rank in a, rank in b) where both say something.
fn paired_stars(a: &[Column], b: &[Column]) -> Vec<(f64, f64, f64)> {
    a.iter()
        .filter_map(|ca| {
            let cb = b.iter().find(|cb| cb.alpha == ca.alpha)?;
            Some((ca.alpha, star_rank(ca)?, star_rank(cb)?))
        })
        .collect()
}

fn no_data(
    source: &'static str,
    quote: &'static str,
    rule: &'static str,
    missing: &str,
) -> Claim {
    Claim {
        source,
        quote,
        rule,
        evidence: format!("needs {missing}; not all of it has been run yet"),
        verdict: Verdict::NoData,
    }
}

/// Every claim, in the paper's order.
pub fn evaluate(an: &Analysis<'_>) -> Vec<Claim> {
    vec![
        spindle(an),
        outcomes(an),
        transition(an),
        unstable(an),
        breakup(an),
        spacing(an),
        few_walk_at_70(an),
        intermediate_80(an),
        reversal_without_adhesion(an),
        similar_without_adhesion(an),
        more_training_without_adhesion(an),
        shift(an),
        global_fit(an),
        speed(an),
    ]
}

fn spindle(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 2(a)",
        "If we collide cells on a single fiber (spindle cells), they almost always form a \
         train (nearly 100% probability at our default parameters).",
        "reproduced: training in at least 90% of the collisions; partly: training dominant \
         (55%); else not.",
    );
    let Some(r) = an.collection.spindle else {
        return no_data(source, quote, rule, "the one-fiber check (sweeps/check-spindle.toml)");
    };
    let (t, w, rv, n) = sums(r.counts.iter());
    let p = if n > 0 { t as f64 / n as f64 } else { 0.0 };
    let point = r
        .counts
        .first()
        .map(|c| format!(" (α = {}, β = {}, σ = {})", c.alpha, c.beta, c.sigma))
        .unwrap_or_default();
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "one fiber{point}: training in {t} of {n} collisions, {}; walk-past {w}, reversal {rv}",
            pct(t, n)
        ),
        verdict: if n == 0 {
            Verdict::NoData
        } else if p >= 0.9 {
            Verdict::Reproduced
        } else if p >= 0.55 {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

fn outcomes(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 2(b) and Fig. 3",
        "We find, depending on the parameters, multiple distinct outcomes, including training, \
         walk-past, and rarely, cell reversals.",
        "at L = 90, σ = 5: reproduced when some points are dominated by training and some by \
         walk-past, and reversals occur in under 5% of the collisions but do occur; partly when \
         one of these fails; else not.",
    );
    let Some(s) = an.collection.diagram(90, 5.0) else {
        return no_data(source, quote, rule, "the L = 90, σ = 5 diagram");
    };
    let (t, w, rv, n) = sums(s.counts());
    let (dt, dw) = (
        with_label(s, Label::Train).len(),
        with_label(s, Label::WalkPast).len(),
    );
    let rare = rv > 0 && rv * 20 < n;
    let both = dt > 0 && dw > 0;
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "{n} collisions: training {}, walk-past {}, reversal {rv} ({}); {dt} points \
             dominated by training, {dw} by walk-past",
            pct(t, n),
            pct(w, n),
            pct(rv, n)
        ),
        verdict: match (both, rare) {
            (true, true) => Verdict::Reproduced,
            (true, false) | (false, true) => Verdict::Partly,
            _ => Verdict::Not,
        },
    }
}

/// Mean of the alphas and betas of `points`.
fn centre(points: &[&Counts]) -> (f64, f64) {
    let n = points.len() as f64;
    (
        points.iter().map(|c| c.alpha).sum::<f64>() / n,
        points.iter().map(|c| c.beta).sum::<f64>() / n,
    )
}

fn transition(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 3",
        "There is a transition between primarily training outcomes (at high α and low β) and \
         primarily walk-past (high β and low α).",
        "at L = 90, σ = 5: reproduced when the training-dominated points lie at higher mean α \
         and lower mean β than the walk-past-dominated ones, and in every α column \
         n_walk − n_train changes sign at most once, from training to walk-past, as β rises; \
         partly when only the first holds.",
    );
    let Some(s) = an.collection.diagram(90, 5.0) else {
        return no_data(source, quote, rule, "the L = 90, σ = 5 diagram");
    };
    let (tr, wp) = (with_label(s, Label::Train), with_label(s, Label::WalkPast));
    if tr.is_empty() || wp.is_empty() {
        return Claim {
            source,
            quote,
            rule,
            evidence: format!(
                "{} training-dominated and {} walk-past-dominated points: no transition to place",
                tr.len(),
                wp.len()
            ),
            verdict: Verdict::Not,
        };
    }
    let (ct, cw) = (centre(&tr), centre(&wp));
    let placed = ct.0 > cw.0 && ct.1 < cw.1;
    // Sign changes per column, in beta order, over collided points.
    let mut alphas: Vec<f64> = s.counts().map(|c| c.alpha).collect();
    alphas.sort_by(|a, b| a.partial_cmp(b).expect("finite"));
    alphas.dedup();
    let mut bad = Vec::new();
    for &a in &alphas {
        let mut col: Vec<&Counts> = s.counts().filter(|c| c.alpha == a && c.collided()).collect();
        col.sort_by(|x, y| x.beta.partial_cmp(&y.beta).expect("finite"));
        let signs: Vec<i64> = col
            .iter()
            .map(|c| (c.n_walk as i64 - c.n_train as i64).signum())
            .filter(|&d| d != 0)
            .collect();
        let changes = signs.windows(2).filter(|w| w[0] != w[1]).count();
        let starts_walk = signs.first() == Some(&1) && signs.contains(&-1);
        if changes > 1 || starts_walk {
            bad.push(format!("{a}"));
        }
    }
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "training-dominated points centre at α = {:.3}, β = {:.1}; walk-past-dominated at \
             α = {:.3}, β = {:.1}; columns whose sign of n_walk − n_train changes more than \
             once: {}",
            ct.0,
            ct.1,
            cw.0,
            cw.1,
            if bad.is_empty() {
                "none".to_string()
            } else {
                format!("α = {}", bad.join(", "))
            }
        ),
        verdict: match (placed, bad.is_empty()) {
            (true, true) => Verdict::Reproduced,
            (true, false) => Verdict::Partly,
            _ => Verdict::Not,
        },
    }
}

fn point_list(points: &[&Counts]) -> String {
    points
        .iter()
        .map(|c| format!("({}, {})", c.alpha, c.beta))
        .collect::<Vec<_>>()
        .join(", ")
}

fn unstable(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 3 (blue dots)",
        "At sufficiently small α (≤ 0.14 in the range of the phase diagram) and large enough β, \
         parallel cells are themselves not stable.",
        "at L = 90, σ = 5: reproduced when unstable points occur, all at α ≤ 0.14, each above \
         (larger β than) every collided point of its column; partly when they occur but one \
         of the two fails; else not.",
    );
    let Some(s) = an.collection.diagram(90, 5.0) else {
        return no_data(source, quote, rule, "the L = 90, σ = 5 diagram");
    };
    let un = with_label(s, Label::Unstable);
    if un.is_empty() {
        return Claim {
            source,
            quote,
            rule,
            evidence: "no point's prep is unstable".into(),
            verdict: Verdict::Not,
        };
    }
    let low = un.iter().all(|c| c.alpha <= 0.14 + 1e-9);
    let above = un.iter().all(|u| {
        s.counts()
            .filter(|c| c.alpha == u.alpha && c.collided())
            .all(|c| c.beta < u.beta)
    });
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "{} unstable points (α, β): {}; all at α ≤ 0.14: {}; each above its column's \
             collisions: {}",
            un.len(),
            point_list(&un),
            if low { "yes" } else { "no" },
            if above { "yes" } else { "no" }
        ),
        verdict: if low && above {
            Verdict::Reproduced
        } else {
            Verdict::Partly
        },
    }
}

fn breakup(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 3 (cyan diamonds)",
        "With even smaller α or larger β, cell phase fields break apart.",
        "at L = 90, σ = 5: reproduced when breakups occur and each lies beyond the unstable \
         region: no unstable or collided point of its column has a larger β, and its α is at \
         most the largest unstable α; partly when they occur elsewhere; else not.",
    );
    let Some(s) = an.collection.diagram(90, 5.0) else {
        return no_data(source, quote, rule, "the L = 90, σ = 5 diagram");
    };
    let br = with_label(s, Label::Breakup);
    let un = with_label(s, Label::Unstable);
    if br.is_empty() {
        return Claim {
            source,
            quote,
            rule,
            evidence: "no point's prep breaks up in this grid".into(),
            verdict: Verdict::Not,
        };
    }
    let max_un = un.iter().map(|c| c.alpha).fold(f64::NEG_INFINITY, f64::max);
    let beyond = br.iter().all(|b| {
        b.alpha <= max_un + 1e-9
            && s.counts()
                .filter(|c| c.alpha == b.alpha && c.label() != Some(Label::Breakup))
                .all(|c| c.beta < b.beta)
    });
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "{} breakup point(s) (α, β): {}; unstable points (α, β): {}",
            br.len(),
            point_list(&br),
            point_list(&un)
        ),
        verdict: if beyond {
            Verdict::Reproduced
        } else {
            Verdict::Partly
        },
    }
}

fn spacing(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 4 and Discussion",
        "Training is far more common at smaller fiber spacing — the transition between \
         training and walk-past moves toward smaller α and larger β.",
        "L = 70 against L = 90 (σ = 5), over the points collided in both: reproduced when \
         training is more frequent at L = 70 and in every α column β* at L = 70 is at least \
         β* at L = 90 (a column with training throughout counts as above); partly when only \
         the first holds; else not.",
    );
    let (Some(a), Some(b)) = (
        an.collection.diagram(70, 5.0),
        an.collection.diagram(90, 5.0),
    ) else {
        return no_data(source, quote, rule, "the L = 70 and L = 90 diagrams at σ = 5");
    };
    let pairs = matched(a, b);
    let (t70, n70) = pairs
        .iter()
        .fold((0, 0), |s, (c, _)| (s.0 + c.n_train, s.1 + collided(c)));
    let (t90, n90) = pairs
        .iter()
        .fold((0, 0), |s, (_, d)| (s.0 + d.n_train, s.1 + collided(d)));
    let (c70, c90) = (an.columns(70, 5.0), an.columns(90, 5.0));
    let stars = paired_stars(c70.unwrap_or(&[]), c90.unwrap_or(&[]));
    let higher = stars.iter().all(|&(_, x, y)| x >= y);
    let more = t70 * n90 > t90 * n70;
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "training in {} of collisions at L = 70 against {} at L = 90 ({} points in both); \
             β* by α (L = 70 / L = 90): {}",
            pct(t70, n70),
            pct(t90, n90),
            pairs.len(),
            stars
                .iter()
                .map(|&(al, x, y)| format!("{al}: {} / {}", star_text(x), star_text(y)))
                .collect::<Vec<_>>()
                .join("; ")
        ),
        verdict: match (more, higher) {
            (true, true) => Verdict::Reproduced,
            (true, false) => Verdict::Partly,
            _ => Verdict::Not,
        },
    }
}

fn few_walk_at_70(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Fig. 4 caption",
        "Compared to the case of L = 90, more points are dominated by training and only a few \
         are dominated by walk-past.",
        "reproduced when L = 70 has more training-dominated and fewer walk-past-dominated \
         points than L = 90 (σ = 5), and at most 10% of its points are walk-past-dominated; \
         partly when only the first holds.",
    );
    let (Some(a), Some(b)) = (
        an.collection.diagram(70, 5.0),
        an.collection.diagram(90, 5.0),
    ) else {
        return no_data(source, quote, rule, "the L = 70 and L = 90 diagrams at σ = 5");
    };
    let (t70, w70) = (
        with_label(a, Label::Train).len(),
        with_label(a, Label::WalkPast).len(),
    );
    let (t90, w90) = (
        with_label(b, Label::Train).len(),
        with_label(b, Label::WalkPast).len(),
    );
    let first = t70 > t90 && w70 < w90;
    let few = w70 * 10 <= a.points.len();
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "training-dominated points: {t70} at L = 70, {t90} at L = 90; walk-past-dominated: \
             {w70} at L = 70 (of {}), {w90} at L = 90",
            a.points.len()
        ),
        verdict: match (first, few) {
            (true, true) => Verdict::Reproduced,
            (true, false) => Verdict::Partly,
            _ => Verdict::Not,
        },
    }
}

fn intermediate_80(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. A1",
        "Collision outcomes with spacing L = 80 are intermediate between L = 70 and L = 90.",
        "σ = 5: reproduced when the training frequency at L = 80 lies between those at L = 70 \
         and L = 90 and in at least 80% of the α columns β*(90) ≤ β*(80) ≤ β*(70); partly when \
         one of the two holds; else not.",
    );
    let (Some(a), Some(m), Some(b)) = (
        an.collection.diagram(70, 5.0),
        an.collection.diagram(80, 5.0),
        an.collection.diagram(90, 5.0),
    ) else {
        return no_data(source, quote, rule, "the L = 70, 80 and 90 diagrams at σ = 5");
    };
    let freq = |s: &Shown<'_>| {
        let (t, _, _, n) = sums(s.counts());
        (t, n)
    };
    let ((t70, n70), (t80, n80), (t90, n90)) = (freq(a), freq(m), freq(b));
    let f = |t: u64, n: u64| t as f64 / n.max(1) as f64;
    let (f70, f80, f90) = (f(t70, n70), f(t80, n80), f(t90, n90));
    let between = (f80 - f70) * (f80 - f90) <= 0.0;
    let c = |l| an.columns(l, 5.0).unwrap_or(&[]);
    let mut ordered = 0;
    let mut total = 0;
    let mut lines = Vec::new();
    for col in c(80) {
        let find = |l| c(l).iter().find(|x| x.alpha == col.alpha).and_then(star_rank);
        if let (Some(s70), Some(s80), Some(s90)) = (find(70), star_rank(col), find(90)) {
            total += 1;
            if s90 <= s80 && s80 <= s70 {
                ordered += 1;
            }
            lines.push(format!(
                "{}: {} / {} / {}",
                col.alpha,
                star_text(s90),
                star_text(s80),
                star_text(s70)
            ));
        }
    }
    let columns_ok = total > 0 && ordered * 5 >= total * 4;
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "training frequency: L = 70 {}, L = 80 {}, L = 90 {}; β* ordered in {ordered} of \
             {total} columns (α: L = 90 / 80 / 70): {}",
            pct(t70, n70),
            pct(t80, n80),
            pct(t90, n90),
            lines.join("; ")
        ),
        verdict: match (between, columns_ok) {
            (true, true) => Verdict::Reproduced,
            (false, false) => Verdict::Not,
            _ => Verdict::Partly,
        },
    }
}

fn reversal_without_adhesion(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Section 3.2, Fig. 5",
        "Cell reversal (classical CIL) emerges as the dominant outcome of collision with large \
         line tension parameter α and small β.",
        "at L = 90, σ = 0: reproduced when some points are reversal-dominated and all of them \
         lie at α above and β below the middle of the grid; partly when they exist elsewhere \
         too, or when none dominates but reversals are most frequent in that corner; else not.",
    );
    let Some(s) = an.collection.diagram(90, 0.0) else {
        return no_data(source, quote, rule, "the L = 90, σ = 0 diagram");
    };
    let mid = |f: fn(&Counts) -> f64| {
        let v: Vec<f64> = s.counts().map(f).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        (lo + hi) / 2.0
    };
    let (ma, mb) = (mid(|c| c.alpha), mid(|c| c.beta));
    let corner = |c: &Counts| c.alpha > ma && c.beta < mb;
    let rev = with_label(s, Label::Reversal);
    let (_, _, r_in, n_in) = sums(s.counts().filter(|c| corner(c)));
    let (_, _, r_out, n_out) = sums(s.counts().filter(|c| !corner(c)));
    let all_in = !rev.is_empty() && rev.iter().all(|c| corner(c));
    let corner_most = r_in * n_out.max(1) > r_out * n_in.max(1);
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "{} reversal-dominated point(s) (α, β): {}; reversals in {} of the collisions at \
             α > {ma:.2}, β < {mb:.0}, against {} elsewhere",
            rev.len(),
            if rev.is_empty() {
                "none".into()
            } else {
                point_list(&rev)
            },
            pct(r_in, n_in),
            pct(r_out, n_out)
        ),
        verdict: if all_in {
            Verdict::Reproduced
        } else if !rev.is_empty() || corner_most {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

fn similar_without_adhesion(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Section 3.2",
        "Outcomes are mostly similar to the results with nonzero cell-cell adhesion, but can be \
         qualitatively different in some regions of the phase diagram.",
        "at L = 90, over the points collided at both σ: reproduced when at least 70% carry the \
         same label at σ = 0 and σ = 5; partly at 50%; else not.",
    );
    let (Some(a), Some(b)) = (
        an.collection.diagram(90, 0.0),
        an.collection.diagram(90, 5.0),
    ) else {
        return no_data(source, quote, rule, "the L = 90 diagrams at σ = 0 and 5");
    };
    let pairs = matched(a, b);
    let same = pairs.iter().filter(|(c, d)| c.label() == d.label()).count();
    let n = pairs.len().max(1);
    let differ: Vec<String> = pairs
        .iter()
        .filter(|(c, d)| c.label() != d.label())
        .map(|(c, d)| {
            let l = |x: &Counts| x.label().map_or("–", Label::as_str);
            format!("({}, {}) {} → {}", c.alpha, c.beta, l(d), l(c))
        })
        .collect();
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "{same} of {} points carry the same label; differing (α, β) σ 5 → σ 0: {}",
            pairs.len(),
            if differ.is_empty() {
                "none".into()
            } else {
                differ.join("; ")
            }
        ),
        verdict: if same * 10 >= 7 * n {
            Verdict::Reproduced
        } else if same * 2 >= n {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

fn more_training_without_adhesion(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Section 3.2",
        "Decreasing cell-cell adhesion increases training and decreases walk-past.",
        "per spacing with both σ run, over the points collided at both: training more and \
         walk-past less frequent at σ = 0; reproduced when so at every such spacing, partly \
         at some, else not.",
    );
    let mut lines = Vec::new();
    let (mut yes, mut total) = (0, 0);
    for l in [90, 80, 70] {
        let (Some(a), Some(b)) = (an.collection.diagram(l, 0.0), an.collection.diagram(l, 5.0))
        else {
            continue;
        };
        let pairs = matched(a, b);
        let (t0, w0, _, n0) = sums(pairs.iter().map(|p| p.0));
        let (t5, w5, _, n5) = sums(pairs.iter().map(|p| p.1));
        total += 1;
        let ok = t0 * n5 > t5 * n0 && w0 * n5 < w5 * n0;
        if ok {
            yes += 1;
        }
        lines.push(format!(
            "L = {l}: training {} at σ 0 against {} at σ 5, walk-past {} against {}",
            pct(t0, n0),
            pct(t5, n5),
            pct(w0, n0),
            pct(w5, n5)
        ));
    }
    if total == 0 {
        return no_data(source, quote, rule, "a spacing run at both σ = 0 and σ = 5");
    }
    Claim {
        source,
        quote,
        rule,
        evidence: lines.join("; "),
        verdict: if yes == total {
            Verdict::Reproduced
        } else if yes > 0 {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

fn shift(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Section 3.3 and Appendix C",
        "The absence of cell-cell adhesion shifts the transition line leftward to smaller α by \
         an amount of 0.0134.",
        "the σ = 0 crossings fitted as the σ = 5 line moved by δ in α (bootstrap 95% \
         interval): reproduced when the interval holds 0.0134 and lies above 0; partly when \
         δ > 0 otherwise; else not.",
    );
    let Some(sh) = &an.shift else {
        return no_data(
            source,
            quote,
            rule,
            "crossings at both σ = 5 (two columns) and σ = 0 (one)",
        );
    };
    let holds = sh.delta_ci[0] <= sh.paper_delta && sh.paper_delta <= sh.delta_ci[1];
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "δ = {:.4} [{:.4}, {:.4}] from {} columns at σ = 5 and {} at σ = 0 (paper: {})",
            sh.delta,
            sh.delta_ci[0],
            sh.delta_ci[1],
            sh.columns_sigma5,
            sh.columns_sigma0,
            sh.paper_delta
        ),
        verdict: if holds && sh.delta_ci[0] > 0.0 {
            Verdict::Reproduced
        } else if sh.delta > 0.0 {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

fn global_fit(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Section 3.3, Eq. (13)",
        "β_crit = 0.6 α̃/L̃ − 12 provides a good global description of the transition between \
         walk-past and training in Fig. 3 and 4 (and also A1).",
        "the line fitted over every spacing at σ = 5 (bootstrap 95% intervals): reproduced when \
         both intervals hold the paper's values, R² ≥ 0.8 and all three spacings are in; \
         partly when one interval holds it or a spacing is missing; else not.",
    );
    let spacings: Vec<u32> = [90, 80, 70]
        .into_iter()
        .filter(|&l| an.collection.diagram(l, 5.0).is_some())
        .collect();
    let fit = match &an.fit5 {
        Ok(f) => f,
        Err(_) if spacings.is_empty() => {
            return no_data(source, quote, rule, "a diagram at σ = 5");
        }
        Err(no) => {
            return Claim {
                source,
                quote,
                rule,
                evidence: format!("no line: {}", no.reason),
                verdict: Verdict::Not,
            }
        }
    };
    let a_in = fit.a_ci[0] <= fit.paper_a && fit.paper_a <= fit.a_ci[1];
    let b_in = fit.b_ci[0] <= fit.paper_b && fit.paper_b <= fit.b_ci[1];
    let all = spacings.len() == 3;
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "a = {:.3} [{:.3}, {:.3}], b = {:.1} [{:.1}, {:.1}], R² = {:.3}, over L = {} \
             ({} columns)",
            fit.a,
            fit.a_ci[0],
            fit.a_ci[1],
            fit.b,
            fit.b_ci[0],
            fit.b_ci[1],
            fit.r2,
            spacings
                .iter()
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", "),
            fit.columns.iter().filter(|c| c.beta_star.is_some()).count()
        ),
        verdict: if a_in && b_in && fit.r2 >= 0.8 && all {
            Verdict::Reproduced
        } else if a_in || b_in {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

/// Spearman's rank correlation of (x, y) pairs (no ties expected in x).
fn spearman(xy: &[(f64, f64)]) -> f64 {
    let rank = |v: Vec<f64>| -> Vec<f64> {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&a, &b| v[a].partial_cmp(&v[b]).expect("finite"));
        let mut r = vec![0.0; v.len()];
        for (k, &i) in idx.iter().enumerate() {
            r[i] = k as f64;
        }
        r
    };
    let rx = rank(xy.iter().map(|p| p.0).collect());
    let ry = rank(xy.iter().map(|p| p.1).collect());
    let n = xy.len() as f64;
    let d2: f64 = rx.iter().zip(&ry).map(|(a, b)| (a - b).powi(2)).sum();
    1.0 - 6.0 * d2 / (n * (n * n - 1.0))
}

fn speed(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Discussion, Fig. A4",
        "In our model, cells with higher positive feedback values β also have higher cell \
         speeds (α = 0.2, L = 90; each point an average of 20 simulations, standard error \
         smaller than the marker).",
        "mean free speed per β at α = 0.2: reproduced when Spearman's rank correlation with β \
         is at least 0.9; partly when positive; else not.",
    );
    let Some(r) = an.collection.speed else {
        return no_data(source, quote, rule, "the speed check (sweeps/check-speed-alpha0.20.toml)");
    };
    let mut rows: Vec<(f64, f64, f64, usize)> = Vec::new();
    for (i, c) in r.counts.iter().enumerate() {
        let cells: Vec<f64> = r
            .prep_speeds
            .as_ref()
            .map(|s| s[i].clone())
            .unwrap_or_else(|| c.free_speed.into_iter().collect());
        if cells.is_empty() || (c.alpha - 0.2).abs() > 1e-9 {
            continue;
        }
        let (m, se) = mean_and_error(&cells);
        rows.push((c.beta, m, se, cells.len()));
    }
    rows.sort_by(|a, b| a.0.partial_cmp(&b.0).expect("finite"));
    if rows.len() < 3 {
        return Claim {
            source,
            quote,
            rule,
            evidence: format!("{} β values with a speed at α = 0.2; three are needed", rows.len()),
            verdict: Verdict::NoData,
        };
    }
    let rho = spearman(&rows.iter().map(|r| (r.0, r.1)).collect::<Vec<_>>());
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    let max_se = rows.iter().map(|r| r.2).fold(0.0, f64::max);
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "speed {:.4} ± {:.4} at β = {} rising to {:.4} ± {:.4} at β = {} (mean ± standard \
             error over {} to {} cells); Spearman ρ = {rho:.2}; largest standard error {:.4}",
            first.1,
            first.2,
            first.0,
            last.1,
            last.2,
            last.0,
            rows.iter().map(|r| r.3).min().unwrap_or(0),
            rows.iter().map(|r| r.3).max().unwrap_or(0),
            max_se
        ),
        verdict: if rho >= 0.9 {
            Verdict::Reproduced
        } else if rho > 0.0 {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

#[cfg(test)]
mod tests {
    use super::spearman;

    #[test]
    fn spearman_is_one_for_a_rising_and_minus_one_for_a_falling_series() {
        let up: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, (i * i) as f64)).collect();
        let down: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, -(i as f64))).collect();
        assert!((spearman(&up) - 1.0).abs() < 1e-12);
        assert!((spearman(&down) + 1.0).abs() < 1e-12);
    }
}
