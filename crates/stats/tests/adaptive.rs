//! The adaptive-replicates rule: exact binomial bounds against published values and exact
//! coverage sums, round sizes, and a Monte Carlo test on synthetic points (no solver) that the
//! share of points settling on a wrong label or sign stays below the stated error.

use cellsweep_stats::adaptive::{assess_with, kinds, Intervals};
use cellsweep_stats::{clopper_pearson, AdaptiveRule, End, Label, PointEnds, Standing};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const RULE: AdaptiveRule = AdaptiveRule {
    batch: 8,
    min_replicates: 8,
    max_replicates: 96,
    error: 0.05,
};

#[test]
fn clopper_pearson_matches_published_intervals() {
    // R: binom.test(5, 10)$conf.int, binom.test(0, 10), binom.test(10, 10), binom.test(1, 96).
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6;
    let i = clopper_pearson(5, 10, 0.05);
    assert!(close(i, [0.187_086_2, 0.812_913_8]), "{i:?}");
    let i = clopper_pearson(0, 10, 0.05);
    assert!(close(i, [0.0, 0.308_497_2]), "{i:?}");
    let i = clopper_pearson(10, 10, 0.05);
    assert!(close(i, [0.691_502_8, 1.0]), "{i:?}");
    // Closed forms at the edges: hi(0, n) = 1 - (delta/2)^(1/n), lo(n, n) = (delta/2)^(1/n).
    for n in [1u64, 7, 96, 1000] {
        let d: f64 = 0.001;
        let expect = (d / 2.0).powf(1.0 / n as f64);
        assert!((clopper_pearson(0, n, d)[1] - (1.0 - expect)).abs() < 1e-9);
        assert!((clopper_pearson(n, n, d)[0] - expect).abs() < 1e-9);
    }
}

fn binomial_pmf(n: u64, p: f64) -> Vec<f64> {
    // Built by the recurrence pmf(k+1) = pmf(k) (n-k)/(k+1) p/(1-p), from (1-p)^n.
    let mut v = vec![(1.0 - p).powi(n as i32)];
    for k in 0..n {
        let next = v[k as usize] * (n - k) as f64 / (k + 1) as f64 * p / (1.0 - p);
        v.push(next);
    }
    v
}

#[test]
fn clopper_pearson_covers_at_least_its_level_for_every_p() {
    // Exact coverage: sum of P(X = k) over the k whose interval holds p.
    for n in [8u64, 24, 96] {
        for delta in [0.05, 0.05 / 48.0] {
            let ivs: Vec<[f64; 2]> = (0..=n).map(|k| clopper_pearson(k, n, delta)).collect();
            for step in 1..200 {
                let p = step as f64 / 200.0;
                let pmf = binomial_pmf(n, p);
                let cover: f64 = (0..=n as usize)
                    .filter(|&k| ivs[k][0] <= p && p <= ivs[k][1])
                    .map(|k| pmf[k])
                    .sum();
                assert!(
                    cover >= 1.0 - delta - 1e-9,
                    "n = {n}, p = {p}: coverage {cover} < {}",
                    1.0 - delta
                );
            }
        }
    }
}

#[test]
fn rounds_run_from_min_to_max_in_batches() {
    assert_eq!(RULE.looks(), 12);
    assert_eq!(RULE.delta(4), 0.05 / 48.0);
    assert_eq!(RULE.complete_round(7), None);
    assert_eq!(RULE.complete_round(8), Some(8));
    assert_eq!(RULE.complete_round(15), Some(8));
    assert_eq!(RULE.complete_round(96), Some(96));
    assert_eq!(RULE.next_round(0), Some(8));
    assert_eq!(RULE.next_round(12), Some(16));
    assert_eq!(RULE.next_round(96), None);
    // A budget that is not a whole number of batches ends on the budget.
    let odd = AdaptiveRule {
        max_replicates: 20,
        ..RULE
    };
    assert_eq!(odd.looks(), 3);
    assert_eq!(odd.next_round(16), Some(20));
    assert_eq!(odd.complete_round(19), Some(16));
    for bad in [
        AdaptiveRule { batch: 0, ..RULE },
        AdaptiveRule {
            min_replicates: 0,
            ..RULE
        },
        AdaptiveRule {
            max_replicates: 4,
            ..RULE
        },
        AdaptiveRule { error: 0.0, ..RULE },
        AdaptiveRule {
            error: f64::NAN,
            ..RULE
        },
    ] {
        assert!(bad.validate().is_err(), "{bad:?}");
    }
}

fn point(beta: f64, ends: &[End]) -> PointEnds {
    PointEnds {
        alpha: 0.1,
        beta,
        L: 90,
        sigma: 5.0,
        others: Default::default(),
        ends: ends.iter().map(|&e| Some(e)).collect(),
    }
}

#[test]
fn clear_points_settle_and_close_calls_stay_open() {
    let mut iv = Intervals::new(&RULE, kinds(1));
    // 16 of 16 training: lo = (0.05/96)^(1/16) = 0.62 >= 0.55.
    let all_train = point(10.0, &[End::Train; 16]);
    // 8 of 8 is not enough: lo = (0.05/96)^(1/8) = 0.39.
    let few = point(10.0, &[End::Train; 8]);
    let half: Vec<End> = (0..96)
        .map(|i| {
            if i % 2 == 0 {
                End::Train
            } else {
                End::WalkPast
            }
        })
        .collect();
    let a = assess_with(&[all_train, few, point(30.0, &half)], &RULE, &mut iv);
    assert_eq!(a[0].standing, Standing::Settled);
    assert_eq!(a[0].certain_label, Some(Label::Train));
    assert_eq!(a[1].standing, Standing::Open);
    assert_eq!(a[1].next_round, Some(16));
    // 48/48 at the full budget: nothing certain, the budget is spent.
    assert_eq!(a[2].standing, Standing::Exhausted);
    // Gaps: replicates 0..3 and 5..15 done, 4 missing: only the first round (8) is complete?
    // No: the prefix is 4, below the first round, so nothing is looked at yet.
    let mut gap = point(10.0, &[End::Train; 16]);
    gap.ends[4] = None;
    let a = assess_with(&[gap], &RULE, &mut iv);
    assert_eq!((a[0].n, a[0].standing), (0, Standing::Open));
    // A point carried by its prep's verdict is final at once.
    let a = assess_with(&[point(10.0, &[End::Unstable; 8])], &RULE, &mut iv);
    assert_eq!(a[0].standing, Standing::Verdict);
    assert_eq!(a[0].certain_label, Some(Label::Unstable));
}

#[test]
fn a_certain_sign_settles_only_away_from_the_crossing() {
    let mut iv = Intervals::new(&RULE, kinds(1));
    // 48 replicates: 3 train, 27 walk-past and 18 reversals give lo_walk - hi_train > 0 (a
    // certain sign) while no outcome is certainly dominant or certainly not.
    let mk = |beta: f64, train: usize, walk: usize, rev: usize| {
        let mut e = vec![End::Train; train];
        e.extend(vec![End::WalkPast; walk]);
        e.extend(vec![End::Reversal; rev]);
        point(beta, &e)
    };
    // A column: training certain at 10 and 14, walk-past (by sign only) at 18..26.
    let col = [
        mk(10.0, 48, 0, 0),
        mk(14.0, 48, 0, 0),
        mk(18.0, 3, 27, 18),
        mk(22.0, 3, 27, 18),
        mk(26.0, 3, 27, 18),
    ];
    let a = assess_with(&col, &RULE, &mut iv);
    assert_eq!(a[2].certain_sign, Some(1), "{:?}", a[2].bounds);
    assert_eq!(a[2].certain_label, None);
    // beta = 18 is next to the crossing (its neighbour 14 has the other sign): it goes on.
    assert_eq!(a[2].standing, Standing::Open);
    // beta = 22 has same-sign neighbours on both sides: settled by sign.
    assert_eq!(a[3].standing, Standing::Sign);
    // The column's last point has one neighbour, of the same sign.
    assert_eq!(a[4].standing, Standing::Sign);
    // Points of other columns are not neighbours.
    let mut other = col.clone();
    other[1].alpha = 0.12;
    let a = assess_with(&other, &RULE, &mut iv);
    assert_eq!(a[2].standing, Standing::Open, "10 -> 18 still crosses");
}

/// The label of true probabilities (SPEC section 6 in probabilities).
fn true_label(p: [f64; 4]) -> Label {
    let labels = [
        Label::Train,
        Label::WalkPast,
        Label::Reversal,
        Label::Undetermined,
    ];
    if let Some(i) = (0..4).find(|&i| p[i] >= 0.55) {
        return labels[i];
    }
    if (p[1] - p[0]).abs() < 0.1 && p[0] + p[1] >= 0.5 {
        Label::Coexist
    } else {
        Label::Mixed
    }
}

fn draw(rng: &mut ChaCha8Rng, p: [f64; 4]) -> End {
    let u: f64 = rng.random();
    let ends = [End::Train, End::WalkPast, End::Reversal, End::Undetermined];
    let mut acc = 0.0;
    for i in 0..4 {
        acc += p[i];
        if u < acc {
            return ends[i];
        }
    }
    End::Undetermined
}

/// Synthetic columns: p_walk rises with beta through every label boundary, with reversals and
/// undetermined outcomes beside. Every column runs its rounds exactly as a sweep would: each
/// open point takes its next batch, then the whole column is assessed again.
#[test]
fn the_rule_settles_on_a_wrong_label_or_sign_less_often_than_its_error() {
    let mut rng = ChaCha8Rng::seed_from_u64(2025);
    let mut iv = Intervals::new(&RULE, kinds(1));
    let betas: Vec<f64> = (0..11).map(|i| 10.0 + 4.0 * i as f64).collect();
    let (mut points, mut wrong_label, mut wrong_sign, mut settled, mut signs) = (0, 0, 0, 0, 0);
    // Mean replicates by true label.
    let mut used: std::collections::BTreeMap<&str, (u64, u64)> = Default::default();
    let columns = 400;
    for c in 0..columns {
        // Other outcomes' share and where the crossing sits vary by column.
        let other = [0.0, 0.05, 0.2, 0.45][c % 4];
        let centre = 12.0 + 36.0 * rng.random::<f64>();
        let width = [1.0, 4.0, 10.0][c % 3];
        let probs: Vec<[f64; 4]> = betas
            .iter()
            .map(|&b| {
                let w = (1.0 - other) / (1.0 + (-(b - centre) / width).exp());
                let t = 1.0 - other - w;
                [t, w, other * 0.7, other * 0.3]
            })
            .collect();
        let mut col: Vec<PointEnds> = betas.iter().map(|&b| point(b, &[])).collect();
        loop {
            let a = assess_with(&col, &RULE, &mut iv);
            let mut grew = false;
            for (i, p) in col.iter_mut().enumerate() {
                if let Some(n) = a[i].next_round {
                    while p.ends.len() < n as usize {
                        p.ends.push(Some(draw(&mut rng, probs[i])));
                    }
                    grew = true;
                }
            }
            if grew {
                continue;
            }
            for (i, ai) in a.iter().enumerate() {
                let truth = true_label(probs[i]);
                points += 1;
                let e = used.entry(truth.as_str()).or_default();
                e.0 += 1;
                e.1 += ai.n as u64;
                match ai.standing {
                    Standing::Settled => {
                        settled += 1;
                        if ai.certain_label != Some(truth) {
                            wrong_label += 1;
                        }
                    }
                    Standing::Sign => {
                        signs += 1;
                        let d = probs[i][1] - probs[i][0];
                        if ai.certain_sign != Some(if d > 0.0 { 1 } else { -1 }) {
                            wrong_sign += 1;
                        }
                    }
                    Standing::Exhausted => assert_eq!(ai.n, 96),
                    s => panic!("a point ended {s:?}"),
                }
            }
            break;
        }
    }
    let wrong = wrong_label + wrong_sign;
    let total_used: u64 = used.values().map(|v| v.1).sum();
    println!(
        "{points} points: {settled} settled on a label ({wrong_label} wrong), {signs} by sign \
         ({wrong_sign} wrong), {} exhausted; mean replicates {:.1} of 96",
        points - settled - signs,
        total_used as f64 / points as f64
    );
    for (label, (n, r)) in &used {
        println!(
            "  true {label}: {n} points, mean replicates {:.1}",
            *r as f64 / *n as f64
        );
    }
    // The guarantee is per point: P(wrong) <= error. Allow three standard deviations of a
    // binomial count at exactly that rate (the union bound makes the real rate far lower).
    let n = points as f64;
    let limit = n * RULE.error + 3.0 * (n * RULE.error * (1.0 - RULE.error)).sqrt();
    assert!((wrong as f64) <= limit, "{wrong} wrong of {points}");
    // And the rule saves work: well below the fixed 96 on average.
    assert!(total_used as f64 / n < 70.0);
}
