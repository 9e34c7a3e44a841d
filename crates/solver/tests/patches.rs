//! Per-cell windows ("patches") against the whole lattice: the kernel on spans, the collision at
//! the paper's lattice size (noise-free and seeded with noise), and the leak check.

mod common;

use common::{same_bits, tiny_params};

use cellsweep_solver::kernel::{
    step_cell, step_cell_in, step_cell_portable_in, RowSpans, Span, StepCoeffs,
};
use cellsweep_solver::patch::{PatchSettings, Patches, Window};
use cellsweep_solver::{
    collide, prepare, Cell, ClassifierSettings, Collision, Fibers, Lattice, Params, Prep, Protocol,
    Silent, Sums,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// A blob centred at column `cx` with noise in the tails.
fn blob(lat: &Lattice, cx: f64, rng: &mut ChaCha8Rng) -> (Vec<f64>, Vec<f64>) {
    let (mut phi, mut p) = (lat.zeros(), lat.zeros());
    for j in 0..lat.ny {
        for i in 0..lat.nx {
            let r = ((i as f64 - cx).powi(2) + (j as f64 - 12.0).powi(2)).sqrt();
            phi[lat.idx(i, j)] =
                (0.5 + 0.5 * ((7.0 - r) / 3.0).tanh()) * rng.random_range(0.9..1.1);
            p[lat.idx(i, j)] = rng.random_range(-1.0..1.0);
        }
    }
    (phi, p)
}

#[test]
fn spans_compute_exactly_what_the_whole_row_computes() {
    // 64 columns run the seam blocks, 62 the plain loop with scalar seam columns.
    for nx in [64, 62] {
        let lat = Lattice::new(nx, 24);
        let params = Params {
            beta: 20.0,
            ..tiny_params()
        };
        let fibers = Fibers::new(&params, lat.ny);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (phi, pol) = blob(&lat, 20.0, &mut rng);
        let (mut other, _) = blob(&lat, 34.0, &mut rng);
        // The other cell's window is columns 16..40: it is exactly zero elsewhere.
        for j in 0..lat.ny {
            for i in (0..16).chain(40..nx) {
                other[lat.idx(i, j)] = 0.0;
            }
        }
        let sums = Sums::of(&lat, &fibers, &phi);
        let k = StepCoeffs::new(&params, &sums, [0.07, -0.02], true);
        let (mut p_full, mut out_full) = (pol.clone(), lat.zeros());
        let s_full = step_cell(
            &lat,
            &fibers,
            &k,
            &phi,
            &mut p_full,
            Some(&other),
            &mut out_full,
            false,
        );

        // Every column, in pieces; the pair terms skipped where the other cell is zero.
        let spans = [
            Span {
                lo: 0,
                hi: 16,
                pair: false,
            },
            Span {
                lo: 16,
                hi: 40,
                pair: true,
            },
            Span {
                lo: 40,
                hi: nx,
                pair: false,
            },
        ];
        let (mut p_sp, mut out_sp) = (pol.clone(), lat.zeros());
        let s_sp = step_cell_in(
            &lat,
            &fibers,
            &k,
            &phi,
            &mut p_sp,
            Some(&other),
            &spans,
            &mut out_sp,
            false,
        );
        assert!(
            out_sp.iter().zip(&out_full).all(|(a, b)| a == b),
            "phi differs (nx = {nx})"
        );
        assert!(
            p_sp.iter().zip(&p_full).all(|(a, b)| a == b),
            "P differs (nx = {nx})"
        );
        // The integrals are summed span by span: the same up to the order of the additions.
        assert!((s_sp.area - s_full.area).abs() <= 1e-14 * s_full.area);
        for f in 0..2 {
            assert!((s_sp.adhesive[f] - s_full.adhesive[f]).abs() <= 1e-13 * s_full.area);
        }

        // The portable path on spans gives the same bits as the dispatched one.
        let (mut p_port, mut out_port) = (pol.clone(), lat.zeros());
        let s_port = step_cell_portable_in(
            &lat,
            &fibers,
            &k,
            &phi,
            &mut p_port,
            Some(&other),
            &spans,
            &mut out_port,
        );
        assert_eq!(s_port, s_sp);
        assert!(same_bits(&out_port, &out_sp));
        assert!(same_bits(&p_port, &p_sp));

        // A window wrapping round the seam writes nothing outside itself.
        let spans = [
            Span {
                lo: 0,
                hi: 8,
                pair: true,
            },
            Span {
                lo: nx - 16,
                hi: nx,
                pair: true,
            },
        ];
        let (mut p_w, mut out_w) = (pol.clone(), lat.zeros());
        step_cell_in(
            &lat,
            &fibers,
            &k,
            &phi,
            &mut p_w,
            Some(&other),
            &spans,
            &mut out_w,
            false,
        );
        for j in 0..lat.ny {
            for i in 0..nx {
                let s = lat.idx(i, j);
                if i < 8 || i >= nx - 16 {
                    assert_eq!(out_w[s], out_full[s]);
                    assert_eq!(p_w[s], p_full[s]);
                } else {
                    assert_eq!(out_w[s], 0.0);
                    assert_eq!(p_w[s].to_bits(), pol[s].to_bits());
                }
            }
        }
    }
}

/// The paper's lattices (200 x 200, pair 400 x 200) with a short free motion.
fn protocol(collide_steps: u64) -> Protocol {
    Protocol {
        free_time: 10.0,
        collide_time: collide_steps as f64 * 0.002,
        stop_early: false,
        ..Protocol::default()
    }
}

fn run(params: &Params, prep: &Prep, patch: PatchSettings, steps: u64, seed: u64) -> Collision {
    let mut protocol = protocol(steps);
    protocol.patch = patch;
    protocol.record_interval = 0.1;
    collide(
        params,
        &protocol,
        &ClassifierSettings::default(),
        prep,
        seed,
        &mut Silent,
        false,
    )
    .unwrap()
}

/// Largest difference between two tracks, each observable scaled by its natural size (the
/// lattice for positions, pi R0^2 for areas and overlap).
fn worst_difference(a: &Collision, b: &Collision, params: &Params) -> f64 {
    assert_eq!(a.track.len(), b.track.len());
    let a0 = PI * params.R0 * params.R0;
    let mut worst: f64 = 0.0;
    for (x, y) in a.track.iter().zip(&b.track) {
        for c in 0..2 {
            worst = worst.max((x.x[c] - y.x[c]).abs() / 400.0);
            worst = worst.max((x.xbar[c] - y.xbar[c]).abs() / 400.0);
            worst = worst.max((x.ybar[c] - y.ybar[c]).abs() / 200.0);
            worst = worst.max((x.area[c] - y.area[c]).abs() / a0);
            for f in 0..2 {
                worst = worst.max((x.adhesive[c][f] - y.adhesive[c][f]).abs() / a0);
            }
        }
        worst = worst.max((x.overlap - y.overlap).abs() / a0);
    }
    worst
}

#[test]
fn windows_match_the_whole_lattice_to_1e9_noise_free_and_with_noise() {
    let steps = 3000;
    for (v0, seeds) in [(0.0, vec![1]), (0.1, vec![5, 6])] {
        let params = Params {
            beta: 14.0,
            v0,
            ..Params::default()
        };
        let prep = prepare(&params, &protocol(steps), 11, &mut Silent).unwrap();
        for seed in seeds {
            let full = run(&params, &prep, PatchSettings::off(), steps, seed);
            let windows = run(&params, &prep, PatchSettings::default(), steps, seed);
            let stats = windows.patch.expect("windows were on");
            assert!(full.patch.is_none());
            // The windows really are narrower than the lattice: the test compares two paths.
            assert!(stats.mean_fraction < 0.9, "windows cover {stats:?}");
            let worst = worst_difference(&full, &windows, &params);
            eprintln!("v0 = {v0}, seed {seed}: worst scaled difference {worst:e}, {stats:?}");
            assert!(
                worst < 1e-9,
                "v0 = {v0}, seed {seed}: differs by {worst:e} ({stats:?})"
            );
            assert_eq!(full.outcome, windows.outcome);
            assert_eq!(full.contact_time, windows.contact_time);
        }
    }
}

#[test]
fn the_leak_check_grows_a_window_whose_edge_reaches_the_bound() {
    let lat = Lattice::new(128, 32);
    let params = tiny_params();
    let fibers = Fibers::new(&params, lat.ny);
    // Two cells as bumps exp(-|x - c| / 3), far apart; no values near the bound at first.
    let field = |c: f64| {
        let mut phi = lat.zeros();
        for j in 0..lat.ny {
            for i in 0..lat.nx {
                let d = (i as f64 - c).abs();
                phi[lat.idx(i, j)] = if d < 12.0 { (-d / 3.0).exp() } else { 0.0 };
            }
        }
        phi
    };
    let mut a = Cell::new(&lat, &fibers, field(30.0), lat.zeros());
    let mut b = Cell::new(&lat, &fibers, field(90.0), lat.zeros());
    let settings = PatchSettings {
        pad: 4,
        ..PatchSettings::default()
    };
    let mut patches = Patches::new(&settings, &lat, &fibers, [&mut a, &mut b]).unwrap();
    // The fields are the same in every row, and so are the windows.
    let row_window = |p: &Patches, k: usize| {
        let w = p.windows()[k];
        assert!(w.iter().all(|x| *x == w[0]));
        w[0]
    };
    let (wa, wb) = (row_window(&patches, 0), row_window(&patches, 1));
    // Columns 19..=41 are above the bound; padded by 4 (15..47) and aligned to 16: 0..48.
    assert_eq!(wa, Window { start: 0, len: 48 });
    assert_eq!(wb, Window { start: 64, len: 48 });
    // Outside its window a cell is exactly zero.
    for i in 48..128 {
        assert!((0..lat.ny).all(|j| a.phi[lat.idx(i, j)] == 0.0));
    }

    // Something reaches the bound on the window's last column (as a tail spreading between
    // checks would): the next check sees it and grows the window past it.
    a.phi[lat.idx(47, 5)] = 2.0 * settings.bound;
    patches.after_step(settings.check_every - 1, &lat, &fibers, [&mut a, &mut b]);
    assert_eq!(
        row_window(&patches, 0),
        wa,
        "no check between check intervals"
    );
    patches.after_step(settings.check_every, &lat, &fibers, [&mut a, &mut b]);
    assert_eq!(patches.stats().edge_hits, 1);
    // Rows 5 - pad to 5 + pad grew past column 47.
    for j in 1..=9 {
        let grown = patches.windows()[0][j];
        assert!(grown.contains(47, lat.nx) && grown.contains(47 + settings.pad, lat.nx));
    }
    assert_eq!(
        patches.windows()[0][20],
        wa,
        "rows far from the leak keep their window"
    );
    assert_eq!(
        a.phi[lat.idx(47, 5)],
        2.0 * settings.bound,
        "nothing above the bound is cut"
    );

    // A refit shrinks a window only over sites that are below the bound, and leaves them
    // exactly zero.
    a.phi[lat.idx(47, 5)] = 0.0;
    a.phi[lat.idx(52, 5)] = 0.5 * settings.bound;
    assert!(patches.windows()[0][5].contains(52, lat.nx));
    patches.after_step(settings.refit_every, &lat, &fibers, [&mut a, &mut b]);
    assert_eq!(row_window(&patches, 0), wa);
    assert_eq!(a.phi[lat.idx(52, 5)], 0.0);
}

#[test]
fn rows_far_from_a_cell_have_no_window_and_the_leak_check_watches_them() {
    let lat = Lattice::new(128, 64);
    let params = tiny_params();
    let fibers = Fibers::new(&params, lat.ny);
    // A blob exp(-r / 2) around (40, 20), cut to zero beyond r = 14: rows 6..=34 are non-zero.
    let blob = |cx: f64| {
        let mut phi = lat.zeros();
        for j in 0..lat.ny {
            for i in 0..lat.nx {
                let r = ((i as f64 - cx).powi(2) + (j as f64 - 20.0).powi(2)).sqrt();
                phi[lat.idx(i, j)] = if r < 14.0 { (-r / 2.0).exp() } else { 0.0 };
            }
        }
        phi
    };
    let mut a = Cell::new(&lat, &fibers, blob(40.0), lat.zeros());
    let mut b = Cell::new(&lat, &fibers, blob(100.0), lat.zeros());
    let settings = PatchSettings {
        bound: 1e-3,
        pad: 2,
        ..PatchSettings::default()
    };
    let mut patches = Patches::new(&settings, &lat, &fibers, [&mut a, &mut b]).unwrap();
    // exp(-r/2) >= 1e-3 for r <= 13.8: rows 7..=33 are hot, 5..=35 have windows (pad 2).
    let w = patches.windows()[0];
    for (j, wj) in w.iter().enumerate() {
        assert_eq!(wj.len > 0, (5..=35).contains(&j), "row {j}: {wj:?}");
    }
    // The narrower rows near the blob's top and bottom have narrower windows.
    assert!(w[6].len < w[20].len);
    let stats_sites: usize = w.iter().map(|x| x.len).sum();
    assert!(stats_sites < 31 * 128 / 2);

    // A value at the bound on row 35, column 40 (inside its window, but row 36 has no window
    // there) is a vertical leak: the next check refits, and the rows below get windows.
    a.phi[lat.idx(40, 35)] = 2.0 * settings.bound;
    patches.after_step(settings.check_every, &lat, &fibers, [&mut a, &mut b]);
    assert_eq!(patches.stats().edge_hits, 1);
    assert!(patches.windows()[0][37].contains(40, lat.nx));
    assert!(patches.windows()[0][36].len > 0);
}

/// Per-row spans that differ from row to row (as the collision's windows do, down to rows with
/// no window at all, at the ends of a block of rows): the step's area and adhesive sums are
/// exactly those of its new phi, every row's columns counted.
#[test]
fn per_row_spans_sum_every_row_they_compute() {
    let lat = Lattice::new(64, 24);
    let params = Params {
        beta: 20.0,
        ..tiny_params()
    };
    let fibers = Fibers::new(&params, lat.ny);
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let (mut phi, mut pol) = blob(&lat, 30.0, &mut rng);
    // (pol and phi are cut to each row's window below.)
    // Row j computes columns lo(j)..hi(j): wide in the middle rows, narrow or empty near the
    // ends of each half (rows 0..12 and 12..24 are the two blocks of the step).
    let window = |j: usize| -> Option<(usize, usize)> {
        match j {
            10 | 11 | 23 => None,
            9 | 22 => Some((24, 40)),
            _ => Some((
                if j.is_multiple_of(2) { 0 } else { 8 },
                if j.is_multiple_of(3) { 64 } else { 48 },
            )),
        }
    };
    let mut offsets = vec![0];
    let mut spans = Vec::new();
    for j in 0..lat.ny {
        if let Some((lo, hi)) = window(j) {
            spans.push(Span {
                lo,
                hi,
                pair: false,
            });
        }
        offsets.push(spans.len());
        for i in 0..lat.nx {
            if !window(j).is_some_and(|(lo, hi)| (lo..hi).contains(&i)) {
                phi[lat.idx(i, j)] = 0.0;
                pol[lat.idx(i, j)] = 0.0;
            }
        }
    }
    let rows = RowSpans::PerRow {
        offsets: &offsets,
        spans: &spans,
    };
    // f64, and f32 (whose squares are flushed to f64 every 8 rows).
    check_sums_on(&lat, &fibers, &params, &phi, &pol, rows, 1e-12);
    let to32 = |f: &[f64]| f.iter().map(|&v| v as f32).collect::<Vec<f32>>();
    check_sums_on(&lat, &fibers, &params, &to32(&phi), &to32(&pol), rows, 1e-6);
}

fn check_sums_on<T: cellsweep_solver::Real>(
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    phi: &[T],
    pol: &[T],
    rows: RowSpans,
    tol: f64,
) {
    let sums = Sums::of(lat, fibers, phi);
    let k = StepCoeffs::<T>::new(params, &sums, [0.07, -0.02], true);
    let (mut p, mut out) = (pol.to_vec(), vec![T::default(); lat.len()]);
    let got = step_cell_in(lat, fibers, &k, phi, &mut p, None, rows, &mut out, false);
    let direct: f64 = out.iter().map(|v| v.to_f64() * v.to_f64()).sum();
    assert!(
        (got.area - direct).abs() < tol * direct,
        "area {} against sum phi^2 = {direct}",
        got.area
    );
    assert_eq!(got, Sums::of(lat, fibers, &out));
}
