//! One site of the step (SPEC section 3) and the coefficients it needs, folded once per step.

use super::Sums;
use crate::params::Params;
use crate::real::Real;
use std::f64::consts::PI;

/// Coefficients of one cell's step, constant over the lattice, folded so that the site update
/// needs as few multiplications as possible (see `site` for the equations they come from).
///
/// mu is computed scaled by 1 / (alpha d^2 / 2) (positive: `Params::validate` requires alpha
/// and d > 0), so that the Laplacian's neighbour sum enters it with coefficient -1; the scale is
/// folded back into the mobility `mobility_*`. Fields named `*_s` carry that scale.
#[derive(Debug, Clone, Copy)]
pub struct StepCoeffs<T: Real = f64> {
    alpha_s: T,
    /// 4 - 4 lambda / (pi R0^2) (1 - S / (pi R0^2)) / (alpha d^2 / 2): the parts of mu linear in
    /// phi, the Laplacian's centre and the area term, are phi * linear_s (scaled).
    linear_s: T,
    /// -6 E0 A_ref / (A_ref + Ad)^2 (scaled): the fiber term is phi (1 - phi) chi neg_fiber_s.
    neg_fiber_s: T,
    two_g_s: T,
    neg_two_sigma_s: T,
    /// -dt (alpha d^2 / 2) / (4 eta) and -dt (alpha d^2 / 2) / gamma: with mu_s = mu / (alpha
    /// d^2 / 2), -dt (mu |grad phi|^2 / eta + mu / gamma) = mu_s (h2 mobility_h2 + mobility_0).
    mobility_h2: T,
    mobility_0: T,
    /// dt A / (2 eta), 0 without the motility force: |grad phi| = sqrt(h2) / 2, h2 below.
    dt_half_a_over_eta: T,
    beta: T,
    /// 1 - dt / tau
    decay: T,
    phi_min: T,
    /// -dt/2 times the uniform velocity noise (vx, vy) of this cell at this step:
    /// -dt vnoise . grad phi = neg_dt_half_noise . (e - w, n - s).
    neg_dt_half_noise: [T; 2],
    /// Whether the fiber terms act (the motility force, or a non-zero fiber adhesion).
    pub(super) fiber_on: bool,
    /// Whether cell-cell adhesion acts (sigma != 0). Without it the pair site skips h_j^2 and
    /// the adhesion factor, which is then exactly alpha_s: the same bits for any finite field,
    /// two multiplications fewer.
    pub(super) adhesion_on: bool,
    /// Whether P is advanced off the fiber rows too (see [`StepCoeffs::polarity_on_fibers_only`]).
    pub(super) polarity_everywhere: bool,
}

impl<T: Real> StepCoeffs<T> {
    /// Coefficients for a cell with integrals `sums`, noise `noise`, and the motility force on
    /// or off.
    pub fn new(p: &Params, sums: &Sums, noise: [f64; 2], motile: bool) -> Self {
        let a0 = PI * p.R0 * p.R0;
        let ad = sums.adhesive_total();
        let scale = p.alpha * (p.d * p.d / 2.0);
        debug_assert!(scale > 0.0, "alpha and d must be positive");
        let area = 4.0 * p.lambda / a0 * (1.0 - sums.area / a0);
        let neg_fiber = -(6.0 * p.E0 * p.A_ref / ((p.A_ref + ad) * (p.A_ref + ad)));
        StepCoeffs {
            alpha_s: T::of(p.alpha / scale),
            linear_s: T::of(4.0 - area / scale),
            neg_fiber_s: T::of(neg_fiber / scale),
            two_g_s: T::of(2.0 * p.g / scale),
            neg_two_sigma_s: T::of(-2.0 * p.sigma / scale),
            mobility_h2: T::of(-p.dt * scale * 0.25 / p.eta),
            mobility_0: T::of(-p.dt * scale * p.inv_gamma),
            dt_half_a_over_eta: T::of(if motile {
                p.dt * 0.5 * p.A / p.eta
            } else {
                0.0
            }),
            beta: T::of(p.beta),
            decay: T::of(1.0 - p.dt / p.tau),
            phi_min: T::of(p.phi_min),
            neg_dt_half_noise: [T::of(-p.dt * 0.5 * noise[0]), T::of(-p.dt * 0.5 * noise[1])],
            fiber_on: motile || neg_fiber != 0.0,
            adhesion_on: p.sigma != 0.0,
            polarity_everywhere: true,
        }
    }

    /// Advance P only on the fiber rows. P enters phi's update only through the motility force
    /// A P phi^2 (1 - phi)^2 chi, which vanishes off the fiber rows (chi = 0), and P's own update
    /// is local (no stencil), so P off the fiber rows never feeds back into phi: phi, and every
    /// observable, come out the same bits either way. The kernel then neither reads nor writes
    /// P on those rows (two memory streams and five operations per site fewer); the caller sets
    /// them to zero, so the P field shows only the polarity that acts.
    pub fn polarity_on_fibers_only(mut self) -> Self {
        self.polarity_everywhere = false;
        self
    }

    /// The pair terms with the adhesion factor computed even at sigma = 0, for the test that
    /// the sigma = 0 specialisation gives the same bits.
    #[doc(hidden)]
    pub fn with_adhesion_term(mut self) -> Self {
        self.adhesion_on = true;
        self
    }
}

/// a * b + c with one rounding. Every instruction-set path uses the same fused operation (a
/// hardware FMA where the CPU has one, the correctly rounded libm `fma` otherwise), so all
/// paths give the same bits.
#[inline(always)]
pub(super) fn fma<T: Real>(a: T, b: T, c: T) -> T {
    a.fma(b, c)
}

/// One site: returns (phi(t+dt), P(t+dt)), SPEC section 3.
///
/// `c` is phi at the site, `e w n s` its four neighbours, `p` the polarity, `pj` the other
/// cell's phi (pair stage only). The equations are regrouped so that every term of mu carrying
/// phi is one product phi * (...): on this CPU the multiply and FMA units are the bottleneck,
/// and the regrouped site needs 13 of them (pair, off the fiber rows) where the term-by-term
/// form needed 20. `kernel_vs_spec` checks it against the term-by-term transcription.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn site<
    T: Real,
    const FIBER: bool,
    const PAIR: bool,
    const ADH: bool,
    const POL: bool,
>(
    k: &StepCoeffs<T>,
    c: T,
    e: T,
    w: T,
    n: T,
    s: T,
    p: T,
    pj: T,
) -> (T, T) {
    let one = T::of(1.0);
    // mu = alpha poly - alpha d^2/2 lap - 4 lambda phi/(pi R0^2) (1 - S/(pi R0^2))
    //      - 6 E0 A_ref phi (1 - phi) chi / (A_ref + Ad)^2
    //      + 2 g phi phi_j^2 - 2 sigma poly phi_j^2 (1 - phi_j)^2,
    // with poly = phi q, q = phi (phi - 1.5) + 0.5, and lap = (e + w + n + s) - 4 phi. Scaled by
    // 1 / (alpha d^2/2) (the `_s` coefficients), with h_j = phi_j (1 - phi_j):
    // mu_s = phi [q (alpha - 2 sigma h_j^2) + linear + neg_fiber (1 - phi) chi + 2 g phi_j^2]_s
    //        - (e + w + n + s).
    let q = fma(c, c - T::of(1.5), T::of(0.5));
    let mut inner = if PAIR {
        let pj2 = pj * pj;
        let exclusion = fma(k.two_g_s, pj2, k.linear_s);
        if ADH {
            let hj = pj - pj2;
            fma(q, fma(k.neg_two_sigma_s, hj * hj, k.alpha_s), exclusion)
        } else {
            // sigma = 0: the adhesion factor is exactly alpha_s (-0 * h_j^2 + alpha_s).
            fma(q, k.alpha_s, exclusion)
        }
    } else {
        fma(k.alpha_s, q, k.linear_s)
    };
    if FIBER {
        inner = fma(k.neg_fiber_s, one - c, inner);
    }
    let mu_s = fma(c, inner, -((e + w) + (n + s)));
    // grad(phi) = (ex, ey) / 2; h2 = 4 |grad phi|^2.
    let ex = e - w;
    let ey = n - s;
    let h2 = fma(ex, ex, ey * ey);
    // delta = dt dphi = -dt (v . grad(phi) + mu / gamma), where
    // v . grad(phi) = (mu |grad phi|^2 - A P phi^2 (1-phi)^2 chi |grad phi|) / eta
    //                 + vnoise . grad(phi).
    let noise = fma(k.neg_dt_half_noise[0], ex, k.neg_dt_half_noise[1] * ey);
    let mut delta = fma(mu_s, fma(h2, k.mobility_h2, k.mobility_0), noise);
    if FIBER {
        // b = phi (1 - phi); |grad phi| = sqrt(h2) / 2.
        let b = c * (one - c);
        delta = fma((k.dt_half_a_over_eta * p) * (b * b), h2.sqrt(), delta);
    }
    // phi(t+dt) = phi + dt dphi
    let phi_new = c + delta;
    // P(t+dt) = (P + dt (beta phi dphi - P / tau)) [phi(t) > phi_min]
    //         = (P (1 - dt/tau) + beta phi delta) [phi(t) > phi_min]
    let p_new = if POL {
        // Computed unconditionally and then selected, without a branch, so that the seam
        // blocks (fully unrolled) vectorise as well as the main loop.
        let v = fma(k.beta * c, delta, p * k.decay);
        if c > k.phi_min {
            v
        } else {
            T::default()
        }
    } else {
        T::default()
    };
    (phi_new, p_new)
}
