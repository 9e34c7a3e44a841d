//! Small, fast configurations shared by the integration tests.
#![allow(dead_code)]

use cellsweep_solver::{ClassifierSettings, Config, Geometry, Params, Protocol};

/// A cell of radius 24 on a 96 x 96 lattice (pair 192 x 96), fibers 48 apart: the paper's shape
/// at a smaller scale (L / R0 = 2, lattice width 4 R0; the boundary width d stays sqrt(20), so
/// smaller cells than this split into one strip per fiber, and narrower lattices let the cell
/// spread round the periodic fiber into a band).
pub fn small_config(geometry: Geometry) -> Config {
    Config {
        params: Params {
            R0: 24.0,
            L: 48,
            geometry,
            ..Params::default()
        },
        protocol: Protocol {
            single_lattice: [96, 96],
            pair_lattice: [192, 96],
            relax_time: 10.0,
            free_time: 10.0,
            collide_time: 4.0,
            ..Protocol::default()
        },
        classifier: ClassifierSettings::default(),
    }
}

/// A cell of radius 8 with fibers 10 apart, for kernel-level tests on lattices of a few dozen
/// sites a side (no protocol: these tests step the kernel directly).
pub fn tiny_params() -> Params {
    Params {
        L: 10,
        R0: 8.0,
        ..Params::default()
    }
}

/// Whether two fields hold the same values bit for bit (f32 values widen to f64 exactly).
pub fn same_bits<T: cellsweep_solver::Real>(a: &[T], b: &[T]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.to_f64().to_bits() == y.to_f64().to_bits())
}

/// Every column of a row of `nx` as two pair spans split at column `at` (the kernel's span path,
/// computing exactly what the whole row computes).
pub fn row_in_two(at: usize, nx: usize) -> [cellsweep_solver::kernel::Span; 2] {
    use cellsweep_solver::kernel::Span;
    [
        Span {
            lo: 0,
            hi: at,
            pair: true,
        },
        Span {
            lo: at,
            hi: nx,
            pair: true,
        },
    ]
}
