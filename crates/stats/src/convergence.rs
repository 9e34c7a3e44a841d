//! Is it converged? Each column's beta* under a variant of the numerics (dt halved, a wider or
//! taller box, f64 collisions, a finer lattice) against the same column of a baseline.
//!
//! Both sides are read by the model of the whole column ([`crate::fit_column`]); a column
//! compared is one both sets hold (same alpha, L, sigma and other axes). The difference
//! d = beta*_variant - beta*_baseline has a 95% interval from the two split normals (the
//! variant's spread below with the baseline's above for the lower side, and the other two for
//! the upper): the two are independent samples where the variant's seeds differ (a new dt is a
//! new prep), and the interval is then exact to the normal approximation; where they share
//! preps and seeds (a wider box) the pairs are positively correlated, and the interval is
//! conservative. The verdict is `agrees` when that interval holds 0 and `moves` when it does
//! not; how small a move the check could see is the interval's half-width, reported beside it.

use serde::{Deserialize, Serialize};

use crate::axes::Others;
use crate::counts::Counts;
use crate::distributions::Z95;
use crate::fit::{read_columns, Column, Method, Scales};
use crate::model_line::Crossing;

/// What the comparison of one column says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The difference's 95% interval holds 0.
    Agrees,
    /// It does not: the variant moves beta*.
    Moves,
    /// One side has no crossing (its reason is given): nothing to compare yet.
    Open,
}

impl Verdict {
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Agrees => "agrees",
            Verdict::Moves => "moves",
            Verdict::Open => "open",
        }
    }
}

/// One side's crossing of a column.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Side {
    pub beta_star: Option<f64>,
    pub ci: Option<[f64; 2]>,
    /// Collisions with walk-past or training that the column's model used.
    pub collisions: u64,
    /// Why there is no crossing, where there is none.
    pub skipped: Option<String>,
}

/// One column in both sets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct ColumnChange {
    pub L: u32,
    pub sigma: f64,
    pub alpha: f64,
    #[serde(default, skip_serializing_if = "Others::is_empty")]
    pub others: Others,
    pub baseline: Side,
    pub variant: Side,
    /// beta*_variant - beta*_baseline and its 95% interval, where both have a crossing.
    pub difference: Option<f64>,
    pub difference_ci: Option<[f64; 2]>,
    pub verdict: Verdict,
}

/// Every column both sets hold, each read by the model, in (L, sigma, alpha) order.
pub fn compare_columns(
    baseline: &[Counts],
    baseline_scales: &Scales,
    variant: &[Counts],
    variant_scales: &Scales,
) -> Vec<ColumnChange> {
    let (base, _, _) = read_columns(baseline, baseline_scales, 0, 0, Method::Model);
    let (var, _, _) = read_columns(variant, variant_scales, 0, 0, Method::Model);
    let mut out = Vec::new();
    for v in &var {
        let Some(b) = base.iter().find(|b| b.key() == v.key()) else {
            continue;
        };
        let (difference, difference_ci, verdict) = match (b.crossing(), v.crossing()) {
            (Some(xb), Some(xv)) => {
                let d = xv.star - xb.star;
                let ci = difference_interval(&xb, &xv);
                let verdict = if ci[0] <= 0.0 && 0.0 <= ci[1] {
                    Verdict::Agrees
                } else {
                    Verdict::Moves
                };
                (Some(d), Some(ci), verdict)
            }
            _ => (None, None, Verdict::Open),
        };
        out.push(ColumnChange {
            L: v.L,
            sigma: v.sigma,
            alpha: v.alpha,
            others: v.others.clone(),
            baseline: side(baseline, b),
            variant: side(variant, v),
            difference,
            difference_ci,
            verdict,
        });
    }
    out.sort_by(|p, q| {
        (p.L, p.sigma, p.alpha)
            .partial_cmp(&(q.L, q.sigma, q.alpha))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    out
}

/// The 95% interval of `variant - baseline` from the two split normals.
fn difference_interval(baseline: &Crossing, variant: &Crossing) -> [f64; 2] {
    let d = variant.star - baseline.star;
    [
        d - Z95 * variant.below.hypot(baseline.above),
        d + Z95 * variant.above.hypot(baseline.below),
    ]
}

fn side(counts: &[Counts], c: &Column) -> Side {
    let collisions = crate::fit::tallies(counts, c)
        .iter()
        .map(|t| t.walk + t.train)
        .sum();
    Side {
        beta_star: c.beta_star,
        ci: c.beta_ci,
        collisions,
        skipped: c.skipped.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::end::End;
    use rand::{Rng, SeedableRng};

    /// A column (L 90, sigma 5, alpha 0.10) with its crossing at `star` and logistic scale 1.5,
    /// sampled at beta 10..42 step 2 with `n` replicates each.
    fn column(star: f64, n: u64, rng: &mut rand_chacha::ChaCha8Rng) -> Vec<Counts> {
        (0..17)
            .map(|j| {
                let beta = 10.0 + 2.0 * j as f64;
                let p = 1.0 / (1.0 + (-(beta - star) / 1.5).exp());
                let walk = (0..n).filter(|_| rng.random::<f64>() < p).count() as u64;
                Counts {
                    tally: [(End::WalkPast, walk), (End::Train, n - walk)]
                        .into_iter()
                        .collect(),
                    ..Counts::none(0.10, beta, 90, 5.0)
                }
            })
            .collect()
    }

    #[test]
    fn a_variant_with_the_baseline_s_crossing_agrees_and_a_shifted_one_moves() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let s = Scales::default();
        let (mut agree_same, mut move_shifted) = (0, 0);
        let trials = 200;
        for _ in 0..trials {
            let base = column(25.0, 48, &mut rng);
            let same = compare_columns(&base, &s, &column(25.0, 48, &mut rng), &s);
            let shifted = compare_columns(&base, &s, &column(28.0, 48, &mut rng), &s);
            assert_eq!((same.len(), shifted.len()), (1, 1));
            agree_same += (same[0].verdict == Verdict::Agrees) as usize;
            move_shifted += (shifted[0].verdict == Verdict::Moves) as usize;
            let d = shifted[0].difference.unwrap();
            assert!((d - 3.0).abs() < 2.0, "{d}");
        }
        // About 95% of identical columns agree (the interval's coverage); a shift of 3 (twice
        // the logistic scale) is seen nearly always at 48 replicates a point.
        assert!(agree_same >= trials * 90 / 100, "{agree_same} of {trials}");
        assert!(
            move_shifted >= trials * 90 / 100,
            "{move_shifted} of {trials}"
        );
    }

    #[test]
    fn a_column_without_a_crossing_on_one_side_is_open_and_columns_pair_by_key() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let s = Scales::default();
        let base = column(25.0, 48, &mut rng);
        // The variant trains everywhere it was sampled.
        let all_train: Vec<Counts> = column(80.0, 48, &mut rng);
        let c = compare_columns(&base, &s, &all_train, &s);
        assert_eq!(c[0].verdict, Verdict::Open);
        assert!(c[0].variant.skipped.is_some() && c[0].difference.is_none());
        // A variant column the baseline lacks is not compared.
        let other: Vec<Counts> = column(25.0, 48, &mut rng)
            .into_iter()
            .map(|p| Counts { L: 70, ..p })
            .collect();
        assert!(compare_columns(&base, &s, &other, &s).is_empty());
    }

    fn crossing(star: f64, half: f64) -> Crossing {
        Crossing::new(0.0, star, [star - half, star + half])
    }

    #[test]
    fn the_difference_interval_adds_the_two_spreads_in_quadrature() {
        // Two intervals of +-1.96 (sd 1): the difference has sd sqrt(2).
        let ci = difference_interval(&crossing(20.0, Z95), &crossing(21.0, Z95));
        let half = Z95 * 2f64.sqrt();
        assert!((ci[0] - (1.0 - half)).abs() < 1e-12 && (ci[1] - (1.0 + half)).abs() < 1e-12);
        // A split interval: the variant's lower spread pairs with the baseline's upper.
        let b = Crossing::new(0.0, 20.0, [20.0 - Z95 * 3.0, 20.0 + Z95 * 4.0]);
        let v = Crossing::new(0.0, 25.0, [25.0 - Z95 * 1.0, 25.0 + Z95 * 2.0]);
        let ci = difference_interval(&b, &v);
        assert!((ci[0] - (5.0 - Z95 * 17f64.sqrt())).abs() < 1e-9);
        assert!((ci[1] - (5.0 + Z95 * 13f64.sqrt())).abs() < 1e-9);
    }
}
