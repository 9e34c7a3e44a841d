//! The floating-point types the step runs in: f64 (the default, everywhere) and f32 (an opt-in
//! for the collision stage; see `Precision`).

use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

/// A float the kernel can run in. Integrals are always returned and folded in f64.
pub trait Real:
    Copy
    + Send
    + Sync
    + Default
    + PartialOrd
    + Debug
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
{
    /// Values per AVX-512 vector: the kernel's natural block of columns.
    const LANES: usize;
    /// Rows whose squares the step sums column by column in this type before adding them to
    /// the f64 column totals of the area S (see `kernel::Partial`): every row of a block in
    /// f64 (the column sums are f64 already, so there is nothing to flush), eight in f32 (so
    /// that no long sum runs in f32).
    const FLUSH_ROWS: usize;
    /// From f64 (rounded to nearest).
    fn of(x: f64) -> Self;
    /// To f64 (exact).
    fn to_f64(self) -> f64;
    /// self * b + c with one rounding.
    fn fma(self, b: Self, c: Self) -> Self;
    fn sqrt(self) -> Self;
}

impl Real for f64 {
    const LANES: usize = 8;
    const FLUSH_ROWS: usize = usize::MAX;
    #[inline(always)]
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn fma(self, b: Self, c: Self) -> Self {
        self.mul_add(b, c)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

impl Real for f32 {
    const LANES: usize = 16;
    const FLUSH_ROWS: usize = 8;
    #[inline(always)]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn fma(self, b: Self, c: Self) -> Self {
        self.mul_add(b, c)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
}
