//! A collision in which a cell breaks up ends in `breakup` (SPEC section 5): checked first, at
//! the check interval, with the prep's rule, its reason and time kept; a whole collision is not
//! touched by the check.

mod common;

use cellsweep_solver::prep::breakup_reason;
use cellsweep_solver::{
    collide, prepare, Cell, Collision, Fibers, Geometry, Lattice, Outcome, Precision, Prep, Silent,
    Verdict,
};
use common::small_config;

/// A short real prep of the small configuration (R0 = 24 on 96 x 96).
fn short_prep() -> (cellsweep_solver::Config, Prep) {
    let cfg = small_config(Geometry::Two);
    let prep = prepare(&cfg.params, &cfg.protocol, 1, &mut Silent).unwrap();
    assert_eq!(prep.verdict, Verdict::Ok);
    (cfg, prep)
}

/// `prep` with the columns `cut` (of its single-cell box) emptied: the cell in two pieces.
fn cut(prep: &Prep, cut: std::ops::Range<usize>) -> Prep {
    let mut p = prep.clone();
    let nx = p.lattice[0];
    for (k, (phi, pol)) in p.phi.iter_mut().zip(p.p.iter_mut()).enumerate() {
        if cut.contains(&(k % nx)) {
            *phi = 0.0;
            *pol = 0.0;
        }
    }
    p
}

fn run(cfg: &cellsweep_solver::Config, prep: &Prep) -> Collision {
    collide(
        &cfg.params,
        &cfg.protocol,
        &cfg.classifier,
        prep,
        7,
        &mut Silent,
        false,
    )
    .unwrap()
}

#[test]
fn the_rule_names_each_way_a_cell_breaks_up() {
    let (cfg, prep) = short_prep();
    let lat = Lattice::new(prep.lattice[0], prep.lattice[1]);
    let fibers = Fibers::new(&cfg.params, prep.lattice[1]);
    let cell = |phi: Vec<f64>| Cell::new(&lat, &fibers, phi, prep.p.clone());
    assert_eq!(
        breakup_reason(&lat, &cfg.params, &cell(prep.phi.clone())),
        None
    );

    let split = cut(&prep, 44..56);
    let why = breakup_reason(&lat, &cfg.params, &cell(split.phi)).expect("two pieces");
    assert!(why.contains("2 pieces"), "{why}");

    let mut nan = prep.phi.clone();
    nan[5] = f64::NAN;
    let why = breakup_reason(&lat, &cfg.params, &cell(nan)).expect("not finite");
    assert!(why.contains("not finite"), "{why}");

    let faint: Vec<f64> = prep.phi.iter().map(|v| v * 0.45).collect();
    let why = breakup_reason(&lat, &cfg.params, &cell(faint)).expect("faint");
    assert!(why.starts_with("max phi"), "{why}");

    // Half the cell gone, what is left in one piece: the area rule.
    let shrunk = cut(&prep, 0..62);
    let why = breakup_reason(&lat, &cfg.params, &cell(shrunk.phi)).expect("small");
    assert!(why.starts_with("S = "), "{why}");
}

#[test]
fn a_cell_in_two_pieces_ends_the_collision_at_the_first_check_in_either_precision() {
    let (mut cfg, prep) = short_prep();
    let split = cut(&prep, 44..56);
    // Checked every 5 steps, before the fibers' pull joins the pieces again.
    cfg.protocol.check_interval = 0.01;
    for precision in [Precision::F64, Precision::F32] {
        cfg.protocol.precision = precision;
        let c = run(&cfg, &split);
        assert_eq!(c.outcome, Outcome::Breakup, "{precision:?}");
        // The first check is at one check interval, and the run stops there.
        let check = cfg.protocol.check_interval;
        assert_eq!(c.decision_time, Some(check), "{precision:?}");
        assert_eq!(c.steps as f64 * cfg.params.dt, check);
        let why = c.breakup_reason.as_deref().unwrap();
        assert!(
            why.starts_with("cell 1: ") && why.contains("pieces"),
            "{why}"
        );
    }
}

#[test]
fn a_field_that_is_not_finite_is_a_breakup_at_once_not_an_error() {
    let (cfg, prep) = short_prep();
    let mut bad = prep.clone();
    let centre = bad.lattice[0] * bad.lattice[1] / 2 + bad.lattice[0] / 2;
    bad.phi[centre] = f64::INFINITY;
    let c = run(&cfg, &bad);
    assert_eq!(c.outcome, Outcome::Breakup);
    assert_eq!(
        c.steps, 1,
        "stopped at the first step whose area is not finite"
    );
    assert!(c.breakup_reason.unwrap().contains("not finite"));
}

#[test]
fn a_whole_collision_is_untouched_by_the_check() {
    // The check only reads the fields: with it every check interval, the trajectory of a
    // collision that does not break up is the one with a single check at the end.
    let (mut cfg, prep) = short_prep();
    let every = run(&cfg, &prep);
    cfg.protocol.check_interval = cfg.protocol.collide_time;
    let once = run(&cfg, &prep);
    assert_ne!(every.outcome, Outcome::Breakup);
    assert_eq!(every.breakup_reason, None);
    assert_eq!(every.track, once.track);
    assert_eq!(every.outcome, once.outcome);
}
