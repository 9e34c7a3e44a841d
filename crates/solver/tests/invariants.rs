//! Invariants of the dynamics on small lattices: determinism per seed, mirror symmetry of the
//! noise-free collision, translation invariance, area under relaxation, fibers' pull.

mod common;

use cellsweep_solver::collision::place_pair;
use cellsweep_solver::observables::components;
use cellsweep_solver::prep::initial_circle;
use cellsweep_solver::{collide, prepare, relax, Cell, Fibers, Geometry, Lattice, Silent, Verdict};
use common::{same_bits, small_config};
use std::f64::consts::PI;

#[test]
fn same_seed_same_trajectory_bit_for_bit() {
    let cfg = small_config(Geometry::Two);
    let a = prepare(&cfg.params, &cfg.protocol, 11, &mut Silent).unwrap();
    let b = prepare(&cfg.params, &cfg.protocol, 11, &mut Silent).unwrap();
    let c = prepare(&cfg.params, &cfg.protocol, 12, &mut Silent).unwrap();
    assert!(same_bits(&a.phi, &b.phi) && same_bits(&a.p, &b.p));
    assert!(
        !same_bits(&a.phi, &c.phi),
        "a different seed must give different noise"
    );
    // Relaxation is deterministic and seed-free.
    assert_eq!(a.relaxed, c.relaxed);

    let run = |seed, parallel| {
        collide(
            &cfg.params,
            &cfg.protocol,
            &cfg.classifier,
            &a,
            seed,
            &mut Silent,
            parallel,
        )
        .unwrap()
    };
    let (x, y, z) = (run(5, false), run(5, true), run(6, false));
    let last = |c: &cellsweep_solver::Collision| c.track.last().unwrap().clone();
    assert_eq!(last(&x), last(&y), "threads must not change the result");
    assert_ne!(last(&x), last(&z));
}

#[test]
fn noise_free_collision_starts_and_stays_mirror_symmetric() {
    let mut cfg = small_config(Geometry::Two);
    cfg.params.v0 = 0.0;
    cfg.params.sigma = 5.0;
    let prep = prepare(&cfg.params, &cfg.protocol, 3, &mut Silent).unwrap();
    let [nx, ny] = cfg.protocol.pair_lattice;
    let [(phi1, p1), (phi2, p2)] = place_pair(&prep, nx);
    let mirror = |f: &[f64], i: usize, j: usize| f[j * nx + (nx - 1 - i)];
    for j in 0..ny {
        for i in 0..nx {
            assert_eq!(phi2[j * nx + i].to_bits(), mirror(&phi1, i, j).to_bits());
            assert_eq!(p2[j * nx + i].to_bits(), mirror(&p1, i, j).to_bits());
        }
    }
    // The shifted cell sits mid-box in its single-cell box (columns 0..Nx_s of the pair lattice).
    let snx = cfg.protocol.single_lattice[0];
    let boxed: Vec<f64> = phi1
        .chunks_exact(nx)
        .flat_map(|row| row[..snx].to_vec())
        .collect();
    let x1 = Lattice::new(snx, ny).centroid_x(&boxed);
    assert!(
        (x1 - (snx as f64 - 1.0) / 2.0).abs() <= 0.5 + 1e-9,
        "centroid {x1}"
    );
    assert!(phi1
        .chunks_exact(nx)
        .all(|row| row[snx..].iter().all(|&v| v == 0.0)));
    let lat = Lattice::new(nx, ny);

    // A few hundred steps of the full two-cell dynamics keep the symmetry to round-off.
    let fibers = Fibers::new(&cfg.params, ny);
    let mut a = Cell::new(&lat, &fibers, phi1, p1);
    let mut b = Cell::new(&lat, &fibers, phi2, p2);
    for _ in 0..300 {
        cellsweep_solver::cell::step_pair(
            &mut a,
            &mut b,
            &lat,
            &fibers,
            &cfg.params,
            [[0.0; 2]; 2],
            false,
        );
    }
    let mut worst: f64 = 0.0;
    for j in 0..ny {
        for i in 0..nx {
            worst = worst.max((b.phi[j * nx + i] - mirror(&a.phi, i, j)).abs());
            worst = worst.max((b.p[j * nx + i] - mirror(&a.p, i, j)).abs());
        }
    }
    assert!(worst < 1e-12, "mirror symmetry broken by {worst:e}");
    assert!((a.sums.area - b.sums.area).abs() < 1e-9);
}

#[test]
fn dynamics_are_invariant_under_translation_along_x() {
    let cfg = small_config(Geometry::Two);
    let lat = Lattice::new(96, 96);
    let fibers = Fibers::new(&cfg.params, 96);
    let mut cell = relax(&cfg.params, &lat, &fibers, 2000, &mut Silent, false);
    cellsweep_solver::prep::kick(&lat, &mut cell);
    let shift = 23;
    let shifted = |f: &[f64]| {
        let mut g = lat.zeros();
        for j in 0..lat.ny {
            for i in 0..lat.nx {
                g[lat.idx((i + shift) % lat.nx, j)] = f[lat.idx(i, j)];
            }
        }
        g
    };
    let mut moved = Cell::new(&lat, &fibers, shifted(&cell.phi), shifted(&cell.p));
    let noise = [0.07, -0.04];
    for _ in 0..500 {
        cell.step(&lat, &fibers, &cfg.params, noise, true, false);
        moved.step(&lat, &fibers, &cfg.params, noise, true, true);
    }
    let want = shifted(&cell.phi);
    let worst = want
        .iter()
        .zip(&moved.phi)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-12, "translation changed phi by {worst:e}");
    let dx = lat.wrap_dx(lat.centroid_x(&cell.phi), lat.centroid_x(&moved.phi));
    assert!((dx - shift as f64).abs() < 1e-9);
}

#[test]
fn relaxation_keeps_the_area_and_spreads_the_cell_on_the_fibers() {
    for geometry in [Geometry::One, Geometry::Two] {
        let cfg = small_config(geometry);
        let p = &cfg.params;
        let lat = Lattice::new(96, 96);
        let fibers = Fibers::new(p, 96);
        let target = PI * p.R0 * p.R0;
        let start = Cell::new(&lat, &fibers, initial_circle(&lat, p), lat.zeros());
        let cell = relax(p, &lat, &fibers, 20_000, &mut Silent, false);
        // The soft constraint holds S within a few percent of pi R0^2 throughout.
        let s = cell.sums.area;
        assert!(
            (s - target).abs() < 0.03 * target,
            "{geometry}: S = {s}, target {target}"
        );
        // The cell stays one piece, centred, with phi in [0, 1] up to the tanh tails.
        let big: Vec<usize> = components(&lat, &cell.phi)
            .into_iter()
            .filter(|&n| n >= 10)
            .collect();
        assert_eq!(big.len(), 1);
        assert!((lat.centroid_x(&cell.phi) - 47.5).abs() < 1e-9);
        assert!((lat.centroid_y(&cell.phi) - 47.5).abs() < 1e-9);
        // It spreads along the fibers: more adhesive area than the circle had.
        assert!(cell.sums.adhesive_total() > 1.1 * start.sums.adhesive_total());
        let extent = |row: usize| (0..96).filter(|&i| cell.phi[lat.idx(i, row)] > 0.5).count();
        let fiber_rows = fibers.rows();
        let widest_fiber_row = fiber_rows.iter().map(|&j| extent(j)).max().unwrap();
        let circle_chord = |row: usize| {
            (0..96)
                .filter(|&i| start.phi[lat.idx(i, row)] > 0.5)
                .count()
        };
        assert!(widest_fiber_row > circle_chord(fiber_rows[0]));
        if geometry == Geometry::Two {
            let [b, t] = cell.sums.adhesive;
            assert!(
                b > 0.0 && (b - t).abs() < 1e-9 * b,
                "both fibers held alike: {b} vs {t}"
            );
        }
    }
}

#[test]
fn a_short_prep_is_ok_and_moves_towards_plus_x() {
    let mut cfg = small_config(Geometry::Two);
    cfg.protocol.free_time = 20.0;
    let prep = prepare(&cfg.params, &cfg.protocol, 1, &mut Silent).unwrap();
    assert_eq!(prep.verdict, Verdict::Ok);
    let v = prep.free_speed.unwrap();
    assert!(v > 0.0, "the kicked cell moves to +x, free speed {v}");
}

#[test]
fn a_cell_without_line_tension_support_breaks_up() {
    // Far too strong a motility force for the soft cell: the prep must not be `ok`.
    let mut cfg = small_config(Geometry::Two);
    cfg.params.A = 5000.0;
    cfg.params.beta = 200.0;
    cfg.protocol.free_time = 40.0;
    let prep = prepare(&cfg.params, &cfg.protocol, 1, &mut Silent).unwrap();
    assert_ne!(prep.verdict, Verdict::Ok, "got {:?}", prep.prepped);
    assert!(prep.verdict_time.is_some());
}
