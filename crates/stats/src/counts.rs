//! From outcome counts to phase-diagram labels (SPEC section 6), with Wilson intervals.

use serde::{Deserialize, Serialize};

use crate::axes::{Axes, ColumnKey, Others};
use crate::distributions::Z95;
use crate::end::{End, Tally};
pub use crate::label::Label;

/// Outcome counts of one grid point, from a store or a counts file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Counts {
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    /// The sweep's other axes at this point (empty for the paper's four).
    #[serde(default, skip_serializing_if = "Others::is_empty")]
    pub others: Others,
    /// How many of its replicates ended each way (`n_train`, `n_walk`, ... in files and JSON).
    #[serde(flatten, with = "crate::end::count_keys")]
    pub tally: Tally,
    /// A prep verdict given for the whole point (counts files), overriding the counts.
    pub verdict: Option<Label>,
    /// Mean free speed of the point's prepped cells, where known.
    pub free_speed: Option<f64>,
    /// Whether a prepped cell of the point is box-limited (SPEC section 4.5; unknown, so
    /// false, where the prep's extent is not known).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub box_limited: bool,
    /// Drops the point's collisions shed (SPEC section 5: counted, not labelled).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub sheddings: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl Counts {
    /// The point (alpha, beta, L, sigma) with no result yet: every count zero, no verdict, no
    /// speed. Callers add to it, or fill in what they know with `..Counts::none(..)`.
    #[allow(non_snake_case)]
    pub fn none(alpha: f64, beta: f64, L: u32, sigma: f64) -> Counts {
        Counts {
            alpha,
            beta,
            L,
            sigma,
            others: Others::default(),
            tally: Tally::default(),
            verdict: None,
            free_speed: None,
            box_limited: false,
            sheddings: 0,
        }
    }

    /// The point's axes.
    pub fn axes(&self) -> Axes {
        Axes {
            alpha: self.alpha,
            beta: self.beta,
            L: self.L,
            sigma: self.sigma,
            others: self.others.clone(),
        }
    }

    /// The identity of the point's column (every axis but beta).
    pub fn column(&self) -> ColumnKey {
        crate::axes::column_key(self.alpha, self.L, self.sigma, &self.others)
    }

    /// All replicates with a result.
    pub fn total(&self) -> u64 {
        self.tally.total()
    }

    /// Replicates whose collision ran, whatever it ended in: the base of every share.
    pub fn collisions(&self) -> u64 {
        self.tally.collisions()
    }

    /// Replicates that walked past.
    pub fn n_walk(&self) -> u64 {
        self.tally[End::WalkPast]
    }

    /// Replicates that trained.
    pub fn n_train(&self) -> u64 {
        self.tally[End::Train]
    }

    /// The label by SPEC section 6: a prep verdict carries the point; an outcome in at least
    /// 55% of the replicates dominates (53 of 96); otherwise walk-past and training coexist when
    /// they differ by less than 10% of the replicates (at most 9 of 96) and together make at
    /// least half of them (48 of 96); otherwise mixed.
    pub fn label(&self) -> Option<Label> {
        if let Some(v) = self.verdict {
            return Some(v);
        }
        let n = self.total();
        if n == 0 {
            return None;
        }
        let dominant = |k: u64| k * 100 >= 55 * n;
        // No two ends can both reach 55%, so the order of the look does not matter.
        if let Some((e, _)) = self.tally.iter().find(|&(_, k)| dominant(k)) {
            return Some(e.label());
        }
        // Coexistence: close in number and together at least half of the replicates (SPEC: the
        // paper's "significant presence of both").
        let (walk, train) = (self.n_walk(), self.n_train());
        if walk.abs_diff(train) * 10 < n && (walk + train) * 2 >= n {
            return Some(Label::Coexist);
        }
        Some(Label::Mixed)
    }

    /// Whether the point has collisions to use (no prep verdict).
    pub fn collided(&self) -> bool {
        !matches!(self.verdict, Some(Label::Unstable | Label::Breakup))
            && self.tally.by_prep() == 0
            && self.total() > 0
    }
}

/// A fraction with its 95% Wilson score interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Fraction {
    pub value: f64,
    pub low: f64,
    pub high: f64,
}

/// k successes of n, with the 95% Wilson interval; NaN for n = 0.
pub fn wilson(k: u64, n: u64) -> Fraction {
    if n == 0 {
        return Fraction {
            value: f64::NAN,
            low: f64::NAN,
            high: f64::NAN,
        };
    }
    let (k, n) = (k as f64, n as f64);
    let p = k / n;
    let z2 = Z95 * Z95;
    let denom = 1.0 + z2 / n;
    let centre = (p + z2 / (2.0 * n)) / denom;
    let half = Z95 / denom * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    Fraction {
        value: p,
        low: (centre - half).max(0.0),
        high: (centre + half).min(1.0),
    }
}
