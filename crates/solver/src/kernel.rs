//! The fused explicit step of one cell (SPEC section 3).
//!
//! One pass over the lattice computes, per site, the stencils, the chemical potential mu, the
//! advection term v . grad(phi), the phi and P updates, and accumulates the next step's area
//! S = sum phi^2 and adhesive areas Ad = sum phi^2 (3 - 2 phi) chi. No full-lattice temporaries.
//!
//! The loop is specialised per row (fiber row or not: chi is constant along a row) and per stage
//! (single cell, or pair with the other cell's phi, with or without the cell-cell adhesion
//! factor: at sigma = 0 it is skipped, which gives the same bits). Reductions use a fixed set
//! of lanes, and every a*b+c the update needs is written as an explicit fused multiply-add (one
//! rounding), so the result does not depend on the instruction set: the AVX-512 and AVX2+FMA
//! builds of the same code, chosen at run time, are bit-identical to the portable one, which
//! calls the correctly rounded libm `fma` (Rust never contracts a*b+c on its own). Fusing, folding the constants
//! and grouping mu's terms as phi * (...) brought the site update from about 47 vector
//! operations to 22 (13 of them multiplications, the units this CPU runs out of first).
//!
//! The step runs in any [`Real`] (f64, or f32 for an opt-in collision stage; the integrals are
//! returned in f64) and over any column [`Span`]s of each row (the collision's per-cell windows,
//! `crate::patch`; the whole row otherwise).

use crate::fibers::Fibers;
use crate::lattice::Lattice;
use crate::params::Params;
use crate::real::Real;
use std::f64::consts::PI;

/// The AVX2+FMA and AVX-512 entry points of an `#[inline(always)]` function generic over
/// `T: Real`: the same body compiled with the wider instruction set enabled (and called only
/// where `isa()` found it; `unsafe` for that reason).
macro_rules! isa_entry_points {
    ($avx2:ident, $avx512:ident => $body:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $avx2<T: Real>($($arg: $ty),*) -> $ret {
            $body($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,fma")]
        #[allow(clippy::too_many_arguments)]
        unsafe fn $avx512<T: Real>($($arg: $ty),*) -> $ret {
            $body($($arg),*)
        }
    };
}

/// Integrals of one cell's phi that the next step needs: S = sum phi^2 and, per fiber,
/// Ad = sum phi^2 (3 - 2 phi) chi.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sums {
    pub area: f64,
    /// Adhesive area on the bottom fiber (index 0) and the top fiber (index 1; 0 with one fiber).
    pub adhesive: [f64; 2],
}

impl Sums {
    /// Total adhesive area Ad (both fibers).
    pub fn adhesive_total(&self) -> f64 {
        self.adhesive[0] + self.adhesive[1]
    }

    /// The sums of a field, accumulated in the same order as the kernel does (so a step's
    /// returned sums are exactly `Sums::of` its new phi).
    pub fn of<T: Real>(lat: &Lattice, fibers: &Fibers, phi: &[T]) -> Sums {
        assert_eq!(phi.len(), lat.len());
        let (nx, h) = (lat.nx, lat.ny / 2);
        let (top, bottom) = phi.split_at(h * nx);
        let half = |first: usize, rows: &[T]| match isa() {
            // SAFETY: `isa()` checked that this CPU runs these instructions.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => unsafe { sums_of_rows_avx512(nx, fibers, first, rows) },
            // SAFETY: as above.
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => unsafe { sums_of_rows_avx2(nx, fibers, first, rows) },
            Isa::Portable => sums_of_rows(nx, fibers, first, rows),
        };
        integrals([half(0, top), half(h, bottom)])
    }
}

/// What rows `first..` (`rows`, whole rows of `nx`) contribute to the integrals, in the
/// kernel's order (see [`Sums::of`]).
#[inline(always)]
fn sums_of_rows<T: Real>(nx: usize, fibers: &Fibers, first: usize, rows: &[T]) -> Partial {
    let full = [Span::full(nx, false)];
    let mut part = Partial::new(nx);
    let mut acc = vec![T::default(); nx];
    let count = rows.len() / nx;
    for (r, row) in rows.chunks_exact(nx).enumerate() {
        for (a, &v) in acc.iter_mut().zip(row) {
            *a = fma(v, v, *a);
        }
        part.row_done(fibers, first + r, r, count, row, &full, &mut acc);
    }
    part
}

isa_entry_points!(
    sums_of_rows_avx2,
    sums_of_rows_avx512 => sums_of_rows(nx: usize, fibers: &Fibers, first: usize, rows: &[T]) -> Partial
);

/// What a block of rows contributes to the integrals of phi(t+dt).
struct Partial {
    /// sum phi^2 of each column over the block's rows: `Real::FLUSH_ROWS` rows at a time in the
    /// field's precision (all of them in f64), then added here in f64.
    columns: Vec<f64>,
    /// Adhesive area per fiber, the block's fiber rows in row order.
    adhesive: [f64; 2],
    /// The columns `lo..hi` that rows since the last flush added squares to (rows of a window
    /// differ, and a row may have none: the flush must cover every row's columns, not just its
    /// own row's).
    pending: (usize, usize),
}

impl Partial {
    fn new(nx: usize) -> Self {
        Partial {
            columns: vec![0.0; nx],
            adhesive: [0.0; 2],
            pending: (nx, 0),
        }
    }

    /// Row `r` (lattice row `j`) of a block of `count` rows is done: `row` is phi(t+dt) there,
    /// and its squares have been added to `acc` in the columns `spans`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn row_done<T: Real>(
        &mut self,
        fibers: &Fibers,
        j: usize,
        r: usize,
        count: usize,
        row: &[T],
        spans: &[Span],
        acc: &mut [T],
    ) {
        // Ad: a handful of fiber rows.
        if let Some(f) = fibers.of_row(j) {
            self.adhesive[f as usize] += adhesive_sum(row, spans);
        }
        for sp in spans {
            self.pending = (self.pending.0.min(sp.lo), self.pending.1.max(sp.hi));
        }
        if (r + 1).is_multiple_of(T::FLUSH_ROWS) || r + 1 == count {
            let (lo, hi) = self.pending;
            if lo < hi {
                let cols = self.columns[lo..hi].iter_mut();
                for (c, a) in cols.zip(&mut acc[lo..hi]) {
                    *c += a.to_f64();
                    *a = T::default();
                }
            }
            self.pending = (acc.len(), 0);
        }
    }
}

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
    fiber_on: bool,
    /// Whether cell-cell adhesion acts (sigma != 0). Without it the pair site skips h_j^2 and
    /// the adhesion factor, which is then exactly alpha_s: the same bits for any finite field,
    /// two multiplications fewer.
    adhesion_on: bool,
    /// Whether P is advanced off the fiber rows too (see [`StepCoeffs::polarity_on_fibers_only`]).
    polarity_everywhere: bool,
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
fn fma<T: Real>(a: T, b: T, c: T) -> T {
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
fn site<T: Real, const FIBER: bool, const PAIR: bool, const ADH: bool, const POL: bool>(
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

/// Number of independent accumulators in the reductions: fixed, so results do not depend on the
/// SIMD width, and four AVX-512 vectors of f64 wide, so the additions need not wait on one FMA
/// chain.
const LANES: usize = 32;

/// The spans of every row of a step: the same in every row, or each row its own (the
/// collision's per-row windows, `crate::patch`).
#[derive(Debug, Clone, Copy)]
pub enum RowSpans<'a> {
    Uniform(&'a [Span]),
    /// Row j's spans are `spans[offsets[j]..offsets[j + 1]]`.
    PerRow {
        offsets: &'a [usize],
        spans: &'a [Span],
    },
}

impl<'a> From<&'a [Span]> for RowSpans<'a> {
    fn from(spans: &'a [Span]) -> Self {
        RowSpans::Uniform(spans)
    }
}

impl<'a, const N: usize> From<&'a [Span; N]> for RowSpans<'a> {
    fn from(spans: &'a [Span; N]) -> Self {
        RowSpans::Uniform(spans)
    }
}

impl<'a> RowSpans<'a> {
    /// The spans of row `j`.
    #[inline(always)]
    pub fn row(&self, j: usize) -> &'a [Span] {
        match *self {
            RowSpans::Uniform(s) => s,
            RowSpans::PerRow { offsets, spans } => &spans[offsets[j]..offsets[j + 1]],
        }
    }
}

/// Ad's share of one fiber row, sum phi^2 (3 - 2 phi) over its columns `spans`: element k of a
/// span goes to accumulator k mod `LANES`, span after span, and the accumulators are added up
/// once. (Plain loops, not closures: closures do not inherit the caller's `target_feature`s,
/// and the FMAs would become calls.)
#[inline(always)]
fn adhesive_sum<T: Real>(row: &[T], spans: &[Span]) -> f64 {
    let (two, three) = (T::of(2.0), T::of(3.0));
    let mut adh = [T::default(); LANES];
    for sp in spans {
        let chunks = row[sp.lo..sp.hi].chunks_exact(LANES);
        let rest = chunks.remainder();
        for chunk in chunks {
            for l in 0..LANES {
                let v = chunk[l];
                adh[l] = fma(v * v, fma(-two, v, three), adh[l]);
            }
        }
        for (l, &v) in rest.iter().enumerate() {
            adh[l] = fma(v * v, fma(-two, v, three), adh[l]);
        }
    }
    lanes_sum(&adh)
}

/// The accumulators' total, added pairwise in a fixed order.
#[inline(always)]
fn lanes_sum<T: Real>(a: &[T; LANES]) -> f64 {
    let mut v = *a;
    let mut n = LANES;
    while n > 1 {
        n /= 2;
        for l in 0..n {
            v[l] = v[l] + v[l + n];
        }
    }
    v[0].to_f64()
}

/// The most columns at each end of a row that run as one vector block from a wrapped copy.
const MAX_EDGE: usize = 16;

/// Columns `lo..hi` of one row of the step: reads phi rows `c` (this row), `up` (j+1), `dn`
/// (j-1), the other cell's row `pj` (ignored unless `PAIR`), updates `p` in place (unless
/// `POL` is false: then `p` is not touched), writes phi(t+dt) into `out` and adds its squares
/// to the column accumulators `acc`. Neighbours wrap round the row (periodic in x).
///
/// The seam columns at either end of the row, whose neighbours wrap round, run as a block of
/// their own from a wrapped copy of the row's end: a whole vector (`T::LANES` columns) where the
/// row and the span are whole vectors, so no scalar remainder is left; one column otherwise.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn step_span<T: Real, const FIBER: bool, const PAIR: bool, const ADH: bool, const POL: bool>(
    k: &StepCoeffs<T>,
    c: &[T],
    up: &[T],
    dn: &[T],
    pj: &[T],
    p: &mut [T],
    out: &mut [T],
    acc: &mut [T],
    lo: usize,
    hi: usize,
) {
    let n = c.len();
    // An empty span would still run its seam block: refuse it (one compare per span).
    assert!(
        lo < hi && hi <= n && n >= 2,
        "span {lo}..{hi} of a row of {n}"
    );
    // One AVX-512 vector of T: 8 columns in f64, 16 in f32.
    const { assert!(T::LANES <= MAX_EDGE) };
    let lanes = T::LANES;
    // Two calls with a constant `edge` each, so that the seam loops have known lengths.
    if n.is_multiple_of(lanes)
        && n >= 4 * lanes
        && lo.is_multiple_of(lanes)
        && hi.is_multiple_of(lanes)
    {
        seams_and_interior::<T, FIBER, PAIR, ADH, POL>(
            k, c, up, dn, pj, p, out, acc, lo, hi, lanes,
        );
    } else {
        seams_and_interior::<T, FIBER, PAIR, ADH, POL>(k, c, up, dn, pj, p, out, acc, lo, hi, 1);
    }
}

/// [`step_span`] with seam blocks of `edge` columns (`lo`, `hi` and the row multiples of it).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn seams_and_interior<
    T: Real,
    const FIBER: bool,
    const PAIR: bool,
    const ADH: bool,
    const POL: bool,
>(
    k: &StepCoeffs<T>,
    c: &[T],
    up: &[T],
    dn: &[T],
    pj: &[T],
    p: &mut [T],
    out: &mut [T],
    acc: &mut [T],
    lo: usize,
    hi: usize,
    edge: usize,
) {
    let n = c.len();
    let (mut a, mut b) = (lo, hi);
    if a == 0 {
        // [phi(n-1), phi(0), ..., phi(edge)]
        let mut buf = [T::default(); MAX_EDGE + 2];
        let cw = &mut buf[..edge + 2];
        cw[0] = c[n - 1];
        cw[1..].copy_from_slice(&c[..=edge]);
        flat::<T, FIBER, PAIR, ADH, POL>(
            k,
            cw,
            &up[..edge],
            &dn[..edge],
            &pj[..edge],
            &mut p[..edge],
            &mut out[..edge],
            &mut acc[..edge],
        );
        a = edge;
    }
    if b == n && a < b {
        // [phi(n-edge-1), ..., phi(n-1), phi(0)]
        let s = n - edge;
        let mut buf = [T::default(); MAX_EDGE + 2];
        let cw = &mut buf[..edge + 2];
        cw[..=edge].copy_from_slice(&c[s - 1..]);
        cw[edge + 1] = c[0];
        flat::<T, FIBER, PAIR, ADH, POL>(
            k,
            cw,
            &up[s..],
            &dn[s..],
            &pj[s..],
            &mut p[s..],
            &mut out[s..],
            &mut acc[s..],
        );
        b = s;
    }
    if a < b {
        flat::<T, FIBER, PAIR, ADH, POL>(
            k,
            &c[a - 1..b + 1],
            &up[a..b],
            &dn[a..b],
            &pj[a..b],
            &mut p[a..b],
            &mut out[a..b],
            &mut acc[a..b],
        );
    }
}

/// The site update over equal-length slices, `cw` holding one extra column at each end, adding
/// each phi(t+dt)^2 to its column's accumulator in `acc`: one plain loop, which the compiler
/// vectorises (the accumulators are element-wise, so there is no reduction in the loop).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn flat<T: Real, const FIBER: bool, const PAIR: bool, const ADH: bool, const POL: bool>(
    k: &StepCoeffs<T>,
    cw: &[T],
    up: &[T],
    dn: &[T],
    pj: &[T],
    p: &mut [T],
    out: &mut [T],
    acc: &mut [T],
) {
    let m = out.len();
    let (cw, up, dn, pj, p, acc) = (
        &cw[..m + 2],
        &up[..m],
        &dn[..m],
        &pj[..m],
        &mut p[..m],
        &mut acc[..m],
    );
    for i in 0..m {
        // P is neither read nor written where it does not act (`POL` false).
        let pi = if POL { p[i] } else { T::default() };
        let (a, b) = site::<T, FIBER, PAIR, ADH, POL>(
            k,
            cw[i + 1],
            cw[i + 2],
            cw[i],
            up[i],
            dn[i],
            pi,
            pj[i],
        );
        out[i] = a;
        if POL {
            p[i] = b;
        }
        // S = sum phi(t+dt)^2, column by column (summed over the columns after the step).
        acc[i] = fma(a, a, acc[i]);
    }
}

/// A run of columns `lo..hi` (`0 <= lo < hi <= nx`) that a cell's step computes in a row (in
/// every row, or in one: see [`RowSpans`]), and whether the other cell's phi may be non-zero
/// there. Where it is exactly zero (outside the
/// other cell's window) the pair terms vanish exactly and are skipped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    pub lo: usize,
    pub hi: usize,
    pub pair: bool,
}

impl Span {
    /// Every column of a row of `nx`.
    pub fn full(nx: usize, pair: bool) -> Span {
        Span {
            lo: 0,
            hi: nx,
            pair,
        }
    }
}

/// Rows `first..first + p.len() / nx` of one cell's step, columns `spans` (`p` and `out` hold
/// just those rows); returns their contributions to the integrals.
///
/// The area sum phi^2 is accumulated in the step's own loop, column by column, into a row of f64
/// accumulators: element-wise, so the compiler vectorises it with the step (per-row reductions
/// into a few accumulators, in a second pass, were left to the SLP vectoriser, which often fell
/// back to scalar code, and cost up to a fifth of the step).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn step_body<T: Real>(
    nx: usize,
    ny: usize,
    fibers: &Fibers,
    k: &StepCoeffs<T>,
    phi: &[T],
    first: usize,
    p: &mut [T],
    other: Option<&[T]>,
    spans: RowSpans,
    out: &mut [T],
) -> Partial {
    let rows = p.len() / nx;
    let mut part = Partial::new(nx);
    // The squares of up to T::FLUSH_ROWS rows, column by column, in T (see `Partial`).
    let mut acc_t = vec![T::default(); nx];
    let (fiber_on, adh) = (k.fiber_on, k.adhesion_on);
    for r in 0..rows {
        let j = first + r;
        let row = |r: usize| r * nx..(r + 1) * nx;
        let rj = row(j);
        let c = &phi[rj.clone()];
        let up = &phi[row((j + 1) % ny)];
        let dn = &phi[row((j + ny - 1) % ny)];
        let pr = &mut p[row(r)];
        let o = &mut out[row(r)];
        let fiber = fibers.of_row(j).is_some() && fiber_on;
        let pjr = match other {
            Some(q) => &q[rj.clone()],
            None => c,
        };
        // P acts only where chi = 1; elsewhere it is advanced only if asked for.
        let pol = fiber || k.polarity_everywhere;
        let acc = &mut acc_t[..];
        let row_spans = spans.row(j);
        for sp in row_spans {
            let pair = sp.pair && other.is_some();
            let (lo, hi) = (sp.lo, sp.hi);
            // One monomorphised loop per combination, all called with the same arguments.
            macro_rules! span {
                ($fiber:literal, $pair:literal, $adh:literal, $pol:literal) => {
                    step_span::<T, $fiber, $pair, $adh, $pol>(k, c, up, dn, pjr, pr, o, acc, lo, hi)
                };
            }
            // Fiber rows always advance P; adhesion matters only with the pair terms.
            match (fiber, pair, adh, pol) {
                (false, false, _, false) => span!(false, false, false, false),
                (false, false, _, true) => span!(false, false, false, true),
                (false, true, false, false) => span!(false, true, false, false),
                (false, true, false, true) => span!(false, true, false, true),
                (false, true, true, false) => span!(false, true, true, false),
                (false, true, true, true) => span!(false, true, true, true),
                (true, false, _, _) => span!(true, false, false, true),
                (true, true, false, _) => span!(true, true, false, true),
                (true, true, true, _) => span!(true, true, true, true),
            }
        }
        part.row_done(fibers, j, r, rows, o, row_spans, &mut acc_t);
    }
    part
}

isa_entry_points!(
    step_body_avx2,
    step_body_avx512 => step_body(
        nx: usize,
        ny: usize,
        fibers: &Fibers,
        k: &StepCoeffs<T>,
        phi: &[T],
        first: usize,
        p: &mut [T],
        other: Option<&[T]>,
        spans: RowSpans,
        out: &mut [T]
    ) -> Partial
);

/// The instruction sets the kernel is built for; every one gives the same bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Isa {
    Portable,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

/// The widest instruction set this CPU runs (`CELLSWEEP_NO_AVX512` caps it at AVX2), decided
/// once per process: the step is called hundreds of thousands of times per trajectory.
fn isa() -> Isa {
    static ISA: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
    *ISA.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("fma")
                && std::env::var_os("CELLSWEEP_NO_AVX512").is_none()
            {
                return Isa::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
            {
                return Isa::Avx2;
            }
        }
        Isa::Portable
    })
}

/// The integrals from the contributions of the two halves of the rows (the same halves whether
/// or not they ran on two threads, so the result is the same bits): the columns' squares added
/// half to half, then across the columns in `LANES` accumulators and a fixed tree.
fn integrals(halves: [Partial; 2]) -> Sums {
    let [a, b] = halves;
    // Column i goes to accumulator i mod LANES.
    let mut lanes = [0.0f64; LANES];
    let (ca, cb) = (a.columns.chunks(LANES), b.columns.chunks(LANES));
    for (xs, ys) in ca.zip(cb) {
        for ((l, x), y) in lanes.iter_mut().zip(xs).zip(ys) {
            *l += x + y;
        }
    }
    Sums {
        area: lanes_sum(&lanes),
        adhesive: [a.adhesive[0] + b.adhesive[0], a.adhesive[1] + b.adhesive[1]],
    }
}

#[allow(clippy::too_many_arguments)]
fn step_with<T: Real>(
    isa: Isa,
    lat: &Lattice,
    fibers: &Fibers,
    k: &StepCoeffs<T>,
    phi: &[T],
    p: &mut [T],
    other: Option<&[T]>,
    spans: RowSpans,
    out: &mut [T],
    parallel: bool,
) -> Sums {
    assert_eq!(phi.len(), lat.len());
    assert_eq!(p.len(), lat.len());
    assert_eq!(out.len(), lat.len());
    if let Some(q) = other {
        assert_eq!(q.len(), lat.len());
    }
    let (nx, ny) = (lat.nx, lat.ny);
    // Every span is checked as it runs (`step_span`).
    if let RowSpans::PerRow { offsets, .. } = spans {
        assert_eq!(offsets.len(), ny + 1);
    }
    let run = |first: usize, p: &mut [T], out: &mut [T]| match isa {
        // SAFETY: `isa()` checked that this CPU runs these instructions.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx512 => unsafe {
            step_body_avx512(nx, ny, fibers, k, phi, first, p, other, spans, out)
        },
        // SAFETY: as above.
        #[cfg(target_arch = "x86_64")]
        Isa::Avx2 => unsafe { step_body_avx2(nx, ny, fibers, k, phi, first, p, other, spans, out) },
        Isa::Portable => step_body(nx, ny, fibers, k, phi, first, p, other, spans, out),
    };
    // Two halves of the rows, on two threads with `parallel`.
    let h = ny / 2;
    let (p0, p1) = p.split_at_mut(h * nx);
    let (o0, o1) = out.split_at_mut(h * nx);
    let halves = if parallel && ny >= 4 {
        rayon::join(|| run(0, p0, o0), || run(h, p1, o1))
    } else {
        (run(0, p0, o0), run(h, p1, o1))
    };
    integrals([halves.0, halves.1])
}

/// Advance one cell by one step: reads `phi` (and the other cell's phi, if any), updates `p` in
/// place, writes phi(t+dt) into `out` and returns the sums of `out`. With `parallel`, the rows
/// are split between two threads; the result is the same bits.
#[allow(clippy::too_many_arguments)]
pub fn step_cell<T: Real>(
    lat: &Lattice,
    fibers: &Fibers,
    k: &StepCoeffs<T>,
    phi: &[T],
    p: &mut [T],
    other: Option<&[T]>,
    out: &mut [T],
    parallel: bool,
) -> Sums {
    let full = [Span::full(lat.nx, other.is_some())];
    let spans = RowSpans::Uniform(&full);
    step_with(isa(), lat, fibers, k, phi, p, other, spans, out, parallel)
}

/// [`step_cell`] restricted to the columns `spans` of each row (the same in every row, or each
/// row its own: a cell's window, see `crate::patch`). Sites outside are neither read as centres
/// nor written: the caller keeps phi and P exactly zero there, in `phi`, `p` and `out` alike,
/// and the sums cover the spans.
#[allow(clippy::too_many_arguments)]
pub fn step_cell_in<'s, T: Real>(
    lat: &Lattice,
    fibers: &Fibers,
    k: &StepCoeffs<T>,
    phi: &[T],
    p: &mut [T],
    other: Option<&[T]>,
    spans: impl Into<RowSpans<'s>>,
    out: &mut [T],
    parallel: bool,
) -> Sums {
    step_with(
        isa(),
        lat,
        fibers,
        k,
        phi,
        p,
        other,
        spans.into(),
        out,
        parallel,
    )
}

/// The portable path of [`step_cell_in`], for tests that compare it with the dispatched one.
#[doc(hidden)]
#[allow(clippy::too_many_arguments)]
pub fn step_cell_portable_in<'s, T: Real>(
    lat: &Lattice,
    fibers: &Fibers,
    k: &StepCoeffs<T>,
    phi: &[T],
    p: &mut [T],
    other: Option<&[T]>,
    spans: impl Into<RowSpans<'s>>,
    out: &mut [T],
) -> Sums {
    step_with(
        Isa::Portable,
        lat,
        fibers,
        k,
        phi,
        p,
        other,
        spans.into(),
        out,
        false,
    )
}

/// The portable path of [`step_cell`], for tests that compare it with the dispatched one.
#[doc(hidden)]
pub fn step_cell_portable<T: Real>(
    lat: &Lattice,
    fibers: &Fibers,
    k: &StepCoeffs<T>,
    phi: &[T],
    p: &mut [T],
    other: Option<&[T]>,
    out: &mut [T],
) -> Sums {
    let full = [Span::full(lat.nx, other.is_some())];
    step_with(
        Isa::Portable,
        lat,
        fibers,
        k,
        phi,
        p,
        other,
        RowSpans::Uniform(&full),
        out,
        false,
    )
}
