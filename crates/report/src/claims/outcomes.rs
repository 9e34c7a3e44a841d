//! What collisions give: on one fiber, and on two at L = 90, sigma = 5 (Fig. 2 and 3).

use cellsweep_stats::{falls_back, Counts, Label, WalkTrain};

use super::{graded, no_data, pct, sums, with_label, Claim, Verdict};
use crate::analysis::Analysis;

pub(super) fn spindle(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 2(a)",
        "If we collide cells on a single fiber (spindle cells), they almost always form a \
         train (nearly 100% probability at our default parameters).",
        "reproduced: training in at least 90% of the collisions; partly: training dominant \
         (55%); else not.",
    );
    let Some(r) = an.collection.spindle else {
        return no_data(
            source,
            quote,
            rule,
            "the one-fiber check (sweeps/check-spindle.toml)",
        );
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

pub(super) fn outcomes(an: &Analysis<'_>) -> Claim {
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

pub(super) fn transition(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Results, Fig. 3",
        "There is a transition between primarily training outcomes (at high α and low β) and \
         primarily walk-past (high β and low α).",
        "at L = 90, σ = 5: reproduced when the training-dominated points lie at higher mean α \
         and lower mean β than the walk-past-dominated ones, and no α column, once walk-past \
         wins significantly, falls back to training significantly (a point's Wilson interval \
         below one half, and training winning pooled from there on: the column model's test \
         for a second crossing); partly when only the first holds.",
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
    // Per column, a significant fall-back to training after walk-past has won: sign changes
    // of n_walk - n_train alone would count the noise of the many points that refinement puts
    // near a crossing, where either may lead by chance.
    let mut alphas: Vec<f64> = s.counts().map(|c| c.alpha).collect();
    alphas.sort_by(|a, b| a.total_cmp(b));
    alphas.dedup();
    let mut bad = Vec::new();
    for &a in &alphas {
        let col: Vec<WalkTrain> = s
            .counts()
            .filter(|c| c.alpha == a && c.collided())
            .map(|c| WalkTrain {
                beta: c.beta,
                walk: c.n_walk(),
                train: c.n_train(),
            })
            .collect();
        if let Some(beta) = falls_back(&col) {
            bad.push(format!("{a} (from β = {beta})"));
        }
    }
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "training-dominated points centre at α = {:.3}, β = {:.1}; walk-past-dominated at \
             α = {:.3}, β = {:.1}; columns that fall back to training after walk-past has \
             won: {}",
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
        verdict: graded(placed, bad.is_empty()),
    }
}

pub(super) fn point_list(points: &[&Counts]) -> String {
    points
        .iter()
        .map(|c| format!("({}, {})", c.alpha, c.beta))
        .collect::<Vec<_>>()
        .join(", ")
}

pub(super) fn unstable(an: &Analysis<'_>) -> Claim {
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

pub(super) fn breakup(an: &Analysis<'_>) -> Claim {
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
