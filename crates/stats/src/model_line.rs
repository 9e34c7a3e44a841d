//! The line through the model's beta* (SPEC section 6), with intervals that carry the columns'
//! intervals through.
//!
//! Each column with a crossing gives beta*_c with a 95% interval [lo_c, hi_c], read as a split
//! normal: sd below (beta*_c - lo_c) / 1.96, above (hi_c - beta*_c) / 1.96. The line is the
//! weighted least squares fit of beta*_c = a x_c + b with weights 1 / s_c^2,
//! s_c = (hi_c - lo_c) / 3.92. If the columns scatter about it more than their intervals
//! allow (Birge's ratio R = sqrt(chi^2 / (n - 2)) above 1), every interval is widened by R,
//! so the line's intervals also cover a line that is not quite straight. The intervals of a and
//! b are the 2.5% and 97.5% percentiles over draws, each drawing every column's beta* from its
//! (widened) split normal and refitting.
//!
//! A column still open at the grid's last value (SPEC section 6) is censored, not missing: its
//! beta* lies above that value `c`. With such columns the line is the maximum-likelihood line
//! of the Tobit model (the crossings normal about the line with their sds; a censored column
//! contributes P(beta* > c)), found by EM: each censored column stands at the mean of its
//! normal above c, mu + s lambda((c - mu) / s) (lambda the inverse Mills ratio), and the
//! weighted fit is repeated until the line stops moving. A censored column's s is the median
//! sd of the crossings, widened by Birge's ratio. Each draw repeats the EM on its crossings.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::distributions::{inverse_mills, Z95};
use crate::sampling::{percentile_95, standard_normal};

/// The line through the columns' beta*.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModelLine {
    pub a: f64,
    pub b: f64,
    pub a_ci: [f64; 2],
    pub b_ci: [f64; 2],
    pub r2: f64,
    /// Birge's ratio (1 where the columns scatter no more than their intervals say).
    pub scatter: f64,
}

/// A column's crossing with the spreads of its interval: (x, beta*, sd below, sd above).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Crossing {
    pub x: f64,
    pub star: f64,
    pub below: f64,
    pub above: f64,
}

impl Crossing {
    /// The crossing at `x` of a beta* with its 95% interval `ci`.
    pub fn new(x: f64, star: f64, ci: [f64; 2]) -> Crossing {
        Crossing {
            x,
            star,
            below: ((star - ci[0]) / Z95).max(0.0),
            above: ((ci[1] - star) / Z95).max(0.0),
        }
    }

    /// The symmetric sd of the weights.
    pub fn sd(&self) -> f64 {
        0.5 * (self.below + self.above)
    }

    /// A draw from the split normal, its spreads widened by `widen`.
    pub fn draw(&self, rng: &mut ChaCha8Rng, widen: f64) -> f64 {
        let z = standard_normal(rng);
        self.star + z * widen * if z < 0.0 { self.below } else { self.above }
    }
}

/// Weighted least squares y = a x + b over (x, y, w); None without two distinct x.
pub(crate) fn weighted_line(pts: &[(f64, f64, f64)]) -> Option<(f64, f64)> {
    let sw: f64 = pts.iter().map(|p| p.2).sum();
    if pts.len() < 2 || sw.is_nan() || sw <= 0.0 {
        return None;
    }
    let mx = pts.iter().map(|p| p.2 * p.0).sum::<f64>() / sw;
    let my = pts.iter().map(|p| p.2 * p.1).sum::<f64>() / sw;
    let sxx: f64 = pts.iter().map(|p| p.2 * (p.0 - mx).powi(2)).sum();
    if sxx <= 1e-12 * sw * mx.abs().max(1.0).powi(2) {
        return None;
    }
    let a = pts
        .iter()
        .map(|p| p.2 * (p.0 - mx) * (p.1 - my))
        .sum::<f64>()
        / sxx;
    Some((a, my - a * mx))
}

/// The sd given a censored column: the median sd of the points (x, y, 1 / sd^2), widened by
/// Birge's ratio `scatter`.
fn censored_sd(pts: &[(f64, f64, f64)], scatter: f64) -> f64 {
    let mut sds: Vec<f64> = pts.iter().map(|p| 1.0 / p.2.sqrt()).collect();
    sds.sort_by(f64::total_cmp);
    sds[sds.len() / 2] * scatter
}

/// The line through points (x, y, 1 / sd^2) and the columns censored above (x, c): the
/// weighted line where none is censored, else the Tobit line (each censored column with the
/// median sd widened by the points' Birge ratio about the weighted line). None without two
/// distinct x among the points.
pub(crate) fn line_with_censored(
    pts: &[(f64, f64, f64)],
    censored: &[(f64, f64)],
) -> Option<(f64, f64)> {
    let (a, b) = weighted_line(pts)?;
    if censored.is_empty() {
        return Some((a, b));
    }
    let scatter = birge(pts.iter().map(|p| (p.1 - (a * p.0 + b)) * p.2.sqrt()), 2);
    Some(censored_line(
        pts,
        censored,
        censored_sd(pts, scatter),
        (a, b),
    ))
}

/// The Tobit line by EM from `start`: the weighted fit of `pts` with each censored column
/// (x, c) at its normal's mean above c (sd `s`), repeated until the line stops moving. `start`
/// itself without censored columns.
fn censored_line(
    pts: &[(f64, f64, f64)],
    censored: &[(f64, f64)],
    s: f64,
    start: (f64, f64),
) -> (f64, f64) {
    if censored.is_empty() {
        return start;
    }
    let (mut a, mut b) = start;
    let mut all = pts.to_vec();
    for _ in 0..200 {
        all.truncate(pts.len());
        for &(x, c) in censored {
            let mu = a * x + b;
            all.push((x, mu + s * inverse_mills((c - mu) / s), 1.0 / (s * s)));
        }
        let Some((a1, b1)) = weighted_line(&all) else {
            break;
        };
        let moved =
            (a1 - a).abs() * pts.iter().map(|p| p.0.abs()).fold(0.0, f64::max) + (b1 - b).abs();
        (a, b) = (a1, b1);
        if moved < 1e-10 {
            break;
        }
    }
    (a, b)
}

/// Weight of a crossing: 1 / sd^2 (a column known to a hair does not take the whole line).
fn weight(c: &Crossing) -> f64 {
    1.0 / c.sd().max(1e-3).powi(2)
}

/// Birge's ratio of residuals r_c (in units of each column's sd) with `params` fitted: at
/// least 1.
pub(crate) fn birge(scaled_residuals: impl Iterator<Item = f64>, params: usize) -> f64 {
    let (mut chi2, mut n) = (0.0, 0usize);
    for r in scaled_residuals {
        chi2 += r * r;
        n += 1;
    }
    if n <= params {
        return 1.0;
    }
    (chi2 / (n - params) as f64).sqrt().max(1.0)
}

/// The line through the columns' model crossings and the columns censored above a value
/// (x, c), with `draws` draws for its intervals.
pub(crate) fn line_from_columns(
    cs: &[Crossing],
    censored: &[(f64, f64)],
    draws: usize,
    seed: u64,
) -> Option<ModelLine> {
    let pts: Vec<(f64, f64, f64)> = cs.iter().map(|c| (c.x, c.star, weight(c))).collect();
    let (a0, b0) = weighted_line(&pts)?;
    let scatter = birge(
        cs.iter()
            .map(|c| (c.star - (a0 * c.x + b0)) / c.sd().max(1e-3)),
        2,
    );
    let s_censored = censored_sd(&pts, scatter);
    let (a, b) = censored_line(&pts, censored, s_censored, (a0, b0));
    let my = cs.iter().map(|c| c.star).sum::<f64>() / cs.len() as f64;
    let ss_tot: f64 = cs.iter().map(|c| (c.star - my).powi(2)).sum();
    let ss_res: f64 = cs.iter().map(|c| (c.star - (a * c.x + b)).powi(2)).sum();
    let r2 = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut as_, mut bs) = (Vec::with_capacity(draws), Vec::with_capacity(draws));
    for _ in 0..draws {
        let drawn: Vec<(f64, f64, f64)> = cs
            .iter()
            .zip(&pts)
            .map(|(c, p)| (c.x, c.draw(&mut rng, scatter), p.2))
            .collect();
        if let Some(start) = weighted_line(&drawn) {
            let (ad, bd) = censored_line(&drawn, censored, s_censored, start);
            as_.push(ad);
            bs.push(bd);
        }
    }
    Some(ModelLine {
        a,
        b,
        a_ci: percentile_95(&mut as_),
        b_ci: percentile_95(&mut bs),
        r2,
        scatter,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distributions::normal_upper_tail;

    /// Crossings on beta = 0.6 x - 12 at x = 50..90, sd 0.5 each.
    fn on_the_line() -> Vec<Crossing> {
        (0..5)
            .map(|k| {
                let x = 50.0 + 10.0 * k as f64;
                let y = 0.6 * x - 12.0 + if k % 2 == 0 { 0.2 } else { -0.2 };
                Crossing::new(x, y, [y - 0.98, y + 0.98])
            })
            .collect()
    }

    /// The Tobit log-likelihood the EM maximizes, written out independently: normal terms for
    /// the crossings, ln P(beta* > c) for the censored columns.
    fn log_likelihood(cs: &[Crossing], censored: &[(f64, f64)], s: f64, a: f64, b: f64) -> f64 {
        let normal: f64 = cs
            .iter()
            .map(|c| -0.5 * ((c.star - a * c.x - b) / c.sd()).powi(2))
            .sum();
        let tails: f64 = censored
            .iter()
            .map(|&(x, c)| normal_upper_tail((c - (a * x + b)) / s).ln())
            .sum();
        normal + tails
    }

    #[test]
    fn no_censored_column_leaves_the_weighted_line_as_it_was() {
        let cs = on_the_line();
        let pts: Vec<(f64, f64, f64)> = cs.iter().map(|c| (c.x, c.star, weight(c))).collect();
        let plain = weighted_line(&pts).unwrap();
        let l = line_from_columns(&cs, &[], 10, 1).unwrap();
        assert_eq!((l.a, l.b), plain);
    }

    #[test]
    fn a_censored_column_is_the_maximum_of_the_tobit_likelihood() {
        let cs = on_the_line();
        // Open at 50 where the line says 48: it pulls the line up at x = 100.
        let censored = [(100.0, 50.0)];
        let plain = line_from_columns(&cs, &[], 0, 1).unwrap();
        let l = line_from_columns(&cs, &censored, 0, 1).unwrap();
        assert!(l.a * 100.0 + l.b > plain.a * 100.0 + plain.b + 0.1);
        // The EM's line is where the likelihood peaks: no small step in a or b raises it.
        let s = 0.5 * l.scatter;
        let at = log_likelihood(&cs, &censored, s, l.a, l.b);
        for (da, db) in [
            (1e-4, 0.0),
            (-1e-4, 0.0),
            (0.0, 1e-3),
            (0.0, -1e-3),
            (1e-4, -1e-2),
        ] {
            assert!(
                log_likelihood(&cs, &censored, s, l.a + da, l.b + db) <= at + 1e-9,
                "({da}, {db}) is higher"
            );
        }
        // A column censored well below the line says almost nothing.
        let weak = line_from_columns(&cs, &[(100.0, 30.0)], 0, 1).unwrap();
        assert!((weak.a - plain.a).abs() < 1e-6 && (weak.b - plain.b).abs() < 1e-4);
    }
}
