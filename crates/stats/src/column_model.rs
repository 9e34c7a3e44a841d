//! beta* of one column from a model of the whole column (SPEC section 6).
//!
//! Of a point's collisions that end in walk-past or training, the fraction that walk past is
//! modelled as a logistic curve in beta,
//!   P(walk-past | walk-past or training, beta) = 1 / (1 + exp(-k (beta - beta*))),   k >= 0,
//! fitted by maximum likelihood to the binomial counts (n_walk of n_walk + n_train) of every
//! collided point of the column. beta* is where walk-past and training are equally frequent,
//! which is the paper's definition; reversals, undetermined ends and collisions that broke up
//! tell nothing about that balance and are left out, as are points whose prep is unstable or
//! broke up (no collision ran).
//!
//! The 95% interval is the profile likelihood's: every beta* whose best k leaves the
//! log-likelihood within half the threshold of its maximum. The threshold is chi-square(1)'s
//! 3.84 when the curve fits; when the deviance says it does not (lack of fit at 5%, for
//! example the preps shared by a point's replicates spreading the points more than binomially),
//! the dispersion phi = deviance / df is estimated and the threshold is phi F(1, df) (the
//! quasi-likelihood interval), so the interval covers the model's misfit too.
//!
//! A column is given a crossing only when the interval is closed inside the betas it sampled
//! and the rise is significant; otherwise the refusal says which: too few points, one outcome
//! everywhere, no rise, or an interval that reaches the column's first or last beta. A column
//! that rises through one half and, significantly, falls back below it (two crossings) is
//! modelled up to the last point of its first walk-past stretch, and says so.

use serde::{Deserialize, Serialize};

use crate::counts::wilson;
use crate::distributions::{chi_square_survival, f1_quantile_95};

/// chi-square(1) at 95%.
const CHI2_1_95: f64 = 3.841_458_820_694_124;
/// The largest slope k per unit beta tried: a rise from 1% to 99% within 0.5 in beta, far
/// steeper than any grid resolves (it stands for a separated column's infinite slope).
const K_MAX: f64 = 20.0;
/// Profile evaluations across the column's betas before the ends are bisected.
const GRID: usize = 800;

/// One point of a column: its beta and its walk-past and training counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkTrain {
    pub beta: f64,
    pub walk: u64,
    pub train: u64,
}

/// The model of a column that has a crossing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColumnModel {
    /// Where walk-past and training are equally frequent (the profile's maximum; the middle of
    /// a flat top where the column is separated).
    pub beta_star: f64,
    /// The 95% profile-likelihood interval.
    pub ci: [f64; 2],
    /// k at the maximum, per unit beta.
    pub slope: f64,
    /// Points the model used.
    pub points: usize,
    /// Deviance of the fit against the saturated model, its degrees of freedom (points - 2)
    /// and the chance of a deviance at least as large if the curve were right (None at 0 df).
    pub deviance: f64,
    pub df: usize,
    pub fit_p: Option<f64>,
    /// The dispersion the interval was widened by (1: the curve fits).
    pub dispersion: f64,
    /// A second, falling crossing: the points from this beta on were left out.
    pub cut_at: Option<f64>,
}

/// Why a column's model gives no crossing.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NoModelCrossing {
    #[error("{0} point(s) with walk-past or training; the model needs three")]
    TooFew(usize),
    #[error("training everywhere the model can see (no walk-past dominant anywhere)")]
    TrainEverywhere,
    #[error("walk-past everywhere the model can see (no training dominant anywhere)")]
    WalkEverywhere,
    #[error("walk-past does not rise significantly with beta")]
    NoRise,
    #[error("the 95% interval reaches the column's {side} beta ({beta}): the crossing is not bounded by the betas sampled")]
    Open { side: &'static str, beta: f64 },
}

/// ln of the logistic function, ln(1 / (1 + e^-z)), without overflow.
fn ln_sigmoid(z: f64) -> f64 {
    if z >= 0.0 {
        -(-z).exp().ln_1p()
    } else {
        z - z.exp().ln_1p()
    }
}

fn sigmoid(z: f64) -> f64 {
    if z >= 0.0 {
        1.0 / (1.0 + (-z).exp())
    } else {
        let e = z.exp();
        e / (1.0 + e)
    }
}

/// The binomial log-likelihood sum_i w_i ln p_i + t_i ln (1 - p_i), p_i = sigma(k (beta_i - c)).
fn log_lik(points: &[WalkTrain], k: f64, c: f64) -> f64 {
    points
        .iter()
        .map(|p| {
            let z = k * (p.beta - c);
            p.walk as f64 * ln_sigmoid(z) + p.train as f64 * ln_sigmoid(-z)
        })
        .sum()
}

/// The best k in [0, K_MAX] for a fixed crossing c, and its log-likelihood. With c fixed the
/// log-likelihood is concave in k, so its derivative
///   g(k) = sum_i (beta_i - c) (w_i - m_i sigma(k (beta_i - c)))
/// falls through zero once at most: bisected.
fn profile_at(points: &[WalkTrain], c: f64) -> (f64, f64) {
    let g = |k: f64| -> f64 {
        points
            .iter()
            .map(|p| {
                let m = (p.walk + p.train) as f64;
                (p.beta - c) * (p.walk as f64 - m * sigmoid(k * (p.beta - c)))
            })
            .sum()
    };
    let k = if g(0.0) <= 0.0 {
        0.0
    } else if g(K_MAX) >= 0.0 {
        K_MAX
    } else {
        let (mut lo, mut hi) = (0.0, K_MAX);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if g(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    };
    (k, log_lik(points, k, c))
}

/// The saturated log-likelihood (each point its own fraction): the deviance's reference.
fn saturated(points: &[WalkTrain]) -> f64 {
    let term = |k: u64, m: u64| {
        if k == 0 {
            0.0
        } else {
            k as f64 * (k as f64 / m as f64).ln()
        }
    };
    points
        .iter()
        .map(|p| term(p.walk, p.walk + p.train) + term(p.train, p.walk + p.train))
        .sum()
}

/// The best constant fraction's log-likelihood: the model without a rise.
fn flat(points: &[WalkTrain]) -> f64 {
    let (w, t): (u64, u64) = points
        .iter()
        .fold((0, 0), |(w, t), p| (w + p.walk, t + p.train));
    let m = (w + t) as f64;
    let term = |k: u64| {
        if k == 0 {
            0.0
        } else {
            k as f64 * (k as f64 / m).ln()
        }
    };
    term(w) + term(t)
}

/// Where a column that rises through one half significantly falls back to training: the beta
/// from which the model leaves its points out, or None for a column that crosses at most once
/// (one point below one half among dozens near a refined crossing is noise, not a fall-back).
pub fn falls_back(tallies: &[WalkTrain]) -> Option<f64> {
    modelled(tallies).1
}

/// The points the model sees, in beta order: those with walk-past or training, and only up to
/// the last point of the first walk-past stretch when the column significantly falls back to
/// training after it (then also the beta from which points were left out).
fn modelled(tallies: &[WalkTrain]) -> (Vec<WalkTrain>, Option<f64>) {
    let mut pts: Vec<WalkTrain> = tallies
        .iter()
        .copied()
        .filter(|t| t.walk + t.train > 0)
        .collect();
    pts.sort_by(|a, b| a.beta.total_cmp(&b.beta));
    let walk_wins = |p: &WalkTrain| wilson(p.walk, p.walk + p.train).low > 0.5;
    let train_wins = |p: &WalkTrain| wilson(p.walk, p.walk + p.train).high < 0.5;
    let Some(first_walk) = pts.iter().position(walk_wins) else {
        return (pts, None);
    };
    // A fall-back is a point where training wins from which on, pooled, training still wins:
    // one point below one half among dozens near a refined crossing is noise, not a second
    // crossing.
    let pooled_train_wins = |from: usize| {
        let (w, t) = pts[from..]
            .iter()
            .fold((0, 0), |(w, t), p| (w + p.walk, t + p.train));
        wilson(w, w + t).high < 0.5
    };
    let Some(back) = (first_walk..pts.len()).find(|&i| train_wins(&pts[i]) && pooled_train_wins(i))
    else {
        return (pts, None);
    };
    let last_walk = (first_walk..back)
        .rev()
        .find(|&i| walk_wins(&pts[i]))
        .unwrap_or(first_walk);
    let cut = pts[back].beta;
    pts.truncate(last_walk + 1);
    (pts, Some(cut))
}

/// The profile log-likelihood on a grid of crossings over the column's sampled betas.
struct Profile {
    lo: f64,
    hi: f64,
    values: Vec<f64>,
}

impl Profile {
    fn over(pts: &[WalkTrain], lo: f64, hi: f64) -> Profile {
        let mut p = Profile {
            lo,
            hi,
            values: Vec::with_capacity(GRID + 1),
        };
        p.values = (0..=GRID).map(|i| profile_at(pts, p.at(i)).1).collect();
        p
    }

    /// The crossing at grid index i.
    fn at(&self, i: usize) -> f64 {
        self.lo + (self.hi - self.lo) * i as f64 / GRID as f64
    }

    /// The maximum (c, l): the grid's best refined by golden section, or the middle of a flat
    /// top.
    fn maximum(&self, pts: &[WalkTrain]) -> (f64, f64) {
        let top = self
            .values
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        let plateau: Vec<usize> = (0..=GRID)
            .filter(|&i| top - self.values[i] <= 1e-9)
            .collect();
        let (mut c_hat, mut l_hat) = (self.at(plateau[0]), top);
        if plateau.len() == 1 {
            let i = plateau[0];
            let (mut a, mut b) = (self.at(i.saturating_sub(1)), self.at((i + 1).min(GRID)));
            let phi = 0.5 * (5f64.sqrt() - 1.0);
            for _ in 0..60 {
                let (x1, x2) = (b - phi * (b - a), a + phi * (b - a));
                if profile_at(pts, x1).1 >= profile_at(pts, x2).1 {
                    b = x2;
                } else {
                    a = x1;
                }
            }
            let c = 0.5 * (a + b);
            let l = profile_at(pts, c).1;
            if l > l_hat {
                (c_hat, l_hat) = (c, l);
            }
        } else {
            // A separated column: every crossing between its last training and first walk-past
            // point fits perfectly; the middle stands for them.
            c_hat = 0.5 * (self.at(plateau[0]) + self.at(plateau[plateau.len() - 1]));
            l_hat = l_hat.max(profile_at(pts, c_hat).1);
        }
        (c_hat, l_hat)
    }

    /// The 95% interval: the hull of the crossings within `threshold` of the maximum, its ends
    /// bisected; refused where it reaches the first or last sampled beta.
    fn interval(
        &self,
        pts: &[WalkTrain],
        l_hat: f64,
        threshold: f64,
    ) -> Result<[f64; 2], NoModelCrossing> {
        let inside = |l: f64| 2.0 * (l_hat - l) <= threshold;
        let first = (0..=GRID).find(|&i| inside(self.values[i])).unwrap_or(0);
        let last = (0..=GRID)
            .rev()
            .find(|&i| inside(self.values[i]))
            .unwrap_or(GRID);
        if first == 0 {
            return Err(NoModelCrossing::Open {
                side: "first",
                beta: self.lo,
            });
        }
        if last == GRID {
            return Err(NoModelCrossing::Open {
                side: "last",
                beta: self.hi,
            });
        }
        let edge = |mut out: f64, mut inn: f64| {
            for _ in 0..50 {
                let mid = 0.5 * (out + inn);
                if inside(profile_at(pts, mid).1) {
                    inn = mid;
                } else {
                    out = mid;
                }
            }
            0.5 * (out + inn)
        };
        Ok([
            edge(self.at(first - 1), self.at(first)),
            edge(self.at(last + 1), self.at(last)),
        ])
    }
}

/// The column's model, or why it gives no crossing.
pub fn fit_column(tallies: &[WalkTrain]) -> Result<ColumnModel, NoModelCrossing> {
    let (pts, cut_at) = modelled(tallies);
    if pts.len() < 3 {
        return Err(NoModelCrossing::TooFew(pts.len()));
    }
    let (lo, hi) = (pts[0].beta, pts[pts.len() - 1].beta);
    if pts.iter().all(|p| p.walk <= p.train) {
        return Err(NoModelCrossing::TrainEverywhere);
    }
    if pts.iter().all(|p| p.walk >= p.train) {
        return Err(NoModelCrossing::WalkEverywhere);
    }
    let profile = Profile::over(&pts, lo, hi);
    let (c_hat, l_hat) = profile.maximum(&pts);
    let slope = profile_at(&pts, c_hat).0;
    // Lack of fit: the deviance against chi-square(points - 2).
    let deviance = (2.0 * (saturated(&pts) - l_hat)).max(0.0);
    let df = pts.len() - 2;
    let fit_p = (df > 0).then(|| chi_square_survival(deviance, df as f64));
    let (dispersion, threshold) = match fit_p {
        Some(p) if p < 0.05 => {
            let phi = deviance / df as f64;
            (phi, phi * f1_quantile_95(df as f64))
        }
        _ => (1.0, CHI2_1_95),
    };
    if 2.0 * (l_hat - flat(&pts)) <= threshold {
        return Err(NoModelCrossing::NoRise);
    }
    let ci = profile.interval(&pts, l_hat, threshold)?;
    Ok(ColumnModel {
        beta_star: c_hat,
        ci,
        slope,
        points: pts.len(),
        deviance,
        df,
        fit_p,
        dispersion,
        cut_at,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tally(beta: f64, walk: u64, train: u64) -> WalkTrain {
        WalkTrain { beta, walk, train }
    }

    #[test]
    fn a_symmetric_column_crosses_in_its_middle() {
        // Fractions 0.1, 0.3, 0.5, 0.7, 0.9 at beta 10..26: the crossing is at 18 by symmetry.
        let col: Vec<WalkTrain> = [(10.0, 10), (14.0, 30), (18.0, 50), (22.0, 70), (26.0, 90)]
            .iter()
            .map(|&(b, w)| tally(b, w, 100 - w))
            .collect();
        let m = fit_column(&col).unwrap();
        assert!((m.beta_star - 18.0).abs() < 1e-6, "{m:?}");
        assert!(
            m.ci[0] < 18.0 && m.ci[1] > 18.0 && m.ci[1] - m.ci[0] < 3.0,
            "{m:?}"
        );
        assert!(
            (m.ci[0] + m.ci[1] - 36.0).abs() < 1e-3,
            "symmetric interval: {m:?}"
        );
    }

    #[test]
    fn a_separated_column_is_bounded_by_its_neighbours() {
        let col = [
            tally(10.0, 0, 96),
            tally(14.0, 0, 96),
            tally(18.0, 96, 0),
            tally(22.0, 96, 0),
        ];
        let m = fit_column(&col).unwrap();
        assert!((m.beta_star - 16.0).abs() < 0.05, "{m:?}");
        assert!(m.ci[0] > 14.0 - 1e-9 && m.ci[1] < 18.0 + 1e-9, "{m:?}");
    }

    #[test]
    fn columns_without_a_bounded_crossing_get_none() {
        let train = [tally(10.0, 0, 50), tally(14.0, 10, 40), tally(18.0, 20, 30)];
        assert_eq!(fit_column(&train), Err(NoModelCrossing::TrainEverywhere));
        let open = [
            tally(10.0, 48, 52),
            tally(14.0, 75, 25),
            tally(18.0, 90, 10),
        ];
        assert!(matches!(
            fit_column(&open),
            Err(NoModelCrossing::Open { side: "first", .. })
        ));
        let flat = [
            tally(10.0, 48, 52),
            tally(14.0, 52, 48),
            tally(18.0, 49, 51),
        ];
        assert_eq!(fit_column(&flat), Err(NoModelCrossing::NoRise));
        assert_eq!(fit_column(&train[..2]), Err(NoModelCrossing::TooFew(2)));
    }

    #[test]
    fn one_point_below_one_half_among_many_at_the_crossing_is_not_a_second_crossing() {
        // L = 90, sigma = 5, alpha = 0.18 as refined: 62/96 at 40.0, then 19/56 at 40.15625,
        // and walk-past winning beyond.
        let col: Vec<WalkTrain> = [
            (30.0, 5, 27),
            (34.0, 21, 67),
            (39.5, 42, 54),
            (40.0, 62, 34),
            (40.15625, 19, 37),
            (40.5, 47, 49),
            (42.0, 58, 38),
            (46.0, 58, 38),
            (50.0, 45, 11),
        ]
        .iter()
        .map(|&(b, w, t)| tally(b, w, t))
        .collect();
        let m = fit_column(&col).unwrap();
        assert_eq!(m.cut_at, None, "{m:?}");
        assert!(m.beta_star > 38.0 && m.beta_star < 42.0, "{m:?}");
    }

    #[test]
    fn a_second_crossing_is_cut_off() {
        let col: Vec<WalkTrain> = [
            (10.0, 5),
            (14.0, 30),
            (18.0, 70),
            (22.0, 95),
            (26.0, 55),
            (30.0, 5),
        ]
        .iter()
        .map(|&(b, w)| tally(b, w, 100 - w))
        .collect();
        let m = fit_column(&col).unwrap();
        assert_eq!(m.cut_at, Some(30.0));
        assert_eq!(m.points, 4);
        assert!(m.beta_star > 14.0 && m.beta_star < 18.0, "{m:?}");
    }
}
