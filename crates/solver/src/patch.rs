//! Per-cell moving windows ("patches") for the collision stage.
//!
//! Each cell of the collision is computed only in a window that follows it, one run of columns
//! per row: in row j, the smallest periodic run of columns holding every site of rows j - pad to
//! j + pad where |phi| or |P| reaches `bound`, widened by `pad` columns on each side. Outside its
//! window a cell's phi and P are held at exactly zero (they were below `bound` when the window
//! last moved off those sites), so:
//!
//! - the stencil at the window's edge reads zeros, as if the cell's tail ended there;
//! - where the *other* cell's window does not reach, the pair terms (which carry phi_j^2) vanish
//!   exactly, and the kernel skips them;
//! - observables summed over the whole lattice (centroids, overlap) need no change.
//!
//! At the paper's size and bound 1e-8 every row has a window: the tail of phi decays only like
//! exp(-r/6) (slower than exp(-r/d): the area term, which pushes a cell a little smaller than
//! pi R0^2 to grow, slows the decay), so it reaches 1e-8 some 110 sites from the 0.5 contour. The
//! rows differ in width, though: the rows of the fibers, along which the cell spreads, are the
//! widest, and per-row windows cover about a fifth less than one run of columns for all rows.
//!
//! The leak check runs every `check_every` steps: if |phi| or |P| on the boundary of a cell's
//! windows (a row's first or last column, or a site whose row above or below has no window
//! there) has reached `bound`, both cells are refitted at once (growing what leaked) and the
//! event is counted; nothing is ever cut off above `bound`. Every `refit_every` steps the windows
//! are refitted anyway, so they follow the cells and shrink behind them.

use serde::{Deserialize, Serialize};

use crate::cell::Cell;
use crate::fibers::Fibers;
use crate::kernel::{RowSpans, Span};
use crate::lattice::Lattice;
use crate::real::Real;

/// How the collision stage restricts each cell to a window. Stored with every result (as part of
/// the protocol), since the bound decides how far the patch path may differ from the full one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PatchSettings {
    /// Sites leave a cell's window only while |phi| and |P| are below this there and within
    /// `pad` sites; 0 turns the windows off (every cell on the whole lattice).
    pub bound: f64,
    /// Extra columns on each side of a row's sites that reach `bound`, and rows above and below
    /// them.
    pub pad: usize,
    /// Steps between leak checks of the windows' boundary.
    pub check_every: u64,
    /// Steps between refits (the windows follow the cells and shrink behind them).
    pub refit_every: u64,
}

impl Default for PatchSettings {
    fn default() -> Self {
        PatchSettings {
            bound: 1e-8,
            pad: 2,
            check_every: 10,
            refit_every: 500,
        }
    }
}

impl PatchSettings {
    /// No windows: every cell on the whole lattice.
    pub fn off() -> Self {
        PatchSettings {
            bound: 0.0,
            ..PatchSettings::default()
        }
    }

    pub fn enabled(&self) -> bool {
        self.bound > 0.0
    }
}

/// What the windows did during one collision.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct PatchStats {
    /// Leak checks that found |phi| or |P| at the bound on a cell's window boundary (each grew
    /// it).
    pub edge_hits: u32,
    /// Refits, scheduled or caused by an edge hit.
    pub refits: u32,
    /// Widest row window of either cell (columns).
    pub widest: usize,
    /// Sites computed per step, both cells together, averaged over the run, as a fraction of
    /// what the full lattice costs.
    pub mean_fraction: f64,
}

/// Windows start and end on multiples of this many columns (when the lattice width allows):
/// one AVX-512 vector of f32 (two of f64).
pub const ALIGN: usize = 16;

/// A periodic run of `len` columns starting at `start` (`len == nx`: every column).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    pub start: usize,
    pub len: usize,
}

impl Window {
    pub fn full(nx: usize) -> Window {
        Window { start: 0, len: nx }
    }

    /// The window's columns as at most two plain ranges within 0..nx.
    pub fn ranges(&self, nx: usize) -> [std::ops::Range<usize>; 2] {
        let end = self.start + self.len.min(nx);
        if end <= nx {
            [self.start..end, 0..0]
        } else {
            [self.start..nx, 0..end - nx]
        }
    }

    /// No column at all.
    pub fn empty() -> Window {
        Window { start: 0, len: 0 }
    }

    pub fn is_full(&self, nx: usize) -> bool {
        self.len >= nx
    }

    /// The columns of this window that `other` lacks, as at most two runs `lo..hi` of
    /// unwrapped columns (`hi` may exceed `nx`: take them modulo `nx`).
    pub fn minus(&self, other: Window, nx: usize) -> [Option<(usize, usize)>; 2] {
        if other.is_full(nx) || self.len == 0 {
            return [None, None];
        }
        if other.len == 0 {
            return [Some((self.start, self.start + self.len)), None];
        }
        // In this window's frame (0..len), `other`'s complement is the circular run that starts
        // where `other` ends, nx - other.len long: cut it to 0..len, once as it is and once a
        // lap earlier.
        let c0 = (other.start + other.len + nx - self.start) % nx;
        let c1 = c0 + nx - other.len;
        let cut = |lo: usize, hi: usize| {
            let (lo, hi) = (lo.min(self.len), hi.min(self.len));
            (lo < hi).then_some((self.start + lo, self.start + hi))
        };
        let first = cut(c0, c1);
        let second = if c1 > nx { cut(0, c1 - nx) } else { None };
        [second, first]
    }

    pub fn contains(&self, i: usize, nx: usize) -> bool {
        (i + nx - self.start) % nx < self.len
    }

    /// The first and last column (the edges the leak check reads).
    pub fn edges(&self, nx: usize) -> [usize; 2] {
        [self.start, (self.start + self.len - 1) % nx]
    }

    /// The smallest window holding every column where `hot` is true, widened by `pad` on each
    /// side (the whole row if that leaves no gap, or if no column is hot).
    pub fn fit(hot: &[bool], pad: usize) -> Window {
        let nx = hot.len();
        let Some(h0) = hot.iter().position(|&h| h) else {
            return Window::full(nx);
        };
        // The longest periodic run of cold columns, walking once round from a hot column.
        let (mut best_start, mut best_len) = (0, 0);
        let mut run_start = 0;
        let mut run_len = 0;
        let mut i = h0;
        for _ in 0..nx {
            i = if i + 1 == nx { 0 } else { i + 1 };
            if hot[i] {
                if run_len > best_len {
                    (best_start, best_len) = (run_start, run_len);
                }
                run_len = 0;
            } else {
                if run_len == 0 {
                    run_start = i;
                }
                run_len += 1;
            }
        }
        if best_len <= 2 * pad {
            return Window::full(nx);
        }
        let start = (best_start + best_len + nx - pad) % nx;
        let len = nx - best_len + 2 * pad;
        // Whole blocks of ALIGN columns where the row allows: the kernel's vector loops then
        // have no scalar remainder at the spans' ends.
        let align = if nx.is_multiple_of(ALIGN) { ALIGN } else { 1 };
        let aligned_start = start / align * align;
        let end = (start - aligned_start + len).div_ceil(align) * align;
        if end >= nx {
            return Window::full(nx);
        }
        Window {
            start: aligned_start,
            len: end,
        }
    }
}

/// The two cells' windows during a collision, row by row, and the kernel spans they give.
#[derive(Debug, Clone)]
pub struct Patches {
    settings: PatchSettings,
    nx: usize,
    ny: usize,
    /// Each cell's window in each row.
    windows: [Vec<Window>; 2],
    /// Each cell's kernel spans, row after row: row j's are `spans[offsets[j]..offsets[j + 1]]`.
    offsets: [Vec<usize>; 2],
    spans: [Vec<Span>; 2],
    stats: PatchStats,
    /// Sites computed per step (both cells), and their sum over the steps, for `mean_fraction`.
    sites: u64,
    site_steps: u64,
    steps: u64,
}

impl Patches {
    /// Windows fitted to the cells' current fields (which must be zero outside them afterwards:
    /// fitting zeroes what lies below the bound outside). `None` when the settings turn patches
    /// off.
    pub fn new<T: Real>(
        settings: &PatchSettings,
        lat: &Lattice,
        fibers: &Fibers,
        cells: [&mut Cell<T>; 2],
    ) -> Option<Patches> {
        if !settings.enabled() {
            return None;
        }
        let (nx, ny) = (lat.nx, lat.ny);
        let mut patches = Patches {
            settings: *settings,
            nx,
            ny,
            windows: [vec![Window::full(nx); ny], vec![Window::full(nx); ny]],
            offsets: [Vec::new(), Vec::new()],
            spans: [Vec::new(), Vec::new()],
            stats: PatchStats::default(),
            sites: 0,
            site_steps: 0,
            steps: 0,
        };
        patches.refit(lat, fibers, cells);
        Some(patches)
    }

    /// The kernel spans of cell 1 and cell 2, row by row.
    pub fn spans(&self) -> [RowSpans<'_>; 2] {
        [0, 1].map(|k| RowSpans::PerRow {
            offsets: &self.offsets[k],
            spans: &self.spans[k],
        })
    }

    /// The windows of cell 1 and cell 2, one per row.
    pub fn windows(&self) -> [&[Window]; 2] {
        [&self.windows[0], &self.windows[1]]
    }

    pub fn stats(&self) -> PatchStats {
        let mut s = self.stats;
        if self.steps > 0 {
            let lattice = (2 * self.nx * self.ny) as f64;
            s.mean_fraction = self.site_steps as f64 / lattice / self.steps as f64;
        }
        s
    }

    /// Bookkeeping after step number `step` (1-based) of the collision: the leak check every
    /// `check_every` steps, a refit every `refit_every` steps or when the check finds a leak.
    pub fn after_step<T: Real>(
        &mut self,
        step: u64,
        lat: &Lattice,
        fibers: &Fibers,
        cells: [&mut Cell<T>; 2],
    ) {
        self.steps += 1;
        self.site_steps += self.sites;
        let mut refit = step.is_multiple_of(self.settings.refit_every);
        if step.is_multiple_of(self.settings.check_every) {
            for (k, cell) in cells.iter().enumerate() {
                if self.leaks(k, &cell.phi, &cell.p) {
                    self.stats.edge_hits += 1;
                    refit = true;
                }
            }
        }
        if refit {
            self.stats.refits += 1;
            self.refit(lat, fibers, cells);
        }
    }

    /// Whether |phi| or |P| of cell `k` reaches the bound on the boundary of its windows: on a
    /// row's first or last column, or where the row above or below has no window.
    fn leaks<T: Real>(&self, k: usize, phi: &[T], p: &[T]) -> bool {
        let (nx, ny) = (self.nx, self.ny);
        let bound = self.settings.bound;
        let hot = |i: usize, j: usize| {
            let s = j * nx + i;
            phi[s].to_f64().abs().max(p[s].to_f64().abs()) >= bound
        };
        let windows = &self.windows[k];
        (0..ny).any(|j| {
            let w = windows[j];
            if w.len == 0 {
                return false;
            }
            if !w.is_full(nx) && w.edges(nx).iter().any(|&i| hot(i, j)) {
                return true;
            }
            [(j + 1) % ny, (j + ny - 1) % ny].iter().any(|&jj| {
                w.minus(windows[jj], nx)
                    .into_iter()
                    .flatten()
                    .any(|(lo, hi)| (lo..hi).any(|i| hot(i % nx, j)))
            })
        })
    }

    /// Fit every row's windows to the fields, zero what leaves them, rebuild the spans.
    ///
    /// A row's window covers the columns where |phi| or |P| reaches the bound in that row or
    /// in any row within `pad` of it, widened by `pad` columns (and aligned), so its boundary
    /// starts below the bound in both directions; a row with no such column has no window.
    pub fn refit<T: Real>(&mut self, lat: &Lattice, fibers: &Fibers, cells: [&mut Cell<T>; 2]) {
        let (nx, ny) = (self.nx, self.ny);
        let (bound, pad) = (self.settings.bound, self.settings.pad);
        for (k, cell) in cells.into_iter().enumerate() {
            // Hot sites (inside the old windows: the rest is exactly zero).
            let old = std::mem::take(&mut self.windows[k]);
            let mut hot = vec![false; nx * ny];
            for (j, w) in old.iter().enumerate() {
                for cols in w.ranges(nx) {
                    let r = j * nx + cols.start..j * nx + cols.end;
                    let fields = cell.phi[r.clone()].iter().zip(&cell.p[r.clone()]);
                    for (h, (&a, &b)) in hot[r].iter_mut().zip(fields) {
                        *h = a.to_f64().abs().max(b.to_f64().abs()) >= bound;
                    }
                }
            }
            // Each row's window: the hot columns of the rows within `pad`.
            let reach = pad.min(ny / 2);
            let new: Vec<Window> = (0..ny)
                .map(|j| {
                    let mut cols = vec![false; nx];
                    for d in 0..=2 * reach {
                        let jj = (j + ny + d - reach) % ny;
                        for (c, &h) in cols.iter_mut().zip(&hot[jj * nx..(jj + 1) * nx]) {
                            *c |= h;
                        }
                    }
                    if cols.iter().any(|&c| c) {
                        Window::fit(&cols, pad)
                    } else {
                        Window::empty()
                    }
                })
                .collect();
            // The sites the windows leave (all below the bound): set to exactly zero.
            let mut dropped = Vec::new();
            for (j, (o, n)) in old.iter().zip(&new).enumerate() {
                for (lo, hi) in o.minus(*n, nx).into_iter().flatten() {
                    dropped.extend((lo..hi).map(|i| j * nx + i % nx));
                }
            }
            if !dropped.is_empty() {
                cell.zero_sites(lat, fibers, &dropped);
            }
            let widest = new.iter().map(|w| w.len).max().unwrap_or(0);
            self.stats.widest = self.stats.widest.max(widest);
            self.windows[k] = new;
        }
        self.sites = 0;
        for k in 0..2 {
            let (offsets, spans) = (&mut self.offsets[k], &mut self.spans[k]);
            offsets.clear();
            spans.clear();
            offsets.push(0);
            for j in 0..ny {
                spans.extend(spans_of(nx, self.windows[k][j], self.windows[1 - k][j]));
                offsets.push(spans.len());
                self.sites += self.windows[k][j].len as u64;
            }
        }
    }
}

/// The kernel spans of a cell with window `own` beside a cell with window `other`: the runs of
/// `own`'s columns within 0..nx, split where `other` starts or ends.
pub fn spans_of(nx: usize, own: Window, other: Window) -> Vec<Span> {
    // Both windows are constant between consecutive ends of their plain ranges.
    let mut cuts = vec![0, nx];
    for r in own.ranges(nx).into_iter().chain(other.ranges(nx)) {
        cuts.extend([r.start, r.end]);
    }
    cuts.sort_unstable();
    cuts.dedup();
    let mut spans: Vec<Span> = Vec::new();
    for c in cuts.windows(2) {
        let (lo, hi) = (c[0], c[1]);
        if !own.contains(lo, nx) {
            continue;
        }
        let pair = other.contains(lo, nx);
        match spans.last_mut() {
            Some(s) if s.hi == lo && s.pair == pair => s.hi = hi,
            _ => spans.push(Span { lo, hi, pair }),
        }
    }
    spans
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hot(nx: usize, cols: &[usize]) -> Vec<bool> {
        (0..nx).map(|i| cols.contains(&i)).collect()
    }

    #[test]
    fn fit_covers_the_hot_columns_with_padding() {
        // Hot 20..26, padded to 18..28, aligned to 16..32.
        let w = Window::fit(&hot(64, &[20, 21, 25]), 2);
        assert_eq!(w, Window { start: 16, len: 16 });
        for i in 16..32 {
            assert!(w.contains(i, 64));
        }
        assert!(!w.contains(15, 64) && !w.contains(32, 64));
        // Widths that are not whole blocks keep the exact padding.
        let w = Window::fit(&hot(42, &[10, 11, 15]), 2);
        assert_eq!(w, Window { start: 8, len: 10 });
    }

    #[test]
    fn fit_wraps_round_the_seam() {
        // Hot 62..2, padded to 59..5, aligned to 48..16.
        let w = Window::fit(&hot(64, &[62, 63, 0, 1]), 3);
        assert_eq!(w, Window { start: 48, len: 32 });
        assert!(w.contains(63, 64) && w.contains(15, 64) && !w.contains(16, 64));
        assert!(!w.contains(47, 64));
        assert_eq!(w.edges(64), [48, 15]);
        // Unaligned: exactly the padding.
        let w = Window::fit(&hot(40, &[38, 39, 0, 1]), 3);
        assert_eq!(w, Window { start: 35, len: 10 });
    }

    /// Windows of a row of `nx` (40 or so): empty, whole, wrapping round the seam, at either
    /// end, one column wide.
    fn some_windows(nx: usize) -> [Window; 10] {
        [
            Window::empty(),
            Window::full(nx),
            Window { start: 7, len: nx },
            Window { start: 0, len: 10 },
            Window { start: 35, len: 10 },
            Window { start: 5, len: 3 },
            Window { start: 30, len: 20 },
            Window { start: 8, len: 30 },
            Window { start: 12, len: 1 },
            Window { start: 39, len: 1 },
        ]
    }

    #[test]
    fn minus_and_ranges_are_the_columns_they_stand_for() {
        let nx = 40;
        let cols = |w: Window, o: Window| {
            let mut v: Vec<usize> = w
                .minus(o, nx)
                .into_iter()
                .flatten()
                .flat_map(|(lo, hi)| lo..hi)
                .map(|i| i % nx)
                .collect();
            v.sort();
            v
        };
        let brute = |w: Window, o: Window| {
            (0..nx)
                .filter(|&i| w.contains(i, nx) && !o.contains(i, nx))
                .collect::<Vec<_>>()
        };
        let some = some_windows(nx);
        for &w in &some {
            for &o in &some {
                assert_eq!(cols(w, o), brute(w, o), "{w:?} minus {o:?}");
            }
            // And its plain ranges are exactly its columns.
            let mut r: Vec<usize> = w.ranges(nx).into_iter().flatten().collect();
            r.sort();
            assert_eq!(
                r,
                (0..nx).filter(|&i| w.contains(i, nx)).collect::<Vec<_>>()
            );
        }
    }

    #[test]
    fn fit_takes_the_whole_row_when_no_gap_is_left() {
        assert!(Window::fit(&hot(20, &[0, 5, 10, 15]), 2).is_full(20));
        assert!(Window::fit(&hot(20, &[]), 2).is_full(20));
    }

    #[test]
    fn spans_are_the_columns_of_the_window_with_the_other_windows_flag() {
        // Column by column, as the spans stand for.
        let brute = |nx: usize, own: Window, other: Window| {
            let mut spans: Vec<Span> = Vec::new();
            for i in (0..nx).filter(|&i| own.contains(i, nx)) {
                let pair = other.contains(i, nx);
                match spans.last_mut() {
                    Some(s) if s.hi == i && s.pair == pair => s.hi = i + 1,
                    _ => spans.push(Span {
                        lo: i,
                        hi: i + 1,
                        pair,
                    }),
                }
            }
            spans
        };
        let nx = 40;
        let some = some_windows(nx);
        for &own in &some {
            for &other in &some {
                assert_eq!(
                    spans_of(nx, own, other),
                    brute(nx, own, other),
                    "{own:?} beside {other:?}"
                );
            }
        }
    }

    #[test]
    fn spans_split_at_the_other_window_and_the_seam() {
        let own = Window { start: 35, len: 10 }; // 35..40, 0..5
        let other = Window { start: 2, len: 6 }; // 2..8
        let s = spans_of(40, own, other);
        assert_eq!(
            s,
            vec![
                Span {
                    lo: 0,
                    hi: 2,
                    pair: false
                },
                Span {
                    lo: 2,
                    hi: 5,
                    pair: true
                },
                Span {
                    lo: 35,
                    hi: 40,
                    pair: false
                },
            ]
        );
        let full = spans_of(40, Window::full(40), Window::full(40));
        assert_eq!(full, vec![Span::full(40, true)]);
    }
}
