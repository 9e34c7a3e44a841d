//! The beta_crit line (SPEC section 6): per (L, sigma, alpha) column a beta*, then
//! beta* = a alpha~ / L~ + b, with alpha~ = 2 pi R0 d alpha_eff / eps0,
//! alpha_eff = alpha + 0.002683 (5 - sigma) (the adhesion shift) and L~ = L / R0.
//!
//! Two readings of a column ([`Method`]):
//! - `model` (the default): the logistic model of the whole column ([`crate::column_model`]),
//!   with its profile-likelihood interval; the line by weighted least squares, its intervals
//!   from the columns' intervals (`model_line`);
//! - `interpolate` (the paper's): where n_walk - n_train changes sign as beta rises, linear
//!   between grid points; the line by least squares, with intervals by bootstrap over
//!   replicates (each point's counts redrawn from its observed frequencies).
//!
//! Each column keeps the interpolated crossing beside the model's, whichever is primary.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::axes::{ColumnKey, Others};
use crate::column_model::{fit_column, ColumnModel, Tally};
use crate::counts::Counts;
use crate::model_line::{line_from_columns, Crossing};
use crate::sampling::{percentile_95, standard_normal};

/// How a column's beta* is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// The logistic model of the whole column, with its profile-likelihood interval.
    #[default]
    Model,
    /// Linear interpolation of n_walk - n_train between grid points (the paper's reading).
    Interpolate,
}

impl Method {
    pub fn as_str(self) -> &'static str {
        match self {
            Method::Model => "model",
            Method::Interpolate => "interpolate",
        }
    }
}

/// The paper's fit: beta_crit = 0.6 alpha~ / L~ - 12.
pub const PAPER_A: f64 = 0.6;
pub const PAPER_B: f64 = -12.0;
/// Line-tension shift per unit of missing adhesion (SPEC section 6): 0.0134 / 5.
pub const SIGMA_SHIFT: f64 = 0.002683;

/// Scales of the nondimensionalisation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Scales {
    pub R0: f64,
    pub d: f64,
}

impl Default for Scales {
    fn default() -> Self {
        Scales {
            R0: 40.0,
            d: 20f64.sqrt(),
        }
    }
}

impl Scales {
    /// The scales at a point whose sweep varies R0 or d: its own values over these.
    pub fn at(&self, others: &Others) -> Scales {
        Scales {
            R0: others.get("R0").unwrap_or(self.R0),
            d: others.get("d").unwrap_or(self.d),
        }
    }

    /// x = alpha~ / L~ of a column, with the adhesion shift.
    pub fn x(&self, alpha: f64, spacing: u32, sigma: f64) -> f64 {
        let alpha_eff = alpha + SIGMA_SHIFT * (5.0 - sigma);
        let alpha_t = 2.0 * PI * self.R0 * self.d * alpha_eff;
        alpha_t / (spacing as f64 / self.R0)
    }

    /// The paper's (or any) line in the (alpha, beta) plane of one (L, sigma) diagram.
    pub fn beta_on_line(&self, a: f64, b: f64, alpha: f64, spacing: u32, sigma: f64) -> f64 {
        a * self.x(alpha, spacing, sigma) + b
    }
}

/// One (L, sigma, alpha) column of the fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Column {
    pub L: u32,
    pub sigma: f64,
    pub alpha: f64,
    /// The sweep's other axes in this column (empty for the paper's four).
    #[serde(default, skip_serializing_if = "Others::is_empty")]
    pub others: Others,
    /// alpha~ / L~ with the sigma shift, at the column's own R0 and d.
    pub x: f64,
    /// The crossing by `method`, if the column has one.
    pub beta_star: Option<f64>,
    /// Its 95% interval: the model's profile likelihood, or the interpolation's bootstrap
    /// (where at least half the resamples have a crossing).
    #[serde(default)]
    pub beta_ci: Option<[f64; 2]>,
    /// Why the column has no beta* by `method`, if it has none.
    pub skipped: Option<String>,
    /// How beta_star was read.
    #[serde(default = "interpolate")]
    pub method: Method,
    /// The paper's reading beside it: the interpolated crossing and its bootstrap interval.
    #[serde(default)]
    pub interpolated: Option<f64>,
    #[serde(default)]
    pub interpolated_ci: Option<[f64; 2]>,
    /// The model's fit (slope, deviance, dispersion), where it gives a crossing.
    #[serde(default)]
    pub model: Option<ColumnModel>,
}

impl Column {
    /// The column's identity, as [`Counts::column`] gives it.
    pub fn key(&self) -> ColumnKey {
        (
            self.alpha.to_bits(),
            self.L,
            self.sigma.to_bits(),
            self.others.bits(),
        )
    }

    /// Its crossing with the spreads of its interval, where it has both.
    pub(crate) fn crossing(&self) -> Option<Crossing> {
        Some(Crossing::new(self.x, self.beta_star?, self.beta_ci?))
    }
}

/// The crossings of the columns that have one.
fn crossings(cols: &[Column]) -> Vec<Crossing> {
    cols.iter().filter_map(Column::crossing).collect()
}

/// Columns written before the model read beta* by interpolation.
fn interpolate() -> Method {
    Method::Interpolate
}

/// The fitted line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fit {
    pub a: f64,
    pub b: f64,
    pub a_ci: [f64; 2],
    pub b_ci: [f64; 2],
    pub r2: f64,
    pub paper_a: f64,
    pub paper_b: f64,
    /// Resamples (interpolate) or draws from the columns' intervals (model) behind the
    /// intervals of a and b.
    pub bootstrap: usize,
    /// How the columns' beta* were read.
    #[serde(default = "interpolate")]
    pub method: Method,
    /// With the model: the scatter of the columns about the line relative to their intervals
    /// (Birge's ratio, sqrt(chi^2 / df)); above 1, the line's intervals were widened by it.
    #[serde(default)]
    pub scatter: Option<f64>,
    pub columns: Vec<Column>,
}

/// Why a fit could not be made, with the columns examined.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoFit {
    pub reason: String,
    pub columns: Vec<Column>,
}

/// Why a column has no beta*.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum NoCrossing {
    #[error("{0} usable point(s); a crossing needs two")]
    TooFew(usize),
    #[error("training at least as frequent as walk-past at every beta")]
    TrainEverywhere,
    #[error("walk-past at least as frequent as training at every beta")]
    WalkEverywhere,
    #[error("n_walk - n_train never rises through zero")]
    NeverRises,
}

/// beta* of one column (points sorted by beta): the first sign change of n_walk - n_train
/// from training to walk-past, interpolated linearly.
fn crossing(points: &[(f64, i64)]) -> Result<f64, NoCrossing> {
    if points.len() < 2 {
        return Err(NoCrossing::TooFew(points.len()));
    }
    for w in points.windows(2) {
        let ((b0, d0), (b1, d1)) = (w[0], w[1]);
        // Training more frequent at b0, walk-past at least as frequent at b1 (exactly b1 if equal).
        if d0 < 0 && d1 >= 0 {
            return Ok(b0 + (b1 - b0) * (-d0) as f64 / (d1 - d0) as f64);
        }
    }
    if points.iter().all(|&(_, d)| d <= 0) {
        Err(NoCrossing::TrainEverywhere)
    } else if points.iter().all(|&(_, d)| d >= 0) {
        Err(NoCrossing::WalkEverywhere)
    } else {
        Err(NoCrossing::NeverRises)
    }
}

/// The columns of `counts` with their crossings; `diff` gives n_walk - n_train of a point.
pub(crate) fn columns(
    counts: &[Counts],
    scales: &Scales,
    diff: &dyn Fn(usize) -> i64,
) -> Vec<Column> {
    let mut firsts: Vec<&Counts> = Vec::new();
    for c in counts {
        if !firsts.iter().any(|f| f.column() == c.column()) {
            firsts.push(c);
        }
    }
    firsts.sort_by(|x, y| {
        (x.L.cmp(&y.L))
            .then(x.sigma.total_cmp(&y.sigma))
            .then(x.alpha.total_cmp(&y.alpha))
            .then(x.others.bits().cmp(&y.others.bits()))
    });
    firsts
        .into_iter()
        .map(|first| {
            let (l, sigma, alpha) = (first.L, first.sigma, first.alpha);
            let key = first.column();
            let mut pts: Vec<(f64, i64)> = counts
                .iter()
                .enumerate()
                .filter(|(_, c)| c.column() == key && c.collided())
                .map(|(i, c)| (c.beta, diff(i)))
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (beta_star, skipped) = match crossing(&pts) {
                Ok(b) => (Some(b), None),
                Err(why) => (None, Some(why.to_string())),
            };
            Column {
                L: l,
                sigma,
                alpha,
                others: first.others.clone(),
                x: scales.at(&first.others).x(alpha, l, sigma),
                beta_star,
                beta_ci: None,
                skipped,
                method: Method::Interpolate,
                interpolated: beta_star,
                interpolated_ci: None,
                model: None,
            }
        })
        .collect()
}

/// Least squares y = a x + b; (a, b, R^2). Needs two distinct x.
pub(crate) fn least_squares(xy: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let n = xy.len() as f64;
    if xy.len() < 2 {
        return None;
    }
    let mx = xy.iter().map(|p| p.0).sum::<f64>() / n;
    let my = xy.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 1e-12 * mx.abs().max(1.0) {
        return None;
    }
    let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let a = sxy / sxx;
    let b = my - a * mx;
    let ss_tot: f64 = xy.iter().map(|p| (p.1 - my).powi(2)).sum();
    let ss_res: f64 = xy.iter().map(|p| (p.1 - (a * p.0 + b)).powi(2)).sum();
    let r2 = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    Some((a, b, r2))
}

pub(crate) fn points_of(cols: &[Column]) -> Vec<(f64, f64)> {
    cols.iter()
        .filter_map(|c| c.beta_star.map(|b| (c.x, b)))
        .collect()
}

/// The walk-past and training counts of each collided point of column `c`.
pub(crate) fn tallies(counts: &[Counts], c: &Column) -> Vec<Tally> {
    counts
        .iter()
        .filter(|p| p.column() == c.key() && p.collided())
        .map(|p| Tally {
            beta: p.beta,
            walk: p.n_walk,
            train: p.n_train,
        })
        .collect()
}

/// The columns of `counts` read by `method`, each with the interpolated crossing beside, and
/// the bootstrap's (a, b) resamples of the interpolated line.
pub(crate) fn read_columns(
    counts: &[Counts],
    scales: &Scales,
    resamples: usize,
    seed: u64,
    method: Method,
) -> (Vec<Column>, Vec<f64>, Vec<f64>) {
    let observed = |i: usize| counts[i].n_walk as i64 - counts[i].n_train as i64;
    let mut cols = columns(counts, scales, &observed);
    // Bootstrap: redraw every point's replicates from its observed outcome frequencies.
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut as_, mut bs) = (Vec::new(), Vec::new());
    let mut stars: Vec<Vec<f64>> = vec![Vec::new(); cols.len()];
    for _ in 0..resamples {
        let diffs = resample_diffs(counts, &mut rng);
        let cols_b = columns(counts, scales, &|i| diffs[i]);
        for (k, c) in cols_b.iter().enumerate() {
            stars[k].extend(c.beta_star);
        }
        if let Some((ab, bb, _)) = least_squares(&points_of(&cols_b)) {
            as_.push(ab);
            bs.push(bb);
        }
    }
    for (c, mut v) in cols.iter_mut().zip(stars) {
        if resamples > 0 && 2 * v.len() >= resamples {
            c.interpolated_ci = Some(percentile_95(&mut v));
        }
        match method {
            Method::Interpolate => c.beta_ci = c.interpolated_ci,
            Method::Model => {
                c.method = Method::Model;
                match fit_column(&tallies(counts, c)) {
                    Ok(m) => {
                        (c.beta_star, c.beta_ci, c.skipped) = (Some(m.beta_star), Some(m.ci), None);
                        c.model = Some(m);
                    }
                    Err(why) => {
                        (c.beta_star, c.beta_ci, c.skipped) = (None, None, Some(why.to_string()))
                    }
                }
            }
        }
    }
    (cols, as_, bs)
}

/// Fit beta* = a alpha~ / L~ + b to `counts`, the columns read by `method`; `resamples`
/// bootstrap resamples (interpolate) or draws from the columns' intervals (model), seeded.
pub fn fit_line(
    counts: &[Counts],
    scales: &Scales,
    resamples: usize,
    seed: u64,
    method: Method,
) -> Result<Fit, NoFit> {
    let (cols, mut as_, mut bs) = read_columns(counts, scales, resamples, seed, method);
    let xy = points_of(&cols);
    let distinct: Vec<f64> = xy.iter().fold(Vec::new(), |mut v, p| {
        if !v.contains(&p.0) {
            v.push(p.0)
        }
        v
    });
    let no_fit = |cols: Vec<Column>| {
        NoFit {
        reason: format!(
            "{} of {} columns have a walk-past/training crossing, at {} distinct alpha~/L~; a line needs two",
            xy.len(),
            cols.len(),
            distinct.len()
        ),
        columns: cols,
    }
    };
    if distinct.len() < 2 {
        return Err(no_fit(cols));
    }
    let fit = |a, b, a_ci, b_ci, r2, scatter| Fit {
        a,
        b,
        a_ci,
        b_ci,
        r2,
        paper_a: PAPER_A,
        paper_b: PAPER_B,
        bootstrap: resamples,
        method,
        scatter,
        columns: cols.clone(),
    };
    match method {
        Method::Interpolate => match least_squares(&xy) {
            Some((a, b, r2)) => Ok(fit(
                a,
                b,
                percentile_95(&mut as_),
                percentile_95(&mut bs),
                r2,
                None,
            )),
            None => Err(no_fit(cols)),
        },
        Method::Model => match line_from_columns(&crossings(&cols), resamples, seed) {
            Some(l) => Ok(fit(l.a, l.b, l.a_ci, l.b_ci, l.r2, Some(l.scatter))),
            None => Err(no_fit(cols)),
        },
    }
}

/// Above this many collisions a point's resampled difference is drawn from its normal limit
/// rather than replicate by replicate (which would take n draws per point per resample: a count
/// of 10^9 would hold the fit for hours). Simulated and paper data sit far below it.
const EXACT_RESAMPLE_MAX: u64 = 100_000;

/// One bootstrap resample: each point's n_walk - n_train with its replicates redrawn from its
/// observed outcome frequencies (n the point's collisions: each point keeps its own n).
pub(crate) fn resample_diffs(counts: &[Counts], rng: &mut ChaCha8Rng) -> Vec<i64> {
    counts
        .iter()
        .map(|c| {
            let n = c.collisions();
            if n == 0 {
                return 0;
            }
            let (pt, pw) = (c.n_train as f64 / n as f64, c.n_walk as f64 / n as f64);
            if n > EXACT_RESAMPLE_MAX {
                // d = sum of n draws of +1 (pw), -1 (pt), 0: mean n (pw - pt),
                // variance n (pw + pt - (pw - pt)^2), clamped to [-n, n].
                let (nf, m) = (n as f64, pw - pt);
                let sd = (nf * (pw + pt - m * m)).max(0.0).sqrt();
                let d = (nf * m + sd * standard_normal(rng)).round();
                return d.clamp(-nf, nf) as i64;
            }
            let mut d = 0i64;
            for _ in 0..n {
                let u: f64 = rng.random();
                if u < pt {
                    d -= 1;
                } else if u < pt + pw {
                    d += 1;
                }
            }
            d
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point of `n` collisions, `w` walk-pasts and `t` trainings.
    fn point(n: u64, w: u64, t: u64) -> Counts {
        let mut c = Counts::none(0.1, 10.0, 90, 5.0);
        (c.n_walk, c.n_train, c.n_reversal) = (w, t, n - w - t);
        c
    }

    /// A count far past the exact draw resamples from the normal limit: every difference lies
    /// in [-n, n], and their mean and spread are the multinomial's, n (pw - pt) and
    /// sqrt(n (pw + pt - (pw - pt)^2)).
    #[test]
    fn huge_counts_resample_from_the_normal_limit() {
        let n = 1_000_000_000u64;
        let c = [point(n, n / 2, n / 4)];
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let d: Vec<f64> = (0..2000)
            .map(|_| resample_diffs(&c, &mut rng)[0] as f64)
            .collect();
        assert!(d.iter().all(|x| x.abs() <= n as f64));
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64).sqrt();
        let want_sd = (n as f64 * (0.75 - 0.0625)).sqrt();
        assert!((mean - n as f64 / 4.0).abs() < 4.0 * want_sd / (d.len() as f64).sqrt());
        assert!((sd / want_sd - 1.0).abs() < 0.1, "sd {sd} vs {want_sd}");
        // A point all one way stays all one way.
        let all = [point(n, n, 0)];
        assert_eq!(resample_diffs(&all, &mut rng), vec![n as i64]);
    }
}
