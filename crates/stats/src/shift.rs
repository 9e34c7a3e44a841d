//! The shift of the beta_crit line when cell-cell adhesion is removed (the paper's appendix:
//! sigma = 5 -> 0 moves the line leftward in alpha by 0.0134, whatever L).
//!
//! Measured without assuming it: the line beta* = a x(alpha, L) + b is fitted to the
//! sigma = 5 columns (x = alpha~ / L~, no shift), then the sigma = 0 columns are fitted with
//! that line moved by one free delta in alpha, beta*(sigma 0) = a x(alpha + delta, L) + b.
//! With k(L) = dx/dalpha and r = beta* - a x(alpha, L) - b, least squares gives
//! delta = sum k r / (a sum k^2).
//!
//! With the column model (the default), the sigma = 5 line is weighted by the columns'
//! intervals as in `model_line`, delta's sum too (weights 1 / s_c^2), and delta's
//! interval comes from draws of every column's beta* from its interval, widened by Birge's
//! ratio of the residuals about the three-number model. With interpolation, the bootstrap
//! redraws the replicates of every point of both sigmas and refits the three numbers together.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::column_shift::{column_shifts, ColumnShifts};
use crate::counts::Counts;
use crate::fit::{columns, read_columns, Column, Method, Scales};
use crate::interpolation::resample_diffs;
use crate::model_line::{birge, line_with_censored};
use crate::sampling::percentile_95;

/// The paper's shift (its appendix): 0.0134 in alpha from sigma = 5 to sigma = 0.
pub const PAPER_SHIFT: f64 = 0.0134;

/// The measured shift of the line, sigma = 5 -> 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Shift {
    /// The sigma = 5 line the shift is measured from.
    pub a: f64,
    pub b: f64,
    /// delta: the sigma = 0 line is the sigma = 5 line moved to smaller alpha by delta.
    pub delta: f64,
    pub delta_ci: [f64; 2],
    pub paper_delta: f64,
    /// Columns with a crossing used at each sigma.
    pub columns_sigma5: usize,
    pub columns_sigma0: usize,
    pub bootstrap: usize,
    /// How the columns' beta* were read.
    #[serde(default = "interpolate")]
    pub method: Method,
    /// With the model: Birge's ratio of the columns about the three-number model (a, b,
    /// delta), by which delta's draws were widened where it is above 1. It measures how far
    /// the columns lie off one straight line and one shift, in units of their own intervals:
    /// narrower columns raise it rather than narrow delta.
    #[serde(default)]
    pub scatter: Option<f64>,
    /// With the model: the shift of each column with a crossing at both sigmas, and the test
    /// of one delta for all of them (`column_shift`).
    #[serde(default)]
    pub per_column: Option<ColumnShifts>,
}

fn interpolate() -> Method {
    Method::Interpolate
}

/// (a, b, delta) of one set of columns, each with its weight (`weight` gives None for a
/// column to leave out): None without a sigma = 5 line or a sigma = 0 crossing.
fn solve(cols: &[Column], scales: &Scales, weight: &Weight) -> Option<(f64, f64, f64)> {
    // x without any adhesion correction is the sigma = 5 x (the shift is what is measured).
    let raw = |c: &Column| scales.at(&c.others).x(c.alpha, c.L, 5.0);
    let five: Vec<(f64, f64, f64)> = cols
        .iter()
        .filter(|c| c.sigma == 5.0)
        .filter_map(|c| Some((raw(c), c.beta_star?, weight(c)?)))
        .collect();
    // Columns open at sigma = 5 enter the line censored, as in `fit` (SPEC section 6).
    let censored: Vec<(f64, f64)> = cols
        .iter()
        .filter(|c| c.sigma == 5.0)
        .filter_map(|c| Some((raw(c), c.censored_above?)))
        .collect();
    let (a, b) = line_with_censored(&five, &censored)?;
    let (mut num, mut den) = (0.0, 0.0);
    for c in cols.iter().filter(|c| c.sigma == 0.0) {
        if let (Some(star), Some(w)) = (c.beta_star, weight(c)) {
            let at = scales.at(&c.others);
            let k = at.x(1.0, c.L, 5.0) - at.x(0.0, c.L, 5.0);
            num += w * k * (star - a * raw(c) - b);
            den += w * k * k;
        }
    }
    (den > 0.0 && a.abs() > 1e-12).then(|| (a, b, num / (a * den)))
}

/// A column's weight in the fit, None to leave it out.
type Weight<'a> = dyn Fn(&Column) -> Option<f64> + 'a;

/// The model's weight of a column: 1 / sd^2 of its interval.
fn model_weight(c: &Column) -> Option<f64> {
    c.crossing().map(|x| 1.0 / x.sd().max(1e-3).powi(2))
}

/// The shift measured from `counts` (points at sigma 5 and 0, any L; others are ignored),
/// the columns read by `method`, with `resamples` bootstrap resamples or draws. None when
/// either sigma has too few crossings.
pub fn measure_shift(
    counts: &[Counts],
    scales: &Scales,
    resamples: usize,
    seed: u64,
    method: Method,
) -> Option<Shift> {
    let counts: Vec<Counts> = counts
        .iter()
        .filter(|c| c.sigma == 5.0 || c.sigma == 0.0)
        .cloned()
        .collect();
    let unweighted = |c: &Column| c.beta_star.map(|_| 1.0);
    let (cols, weight): (Vec<Column>, &Weight<'_>) = match method {
        Method::Interpolate => {
            let observed = |i: usize| counts[i].n_walk() as i64 - counts[i].n_train() as i64;
            (columns(&counts, scales, &observed), &unweighted)
        }
        Method::Model => (
            read_columns(&counts, scales, 0, seed, method).0,
            &model_weight,
        ),
    };
    let (a, b, delta) = solve(&cols, scales, weight)?;
    let used = |s: f64| {
        cols.iter()
            .filter(|c| c.sigma == s && c.beta_star.is_some())
            .count()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut deltas = Vec::new();
    let mut scatter = None;
    let mut per_column = None;
    match method {
        Method::Interpolate => {
            for _ in 0..resamples {
                let diffs = resample_diffs(&counts, &mut rng);
                let cols_b = columns(&counts, scales, &|i| diffs[i]);
                if let Some((_, _, d)) = solve(&cols_b, scales, &unweighted) {
                    deltas.push(d);
                }
            }
        }
        Method::Model => {
            let widen = model_scatter(&cols, scales, (a, b, delta));
            scatter = Some(widen);
            per_column = column_shifts(&cols, scales, a);
            for _ in 0..resamples {
                let drawn: Vec<Column> = cols
                    .iter()
                    .map(|c| {
                        let mut d = c.clone();
                        d.beta_star = c.crossing().map(|x| x.draw(&mut rng, widen));
                        d
                    })
                    .collect();
                // The weights stay those of the observed columns.
                let w = |c: &Column| {
                    let obs = cols.iter().find(|o| o.key() == c.key())?;
                    model_weight(obs)
                };
                if let Some((_, _, d)) = solve(&drawn, scales, &w) {
                    deltas.push(d);
                }
            }
        }
    }
    Some(Shift {
        a,
        b,
        delta,
        delta_ci: percentile_95(&mut deltas),
        paper_delta: PAPER_SHIFT,
        columns_sigma5: used(5.0),
        columns_sigma0: used(0.0),
        bootstrap: resamples,
        method,
        scatter,
        per_column,
    })
}

/// Birge's ratio of the columns about the fitted three-number model (a, b, delta).
fn model_scatter(cols: &[Column], scales: &Scales, (a, b, delta): (f64, f64, f64)) -> f64 {
    let residuals = cols.iter().filter_map(|c| {
        let x = c.crossing()?;
        let alpha = if c.sigma == 0.0 {
            c.alpha + delta
        } else {
            c.alpha
        };
        let line = a * scales.at(&c.others).x(alpha, c.L, 5.0) + b;
        Some((x.star - line) / x.sd().max(1e-3))
    });
    birge(residuals, 3)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::end::End;

    /// A column of points at (L, sigma, alpha) whose n_walk - n_train crosses zero exactly at
    /// `star` (linear interpolation between beta = star -2 and star + 2).
    fn column(l: u32, sigma: f64, alpha: f64, star: f64) -> Vec<Counts> {
        [star - 2.0, star + 2.0]
            .iter()
            .enumerate()
            .map(|(k, &beta)| Counts {
                tally: [
                    (End::Train, if k == 0 { 10 } else { 0 }),
                    (End::WalkPast, if k == 0 { 0 } else { 10 }),
                ]
                .into_iter()
                .collect(),
                ..Counts::none(alpha, beta, l, sigma)
            })
            .collect()
    }

    #[test]
    fn a_line_moved_by_a_known_delta_is_measured_back() {
        // beta* = 0.6 x - 12 at sigma 5; at sigma 0 the same line at alpha + 0.02.
        let s = Scales::default();
        let x = |alpha: f64, l: u32| {
            2.0 * std::f64::consts::PI * 40.0 * 20f64.sqrt() * alpha / (l as f64 / 40.0)
        };
        let mut counts = Vec::new();
        for l in [90, 70] {
            for alpha in [0.12, 0.16, 0.2] {
                counts.extend(column(l, 5.0, alpha, 0.6 * x(alpha, l) - 12.0));
                counts.extend(column(l, 0.0, alpha, 0.6 * x(alpha + 0.02, l) - 12.0));
            }
        }
        let m = measure_shift(&counts, &s, 50, 1, Method::Interpolate).unwrap();
        assert!(
            (m.a - 0.6).abs() < 1e-9 && (m.b + 12.0).abs() < 1e-6,
            "{m:?}"
        );
        assert!((m.delta - 0.02).abs() < 1e-9, "{m:?}");
        // Every count is 0 or n: the resamples are the data, so is the interval.
        assert!((m.delta_ci[0] - 0.02).abs() < 1e-9 && (m.delta_ci[1] - 0.02).abs() < 1e-9);
        assert_eq!((m.columns_sigma5, m.columns_sigma0), (6, 6));
    }

    /// A column read by the model: 200 collisions at each beta within 6 of `star`, walk-past
    /// at exactly the logistic share 1 / (1 + exp(-0.5 (beta - star))) of them.
    fn logistic_column(l: u32, sigma: f64, alpha: f64, star: f64) -> Vec<Counts> {
        (-6..=6)
            .map(|i| {
                let beta = star.round() + i as f64;
                let w = (200.0 / (1.0 + (-0.5 * (beta - star)).exp())).round() as u64;
                Counts {
                    tally: [(End::Train, 200 - w), (End::WalkPast, w)]
                        .into_iter()
                        .collect(),
                    ..Counts::none(alpha, beta, l, sigma)
                }
            })
            .collect()
    }

    #[test]
    fn the_model_s_scatter_says_when_the_columns_lie_off_one_line_and_one_shift() {
        let s = Scales::default();
        let on_line = |alpha: f64, l: u32| s.beta_on_line(0.6, -12.0, alpha, l, 5.0);
        let measure = |off: f64| {
            let mut counts = Vec::new();
            for (k, l) in [90, 80, 70].into_iter().enumerate() {
                for (j, alpha) in [0.12, 0.14, 0.16].into_iter().enumerate() {
                    // `off` alternates in sign from column to column: not a line at all.
                    let kink = if (k + j) % 2 == 0 { off } else { -off };
                    counts.extend(logistic_column(l, 5.0, alpha, on_line(alpha, l) + kink));
                    let star0 = on_line(alpha + 0.01, l) + kink;
                    counts.extend(logistic_column(l, 0.0, alpha, star0));
                }
            }
            measure_shift(&counts, &s, 200, 1, Method::Model).unwrap()
        };
        let straight = measure(0.0);
        assert!((straight.delta - 0.01).abs() < 5e-4, "{straight:?}");
        assert!(straight.scatter.unwrap() < 1.5, "{straight:?}");
        let kinked = measure(1.5);
        assert!(kinked.scatter.unwrap() > 3.0, "{kinked:?}");
        // The kinks are shared by each column's two sigmas: column by column the shift is the
        // same 0.01, and one shift for all passes its test, kinked or straight.
        for m in [&straight, &kinked] {
            let each = m.per_column.as_ref().unwrap();
            assert_eq!(each.columns.len(), 9);
            assert!((each.mean - 0.01).abs() < 5e-4 && each.p > 0.05, "{each:?}");
        }
        let width = |m: &Shift| m.delta_ci[1] - m.delta_ci[0];
        assert!(
            width(&kinked) > 2.0 * width(&straight),
            "{straight:?} {kinked:?}"
        );
    }

    #[test]
    fn no_sigma_zero_crossing_means_no_shift() {
        let counts = column(90, 5.0, 0.1, 20.0);
        assert!(measure_shift(&counts, &Scales::default(), 10, 1, Method::Interpolate).is_none());
    }
}
