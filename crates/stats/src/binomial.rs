//! Exact (Clopper-Pearson) confidence bounds for a binomial proportion.
//!
//! For k successes in n trials, the two-sided interval at level `delta` (the chance that it
//! misses the true p) is [lo, hi] with
//!   P(X >= k | n, lo) = delta / 2   (lo = 0 when k = 0),
//!   P(X <= k | n, hi) = delta / 2   (hi = 1 when k = n),
//! that is lo = B^-1(delta/2; k, n - k + 1) and hi = B^-1(1 - delta/2; k + 1, n - k), B the
//! regularized incomplete beta function. The bound holds for every p and every n: it is exact,
//! never an approximation that can undercover at small n (Wilson's can).

/// ln Gamma(x), x > 0 (Lanczos, g = 7, 9 terms: about 15 significant digits).
pub(crate) fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Gamma(x) Gamma(1 - x) = pi / sin(pi x).
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The continued fraction of the incomplete beta function (modified Lentz).
fn beta_cf(a: f64, b: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..=400 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        if d.abs() < TINY {
            d = TINY;
        }
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        if d.abs() < TINY {
            d = TINY;
        }
        c = 1.0 + aa / c;
        if c.abs() < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let del = d * c;
        h *= del;
        if (del - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// The regularized incomplete beta function I_x(a, b), a, b > 0, 0 <= x <= 1.
pub fn beta_inc(a: f64, b: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let ln_front = ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln();
    let front = ln_front.exp();
    // The fraction converges fast for x < (a + 1) / (a + b + 2); use the symmetry otherwise.
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_cf(a, b, x) / a
    } else {
        1.0 - front * beta_cf(b, a, 1.0 - x) / b
    }
}

/// The x with I_x(a, b) = q, by bisection (I is increasing in x).
pub(crate) fn beta_inc_inverse(a: f64, b: f64, q: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if beta_inc(a, b, mid) < q {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The Clopper-Pearson interval of k successes in n trials that misses the true proportion
/// with probability at most `delta` (two-sided: delta / 2 on each side). n = 0 gives [0, 1].
pub fn clopper_pearson(k: u64, n: u64, delta: f64) -> [f64; 2] {
    assert!(k <= n, "k = {k} successes of n = {n} trials");
    if n == 0 {
        return [0.0, 1.0];
    }
    let (k, nf) = (k as f64, n as f64);
    let lo = if k == 0.0 {
        0.0
    } else {
        beta_inc_inverse(k, nf - k + 1.0, delta / 2.0)
    };
    let hi = if k == nf {
        1.0
    } else {
        beta_inc_inverse(k + 1.0, nf - k, 1.0 - delta / 2.0)
    };
    [lo, hi]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_incomplete_beta_matches_closed_forms() {
        // I_x(1, b) = 1 - (1 - x)^b and I_x(a, 1) = x^a.
        for &x in &[0.01, 0.3, 0.5, 0.77, 0.99] {
            assert!((beta_inc(1.0, 5.0, x) - (1.0 - (1.0 - x).powi(5))).abs() < 1e-13);
            assert!((beta_inc(7.0, 1.0, x) - x.powi(7)).abs() < 1e-13);
            // I_x(2, 2) = 3x^2 - 2x^3.
            assert!((beta_inc(2.0, 2.0, x) - (3.0 * x * x - 2.0 * x * x * x)).abs() < 1e-13);
        }
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-13);
    }
}
