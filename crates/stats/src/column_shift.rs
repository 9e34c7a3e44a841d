//! The shift from sigma = 5 to sigma = 0 column by column, and whether it is one number.
//!
//! [`measure_shift`](crate::measure_shift) fits one delta for every column. Here each
//! (L, alpha) column that has a model crossing at both sigmas gives its own:
//! delta_c = (beta*_0 - beta*_5) / (a k(L)), with k = dx/dalpha and a the sigma = 5 line's
//! slope, so delta_c is how far along alpha the sigma = 5 line must move to pass through this
//! column's sigma = 0 crossing. The two crossings share their prepped cells (SPEC section 6: a
//! prep's seed ignores sigma), so the pair differs by adhesion alone.
//!
//! Its 95% interval combines the two columns' split normals (the sigma = 0 spread below with
//! the sigma = 5 spread above for the lower side, and the other two for the upper). Whether one
//! delta fits them all is the homogeneity test: chi^2 = sum w_c (delta_c - mean)^2 about their
//! weighted mean (w_c = 1 / sd_c^2) on n - 1 degrees of freedom; the mean's interval is widened
//! by Birge's ratio sqrt(chi^2 / (n - 1)) where that is above 1. A small p says the shift
//! depends on the column, and one delta is an average over the columns measured, not a
//! constant of the model.

use serde::{Deserialize, Serialize};

use crate::axes::column_key;
use crate::distributions::{chi_square_survival, Z95};
use crate::fit::{Column, Scales};

/// One column's shift.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct ColumnShift {
    pub L: u32,
    pub alpha: f64,
    /// The two crossings it comes from.
    pub beta_star_sigma5: f64,
    pub beta_star_sigma0: f64,
    pub delta: f64,
    pub delta_ci: [f64; 2],
}

/// The columns' shifts and the test of one delta for all of them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColumnShifts {
    pub columns: Vec<ColumnShift>,
    /// Their weighted mean and its 95% interval (from their spreads, widened by Birge's ratio
    /// sqrt(chi^2 / df) where that is above 1).
    pub mean: f64,
    pub mean_ci: [f64; 2],
    /// chi^2 of the columns about the mean, its degrees of freedom and p-value.
    pub chi2: f64,
    pub df: usize,
    pub p: f64,
}

/// The shift of every column with a crossing at both sigmas (sigma 5 and 0 at the same L,
/// alpha and other axes), `a` the slope of the sigma = 5 line. None with fewer than two pairs.
pub fn column_shifts(cols: &[Column], scales: &Scales, a: f64) -> Option<ColumnShifts> {
    if !(a.is_finite() && a.abs() > 1e-12) {
        return None;
    }
    let mut shifts = Vec::new();
    let mut sds = Vec::new();
    for zero in cols.iter().filter(|c| c.sigma == 0.0) {
        let key = column_key(zero.alpha, zero.L, 5.0, &zero.others);
        let Some(five) = cols.iter().find(|c| c.key() == key) else {
            continue;
        };
        let (Some(x0), Some(x5)) = (zero.crossing(), five.crossing()) else {
            continue;
        };
        let at = scales.at(&zero.others);
        // a k: how far beta* moves per unit of alpha along the sigma = 5 line.
        let per_alpha = a * (at.x(1.0, zero.L, 5.0) - at.x(0.0, zero.L, 5.0));
        let delta = (x0.star - x5.star) / per_alpha;
        let below = x0.below.hypot(x5.above) / per_alpha.abs();
        let above = x0.above.hypot(x5.below) / per_alpha.abs();
        let (below, above) = if per_alpha > 0.0 {
            (below, above)
        } else {
            (above, below)
        };
        shifts.push(ColumnShift {
            L: zero.L,
            alpha: zero.alpha,
            beta_star_sigma5: x5.star,
            beta_star_sigma0: x0.star,
            delta,
            delta_ci: [delta - Z95 * below, delta + Z95 * above],
        });
        sds.push((x0.sd().hypot(x5.sd()) / per_alpha.abs()).max(1e-9));
    }
    if shifts.len() < 2 {
        return None;
    }
    let w: Vec<f64> = sds.iter().map(|s| 1.0 / (s * s)).collect();
    let sw: f64 = w.iter().sum();
    let mean = shifts.iter().zip(&w).map(|(s, w)| w * s.delta).sum::<f64>() / sw;
    let chi2: f64 = shifts
        .iter()
        .zip(&w)
        .map(|(s, w)| w * (s.delta - mean).powi(2))
        .sum();
    let df = shifts.len() - 1;
    // Where the columns scatter more than their spreads allow, the mean's interval is widened
    // by Birge's ratio, as the line's are: it then speaks for the columns measured.
    let half = Z95 / sw.sqrt() * (chi2 / df as f64).sqrt().max(1.0);
    shifts.sort_by(|p, q| p.L.cmp(&q.L).then(p.alpha.total_cmp(&q.alpha)));
    Some(ColumnShifts {
        columns: shifts,
        mean,
        mean_ci: [mean - half, mean + half],
        chi2,
        df,
        p: chi_square_survival(chi2, df as f64),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::Method;

    /// A column with its crossing at `star`, an interval of +-`half` about it.
    fn col(l: u32, sigma: f64, alpha: f64, star: f64, half: f64) -> Column {
        let s = Scales::default();
        Column {
            L: l,
            sigma,
            alpha,
            others: Default::default(),
            x: s.x(alpha, l, sigma),
            beta_star: Some(star),
            beta_ci: Some([star - half, star + half]),
            skipped: None,
            method: Method::Model,
            interpolated: None,
            interpolated_ci: None,
            model: None,
            censored_above: None,
        }
    }

    /// The sigma = 0 crossing of the line 0.6 x - 12 moved by `delta` along alpha.
    fn moved(l: u32, alpha: f64, delta: f64) -> f64 {
        Scales::default().beta_on_line(0.6, -12.0, alpha + delta, l, 5.0)
    }

    #[test]
    fn each_column_s_shift_is_read_back_and_one_shift_for_all_passes_the_test() {
        let s = Scales::default();
        let mut cols = Vec::new();
        for l in [90, 80, 70] {
            for alpha in [0.10, 0.12, 0.14] {
                cols.push(col(l, 5.0, alpha, moved(l, alpha, 0.0), 0.5));
                cols.push(col(l, 0.0, alpha, moved(l, alpha, 0.008), 0.5));
            }
        }
        // A sigma = 0 column without its sigma = 5 partner is left out.
        cols.push(col(60, 0.0, 0.1, 30.0, 0.5));
        let m = column_shifts(&cols, &s, 0.6).unwrap();
        assert_eq!(m.columns.len(), 9);
        for c in &m.columns {
            assert!((c.delta - 0.008).abs() < 1e-12, "{c:?}");
            // sd of the difference sqrt(2) * 0.5 / 1.96 in beta, over a k in alpha.
            let per_alpha = 0.6 * (s.x(1.0, c.L, 5.0) - s.x(0.0, c.L, 5.0));
            let half = 0.5 * 2f64.sqrt() / per_alpha;
            assert!((c.delta_ci[1] - c.delta - half).abs() < 1e-9, "{c:?}");
            assert!((c.delta - c.delta_ci[0] - half).abs() < 1e-9, "{c:?}");
        }
        assert!((m.mean - 0.008).abs() < 1e-12 && m.chi2 < 1e-12 && m.df == 8);
        assert!(m.p > 0.99, "{m:?}");
        assert!(m.mean_ci[0] < 0.008 && 0.008 < m.mean_ci[1]);
    }

    #[test]
    fn a_shift_that_grows_with_alpha_fails_the_test_of_one_shift() {
        let s = Scales::default();
        let mut cols = Vec::new();
        for l in [90, 80, 70] {
            for (j, alpha) in [0.10, 0.12, 0.14, 0.16].into_iter().enumerate() {
                // 0.004 to 0.013 in alpha, each column 0.25 wide in beta.
                let delta = 0.004 + 0.003 * j as f64;
                cols.push(col(l, 5.0, alpha, moved(l, alpha, 0.0), 0.25));
                cols.push(col(l, 0.0, alpha, moved(l, alpha, delta), 0.25));
            }
        }
        let m = column_shifts(&cols, &s, 0.6).unwrap();
        assert_eq!((m.columns.len(), m.df), (12, 11));
        assert!(m.p < 1e-6, "{m:?}");
        let first = &m.columns[0];
        assert_eq!((first.L, first.alpha), (70, 0.10));
        assert!((first.delta - 0.004).abs() < 1e-12);
        // The mean, chi^2 and the mean's interval from the known shifts and spreads: each
        // column's sd in alpha is sqrt(2) (0.25 / z) / (0.6 k(L)), weight 1 / sd^2.
        let (mut sw, mut swd) = (0.0, 0.0);
        let mut known = Vec::new();
        for l in [90u32, 80, 70] {
            let k = 2.0 * std::f64::consts::PI * 40.0 * 20f64.sqrt() * 40.0 / l as f64;
            let sd = 2f64.sqrt() * 0.25 / 1.959_963_984_540_054 / (0.6 * k);
            for j in 0..4 {
                let (w, d) = (1.0 / (sd * sd), 0.004 + 0.003 * j as f64);
                sw += w;
                swd += w * d;
                known.push((w, d));
            }
        }
        let mean = swd / sw;
        let chi2: f64 = known.iter().map(|(w, d)| w * (d - mean).powi(2)).sum();
        assert!((m.mean - mean).abs() < 1e-12, "{m:?}");
        assert!((m.chi2 / chi2 - 1.0).abs() < 1e-9, "{m:?} {chi2}");
        // The mean's interval is widened by the scatter: sqrt(chi^2 / df) times the spreads'.
        let half = 1.959_963_984_540_054 / sw.sqrt() * (chi2 / 11.0).sqrt();
        assert!((m.mean_ci[1] - m.mean - half).abs() < 1e-9, "{m:?}");
        assert!((m.mean - m.mean_ci[0] - half).abs() < 1e-9, "{m:?}");
    }

    #[test]
    fn fewer_than_two_pairs_or_no_slope_give_nothing() {
        let s = Scales::default();
        let cols = vec![
            col(90, 5.0, 0.1, 20.0, 0.5),
            col(90, 0.0, 0.1, 21.0, 0.5),
            col(80, 5.0, 0.1, 24.0, 0.5),
        ];
        assert!(column_shifts(&cols, &s, 0.6).is_none());
        let mut two = cols.clone();
        two.push(col(80, 0.0, 0.1, 25.0, 0.5));
        assert!(column_shifts(&two, &s, 0.6).is_some());
        assert!(column_shifts(&two, &s, 0.0).is_none());
        assert!(column_shifts(&two, &s, f64::NAN).is_none());
    }
}
