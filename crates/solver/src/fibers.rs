//! The fiber field chi: which lattice rows are fiber rows (SPEC section 1).

use serde::{Deserialize, Serialize};

use crate::params::{Geometry, Params};

/// Which fiber a row belongs to. With one fiber there is only `Bottom`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Fiber {
    Bottom = 0,
    Top = 1,
}

/// chi on a lattice of height `ny`: each fiber two rows wide, spanning all x.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fibers {
    /// For each row, the fiber it belongs to (chi = 1), or `None` (chi = 0).
    row_fiber: Vec<Option<Fiber>>,
    count: usize,
}

impl Fibers {
    /// The fibers of `params.geometry` on a lattice of height `ny` (`ny` even, `L` validated).
    ///
    /// One fiber: rows Ny/2 - 1 and Ny/2. Two fibers at spacing L: rows Ny/2 - L/2 - 1,
    /// Ny/2 - L/2 (bottom) and Ny/2 + L/2 - 1, Ny/2 + L/2 (top).
    pub fn new(params: &Params, ny: usize) -> Self {
        Fibers::at_resolution(params, ny, 1)
    }

    /// The fibers on a lattice of resolution `k` (SPEC section 6; `params` in its units, L in
    /// its sites): each fiber 2k rows, Ny/2 - L/2 - k to Ny/2 - L/2 + k - 1 and Ny/2 + L/2 - k
    /// to Ny/2 + L/2 + k - 1 (one fiber: Ny/2 - k to Ny/2 + k - 1). At k = 1, [`Fibers::new`].
    pub fn at_resolution(params: &Params, ny: usize, k: u32) -> Self {
        let mut row_fiber = vec![None; ny];
        let (h, k) = (ny / 2, k.max(1) as usize);
        let mut lay = |centre: usize, fiber: Fiber| {
            for row in &mut row_fiber[centre - k..centre + k] {
                *row = Some(fiber);
            }
        };
        let count = match params.geometry {
            Geometry::One => {
                lay(h, Fiber::Bottom);
                1
            }
            Geometry::Two => {
                let half = params.L as usize / 2;
                lay(h - half, Fiber::Bottom);
                lay(h + half, Fiber::Top);
                2
            }
        };
        Fibers { row_fiber, count }
    }

    /// The fiber of row `j`, if `j` is a fiber row.
    #[inline]
    pub fn of_row(&self, j: usize) -> Option<Fiber> {
        self.row_fiber[j]
    }

    /// Number of fibers (1 or 2).
    pub fn count(&self) -> usize {
        self.count
    }

    /// The fiber rows, bottom to top.
    pub fn rows(&self) -> Vec<usize> {
        (0..self.row_fiber.len())
            .filter(|&j| self.row_fiber[j].is_some())
            .collect()
    }
}
