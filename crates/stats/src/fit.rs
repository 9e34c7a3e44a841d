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

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::axes::{ColumnKey, Others};
use crate::column_model::{fit_column, ColumnModel, NoModelCrossing, WalkTrain};
use crate::counts::Counts;
use crate::interpolation::{crossing, least_squares, resample_diffs};
use crate::model_line::{line_from_columns, Crossing};
use crate::sampling::percentile_95;

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
    /// A column open at the grid's last beta (walk-past reaches one half only there): its
    /// beta* lies above this value, and the model's line counts it so (censored, SPEC 6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub censored_above: Option<f64>,
}

impl Column {
    /// The column's identity, as [`Counts::column`] gives it.
    pub fn key(&self) -> ColumnKey {
        crate::axes::column_key(self.alpha, self.L, self.sigma, &self.others)
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
                censored_above: None,
            }
        })
        .collect()
}

pub(crate) fn points_of(cols: &[Column]) -> Vec<(f64, f64)> {
    cols.iter()
        .filter_map(|c| c.beta_star.map(|b| (c.x, b)))
        .collect()
}

/// The walk-past and training counts of each collided point of column `c`.
pub(crate) fn tallies(counts: &[Counts], c: &Column) -> Vec<WalkTrain> {
    counts
        .iter()
        .filter(|p| p.column() == c.key() && p.collided())
        .map(|p| WalkTrain {
            beta: p.beta,
            walk: p.n_walk(),
            train: p.n_train(),
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
    let observed = |i: usize| counts[i].n_walk() as i64 - counts[i].n_train() as i64;
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
                        if let NoModelCrossing::Open { side: "last", beta } = why {
                            c.censored_above = Some(beta);
                        }
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
    if method == Method::Model {
        return fit_columns(cols, resamples, seed);
    }
    let xy = points_of(&cols);
    match least_squares(&xy) {
        Some((a, b, r2)) if distinct_x(&xy) >= 2 => Ok(Fit {
            a,
            b,
            a_ci: percentile_95(&mut as_),
            b_ci: percentile_95(&mut bs),
            r2,
            paper_a: PAPER_A,
            paper_b: PAPER_B,
            bootstrap: resamples,
            method,
            scatter: None,
            columns: cols,
        }),
        _ => Err(NoFit::of(cols)),
    }
}

/// The line through columns the model has read (`Method::Model`), with `draws` draws from
/// their intervals for its own: one sweep's columns, or columns pooled from several sweeps,
/// each at its own x (its own R0, d, L and sigma). This is the collapse test: if beta* depends
/// on the parameters only through alpha~/L~, every column lies on this one line.
pub fn fit_columns(columns: Vec<Column>, draws: usize, seed: u64) -> Result<Fit, NoFit> {
    if distinct_x(&points_of(&columns)) < 2 {
        return Err(NoFit::of(columns));
    }
    let censored: Vec<(f64, f64)> = columns
        .iter()
        .filter_map(|c| Some((c.x, c.censored_above?)))
        .collect();
    match line_from_columns(&crossings(&columns), &censored, draws, seed) {
        Some(l) => Ok(Fit {
            a: l.a,
            b: l.b,
            a_ci: l.a_ci,
            b_ci: l.b_ci,
            r2: l.r2,
            paper_a: PAPER_A,
            paper_b: PAPER_B,
            bootstrap: draws,
            method: Method::Model,
            scatter: Some(l.scatter),
            columns,
        }),
        None => Err(NoFit::of(columns)),
    }
}

/// The number of distinct x among crossings.
fn distinct_x(xy: &[(f64, f64)]) -> usize {
    let mut xs: Vec<f64> = xy.iter().map(|p| p.0).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    xs.len()
}

impl NoFit {
    /// No line through `columns`: too few of them cross, at too few distinct x.
    fn of(columns: Vec<Column>) -> NoFit {
        let xy = points_of(&columns);
        NoFit {
            reason: format!(
                "{} of {} columns have a walk-past/training crossing, at {} distinct alpha~/L~; \
                 a line needs two",
                xy.len(),
                columns.len(),
                distinct_x(&xy)
            ),
            columns,
        }
    }
}
