//! The two pieces every bootstrap and every draw of this crate shares: a standard normal draw
//! and the 95% percentile interval of a sample.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// One standard normal draw (Box-Muller).
pub(crate) fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let v: f64 = rng.random();
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

/// The 2.5% and 97.5% percentiles of `v` (NaN for none).
pub(crate) fn percentile_95(v: &mut [f64]) -> [f64; 2] {
    if v.is_empty() {
        return [f64::NAN, f64::NAN];
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let q = |p: f64| v[((p * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
    [q(0.025), q(0.975)]
}
