//! The breakup rule of SPEC sections 4 and 5, one check after another ([`BreakupWatch`]).
//!
//! A cell breaks up at once when its fields are not finite, max phi < 0.5 or S < 0.5 pi R0^2.
//! A cell in pieces breaks up only when a second piece is big and lasts: the region phi > 0.5
//! has a piece besides the largest of at least max(10 sites, 5% of the region's sites), and the
//! same piece (one that shares a site with it) was one at the check before. A smaller piece, or
//! one seen at a single check, is a drop the cell shed (a radius under about 2d cannot
//! persist): counted, never a label.

use std::f64::consts::PI;

use crate::cell::Cell;
use crate::lattice::Lattice;
use crate::observables::{all_finite, max_of, pieces};
use crate::params::Params;
use crate::real::Real;

/// The fewest sites a piece of the region phi > 0.5 needs to count at all (SPEC: 10 sites).
pub const MIN_PIECE: usize = 10;

/// The share of the region's sites a second piece needs to break the cell up (SPEC: 5%).
pub const MIN_SHARE: f64 = 0.05;

/// A second piece seen at one check: its sites (in lattice order) and whether it was big
/// enough to break the cell up.
#[derive(Debug, Clone)]
struct Piece {
    sites: Vec<usize>,
    big: bool,
}

/// The breakup rule applied to one cell check after check: it remembers the second pieces of
/// the previous check and counts the drops the cell shed.
#[derive(Debug, Clone)]
pub struct BreakupWatch {
    /// [`MIN_PIECE`] in this lattice's sites (k^2 times more at resolution k).
    min_piece: usize,
    previous: Vec<Piece>,
    /// Second pieces (of [`MIN_PIECE`] sites or more) that appeared and did not go on to
    /// break the cell up: the drops it shed.
    pub sheddings: u32,
}

impl Default for BreakupWatch {
    fn default() -> Self {
        BreakupWatch::new()
    }
}

impl BreakupWatch {
    /// The watch of a cell on the paper's lattice.
    pub fn new() -> BreakupWatch {
        BreakupWatch::at_resolution(1)
    }

    /// The watch of a cell on a lattice of resolution `k` (SPEC section 6: the 10 sites are
    /// an area, 10 k^2 sites).
    pub fn at_resolution(k: u32) -> BreakupWatch {
        let k = k.max(1) as usize;
        BreakupWatch {
            min_piece: MIN_PIECE * k * k,
            previous: Vec::new(),
            sheddings: 0,
        }
    }

    /// One check of `cell`: why it broke up, in words, or `None` while it has not.
    pub fn check<T: Real>(
        &mut self,
        lat: &Lattice,
        params: &Params,
        cell: &Cell<T>,
    ) -> Option<String> {
        if let Some(why) = lost(params, cell) {
            return Some(why);
        }
        let (label, sizes) = pieces(lat, &cell.phi);
        let region: usize = sizes.iter().sum();
        let big = self
            .min_piece
            .max((MIN_SHARE * region as f64).ceil() as usize);
        let main = (0..sizes.len()).max_by_key(|&k| (sizes[k], usize::MAX - k));
        // Every second piece that counts, with its sites.
        let mut slot = vec![usize::MAX; sizes.len()];
        let mut now: Vec<Piece> = Vec::new();
        for (k, &n) in sizes.iter().enumerate() {
            if Some(k) != main && n >= self.min_piece {
                slot[k] = now.len();
                now.push(Piece {
                    sites: Vec::with_capacity(n),
                    big: n >= big,
                });
            }
        }
        for (s, &l) in label.iter().enumerate() {
            if l != 0 && slot[l as usize - 1] != usize::MAX {
                now[slot[l as usize - 1]].sites.push(s);
            }
        }
        // Which of the previous check's pieces each site belonged to.
        let mut before = vec![u32::MAX; label.len()];
        for (k, p) in self.previous.iter().enumerate() {
            for &s in &p.sites {
                before[s] = k as u32;
            }
        }
        // The largest piece that lasted big, and how many did.
        let (mut broke, mut broken) = (None::<usize>, 0);
        for p in &now {
            let mut seen = p
                .sites
                .iter()
                .map(|&s| before[s])
                .filter(|&k| k != u32::MAX);
            let first = seen.next();
            if first.is_none() {
                self.sheddings += 1;
            }
            let lasted_big = first
                .into_iter()
                .chain(seen)
                .any(|k| self.previous[k as usize].big);
            if p.big && lasted_big {
                broken += 1;
                broke = broke.max(Some(p.sites.len()));
            }
        }
        self.previous = now;
        broke.map(|second| {
            // The pieces that broke the cell were counted as drops when they first appeared.
            self.sheddings = self.sheddings.saturating_sub(broken);
            let min = self.min_piece;
            let mut all: Vec<usize> = sizes.iter().copied().filter(|&n| n >= min).collect();
            all.sort_unstable_by(|a, b| b.cmp(a));
            let all: Vec<String> = all.iter().map(usize::to_string).collect();
            format!(
                "the region phi > 0.5 is in {} pieces of {min} or more sites ({} sites): a second \
                 piece of {second} sites, at least max({min}, 5% of {region}) = {big}, at two \
                 consecutive checks",
                all.len(),
                all.join(", ")
            )
        })
    }
}

/// The rules that break a cell up at once: fields not finite, max phi < 0.5, S < 0.5 pi R0^2.
fn lost<T: Real>(params: &Params, cell: &Cell<T>) -> Option<String> {
    let half_area = 0.5 * PI * params.R0 * params.R0;
    let max_phi = max_of(&cell.phi);
    if !all_finite(&[&cell.phi, &cell.p]) || !cell.sums.area.is_finite() {
        Some("the fields are not finite (NaN or infinite values)".to_string())
    } else if max_phi < 0.5 {
        Some(format!("max phi = {max_phi:.4} < 0.5"))
    } else if cell.sums.area < half_area {
        Some(format!(
            "S = {:.1} < 0.5 pi R0^2 = {half_area:.1}",
            cell.sums.area
        ))
    } else {
        None
    }
}
