//! A collision in which a cell breaks up ends in `breakup` (SPEC section 5): checked first, at
//! the check interval, with the prep's rule, its reason and time kept; a second piece breaks a
//! cell up only when it is big (max(10 sites, 5% of the region)) and lasts two checks, and a
//! smaller one is a drop shed, counted; a whole collision is not touched by the check.

mod common;

use cellsweep_solver::{
    collide, prepare, BreakupWatch, Cell, Collision, Fibers, Geometry, Lattice, Outcome, Precision,
    Prep, Silent, Verdict,
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

/// `phi` with the block of columns `xs` and rows `ys` set to 1: a drop apart from the cell.
fn with_drop(
    phi: &[f64],
    nx: usize,
    xs: std::ops::Range<usize>,
    ys: std::ops::Range<usize>,
) -> Vec<f64> {
    let mut out = phi.to_vec();
    for j in ys {
        for i in xs.clone() {
            out[j * nx + i] = 1.0;
        }
    }
    out
}

#[test]
fn the_rule_names_each_way_a_cell_breaks_up() {
    let (cfg, prep) = short_prep();
    let lat = Lattice::new(prep.lattice[0], prep.lattice[1]);
    let fibers = Fibers::new(&cfg.params, prep.lattice[1]);
    let nx = prep.lattice[0];
    let cell = |phi: Vec<f64>| Cell::new(&lat, &fibers, phi, prep.p.clone());
    // The rules that need no second look, each on a fresh watch.
    let once = |phi: Vec<f64>| BreakupWatch::new().check(&lat, &cfg.params, &cell(phi));
    assert_eq!(once(prep.phi.clone()), None);

    let mut nan = prep.phi.clone();
    nan[5] = f64::NAN;
    let why = once(nan).expect("not finite");
    assert!(why.contains("not finite"), "{why}");

    let faint: Vec<f64> = prep.phi.iter().map(|v| v * 0.45).collect();
    let why = once(faint).expect("faint");
    assert!(why.starts_with("max phi"), "{why}");

    // Half the cell gone, what is left in one piece: the area rule.
    let shrunk = cut(&prep, 0..62);
    let why = once(shrunk.phi).expect("small");
    assert!(why.starts_with("S = "), "{why}");

    // A cell cut in two: not at the first look, a breakup at the second.
    let split = cell(cut(&prep, 44..56).phi);
    let mut watch = BreakupWatch::new();
    assert_eq!(watch.check(&lat, &cfg.params, &split), None);
    let why = watch
        .check(&lat, &cfg.params, &split)
        .expect("two pieces, twice");
    assert!(
        why.contains("2 pieces") && why.contains("two consecutive checks"),
        "{why}"
    );
    assert_eq!(
        watch.sheddings, 0,
        "the piece that broke the cell is not a drop"
    );

    // A drop of 25 sites (10 or more, under 5% of the cell's region) seen at two checks is
    // shed, once, not a breakup; a new drop later is a second shedding.
    let region = prep.phi.iter().filter(|&&v| v > 0.5).count();
    assert!(25 * 20 < region, "the drop is under 5% of {region} sites");
    let drop = cell(with_drop(&prep.phi, nx, 2..7, 2..7));
    let mut watch = BreakupWatch::new();
    for _ in 0..3 {
        assert_eq!(watch.check(&lat, &cfg.params, &drop), None);
    }
    assert_eq!(watch.sheddings, 1);
    let elsewhere = cell(with_drop(&prep.phi, nx, 2..7, 20..25));
    assert_eq!(watch.check(&lat, &cfg.params, &elsewhere), None);
    assert_eq!(watch.sheddings, 2);
    // Under 10 sites is no piece at all.
    let mut watch = BreakupWatch::new();
    let speck = cell(with_drop(&prep.phi, nx, 2..5, 2..5));
    assert_eq!(watch.check(&lat, &cfg.params, &speck), None);
    assert_eq!(watch.sheddings, 0);
    // A second piece of 5% or more that is gone at the next check broke nothing.
    let side = ((region as f64 * 0.05).sqrt().ceil() as usize) + 1;
    let big = cell(with_drop(&prep.phi, nx, 2..2 + side, 2..2 + side));
    let mut watch = BreakupWatch::new();
    assert_eq!(watch.check(&lat, &cfg.params, &big), None);
    assert_eq!(
        watch.check(&lat, &cfg.params, &cell(prep.phi.clone())),
        None
    );
    assert_eq!(
        watch.check(&lat, &cfg.params, &big),
        None,
        "not the same piece twice in a row"
    );
    assert!(watch.check(&lat, &cfg.params, &big).is_some());
}

#[test]
fn a_cell_in_two_pieces_ends_the_collision_at_the_second_check_in_either_precision() {
    let (mut cfg, prep) = short_prep();
    let split = cut(&prep, 44..56);
    // Checked every 5 steps, before the fibers' pull joins the pieces again: two checks.
    cfg.protocol.check_interval = 0.01;
    for precision in [Precision::F64, Precision::F32] {
        cfg.protocol.precision = precision;
        let c = run(&cfg, &split);
        assert_eq!(c.outcome, Outcome::Breakup, "{precision:?}");
        // The second check is at two check intervals, and the run stops there.
        let twice = 2.0 * cfg.protocol.check_interval;
        let at = c.decision_time.unwrap();
        assert!((at - twice).abs() < 1e-9, "{precision:?}: {at}");
        assert!((c.steps as f64 * cfg.params.dt - twice).abs() < 1e-9);
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
    assert_eq!(every.sheddings, 0);
    assert_eq!(every.track, once.track);
    assert_eq!(every.outcome, once.outcome);
}

#[test]
fn a_drop_shed_in_a_collision_is_counted_and_does_not_end_it() {
    let (mut cfg, prep) = short_prep();
    let nx = prep.lattice[0];
    // A 25-site drop far from the cell (cell 2, the mirror image, gets one too).
    let mut dropped = prep.clone();
    dropped.phi = with_drop(&prep.phi, nx, 2..7, 2..7);
    cfg.protocol.check_interval = 0.01;
    let c = run(&cfg, &dropped);
    assert_ne!(c.outcome, Outcome::Breakup, "{:?}", c.breakup_reason);
    assert_eq!(c.sheddings, 2, "one drop each");
}
