//! The reference distributions of the crate's intervals and checks: the normal's two-sided 95%
//! z, the chi-square survival function (the deviance's lack-of-fit test, the shift's test of one
//! delta) and the 95% quantile of F(1, df) (the profile threshold once the dispersion is
//! estimated).

use crate::binomial::{beta_inc_inverse, ln_gamma};

/// z of a two-sided 95% interval of the normal.
pub const Z95: f64 = 1.959_963_984_540_054;

/// Q(a, x) = Gamma(a, x) / Gamma(a), the regularized upper incomplete gamma function (series
/// below a + 1, Lentz's continued fraction above; Numerical Recipes 6.2).
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let front = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        // P(a, x) = e^-x x^a / Gamma(a) * sum_n x^n / (a (a+1) ... (a+n)).
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - front * sum).clamp(0.0, 1.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (front * h).clamp(0.0, 1.0)
    }
}

/// P(X > x) for X chi-square with `df` degrees of freedom.
pub fn chi_square_survival(x: f64, df: f64) -> f64 {
    gamma_q(df / 2.0, x / 2.0)
}

/// P(Z > z) for a standard normal Z: erfc(z / sqrt 2) / 2 = Q(1/2, z^2 / 2) / 2.
pub fn normal_upper_tail(z: f64) -> f64 {
    let half = 0.5 * gamma_q(0.5, 0.5 * z * z);
    if z >= 0.0 {
        half
    } else {
        1.0 - half
    }
}

/// The inverse Mills ratio phi(z) / P(Z > z): the mean of a standard normal above z is this.
pub fn inverse_mills(z: f64) -> f64 {
    if z > 8.0 {
        // The asymptotic series (the tail's own ratio underflows first).
        return z + 1.0 / z - 2.0 / z.powi(3);
    }
    let density = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt();
    density / normal_upper_tail(z)
}

/// The 95% quantile of F(1, df): the square of Student's t at 97.5%, from
/// P(F > f) = I_{df / (df + f)}(df / 2, 1 / 2).
pub fn f1_quantile_95(df: f64) -> f64 {
    let x = beta_inc_inverse(df / 2.0, 0.5, 0.05);
    df * (1.0 - x) / x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_are_reproduced() {
        // Chi-square: P(X > 3.841) = 0.05 at 1 df; P(X > 11.07) = 0.05 at 5 df; at 2 df the
        // survival is exactly e^(-x/2).
        assert!((chi_square_survival(3.841_458_8, 1.0) - 0.05).abs() < 1e-6);
        assert!((chi_square_survival(11.070_498, 5.0) - 0.05).abs() < 1e-6);
        assert!((chi_square_survival(30.0, 2.0) - (-15f64).exp()).abs() < 1e-12);
        // F(1, df) 95%: 161.45 (1), 18.513 (2), 5.9874 (6), 4.0847 (40).
        for (df, f) in [
            (1.0, 161.447_6),
            (2.0, 18.512_8),
            (6.0, 5.987_4),
            (40.0, 4.084_7),
        ] {
            assert!((f1_quantile_95(df) - f).abs() < 1e-3 * f, "df {df}");
        }
    }
}
