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

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::distributions::Z95;
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

/// The line through the columns' model crossings, with `draws` draws for its intervals.
pub(crate) fn line_from_columns(cs: &[Crossing], draws: usize, seed: u64) -> Option<ModelLine> {
    let pts: Vec<(f64, f64, f64)> = cs.iter().map(|c| (c.x, c.star, weight(c))).collect();
    let (a, b) = weighted_line(&pts)?;
    let scatter = birge(
        cs.iter()
            .map(|c| (c.star - (a * c.x + b)) / c.sd().max(1e-3)),
        2,
    );
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
        if let Some((ad, bd)) = weighted_line(&drawn) {
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
