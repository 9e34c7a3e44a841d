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
//!
//! Layout: `site` holds the per-site update and the [`StepCoeffs`] it uses, `rows` the loop
//! over a block of rows and their column [`Span`]s, `sums` the integrals ([`Sums`]) in their
//! fixed order; this module picks the instruction set and splits the rows between two threads.

/// The AVX2+FMA and AVX-512 entry points of an `#[inline(always)]` function generic over
/// `T: Real`: the same body compiled with the wider instruction set enabled (and called only
/// where `isa()` found it; `unsafe` for that reason), with the visibility given before them.
macro_rules! isa_entry_points {
    ($vis:vis $avx2:ident, $avx512:ident => $body:ident($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty) => {
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        #[allow(clippy::too_many_arguments)]
        $vis unsafe fn $avx2<T: Real>($($arg: $ty),*) -> $ret {
            $body($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx512f,fma")]
        #[allow(clippy::too_many_arguments)]
        $vis unsafe fn $avx512<T: Real>($($arg: $ty),*) -> $ret {
            $body($($arg),*)
        }
    };
}

mod rows;
mod site;
mod span;
mod sums;

pub use site::StepCoeffs;
pub use span::{RowSpans, Span};
pub use sums::Sums;

use crate::fibers::Fibers;
use crate::lattice::Lattice;
use crate::real::Real;
use rows::step_body;
#[cfg(target_arch = "x86_64")]
use rows::{step_body_avx2, step_body_avx512};
use sums::integrals;

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
    step_cell_in(lat, fibers, k, phi, p, other, &full, out, parallel)
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
    step_cell_portable_in(lat, fibers, k, phi, p, other, &full, out)
}
