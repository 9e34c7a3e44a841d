//! The paper's reading of a column (SPEC section 6): beta* where n_walk - n_train first rises
//! through zero as beta rises, linear between grid points; the line through such crossings by
//! ordinary least squares; and the bootstrap that gives both their intervals, each point's
//! replicates redrawn from its observed outcome frequencies.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::counts::Counts;
use crate::sampling::standard_normal;

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
pub(crate) fn crossing(points: &[(f64, i64)]) -> Result<f64, NoCrossing> {
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
            let (pt, pw) = (c.n_train() as f64 / n as f64, c.n_walk() as f64 / n as f64);
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
    use crate::end::End;
    use rand::SeedableRng;

    /// A point of `n` collisions, `w` walk-pasts and `t` trainings.
    fn point(n: u64, w: u64, t: u64) -> Counts {
        let mut c = Counts::none(0.1, 10.0, 90, 5.0);
        c.tally = [
            (End::WalkPast, w),
            (End::Train, t),
            (End::Reversal, n - w - t),
        ]
        .into_iter()
        .collect();
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
