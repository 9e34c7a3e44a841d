//! Labels at their edges, Wilson intervals, and the beta_crit fit on synthetic counts.

use cellsweep_stats::{
    fit_columns, fit_line, wilson, Counts, End, Label, Method, Others, Scales, Tally,
};

fn counts(n_train: u64, n_walk: u64, n_reversal: u64, n_undetermined: u64) -> Counts {
    Counts {
        tally: [
            (End::Train, n_train),
            (End::WalkPast, n_walk),
            (End::Reversal, n_reversal),
            (End::Undetermined, n_undetermined),
        ]
        .into_iter()
        .collect(),
        ..Counts::none(0.1, 10.0, 90, 5.0)
    }
}

/// walk walk-past and train training replicates, nothing else.
fn walk_train(walk: u64, train: u64) -> Tally {
    [(End::WalkPast, walk), (End::Train, train)]
        .into_iter()
        .collect()
}

#[test]
fn dominance_starts_at_53_of_96() {
    assert_eq!(counts(53, 43, 0, 0).label(), Some(Label::Train));
    assert_eq!(counts(43, 53, 0, 0).label(), Some(Label::WalkPast));
    assert_eq!(counts(0, 0, 53, 43).label(), Some(Label::Reversal));
    assert_eq!(counts(20, 23, 0, 53).label(), Some(Label::Undetermined));
    // 52 of 96 is not dominant; 52 vs 44 differ by 8 < 9.6: coexistence.
    assert_eq!(counts(52, 44, 0, 0).label(), Some(Label::Coexist));
}

#[test]
fn coexistence_needs_a_difference_below_ten_percent() {
    // 96 replicates: a difference of 9 coexists, 10 does not.
    assert_eq!(counts(44, 35, 17, 0).label(), Some(Label::Coexist));
    assert_eq!(counts(45, 35, 16, 0).label(), Some(Label::Mixed));
    assert_eq!(counts(35, 45, 16, 0).label(), Some(Label::Mixed));
    assert_eq!(counts(0, 0, 0, 0).label(), None);
}

#[test]
fn coexistence_needs_walk_past_and_training_in_half_the_replicates() {
    // SPEC section 6: close in number is not enough; together they must be at least 48 of 96.
    assert_eq!(counts(24, 24, 48, 0).label(), Some(Label::Coexist));
    assert_eq!(counts(24, 23, 49, 0).label(), Some(Label::Mixed));
    assert_eq!(counts(10, 10, 40, 36).label(), Some(Label::Mixed));
    // Odd totals: 2 (n_walk + n_train) >= n.
    assert_eq!(counts(3, 3, 3, 0).label(), Some(Label::Coexist));
    assert_eq!(counts(2, 2, 4, 1).label(), Some(Label::Mixed));
}

#[test]
fn prep_verdicts_carry_the_point() {
    let mut c = counts(0, 0, 0, 0);
    c.tally[End::Unstable] = 96;
    assert_eq!(c.label(), Some(Label::Unstable));
    assert!(!c.collided());
    let mut c = counts(0, 0, 0, 0);
    c.tally[End::Breakup] = 96;
    assert_eq!(c.label(), Some(Label::Breakup));
    // A verdict given by a counts file wins over counts.
    let mut c = counts(96, 0, 0, 0);
    c.verdict = Some(Label::Unstable);
    assert_eq!(c.label(), Some(Label::Unstable));
}

#[test]
fn wilson_intervals_match_known_values() {
    let f = wilson(5, 10);
    assert!((f.value - 0.5).abs() < 1e-12);
    assert!(
        (f.low - 0.236_593).abs() < 1e-5 && (f.high - 0.763_407).abs() < 1e-5,
        "{f:?}"
    );
    let z = wilson(0, 10);
    assert_eq!(z.low, 0.0);
    assert!((z.high - 0.277_533).abs() < 1e-5, "{z:?}");
    let all = wilson(96, 96);
    assert_eq!(all.high, 1.0);
    assert!(wilson(0, 0).value.is_nan());
}

/// Counts drawn from a known line: walk-past probability rises through 1/2 at beta_crit.
fn synthetic(a: f64, b: f64) -> Vec<Counts> {
    let scales = Scales::default();
    let mut out = Vec::new();
    for l in [90u32, 70] {
        for k in 0..6 {
            let alpha = 0.10 + 0.02 * k as f64;
            let crit = a * scales.x(alpha, l, 5.0) + b;
            for j in 0..11 {
                let beta = 10.0 + 4.0 * j as f64;
                let p = 1.0 / (1.0 + (-(beta - crit) / 1.5).exp());
                let n_walk = (96.0 * p).round() as u64;
                out.push(Counts {
                    alpha,
                    beta,
                    L: l,
                    tally: walk_train(n_walk, 96 - n_walk),
                    ..counts(0, 0, 0, 0)
                });
            }
        }
    }
    out
}

#[test]
fn the_fit_recovers_a_known_line_and_reports_unusable_columns() {
    let data = synthetic(0.6, -12.0);
    let fit = fit_line(&data, &Scales::default(), 200, 7, Method::Interpolate).unwrap();
    assert!((fit.a - 0.6).abs() < 0.02, "a = {}", fit.a);
    assert!((fit.b + 12.0).abs() < 1.5, "b = {}", fit.b);
    assert!(fit.r2 > 0.99);
    assert!(
        fit.a_ci[0] <= fit.a && fit.a <= fit.a_ci[1],
        "{:?}",
        fit.a_ci
    );
    assert!(
        fit.b_ci[0] <= fit.b && fit.b <= fit.b_ci[1],
        "{:?}",
        fit.b_ci
    );
    // Stiff cells at narrow spacing cross above beta = 50: those columns are skipped, with why.
    let skipped: Vec<_> = fit.columns.iter().filter(|c| c.skipped.is_some()).collect();
    assert!(!skipped.is_empty());
    assert!(
        skipped.iter().all(|c| c.L == 70 && c.alpha >= 0.16),
        "{skipped:?}"
    );
    assert!(skipped[0]
        .skipped
        .as_ref()
        .unwrap()
        .contains("training at least as frequent"));
}

#[test]
fn the_column_model_recovers_the_same_line_with_intervals_that_hold_it() {
    let data = synthetic(0.6, -12.0);
    let fit = fit_line(&data, &Scales::default(), 300, 7, Method::Model).unwrap();
    assert_eq!(fit.method, Method::Model);
    assert!((fit.a - 0.6).abs() < 0.01, "a = {}", fit.a);
    assert!((fit.b + 12.0).abs() < 0.6, "b = {}", fit.b);
    assert!(fit.a_ci[0] <= 0.6 && 0.6 <= fit.a_ci[1], "{:?}", fit.a_ci);
    assert!(
        fit.b_ci[0] <= -12.0 && -12.0 <= fit.b_ci[1],
        "{:?}",
        fit.b_ci
    );
    let scales = Scales::default();
    for c in &fit.columns {
        // Every column keeps its interpolated crossing beside the model's.
        assert_eq!(c.method, Method::Model);
        let truth = 0.6 * scales.x(c.alpha, c.L, 5.0) - 12.0;
        match (c.beta_star, c.beta_ci) {
            (Some(b), Some(ci)) => {
                assert!(ci[0] <= truth && truth <= ci[1], "{c:?}, truth {truth}");
                assert!((b - truth).abs() < 0.5, "{c:?}, truth {truth}");
            }
            // No crossing given where the truth lies beyond the rows (or by their edge).
            _ => assert!(!(14.0..=46.0).contains(&truth), "{c:?}, truth {truth}"),
        }
    }
}

#[test]
fn a_fit_without_two_usable_columns_says_why() {
    let data: Vec<Counts> = synthetic(0.6, -12.0)
        .into_iter()
        .filter(|c| c.L == 90 && c.alpha == 0.1)
        .collect();
    let no = fit_line(&data, &Scales::default(), 10, 1, Method::Interpolate).unwrap_err();
    assert!(no.reason.contains("a line needs two"), "{}", no.reason);
    assert_eq!(no.columns.len(), 1);
    assert!(no.columns[0].beta_star.is_some());
}

#[test]
fn the_sigma_shift_moves_the_line_left() {
    let s = Scales::default();
    // At sigma = 0 the same x is reached 0.0134 lower in alpha.
    assert!((s.x(0.1, 90, 0.0) - s.x(0.1 + 0.013415, 90, 5.0)).abs() < 1e-9);
    assert!((s.x(0.1, 40, 5.0) - 1123.97 * 0.1).abs() < 0.01);
}

/// Counts at R0 = 32 (an axis of their sweep) drawn from the line a x + b, on the spacing and
/// alphas that give the R0 = 40 columns of `synthetic` their x: L = 72, alpha x 40/32.
fn synthetic_r0_32(a: f64, b: f64) -> Vec<Counts> {
    let scales = Scales {
        R0: 32.0,
        ..Scales::default()
    };
    let mut out = Vec::new();
    for k in 0..6 {
        let alpha = (0.10 + 0.02 * k as f64) * 40.0 / 32.0;
        let crit = a * scales.x(alpha, 72, 5.0) + b;
        for j in 0..11 {
            let beta = 10.0 + 4.0 * j as f64;
            let p = 1.0 / (1.0 + (-(beta - crit) / 1.5).exp());
            let n_walk = (96.0 * p).round() as u64;
            out.push(Counts {
                alpha,
                beta,
                L: 72,
                tally: walk_train(n_walk, 96 - n_walk),
                others: Others(vec![("R0".into(), 32.0)]),
                ..counts(0, 0, 0, 0)
            });
        }
    }
    out
}

#[test]
fn columns_pooled_across_r0_fall_on_one_line_only_where_the_data_collapse() {
    let scales = Scales::default();
    let read = |data: &[Counts]| match fit_line(data, &scales, 0, 1, Method::Model) {
        Ok(f) => f.columns,
        Err(no) => no.columns,
    };
    let at40 = read(&synthetic(0.6, -12.0));
    // Each R0 = 32 column's x is its own (R0 from its axes), equal to its R0 = 40 partner's.
    let collapsed = read(&synthetic_r0_32(0.6, -12.0));
    for c in &collapsed {
        let partner = at40
            .iter()
            .find(|p| p.L == 90 && (p.alpha * 40.0 / 32.0 - c.alpha).abs() < 1e-12)
            .unwrap();
        assert!(
            (c.x - partner.x).abs() < 1e-9 * partner.x,
            "{c:?} vs {partner:?}"
        );
    }
    let pooled = fit_columns([at40.clone(), collapsed].concat(), 300, 7).unwrap();
    assert!((pooled.a - 0.6).abs() < 0.01, "a = {}", pooled.a);
    assert!((pooled.b + 12.0).abs() < 0.6, "b = {}", pooled.b);
    assert!(pooled.scatter.unwrap() < 1.5, "{:?}", pooled.scatter);
    // Pooling one sweep's own columns gives its own fit.
    let alone = fit_line(&synthetic(0.6, -12.0), &scales, 300, 7, Method::Model).unwrap();
    let again = fit_columns(at40.clone(), 300, 7).unwrap();
    assert_eq!(
        (again.a, again.b, again.a_ci),
        (alone.a, alone.b, alone.a_ci)
    );
    // Where R0 = 32 crosses 6 higher, the pooled columns scatter far beyond their intervals.
    let broken = read(&synthetic_r0_32(0.6, -6.0));
    let off = fit_columns([at40, broken].concat(), 300, 7).unwrap();
    assert!(off.scatter.unwrap() > 3.0, "{:?}", off.scatter);
}
