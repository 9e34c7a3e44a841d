//! The columns a cell's step computes: a [`Span`] of one row, and the [`RowSpans`] of a step.

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
