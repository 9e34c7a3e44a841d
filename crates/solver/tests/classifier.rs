//! The outcome classifier on synthetic centroid tracks (SPEC section 5).

use cellsweep_solver::{Classifier, ClassifierSettings, Decision, Outcome};

const DT: f64 = 0.5; // one sample every 0.5 tau0
const R0: f64 = 40.0;

/// Feed a track given as functions of time until `t_end`; return the first decision.
fn classify(
    free_speed: f64,
    t_end: f64,
    x1: impl Fn(f64) -> f64,
    x2: impl Fn(f64) -> f64,
    overlap: impl Fn(f64) -> f64,
) -> Option<Decision> {
    let mut c = Classifier::new(&ClassifierSettings::default(), free_speed, R0);
    let mut first = None;
    let n = (t_end / DT).round() as usize;
    for k in 0..=n {
        let t = k as f64 * DT;
        let d = c.observe(t, x1(t), x2(t), overlap(t));
        if first.is_none() {
            first = d;
        }
        // Once decided, the decision never changes.
        if let (Some(a), Some(b)) = (first, d) {
            assert_eq!(a, b);
        }
    }
    first
}

/// Cells approach at speed v from x = 100 and 300 and touch (overlap 100) when 80 apart.
fn approach(v: f64) -> (f64, impl Fn(f64) -> f64) {
    let t_contact = (200.0 - 80.0) / (2.0 * v);
    (
        t_contact,
        move |t: f64| if t >= t_contact { 100.0 } else { 0.0 },
    )
}

#[test]
fn walk_past_when_the_cells_exchange_order() {
    let v = 1.0;
    let d = classify(
        v,
        400.0,
        |t| 100.0 + v * t,
        |t| 300.0 - v * t,
        |t| {
            if (60.0..160.0).contains(&t) {
                200.0
            } else {
                0.0
            }
        },
    )
    .expect("decided");
    assert_eq!(d.outcome, Outcome::WalkPast);
    // Delta = 200 - 2 t < -20 first at t = 110.5 on the 0.5 grid.
    assert_eq!(d.time, 110.5);
}

#[test]
fn train_when_both_move_the_same_way_for_the_sustained_window() {
    let v = 1.0;
    let (tc, ov) = approach(v);
    // After contact they stand still 20 tau0, then both move to -x at 0.6.
    let go = tc + 20.0;
    let x1 = move |t: f64| {
        if t < tc {
            100.0 + v * t
        } else if t < go {
            100.0 + v * tc
        } else {
            100.0 + v * tc - 0.6 * (t - go)
        }
    };
    let x2 = move |t: f64| x1(t) + if t < tc { 200.0 - 2.0 * v * t } else { 80.0 };
    let d = classify(v, 400.0, x1, x2, ov).expect("decided");
    assert_eq!(d.outcome, Outcome::Train);
    // Velocity over 10 tau0 exceeds 0.25 once the window holds > 10/0.6*0.25 of motion, then 25 more.
    assert!(
        d.time > go + 25.0 && d.time < go + 40.0,
        "decided at {}",
        d.time
    );
}

#[test]
fn reversal_needs_separation_and_lost_contact() {
    let v = 1.0;
    let (tc, _) = approach(v);
    let back = tc + 10.0;
    let x1 = move |t: f64| {
        if t < tc {
            100.0 + v * t
        } else if t < back {
            100.0 + v * tc
        } else {
            100.0 + v * tc - 0.5 * (t - back)
        }
    };
    let x2 = move |t: f64| 400.0 - x1(t);
    // Contact lasts until they are 10 apart more.
    let ov = move |t: f64| {
        if t >= tc && x2(t) - x1(t) < 90.0 {
            100.0
        } else {
            0.0
        }
    };
    let d = classify(v, 400.0, x1, x2, ov).expect("decided");
    assert_eq!(d.outcome, Outcome::Reversal);
    assert!(d.time >= back + 25.0);

    // The same motion with the cells still touching is not (yet) a reversal.
    let sticky = move |t: f64| if t >= tc { 100.0 } else { 0.0 };
    assert_eq!(classify(v, 400.0, x1, x2, sticky), None);
}

#[test]
fn undetermined_cases_stay_undetermined() {
    let v = 1.0;
    // Never in contact: moving apart from the start (no contact) is not a reversal.
    assert_eq!(
        classify(v, 400.0, |t| 100.0 - v * t, |t| 300.0 + v * t, |_| 0.0),
        None
    );
    // Never in contact, moving together the same way: not a train.
    assert_eq!(
        classify(v, 400.0, |t| 100.0 + v * t, |t| 300.0 + v * t, |_| 0.0),
        None
    );
    // A standoff: nose to nose, nearly still, jittering around.
    let (tc, ov) = approach(v);
    let x1 = move |t: f64| {
        if t < tc {
            100.0 + v * t
        } else {
            100.0 + v * tc + 0.5 * (t * 0.7).sin()
        }
    };
    let x2 = move |t: f64| {
        if t < tc {
            300.0 - v * t
        } else {
            300.0 - v * tc + 0.5 * (t * 0.9).cos()
        }
    };
    assert_eq!(classify(v, 400.0, x1, x2, &ov), None);
    // A train too short to be sustained (it stops after 20 tau0).
    let x1s = move |t: f64| {
        if t < tc {
            100.0 + v * t
        } else {
            100.0 + v * tc - 0.6 * (t - tc).min(20.0)
        }
    };
    let x2s = move |t: f64| x1s(t) + if t < tc { 200.0 - 2.0 * v * t } else { 80.0 };
    assert_eq!(classify(v, 400.0, x1s, x2s, &ov), None);
    // A jam jittering around Delta = 0 never counts as a walk-past.
    let jam1 = |t: f64| 200.0 - 5.0 * (t * 0.3).sin();
    let jam2 = |t: f64| 200.0 + 5.0 * (t * 0.3).sin();
    assert_eq!(classify(v, 400.0, jam1, jam2, |_| 300.0), None);
}

#[test]
fn the_threshold_speed_is_a_quarter_of_the_free_speed_with_a_floor() {
    let s = ClassifierSettings::default();
    assert_eq!(s.threshold_speed(2.0), 0.5);
    assert_eq!(s.threshold_speed(0.01), s.min_speed);
    assert_eq!(s.threshold_speed(f64::NAN), s.min_speed);
}

#[test]
fn a_prefix_of_a_track_never_decides_differently() {
    // Causality: the decision at time t only depends on samples up to t.
    let v = 1.0;
    let (tc, ov) = approach(v);
    let x1 = move |t: f64| {
        if t < tc {
            100.0 + v * t
        } else {
            100.0 + v * tc + 0.6 * (t - tc)
        }
    };
    let x2 = move |t: f64| x1(t) + if t < tc { 200.0 - 2.0 * v * t } else { 80.0 };
    let full = classify(v, 400.0, x1, x2, &ov).unwrap();
    for end in [full.time - 0.5, full.time, full.time + 50.0] {
        let d = classify(v, end, x1, x2, &ov);
        if end < full.time {
            assert_eq!(d, None);
        } else {
            assert_eq!(d, Some(full));
        }
    }
}
