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
        let mut row_fiber = vec![None; ny];
        let h = ny / 2;
        let count = match params.geometry {
            Geometry::One => {
                row_fiber[h - 1] = Some(Fiber::Bottom);
                row_fiber[h] = Some(Fiber::Bottom);
                1
            }
            Geometry::Two => {
                let half = params.L as usize / 2;
                row_fiber[h - half - 1] = Some(Fiber::Bottom);
                row_fiber[h - half] = Some(Fiber::Bottom);
                row_fiber[h + half - 1] = Some(Fiber::Top);
                row_fiber[h + half] = Some(Fiber::Top);
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
