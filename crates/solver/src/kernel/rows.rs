//! One cell's step over a block of rows: the row loop, its column spans, the seams where the
//! row wraps round, and the monomorphised inner loop over the sites.

use super::site::{fma, site, StepCoeffs};
use super::span::RowSpans;
use super::sums::Partial;
use crate::fibers::Fibers;
use crate::real::Real;

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

/// Rows `first..first + p.len() / nx` of one cell's step, columns `spans` (`p` and `out` hold
/// just those rows); returns their contributions to the integrals.
///
/// The area sum phi^2 is accumulated in the step's own loop, column by column, into a row of f64
/// accumulators: element-wise, so the compiler vectorises it with the step (per-row reductions
/// into a few accumulators, in a second pass, were left to the SLP vectoriser, which often fell
/// back to scalar code, and cost up to a fifth of the step).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn step_body<T: Real>(
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
    pub(super) step_body_avx2,
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
