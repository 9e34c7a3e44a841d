//! The paper's qualitative claims (results section, captions, discussion), each checked
//! against the data by a stated rule and given a [`Verdict`]. A claim whose diagrams have not
//! been run gets [`Verdict::NoData`], never a guess.

//!
//! One module per part of the paper: [`outcomes`] (what collisions give at L = 90, sigma = 5,
//! and on one fiber), [`spacing`] (the fiber spacing), [`adhesion`] (sigma = 0), [`line`] (the
//! beta_crit line and the speed).

mod adhesion;
mod line;
mod outcomes;
mod spacing;

use cellsweep_store::{wilson, Column, Counts, Label};

use crate::analysis::Analysis;
use crate::collection::Shown;
use adhesion::*;
use line::*;
use outcomes::*;
use spacing::*;

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

pub(super) fn collided(c: &Counts) -> u64 {
    c.n_train + c.n_walk + c.n_reversal + c.n_undetermined
}

pub(super) fn pct(k: u64, n: u64) -> String {
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
pub(super) fn with_label<'s>(s: &'s Shown<'_>, label: Label) -> Vec<&'s Counts> {
    s.counts().filter(|c| c.label() == Some(label)).collect()
}

/// Outcome sums of the collided points of a diagram: (train, walk, reversal, collisions).
pub(super) fn sums<'c>(points: impl Iterator<Item = &'c Counts>) -> (u64, u64, u64, u64) {
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
pub(super) fn matched<'x>(a: &'x Shown<'_>, b: &'x Shown<'_>) -> Vec<(&'x Counts, &'x Counts)> {
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
pub(super) fn star_rank(c: &Column) -> Option<f64> {
    match (c.beta_star, c.skipped.as_deref()) {
        (Some(b), _) => Some(b),
        (None, Some(why)) if why.starts_with("training") => Some(f64::INFINITY),
        (None, Some(why)) if why.starts_with("walk-past") => Some(f64::NEG_INFINITY),
        _ => None,
    }
}

pub(super) fn star_text(v: f64) -> String {
    if v == f64::INFINITY {
        "none (training throughout)".into()
    } else if v == f64::NEG_INFINITY {
        "none (walk-past throughout)".into()
    } else {
        format!("{v:.1}")
    }
}

/// Columns of two diagrams by alpha: (alpha, rank in a, rank in b) where both say something.
pub(super) fn paired_stars(a: &[Column], b: &[Column]) -> Vec<(f64, f64, f64)> {
    a.iter()
        .filter_map(|ca| {
            let cb = b.iter().find(|cb| cb.alpha == ca.alpha)?;
            Some((ca.alpha, star_rank(ca)?, star_rank(cb)?))
        })
        .collect()
}

pub(super) fn no_data(
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
