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
