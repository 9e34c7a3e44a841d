//! Adaptive replicates (SPEC section 6): a point stops taking replicates once its label is
//! settled at a stated error, looked at after every round.
//!
//! # The rule
//! A point runs rounds of replicates in index order: `min_replicates` first, then `batch` more
//! at a time, at most `max_replicates` in all, so it is looked at after at most
//! K = 1 + ceil((max - min) / batch) rounds. At every look, each outcome's probability gets a
//! Clopper-Pearson interval at level delta = error / (m K), m the number of outcome kinds a
//! replicate can have (5: train, walk-past, reversal, undetermined, a collision that broke up;
//! 7 where a point has several preps and some replicates can carry a prep verdict), and p_walk - p_train the interval
//! [lo_walk - hi_train, hi_walk - lo_train]. The point is **settled** when every probability
//! vector inside those intervals has the same label (SPEC section 6, in probabilities):
//! - dominant o: lo_o >= 0.55;
//! - coexist: every hi < 0.55, the difference's interval inside (-0.1, 0.1), and
//!   lo_walk + lo_train >= 0.5;
//! - mixed: every hi < 0.55, and the difference's interval outside (-0.1, 0.1) or
//!   hi_walk + hi_train < 0.5.
//!
//! It is settled **by sign** when p_walk - p_train has a certain sign (the difference's interval
//! excludes 0) and its nearest collided neighbours in beta, in the same (L, sigma, alpha) column,
//! have a certain sign too and the same one: it is not next to the column's crossing, which is
//! all the beta_crit fit needs of it. A point next to a crossing runs to `max_replicates`
//! (**exhausted**). A point whose prep is not `ok` carries its verdict at once.
//!
//! # Why it is valid under repeated looks
//! The chance that some interval misses its true probability at some look is at most the sum of
//! the chances at every (outcome, look) pair that could happen: m K delta = error (Bonferroni),
//! whatever rule decides when to stop. Outside that event every look's box of intervals holds
//! the true probabilities, so a point that settles on a label has that label, and a sign that is
//! certain is the true sign. Hence P(a point settles on a wrong label or sign) <= error. The
//! same box holds the observed frequencies, so the label the counts give (`Counts::label`) is
//! the settled label. The union bound is conservative: the Monte Carlo test
//! (`tests/adaptive.rs`) measures the real error far below `error`.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use crate::axes::{Axes, ColumnKey, Others, PointKey};
use crate::binomial::clopper_pearson;
use crate::counts::{Counts, Label};
use crate::end::{End, PerEnd};

/// Dominance threshold, coexistence band and share (SPEC section 6).
const DOMINANT: f64 = 0.55;
const BAND: f64 = 0.1;
const TOGETHER: f64 = 0.5;

/// The adaptive settings of a sweep (`[adaptive]` in a sweep file).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveRule {
    /// Replicates added to an unsettled point per round.
    pub batch: u32,
    /// Replicates of the first round.
    pub min_replicates: u32,
    /// The point's whole budget.
    pub max_replicates: u32,
    /// The chance that a point settles on a label (or sign) other than its true one.
    pub error: f64,
}

impl AdaptiveRule {
    /// Checks the settings; the message names the offending key.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        if self.batch == 0 {
            return Err(("batch", "must be at least 1".into()));
        }
        if self.min_replicates == 0 {
            return Err(("min_replicates", "must be at least 1".into()));
        }
        if self.max_replicates < self.min_replicates {
            return Err((
                "max_replicates",
                format!(
                    "{} is below min_replicates = {}",
                    self.max_replicates, self.min_replicates
                ),
            ));
        }
        if !(self.error > 0.0 && self.error < 1.0) {
            return Err(("error", format!("{} must lie in (0, 1)", self.error)));
        }
        Ok(())
    }

    /// How many times a point can be looked at: K = 1 + ceil((max - min) / batch).
    pub fn looks(&self) -> u32 {
        1 + (self.max_replicates - self.min_replicates).div_ceil(self.batch)
    }

    /// The replicates a point holds after round `round` (0-based): min, min + batch, ..., max.
    pub fn round_size(&self, round: u32) -> u32 {
        (self.min_replicates as u64 + round as u64 * self.batch as u64)
            .min(self.max_replicates as u64) as u32
    }

    /// The largest round size at most `n`, if any.
    pub fn complete_round(&self, n: u32) -> Option<u32> {
        if n < self.min_replicates {
            return None;
        }
        if n >= self.max_replicates {
            return Some(self.max_replicates);
        }
        let k = (n - self.min_replicates) / self.batch;
        Some(self.round_size(k))
    }

    /// The round size after `n` replicates (the first round if `n` is below it), if any.
    pub fn next_round(&self, n: u32) -> Option<u32> {
        match self.complete_round(n) {
            None => Some(self.min_replicates),
            Some(s) if s >= self.max_replicates => None,
            Some(s) => Some((s + self.batch).min(self.max_replicates)),
        }
    }

    /// The level of each interval: error / (outcome kinds x looks).
    pub fn delta(&self, kinds: u32) -> f64 {
        self.error / (kinds as f64 * self.looks() as f64)
    }
}

/// Where a point stands under the rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Standing {
    /// More rounds to come.
    Open,
    /// Its label is settled at the stated error.
    Settled,
    /// The sign of p_walk - p_train is settled, away from the column's crossing.
    Sign,
    /// It ran its whole budget without settling (next to a crossing, or a close call).
    Exhausted,
    /// Its prep is not `ok`: the verdict carries it.
    Verdict,
}

impl Standing {
    pub fn as_str(self) -> &'static str {
        match self {
            Standing::Open => "open",
            Standing::Settled => "settled",
            Standing::Sign => "sign",
            Standing::Exhausted => "exhausted",
            Standing::Verdict => "verdict",
        }
    }

    /// Whether the point takes no more replicates.
    pub fn is_final(self) -> bool {
        self != Standing::Open
    }
}

/// Simultaneous bounds of one look.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    /// Each end's share (`train`, `walk_past`, ... in JSON).
    #[serde(flatten)]
    pub ends: PerEnd<[f64; 2]>,
    /// p_walk - p_train.
    pub walk_minus_train: [f64; 2],
}

/// The assessment of one point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Assessment {
    /// The replicates looked at: the point's latest complete round (0 before the first).
    pub n: u32,
    pub standing: Standing,
    /// The label certain at the stated error, if any.
    pub certain_label: Option<Label>,
    /// The certain sign of p_walk - p_train (+1 walk-past, -1 training), if any.
    pub certain_sign: Option<i8>,
    pub bounds: Option<Bounds>,
    /// The round the point needs next, if it is open.
    pub next_round: Option<u32>,
}

/// Finds a point by its axes (exactly, bit for bit, as the sweep wrote them).
#[derive(Debug, Clone, Default)]
pub struct GridIndex(HashMap<PointKey, usize>);

impl GridIndex {
    /// The index of the point at `axes` in its sweep.
    pub fn of(&self, axes: &Axes) -> Option<usize> {
        self.0.get(&axes.key()).copied()
    }
}

/// One point's finished replicates, by replicate index (None: not finished).
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)]
pub struct PointEnds {
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    /// The sweep's other axes at this point (empty for the paper's four).
    pub others: Others,
    pub ends: Vec<Option<End>>,
}

impl PointEnds {
    /// The point (alpha, beta, L, sigma) with no replicate finished yet.
    #[allow(non_snake_case)]
    pub fn new(alpha: f64, beta: f64, L: u32, sigma: f64) -> PointEnds {
        PointEnds::at(Axes::new(alpha, beta, L, sigma))
    }

    /// The point at `axes` with no replicate finished yet.
    pub fn at(axes: Axes) -> PointEnds {
        PointEnds {
            alpha: axes.alpha,
            beta: axes.beta,
            L: axes.L,
            sigma: axes.sigma,
            others: axes.others,
            ends: Vec::new(),
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

    /// Every point of a sweep, in its order, with no replicate finished yet, and the index
    /// that finds a point by its axes.
    pub fn grid(points: impl IntoIterator<Item = Axes>) -> (Vec<PointEnds>, GridIndex) {
        let ends: Vec<PointEnds> = points.into_iter().map(PointEnds::at).collect();
        let index = GridIndex(
            ends.iter()
                .enumerate()
                .map(|(i, p)| (p.axes().key(), i))
                .collect(),
        );
        (ends, index)
    }

    /// Replicate `replicate` ended in `end`; false (and nothing changed) if it already had.
    pub fn record(&mut self, replicate: u32, end: End) -> bool {
        let k = replicate as usize;
        if self.ends.len() <= k {
            self.ends.resize(k + 1, None);
        }
        if self.ends[k].is_some() {
            return false;
        }
        self.ends[k] = Some(end);
        true
    }

    /// The number of replicates finished in index order, without a gap.
    pub fn prefix(&self) -> u32 {
        self.ends.iter().take_while(|e| e.is_some()).count() as u32
    }

    /// Outcome counts of the first `n` replicates (all finished).
    pub fn counts(&self, n: u32) -> Counts {
        let mut c = Counts {
            others: self.others.clone(),
            ..Counts::none(self.alpha, self.beta, self.L, self.sigma)
        };
        for &end in self.ends.iter().take(n as usize).flatten() {
            c.tally.add(end, 1);
        }
        c
    }
}

/// Clopper-Pearson intervals of one rule, memoised by (k, n).
pub struct Intervals {
    delta: f64,
    memo: HashMap<(u64, u64), [f64; 2]>,
}

impl Intervals {
    pub fn new(rule: &AdaptiveRule, kinds: u32) -> Self {
        Intervals {
            delta: rule.delta(kinds),
            memo: HashMap::new(),
        }
    }

    pub fn get(&mut self, k: u64, n: u64) -> [f64; 2] {
        let delta = self.delta;
        *self
            .memo
            .entry((k, n))
            .or_insert_with(|| clopper_pearson(k, n, delta))
    }
}

/// The bounds of one look at `c`, and what is certain in them.
pub fn look(c: &Counts, iv: &mut Intervals) -> (Bounds, Option<Label>, Option<i8>) {
    let n = c.total();
    let ends = PerEnd::from_fn(|e| iv.get(c.tally[e], n));
    let (walk, train) = (ends[End::WalkPast], ends[End::Train]);
    let b = Bounds {
        ends,
        walk_minus_train: [walk[0] - train[1], walk[1] - train[0]],
    };
    // Every collision outcome is a candidate; replicates decided by a prep verdict (several
    // preps per point) only where there are some.
    let candidates: Vec<([f64; 2], Label)> = c
        .tally
        .iter()
        .filter(|&(e, k)| e.is_collision() || k > 0)
        .map(|(e, _)| (b.ends[e], e.label()))
        .collect();
    let [d_lo, d_hi] = b.walk_minus_train;
    let label = if let Some((_, l)) = candidates.iter().find(|(i, _)| i[0] >= DOMINANT) {
        Some(*l)
    } else if candidates.iter().all(|(i, _)| i[1] < DOMINANT) {
        let inside = d_lo > -BAND && d_hi < BAND;
        let outside = d_lo >= BAND || d_hi <= -BAND;
        if inside && walk[0] + train[0] >= TOGETHER {
            Some(Label::Coexist)
        } else if outside || walk[1] + train[1] < TOGETHER {
            Some(Label::Mixed)
        } else {
            None
        }
    } else {
        None
    };
    let sign = if d_lo > 0.0 {
        Some(1)
    } else if d_hi < 0.0 {
        Some(-1)
    } else {
        None
    };
    (b, label, sign)
}

/// The outcome kinds a replicate of a sweep can have: 5 (train, walk-past, reversal,
/// undetermined, a collision that broke up), or 7 with several preps per point.
pub fn kinds(preps_per_point: u32) -> u32 {
    if preps_per_point > 1 {
        7
    } else {
        5
    }
}

/// Assess every point of a sweep (any order; columns are found by every axis but beta).
pub fn assess(points: &[PointEnds], rule: &AdaptiveRule, kinds: u32) -> Vec<Assessment> {
    let mut iv = Intervals::new(rule, kinds);
    assess_with(points, rule, &mut iv)
}

/// [`assess`] with a shared interval memo (for many calls with one rule).
pub fn assess_with(
    points: &[PointEnds],
    rule: &AdaptiveRule,
    iv: &mut Intervals,
) -> Vec<Assessment> {
    // First each point on its own, then the sign rule against its neighbours.
    let mut out: Vec<Assessment> = points.iter().map(|p| assess_point(p, rule, iv)).collect();
    settle_by_sign(points, &mut out);
    for a in out.iter_mut().filter(|a| a.standing == Standing::Open) {
        if a.n >= rule.max_replicates {
            a.standing = Standing::Exhausted;
        } else {
            a.next_round = rule.next_round(a.n);
        }
    }
    out
}

/// One point on its own, over its complete rounds: settled if its label is certain, decided
/// by its preps if no collision ran, else open (with its bounds and any certain sign).
fn assess_point(p: &PointEnds, rule: &AdaptiveRule, iv: &mut Intervals) -> Assessment {
    let n = rule.complete_round(p.prefix()).unwrap_or(0);
    if n == 0 {
        return Assessment {
            n,
            standing: Standing::Open,
            certain_label: None,
            certain_sign: None,
            bounds: None,
            next_round: rule.next_round(0),
        };
    }
    let c = p.counts(n);
    let verdict_only = c.tally.collisions() == 0;
    if verdict_only {
        return Assessment {
            n,
            standing: Standing::Verdict,
            certain_label: c.label(),
            certain_sign: None,
            bounds: None,
            next_round: None,
        };
    }
    let (bounds, label, sign) = look(&c, iv);
    Assessment {
        n,
        standing: if label.is_some() {
            Standing::Settled
        } else {
            Standing::Open
        },
        certain_label: label,
        certain_sign: sign,
        bounds: Some(bounds),
        next_round: None,
    }
}

/// The sign rule: an open point whose sign of (walk-past - training) is certain is settled by
/// sign when its nearest collided neighbours in beta, in its column, have the same certain sign.
fn settle_by_sign(points: &[PointEnds], out: &mut [Assessment]) {
    let mut columns: HashMap<ColumnKey, Vec<usize>> = HashMap::new();
    for (i, p) in points.iter().enumerate() {
        if out[i].standing != Standing::Verdict {
            columns.entry(p.axes().column()).or_default().push(i);
        }
    }
    let mut by_sign = Vec::new();
    for col in columns.values_mut() {
        col.sort_by(|&a, &b| points[a].beta.total_cmp(&points[b].beta));
        for (k, &i) in col.iter().enumerate() {
            let Some(s) = out[i].certain_sign else {
                continue;
            };
            let neighbours = [k.checked_sub(1), Some(k + 1)];
            let agree = neighbours
                .iter()
                .flatten()
                .filter_map(|&j| col.get(j))
                .all(|&j| out[j].certain_sign == Some(s));
            if agree && out[i].standing == Standing::Open {
                by_sign.push(i);
            }
        }
    }
    for i in by_sign {
        out[i].standing = Standing::Sign;
    }
}
