//! Fiber rows (SPEC section 1) and the periodic centroid (SPEC section 5).

use cellsweep_solver::{Fiber, Fibers, Geometry, Lattice, Params};

#[test]
fn fiber_rows_are_exactly_the_specs() {
    let rows = |geometry, l| {
        Fibers::new(
            &Params {
                geometry,
                L: l,
                ..Params::default()
            },
            200,
        )
        .rows()
    };
    assert_eq!(rows(Geometry::One, 90), vec![99, 100]);
    assert_eq!(rows(Geometry::Two, 90), vec![54, 55, 144, 145]);
    assert_eq!(rows(Geometry::Two, 80), vec![59, 60, 139, 140]);
    assert_eq!(rows(Geometry::Two, 70), vec![64, 65, 134, 135]);
    let f = Fibers::new(&Params::default(), 200);
    assert_eq!(f.of_row(54), Some(Fiber::Bottom));
    assert_eq!(f.of_row(145), Some(Fiber::Top));
    assert_eq!(f.of_row(100), None);
}

fn blob(lat: &Lattice, x0: f64) -> Vec<f64> {
    let mut phi = lat.zeros();
    for j in 0..lat.ny {
        for i in 0..lat.nx {
            let dx = lat.wrap_dx(x0, i as f64);
            let r = (dx * dx + (j as f64 - 9.5).powi(2)).sqrt();
            phi[lat.idx(i, j)] = 0.5 + 0.5 * ((6.0 - r) / 2.0).tanh();
        }
    }
    phi
}

#[test]
fn the_centroid_follows_a_cell_across_the_periodic_seam() {
    let lat = Lattice::new(80, 20);
    for x0 in [40.0, 0.0, 1.5, 78.25, 79.5] {
        let x = lat.centroid_x(&blob(&lat, x0));
        assert!(
            lat.wrap_dx(x0, x).abs() < 1e-6,
            "blob at {x0}: centroid {x}"
        );
        // SPEC: the formula maps into (0, Nx]; Nx is reported as 0, so x lies in [0, Nx).
        assert!(
            (0.0..80.0).contains(&x),
            "blob at {x0}: centroid {x} outside [0, 80)"
        );
    }
    // A naive mean would put a blob straddling the seam at mid-lattice.
    let phi = blob(&lat, 0.0);
    let naive: f64 = (0..phi.len())
        .map(|k| phi[k] * (k % 80) as f64)
        .sum::<f64>()
        / phi.iter().sum::<f64>();
    assert!((naive - 40.0).abs() < 5.0);
    assert!((lat.centroid_y(&phi) - 9.5).abs() < 1e-9);
    assert_eq!(lat.wrap_dx(79.0, 1.0), 2.0);
    assert_eq!(lat.wrap_dx(1.0, 79.0), -2.0);
}
