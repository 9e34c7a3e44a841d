//! The integrals the next step needs (S and Ad), accumulated in a fixed order so that every
//! instruction-set path, and the two halves of the rows on two threads or one, give the same bits.

use super::site::fma;
use super::span::Span;
use super::{isa, Isa};
use crate::fibers::Fibers;
use crate::lattice::Lattice;
use crate::real::Real;

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
pub(super) struct Partial {
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
    pub(super) fn new(nx: usize) -> Self {
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
    pub(super) fn row_done<T: Real>(
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

/// Number of independent accumulators in the reductions: fixed, so results do not depend on the
/// SIMD width, and four AVX-512 vectors of f64 wide, so the additions need not wait on one FMA
/// chain.
pub(super) const LANES: usize = 32;

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

/// The integrals from the contributions of the two halves of the rows (the same halves whether
/// or not they ran on two threads, so the result is the same bits): the columns' squares added
/// half to half, then across the columns in `LANES` accumulators and a fixed tree.
pub(super) fn integrals(halves: [Partial; 2]) -> Sums {
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
