//! Bad parameters and protocols are refused with an error that names the problem.

use cellsweep_solver::{Geometry, ParamError, Params, Protocol};

fn err(p: Params) -> ParamError {
    Protocol::default().validate(&p).unwrap_err()
}

#[test]
fn defaults_are_valid() {
    let steps = Protocol::default().validate(&Params::default()).unwrap();
    assert_eq!(
        (steps.relax, steps.free, steps.collide),
        (20_000, 200_000, 200_000)
    );
    assert_eq!((steps.record_every, steps.check_every), (250, 500));
}

#[test]
fn the_stability_guard_rejects_unstable_explicit_steps() {
    // (1/gamma) alpha d^2/2 dt = 50 * 0.26 * 10 * 0.002 = 0.26 > 0.25
    let e = err(Params {
        alpha: 0.26,
        ..Params::default()
    });
    assert!(matches!(e, ParamError::Unstable { .. }), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("alpha = 0.26") && msg.contains("dt = 0.002"),
        "{msg}"
    );
    // 0.25 exactly is allowed; halving dt makes 0.4 stable again.
    Protocol::default()
        .validate(&Params {
            alpha: 0.25,
            ..Params::default()
        })
        .unwrap();
    Protocol::default()
        .validate(&Params {
            alpha: 0.4,
            dt: 0.001,
            t_sample: 0.002,
            ..Params::default()
        })
        .unwrap();
}

#[test]
fn fiber_spacing_must_be_even_and_fit() {
    assert_eq!(
        err(Params {
            L: 91,
            ..Params::default()
        }),
        ParamError::OddSpacing(91)
    );
    assert!(matches!(
        err(Params {
            L: 200,
            ..Params::default()
        }),
        ParamError::SpacingTooLarge { .. }
    ));
    assert!(matches!(
        err(Params {
            L: 2,
            ..Params::default()
        }),
        ParamError::SpacingTooSmall { .. }
    ));
    // One fiber ignores L.
    Protocol::default()
        .validate(&Params {
            L: 91,
            geometry: Geometry::One,
            ..Params::default()
        })
        .unwrap();
}

#[test]
fn non_physical_values_are_named() {
    for (name, p) in [
        (
            "alpha",
            Params {
                alpha: 0.0,
                ..Params::default()
            },
        ),
        (
            "eta",
            Params {
                eta: -1.0,
                ..Params::default()
            },
        ),
        (
            "tau",
            Params {
                tau: 0.0,
                ..Params::default()
            },
        ),
        (
            "dt",
            Params {
                dt: 0.0,
                ..Params::default()
            },
        ),
        (
            "R0",
            Params {
                R0: -40.0,
                ..Params::default()
            },
        ),
        (
            "sigma",
            Params {
                sigma: -5.0,
                ..Params::default()
            },
        ),
        (
            "v0",
            Params {
                v0: -0.1,
                ..Params::default()
            },
        ),
        (
            "beta",
            Params {
                beta: f64::NAN,
                ..Params::default()
            },
        ),
    ] {
        let msg = err(p).to_string();
        assert!(msg.contains(name), "{name}: {msg}");
    }
}

#[test]
fn t_sample_must_be_a_whole_multiple_of_dt() {
    let e = err(Params {
        t_sample: 0.003,
        ..Params::default()
    });
    assert!(matches!(e, ParamError::SampleNotMultiple { .. }), "{e}");
    let ok = Params {
        dt: 0.0005,
        t_sample: 0.002,
        ..Params::default()
    };
    Protocol::default().validate(&ok).unwrap();
    assert_eq!(ok.sample_every(), 4);
}

#[test]
fn lattices_and_durations_are_checked() {
    let p = Params::default();
    let with = |f: fn(&mut Protocol)| {
        let mut pr = Protocol::default();
        f(&mut pr);
        pr.validate(&p).unwrap_err()
    };
    assert!(matches!(
        with(|pr| pr.single_lattice = [201, 200]),
        ParamError::OddLattice { .. }
    ));
    assert!(matches!(
        with(|pr| pr.single_lattice = [60, 60]),
        ParamError::LatticeTooSmall { .. }
    ));
    assert!(matches!(
        with(|pr| pr.pair_lattice = [300, 200]),
        ParamError::PairLattice { .. }
    ));
    assert!(matches!(
        with(|pr| pr.free_time = 0.0011),
        ParamError::DurationNotMultiple { .. }
    ));
}

#[test]
fn parameters_are_settable_by_their_spec_names() {
    let mut p = Params::default();
    for (name, v) in [
        ("R0", 20.0),
        ("E0", 1000.0),
        ("A_ref", 2.0),
        ("A", 150.0),
        ("inv_gamma", 40.0),
        ("L", 70.0),
    ] {
        p.set(name, v).unwrap();
    }
    assert_eq!(
        (p.R0, p.E0, p.A_ref, p.A, p.inv_gamma, p.L),
        (20.0, 1000.0, 2.0, 150.0, 40.0, 70)
    );
    assert!(p
        .set("gamma", 1.0)
        .unwrap_err()
        .to_string()
        .contains("unknown parameter"));
    assert!(p.set("L", 70.5).is_err());
    // Serialized with the SPEC's symbols.
    let json = serde_json::to_value(&p).unwrap();
    assert_eq!(json["R0"], 20.0);
    assert_eq!(json["L"], 70);
}
