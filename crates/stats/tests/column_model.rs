//! The column model validated by simulation (issue 28): columns drawn from known logistic
//! curves, with slopes and replicate counts like the paper's adaptive diagrams, must get 95%
//! intervals that cover the true beta* 93-97% of the time with a bias below 0.2, and columns
//! without a crossing must never be given one.
//!
//! The real diagrams (data/paper) have rows beta = 10, 14, ..., 50, and their walk-past
//! columns fit slopes k = 0.13 to 0.77 per unit beta (a rise from 0.1 to 0.9 over 6 to 34 in beta); the
//! adaptive rule spends up to 96 replicates near the crossing and 16 to 40 far from it.

use cellsweep_stats::{fit_column, NoModelCrossing, WalkTrain};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ROWS: [f64; 11] = [
    10.0, 14.0, 18.0, 22.0, 26.0, 30.0, 34.0, 38.0, 42.0, 46.0, 50.0,
];

fn sigmoid(z: f64) -> f64 {
    1.0 / (1.0 + (-z).exp())
}

fn binomial(rng: &mut ChaCha8Rng, n: u64, p: f64) -> u64 {
    (0..n).filter(|_| rng.random::<f64>() < p).count() as u64
}

/// A column drawn from the walk-past fraction `p(beta)`: replicates as the adaptive rule
/// spends them (96 where the fraction is between 0.15 and 0.85, else 16 to 40), of which 5%
/// end neither in walk-past nor training (reversal, undetermined).
fn draw(rng: &mut ChaCha8Rng, p: &dyn Fn(f64) -> f64) -> Vec<WalkTrain> {
    ROWS.iter()
        .map(|&beta| {
            let q = p(beta);
            let n = if (0.15..=0.85).contains(&q) {
                96
            } else {
                [16, 24, 40][rng.random_range(0..3)]
            };
            let m = binomial(rng, n, 0.95);
            let walk = binomial(rng, m, q);
            WalkTrain {
                beta,
                walk,
                train: m - walk,
            }
        })
        .collect()
}

struct Score {
    columns: usize,
    given: usize,
    covered: usize,
    error_sum: f64,
    width_sum: f64,
}

impl Score {
    fn new() -> Self {
        Score {
            columns: 0,
            given: 0,
            covered: 0,
            error_sum: 0.0,
            width_sum: 0.0,
        }
    }

    fn add(&mut self, col: &[WalkTrain], truth: f64) {
        self.columns += 1;
        if let Ok(m) = fit_column(col) {
            self.given += 1;
            self.covered += usize::from(m.ci[0] <= truth && truth <= m.ci[1]);
            self.error_sum += m.beta_star - truth;
            self.width_sum += m.ci[1] - m.ci[0];
        }
    }

    fn coverage(&self) -> f64 {
        self.covered as f64 / self.given as f64
    }

    fn bias(&self) -> f64 {
        self.error_sum / self.given as f64
    }
}

#[test]
fn intervals_cover_the_true_crossing_at_their_level() {
    let mut rng = ChaCha8Rng::seed_from_u64(28);
    let mut s = Score::new();
    for _ in 0..2000 {
        // Anywhere between the second and the second-last row, on or between rows.
        let star = rng.random_range(14.0..46.0);
        let k = rng.random_range(0.13..0.77);
        let col = draw(&mut rng, &|b| sigmoid(k * (b - star)));
        s.add(&col, star);
    }
    let (cov, bias) = (s.coverage(), s.bias());
    println!(
        "{} of {} columns given a crossing; coverage {:.3}, bias {:+.3}, mean width {:.2}",
        s.given,
        s.columns,
        cov,
        bias,
        s.width_sum / s.given as f64
    );
    assert!((0.93..=0.97).contains(&cov), "coverage {cov}");
    assert!(bias.abs() < 0.2, "bias {bias}");
    assert!(s.given as f64 > 0.9 * s.columns as f64, "given {}", s.given);
}

#[test]
fn columns_that_cross_twice_are_modelled_on_their_first_crossing() {
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let mut s = Score::new();
    let mut cut = 0;
    for _ in 0..500 {
        // Up through one half at `up`, back down at `down`, 16 to 24 later.
        let up = rng.random_range(14.0..26.0);
        let down = up + rng.random_range(16.0..24.0);
        let k = rng.random_range(0.3..0.6);
        let p = move |b: f64| sigmoid(k * (b - up)) * sigmoid(k * (down - b)) * 1.2;
        // The true first crossing, by bisection on the rising side.
        let (mut lo, mut hi) = (up - 20.0, 0.5 * (up + down));
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if p(mid) < 0.5 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let col = draw(&mut rng, &p);
        cut += usize::from(fit_column(&col).is_ok_and(|m| m.cut_at.is_some()));
        s.add(&col, 0.5 * (lo + hi));
    }
    println!(
        "{} of {} given a crossing, {cut} with the second one cut off; coverage {:.3}, bias {:+.3}",
        s.given,
        s.columns,
        s.coverage(),
        s.bias()
    );
    assert!(
        cut as f64 > 0.8 * s.given as f64,
        "cut {cut} of {}",
        s.given
    );
    assert!(s.coverage() >= 0.9, "coverage {}", s.coverage());
    assert!(s.bias().abs() < 0.3, "bias {}", s.bias());
}

#[test]
fn a_column_with_no_crossing_is_never_given_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    for _ in 0..500 {
        // Flat at a fraction away from one half, or crossing 12 or more beyond the rows.
        let p_flat = [0.1, 0.25, 0.35, 0.65, 0.75, 0.9][rng.random_range(0..6)];
        let flat = draw(&mut rng, &|_| p_flat);
        assert!(fit_column(&flat).is_err(), "flat at {p_flat}: {flat:?}");
        let k = rng.random_range(0.13..0.77);
        let star = if rng.random::<bool>() {
            rng.random_range(-20.0..-2.0)
        } else {
            rng.random_range(62.0..80.0)
        };
        let outside = draw(&mut rng, &|b| sigmoid(k * (b - star)));
        assert!(
            fit_column(&outside).is_err(),
            "crossing at {star}: {outside:?}"
        );
    }
    // And the refusals say why.
    let none = draw(&mut rng, &|_| 0.1);
    assert!(matches!(
        fit_column(&none),
        Err(NoModelCrossing::TrainEverywhere | NoModelCrossing::NoRise)
    ));
}
