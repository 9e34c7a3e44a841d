//! P off the fiber rows never acts on phi (SPEC section 3: the motility force carries chi, and
//! P's update has no stencil), so the collision may advance P on the fiber rows only. These
//! tests hold that claim to the bit: phi and every observable are the same either way.

mod common;

use common::{row_in_two, same_bits};

use cellsweep_solver::cell::{step_pair, step_pair_in};
use cellsweep_solver::noise::Noise;
use cellsweep_solver::{
    collide, prepare, Cell, ClassifierSettings, Collision, Fibers, Geometry, Lattice, Monitor,
    Params, PatchSettings, Prep, Protocol, Silent,
};

/// A kicked circle of radius `r` centred at (`cx`, ny/2 - 1/2) moving towards `dir`.
fn kicked(lat: &Lattice, cx: f64, r: f64, dir: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut phi, mut p) = (lat.zeros(), lat.zeros());
    let cy = (lat.ny as f64 - 1.0) / 2.0;
    for j in 0..lat.ny {
        for i in 0..lat.nx {
            let rr = ((i as f64 - cx).powi(2) + (j as f64 - cy).powi(2)).sqrt();
            let v = 0.5 + 0.5 * ((r - rr) / (2.0 * 20f64.sqrt())).tanh();
            phi[lat.idx(i, j)] = v;
            if v > 0.5 && (i as f64 - cx) * dir >= 0.0 {
                p[lat.idx(i, j)] = 1.0;
            }
        }
    }
    (phi, p)
}

#[test]
fn p_on_fiber_rows_only_gives_the_same_phi_bit_for_bit() {
    let lat = Lattice::new(128, 48);
    let params = Params {
        R0: 14.0,
        L: 24,
        beta: 20.0,
        ..Params::default()
    };
    let fibers = Fibers::new(&params, lat.ny);
    let (phi1, p1) = kicked(&lat, 40.0, 14.0, 1.0);
    let (phi2, p2) = kicked(&lat, 88.0, 14.0, -1.0);
    let mut literal = [
        Cell::new(&lat, &fibers, phi1.clone(), p1.clone()),
        Cell::new(&lat, &fibers, phi2.clone(), p2.clone()),
    ];
    let mut fast = literal.clone();
    for c in &mut fast {
        c.polarity_on_fibers_only(&lat, &fibers);
        assert!(!c.polarity_everywhere());
    }
    // Whole rows, and rows in two spans (the kernel path of the collision's windows).
    let spans = row_in_two(32, 128);
    let mut noise = Noise::new(9, 2, params.v0, params.sample_every());
    let mut acted = false;
    for s in 0..600 {
        let nz = noise.at(s);
        let nz = [nz[0], nz[1]];
        for [a, b] in [&mut literal, &mut fast] {
            if s % 2 == 0 {
                step_pair(a, b, &lat, &fibers, &params, nz, false);
            } else {
                step_pair_in(a, b, &lat, &fibers, &params, nz, [&spans, &spans], false);
            }
        }
        for (l, f) in literal.iter().zip(&fast) {
            assert!(same_bits(&l.phi, &f.phi), "phi differs at step {s}");
            assert_eq!(l.sums, f.sums);
            for j in 0..lat.ny {
                let row = j * lat.nx..(j + 1) * lat.nx;
                if fibers.of_row(j).is_some() {
                    assert!(
                        same_bits(&l.p[row.clone()], &f.p[row]),
                        "P on fiber row {j}"
                    );
                } else {
                    assert!(f.p[row.clone()].iter().all(|&v| v == 0.0));
                    acted |= l.p[row].iter().any(|&v| v != 0.0);
                }
            }
        }
    }
    // The literal run really had P off the fiber rows, so the two runs differ in what they
    // computed, not just in what they stored.
    assert!(acted);
    // The cells moved: the motility force (through P on the fiber rows) did act.
    let moved = literal[0]
        .phi
        .iter()
        .zip(&phi1)
        .any(|(a, b)| (a - b).abs() > 1e-3);
    assert!(moved);
}

/// Asks for fields (so the collision keeps P on every row) but never looks at them.
struct WantsFields;

impl Monitor for WantsFields {
    fn records_fields(&self) -> bool {
        true
    }
}

fn collide_with(
    params: &Params,
    protocol: &Protocol,
    prep: &Prep,
    m: &mut dyn Monitor,
) -> Collision {
    collide(
        params,
        protocol,
        &ClassifierSettings::default(),
        prep,
        4,
        m,
        false,
    )
    .unwrap()
}

#[test]
fn a_collision_records_the_same_track_whether_or_not_p_is_kept_everywhere() {
    for patch in [PatchSettings::default(), PatchSettings::off()] {
        let mut config = common::small_config(Geometry::Two);
        config.protocol.patch = patch;
        config.protocol.stop_early = false;
        config.protocol.record_interval = 0.1;
        let (params, protocol) = (&config.params, &config.protocol);
        let prep = prepare(params, protocol, 3, &mut Silent).unwrap();
        let fast = collide_with(params, protocol, &prep, &mut Silent);
        let literal = collide_with(params, protocol, &prep, &mut WantsFields);
        assert_eq!(fast.track, literal.track, "patch {patch:?}");
        assert_eq!(fast.outcome, literal.outcome);
        assert_eq!(fast.steps, literal.steps);
    }
}
