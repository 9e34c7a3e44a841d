//! Per-cell moving windows ("patches") for the collision stage.
//!
//! Each cell of the collision is computed only in a window of whole columns that follows it: the
//! smallest periodic run of columns holding every site where |phi| or |P| reaches `bound`, widened
//! by `pad` columns on each side. Outside its window a cell's phi and P are held at exactly zero
//! (they were below `bound` when the window last moved off those columns), so:
//!
//! - the stencil at the window's edge reads zeros, as if the cell's tail ended there;
//! - where the *other* cell's window does not reach, the pair terms (which carry phi_j^2) vanish
//!   exactly, and the kernel skips them;
//! - observables summed over the whole lattice (centroids, overlap) need no change.
//!
//! Windows span the full height: at the paper's fiber spacings the cell body reaches within about
//! 40 rows of the lattice's top and bottom, and its tail (phi ~ exp(-r/d), d = sqrt(20)) is
//! above 1e-9 out to about 90 sites from the 0.5 contour.
//!
//! The leak check runs every `check_every` steps: if |phi| or |P| on a window's first or last
//! column has reached `bound`, both windows are refitted at once (growing the one that leaked)
//! and the event is counted; nothing is ever cut off above `bound`. Every `refit_every` steps the
//! windows are refitted anyway, so they follow the cells and shrink behind them.

use serde::{Deserialize, Serialize};

use crate::cell::Cell;
use crate::fibers::Fibers;
use crate::kernel::Span;
use crate::lattice::Lattice;
use crate::real::Real;

/// How the collision stage restricts each cell to a window. Stored with every result (as part of
/// the protocol), since the bound decides how far the patch path may differ from the full one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PatchSettings {
    /// Columns leave a cell's window only while |phi| and |P| are below this in every one of
    /// their sites; 0 turns the windows off (every cell on the whole lattice).
    pub bound: f64,
    /// Extra columns on each side of the columns that reach `bound`.
    pub pad: usize,
    /// Steps between leak checks of each window's edge columns.
    pub check_every: u64,
    /// Steps between refits (the windows follow the cells and shrink behind them).
    pub refit_every: u64,
}

impl Default for PatchSettings {
    fn default() -> Self {
        PatchSettings {
            bound: 1e-8,
            pad: 8,
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
    /// Leak checks that found |phi| or |P| at the bound on a window's edge (each grew it).
    pub edge_hits: u32,
    /// Refits, scheduled or caused by an edge hit.
    pub refits: u32,
    /// Widest window of either cell (columns).
    pub widest: usize,
    /// Columns computed per step, both cells together, averaged over the run, as a fraction of
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

    pub fn is_full(&self, nx: usize) -> bool {
        self.len >= nx
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
        for step in 1..=nx {
            let i = (h0 + step) % nx;
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
        let align = if nx % ALIGN == 0 { ALIGN } else { 1 };
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

/// The two cells' windows during a collision, and the kernel spans they give.
#[derive(Debug, Clone)]
pub struct Patches {
    settings: PatchSettings,
    nx: usize,
    windows: [Window; 2],
    spans: [Vec<Span>; 2],
    stats: PatchStats,
    /// Sum over steps of the columns computed (both cells), for `mean_fraction`.
    column_steps: u64,
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
        let nx = lat.nx;
        let mut patches = Patches {
            settings: *settings,
            nx,
            windows: [Window::full(nx); 2],
            spans: [Vec::new(), Vec::new()],
            stats: PatchStats::default(),
            column_steps: 0,
            steps: 0,
        };
        patches.refit(lat, fibers, cells);
        Some(patches)
    }

    /// The kernel spans of cell 1 and cell 2.
    pub fn spans(&self) -> [&[Span]; 2] {
        [&self.spans[0], &self.spans[1]]
    }

    pub fn windows(&self) -> [Window; 2] {
        self.windows
    }

    pub fn stats(&self) -> PatchStats {
        let mut s = self.stats;
        if self.steps > 0 {
            s.mean_fraction = self.column_steps as f64 / (2 * self.nx) as f64 / self.steps as f64;
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
        self.column_steps += (self.windows[0].len + self.windows[1].len) as u64;
        let mut refit = step % self.settings.refit_every == 0;
        if step % self.settings.check_every == 0 {
            let bound = self.settings.bound;
            for (w, cell) in self.windows.iter().zip(cells.iter()) {
                if w.is_full(self.nx) {
                    continue;
                }
                if w.edges(self.nx)
                    .iter()
                    .any(|&i| column_max(lat, &cell.phi, &cell.p, i) >= bound)
                {
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

    /// Fit both windows to the fields, zero what leaves them, rebuild the spans.
    fn refit<T: Real>(&mut self, lat: &Lattice, fibers: &Fibers, cells: [&mut Cell<T>; 2]) {
        let nx = self.nx;
        let bound = self.settings.bound;
        for (k, cell) in cells.into_iter().enumerate() {
            let old = self.windows[k];
            let hot: Vec<bool> = column_maxima(lat, &cell.phi, &cell.p)
                .iter()
                .enumerate()
                .map(|(i, &m)| old.contains(i, nx) && m >= bound)
                .collect();
            let new = Window::fit(&hot, self.settings.pad);
            let dropped: Vec<bool> = (0..nx)
                .map(|i| old.contains(i, nx) && !new.contains(i, nx))
                .collect();
            if dropped.iter().any(|&d| d) {
                cell.zero_columns(lat, fibers, &dropped);
            }
            self.windows[k] = new;
            self.stats.widest = self.stats.widest.max(new.len);
        }
        for k in 0..2 {
            self.spans[k] = spans_of(nx, self.windows[k], self.windows[1 - k]);
        }
    }
}

/// max over the rows of |phi| and |P|, for every column (one pass in memory order).
fn column_maxima<T: Real>(lat: &Lattice, phi: &[T], p: &[T]) -> Vec<f64> {
    let mut m = vec![0.0f64; lat.nx];
    for (rphi, rp) in phi.chunks_exact(lat.nx).zip(p.chunks_exact(lat.nx)) {
        for ((m, &a), &b) in m.iter_mut().zip(rphi).zip(rp) {
            *m = m.max(a.to_f64().abs()).max(b.to_f64().abs());
        }
    }
    m
}

/// max over the rows of |phi| and |P| in column `i`.
fn column_max<T: Real>(lat: &Lattice, phi: &[T], p: &[T], i: usize) -> f64 {
    (0..lat.ny)
        .map(|j| {
            let s = j * lat.nx + i;
            phi[s].to_f64().abs().max(p[s].to_f64().abs())
        })
        .fold(0.0, f64::max)
}

/// The kernel spans of a cell with window `own` beside a cell with window `other`: the runs of
/// `own`'s columns within 0..nx, split where `other` starts or ends.
pub fn spans_of(nx: usize, own: Window, other: Window) -> Vec<Span> {
    let mut spans: Vec<Span> = Vec::new();
    for i in 0..nx {
        if !own.contains(i, nx) {
            continue;
        }
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

    #[test]
    fn fit_takes_the_whole_row_when_no_gap_is_left() {
        assert!(Window::fit(&hot(20, &[0, 5, 10, 15]), 2).is_full(20));
        assert!(Window::fit(&hot(20, &[]), 2).is_full(20));
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
