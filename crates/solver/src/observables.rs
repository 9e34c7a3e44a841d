//! Observables of phase fields (SPEC sections 4 and 5) that are not part of the step itself.

use serde::{Deserialize, Serialize};

use crate::fibers::Fibers;
use crate::kernel::Sums;
use crate::lattice::Lattice;
use crate::real::Real;

/// Summary of one cell's field, as printed by `cellsweep relax --json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldSummary {
    pub steps: u64,
    /// sum phi
    #[serde(with = "crate::nonfinite")]
    pub sum_phi: f64,
    /// S = sum phi^2
    #[serde(with = "crate::nonfinite")]
    pub area: f64,
    /// Ad = sum phi^2 (3 - 2 phi) chi
    #[serde(with = "crate::nonfinite")]
    pub adhesive_area: f64,
    /// Ad restricted to the bottom fiber's rows (the single fiber's with one fiber).
    #[serde(with = "crate::nonfinite")]
    pub adhesive_area_bottom: f64,
    /// Ad restricted to the top fiber's rows (the single fiber's with one fiber).
    #[serde(with = "crate::nonfinite")]
    pub adhesive_area_top: f64,
    #[serde(with = "crate::nonfinite")]
    pub xbar: f64,
    #[serde(with = "crate::nonfinite")]
    pub ybar: f64,
    #[serde(with = "crate::nonfinite")]
    pub max_phi: f64,
}

impl FieldSummary {
    /// The summary of a lattice of resolution `k` in the paper's units (areas in l0^2,
    /// positions in l0); the same at k = 1.
    pub fn in_paper_units(self, k: u32) -> FieldSummary {
        if k <= 1 {
            return self;
        }
        let (l, a) = (f64::from(k), f64::from(k * k));
        FieldSummary {
            sum_phi: self.sum_phi / a,
            area: self.area / a,
            adhesive_area: self.adhesive_area / a,
            adhesive_area_bottom: self.adhesive_area_bottom / a,
            adhesive_area_top: self.adhesive_area_top / a,
            xbar: self.xbar / l,
            ybar: self.ybar / l,
            ..self
        }
    }

    pub fn of(lat: &Lattice, fibers: &Fibers, phi: &[f64], steps: u64) -> Self {
        let sums = Sums::of(lat, fibers, phi);
        let (bottom, top) = if fibers.count() == 1 {
            (sums.adhesive[0], sums.adhesive[0])
        } else {
            (sums.adhesive[0], sums.adhesive[1])
        };
        let [xbar, ybar] = lat.centroid(phi);
        FieldSummary {
            steps,
            sum_phi: phi.iter().sum(),
            area: sums.area,
            adhesive_area: sums.adhesive_total(),
            adhesive_area_bottom: bottom,
            adhesive_area_top: top,
            xbar,
            ybar,
            max_phi: max_of(phi),
        }
    }
}

/// Largest value of a field (NaN if any value is NaN).
pub fn max_of<T: Real>(f: &[T]) -> f64 {
    f.iter().fold(f64::NEG_INFINITY, |m, &v| {
        let v = v.to_f64();
        if v.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(v)
        }
    })
}

/// Whether every value of the fields is finite.
pub fn all_finite<T: Real>(fields: &[&[T]]) -> bool {
    fields
        .iter()
        .all(|f| f.iter().all(|v| v.to_f64().is_finite()))
}

/// Overlap O = sum phi_1 phi_2 of two fields on a lattice `nx` wide: summed column by column
/// over the rows first (element-wise, so the pass vectorises), then across the columns.
pub fn overlap<T: Real>(nx: usize, a: &[T], b: &[T]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut col = vec![0.0f64; nx];
    for (ra, rb) in a.chunks_exact(nx).zip(b.chunks_exact(nx)) {
        for ((o, x), y) in col.iter_mut().zip(ra).zip(rb) {
            *o += x.to_f64() * y.to_f64();
        }
    }
    col.iter().sum()
}

/// Sizes of the 4-connected components (periodic in both directions) of the region phi > 0.5.
pub fn components<T: Real>(lat: &Lattice, phi: &[T]) -> Vec<usize> {
    pieces(lat, phi).1
}

/// The 4-connected components (periodic in both directions) of the region phi > 0.5: each
/// site's piece (0 outside the region, k + 1 in the k-th piece) and each piece's size.
pub fn pieces<T: Real>(lat: &Lattice, phi: &[T]) -> (Vec<u32>, Vec<usize>) {
    let (nx, ny) = (lat.nx, lat.ny);
    // u32::MAX: in the region, not reached yet.
    let mut label: Vec<u32> = phi
        .iter()
        .map(|&v| if v.to_f64() > 0.5 { u32::MAX } else { 0 })
        .collect();
    let mut sizes = Vec::new();
    let mut stack = Vec::new();
    for start in 0..phi.len() {
        if label[start] != u32::MAX {
            continue;
        }
        let id = sizes.len() as u32 + 1;
        label[start] = id;
        stack.push(start);
        let mut size = 0;
        while let Some(s) = stack.pop() {
            size += 1;
            let (i, j) = (s % nx, s / nx);
            let neighbours = [
                j * nx + (i + 1) % nx,
                j * nx + (i + nx - 1) % nx,
                ((j + 1) % ny) * nx + i,
                ((j + ny - 1) % ny) * nx + i,
            ];
            for q in neighbours {
                if label[q] == u32::MAX {
                    label[q] = id;
                    stack.push(q);
                }
            }
        }
        sizes.push(size);
    }
    (label, sizes)
}

/// Which fibers a cell holds on to, from its adhesive areas: a fiber whose adhesive area is
/// below 10% of the other's has been let go (SPEC section 4, the `unstable` rule).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Attachment {
    /// On both fibers (two-fiber geometry).
    Both,
    /// Only on the bottom fiber.
    Bottom,
    /// Only on the top fiber.
    Top,
    /// On the single fiber (one-fiber geometry).
    Single,
    /// On no fiber.
    Detached,
}

/// Fraction below which a fiber counts as let go.
pub const LET_GO_FRACTION: f64 = 0.1;

impl Attachment {
    pub fn of(fibers: &Fibers, sums: &Sums) -> Self {
        let [b, t] = sums.adhesive;
        if fibers.count() == 1 {
            return if b > 0.0 {
                Attachment::Single
            } else {
                Attachment::Detached
            };
        }
        let max = b.max(t);
        if max <= 0.0 || !max.is_finite() {
            Attachment::Detached
        } else if b < LET_GO_FRACTION * t {
            Attachment::Top
        } else if t < LET_GO_FRACTION * b {
            Attachment::Bottom
        } else {
            Attachment::Both
        }
    }
}
