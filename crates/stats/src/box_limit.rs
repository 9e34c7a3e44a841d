//! Box-limited points (SPEC section 4.5): a prepped cell so long that, placed in the pair
//! lattice, its front starts less than 0.35 Nx_s from the other cell's: the cells touch within
//! a few tau0 instead of meeting head-on in steady motion, and the outcome depends on the box.

/// The clearance between the two fronts at placement, as a share of the single-cell width,
/// below which a point is box-limited (0.35: at the paper's 400 x 200 pair lattice, a cell
/// longer than 0.65 Nx_s = 130 sites).
pub const CLEARANCE: f64 = 0.35;

/// Whether a prepped cell `extent` long (along x, l0) is box-limited on a single-cell lattice
/// `single_nx` wide and a pair lattice `pair_nx` wide: its front and the mirror image's start
/// `pair_nx - single_nx - extent` apart, less than [`CLEARANCE`] `single_nx`.
pub fn box_limited(extent: f64, single_nx: f64, pair_nx: f64) -> bool {
    pair_nx - single_nx - extent < CLEARANCE * single_nx
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_s_lattice_flags_cells_longer_than_130_sites_and_a_wider_one_none() {
        assert!(!box_limited(130.0, 200.0, 400.0));
        assert!(box_limited(131.0, 200.0, 400.0));
        assert!(box_limited(158.0, 200.0, 400.0));
        // 600 wide: the fronts start 400 - extent apart, at least 200 for any cell of its box.
        assert!(!box_limited(200.0, 200.0, 600.0));
    }
}
