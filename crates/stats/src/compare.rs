//! Two result sets compared point by point and replicate by replicate: one sweep under two
//! solver versions, or two sweeps that differ only in how they are solved (the collision's
//! precision, the window bound), which is how a faster method is shown not to change the
//! outcome statistics.
//!
//! Replicates pair up by grid point and replicate index. A pair is *matched* when both jobs ran
//! from the same prep seed with the same collision seed (seeds derive from the sweep seed, the
//! point and the replicate, never from the solver version or the precision, so such a pair saw
//! the same prepped cell and the same noise). A point whose replicates all match is tested with
//! an exact symmetry test of its discordant pairs; any other point (other seeds, or replicates
//! missing from one side) as two independent samples, with a permutation test.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::axes::{Axes, PointKey};
use crate::counts::{Counts, Label};
use crate::end::{End, PerEnd, Replicate, Tally};

/// One grid point in both result sets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct PointComparison {
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    pub counts_a: Tally,
    pub counts_b: Tally,
    /// The point's label (SPEC section 6) in each set.
    pub label_a: Option<Label>,
    pub label_b: Option<Label>,
    /// Replicates present in both sets with the same prep and collision seeds.
    pub matched: u64,
    /// Matched pairs that ended alike.
    pub alike: u64,
    /// Mean and largest |difference| in decision time (tau0) over the matched pairs decided
    /// alike (both with a decision time).
    pub decision_shift_mean: Option<f64>,
    pub decision_shift_max: Option<f64>,
    /// How the counts were tested: the matched pairs, or two independent samples.
    pub test: Test,
    /// The test's p-value: small when the two sets' outcome statistics differ.
    pub p_value: f64,
}

/// The test behind a p-value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Test {
    /// Exact symmetry test of the discordant matched pairs (McNemar's exact test for two
    /// outcomes; Monte Carlo beyond 20 discordant pairs).
    Paired,
    /// Permutation test of the chi-square statistic, for points whose replicates do not all
    /// match (other seeds, or replicates missing from one side).
    Independent,
}

/// Both result sets, point by point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    pub points: Vec<PointComparison>,
    /// Grid points present in only one of the sets.
    pub only_a: usize,
    pub only_b: usize,
    pub matched: u64,
    pub alike: u64,
    /// Points whose label differs.
    pub labels_differ: usize,
    /// The paired test over every point tested as paired, at once (the statistic summed over
    /// the points, so that changes at two points cannot cancel); `None` when no point was.
    pub p_value_paired: Option<f64>,
}

/// Monte Carlo draws where exact enumeration is too long.
const DRAWS: u32 = 20_000;
/// Exact enumeration up to this many discordant pairs (2^20 sign patterns).
const EXACT_UP_TO: usize = 20;

fn key(r: &Replicate) -> PointKey {
    Axes {
        alpha: r.alpha,
        beta: r.beta,
        L: r.L,
        sigma: r.sigma,
        others: r.others.clone(),
    }
    .key()
}

/// The distinct grid points of a result set, in the order they first appear.
fn point_keys(rs: &[Replicate]) -> Vec<PointKey> {
    let mut keys: Vec<PointKey> = Vec::new();
    for r in rs {
        if !keys.contains(&key(r)) {
            keys.push(key(r));
        }
    }
    keys
}

/// Compare result set `a` with `b`.
pub fn compare(a: &[Replicate], b: &[Replicate]) -> Comparison {
    let (keys_a, keys_b) = (point_keys(a), point_keys(b));
    let only_a = keys_a.iter().filter(|k| !keys_b.contains(k)).count();
    let only_b = keys_b.iter().filter(|k| !keys_a.contains(k)).count();

    let mut points = Vec::new();
    let mut all_discordant: Vec<Vec<(End, End)>> = Vec::new();
    for k in keys_a.into_iter().filter(|k| keys_b.contains(k)) {
        let ra: Vec<&Replicate> = a.iter().filter(|r| key(r) == k).collect();
        let rb: Vec<&Replicate> = b.iter().filter(|r| key(r) == k).collect();
        let (p, discordant) = compare_point(&ra, &rb);
        if p.test == Test::Paired {
            all_discordant.push(discordant);
        }
        points.push(p);
    }
    let matched = points.iter().map(|p| p.matched).sum();
    let alike = points.iter().map(|p| p.alike).sum();
    let labels_differ = points.iter().filter(|p| p.label_a != p.label_b).count();
    let p_value_paired = (!all_discordant.is_empty()).then(|| symmetry_test(&all_discordant));
    Comparison {
        points,
        only_a,
        only_b,
        matched,
        alike,
        labels_differ,
        p_value_paired,
    }
}

fn counts_of(rs: &[&Replicate]) -> Tally {
    let mut c = Tally::default();
    for r in rs {
        c.add(r.end, 1);
    }
    c
}

fn label_of(c: &Tally, first: &Replicate) -> Option<Label> {
    Counts {
        others: first.others.clone(),
        tally: *c,
        ..Counts::none(first.alpha, first.beta, first.L, first.sigma)
    }
    .label()
}

/// One point (both sides non-empty); also returns its discordant matched pairs.
fn compare_point(ra: &[&Replicate], rb: &[&Replicate]) -> (PointComparison, Vec<(End, End)>) {
    let (counts_a, counts_b) = (counts_of(ra), counts_of(rb));
    let mut pairs = Vec::new();
    for x in ra {
        if let Some(y) = rb.iter().find(|y| y.replicate == x.replicate) {
            if x.seed == y.seed && x.prep_seed == y.prep_seed {
                pairs.push((*x, *y));
            }
        }
    }
    let alike = pairs.iter().filter(|(x, y)| x.end == y.end).count() as u64;
    let shifts: Vec<f64> = pairs
        .iter()
        .filter(|(x, y)| x.end == y.end)
        .filter_map(|(x, y)| Some((x.decision_time? - y.decision_time?).abs()))
        .collect();
    let discordant: Vec<(End, End)> = pairs
        .iter()
        .filter(|(x, y)| x.end != y.end)
        .map(|(x, y)| (x.end, y.end))
        .collect();
    // Paired when every replicate of both sides has its match; otherwise the two sides are
    // independent samples of the point.
    let paired = !pairs.is_empty() && pairs.len() == ra.len() && pairs.len() == rb.len();
    let (test, p_value) = if paired {
        (
            Test::Paired,
            symmetry_test(std::slice::from_ref(&discordant)),
        )
    } else {
        (Test::Independent, permutation_test(&counts_a, &counts_b))
    };
    let first = ra[0];
    let point = PointComparison {
        alpha: first.alpha,
        beta: first.beta,
        L: first.L,
        sigma: first.sigma,
        counts_a,
        counts_b,
        label_a: label_of(&counts_a, first),
        label_b: label_of(&counts_b, first),
        matched: pairs.len() as u64,
        alike,
        decision_shift_mean: (!shifts.is_empty())
            .then(|| shifts.iter().sum::<f64>() / shifts.len() as f64),
        decision_shift_max: shifts.iter().copied().reduce(f64::max),
        test,
        p_value,
    };
    (point, if paired { discordant } else { Vec::new() })
}

/// The statistic of the paired test: over the points, the L1 distance between the two sides'
/// counts, sum_c |n_a(c) - n_b(c)|. Pairs that ended alike add to both sides equally, so only the
/// discordant pairs, `(end in a, end in b)` with `swapped` telling which are flipped, enter.
fn l1_distance(points: &[Vec<(End, End)>], swapped: impl Fn(usize) -> bool) -> u64 {
    let mut stat = 0;
    let mut i = 0;
    for pairs in points {
        let mut diff = PerEnd::<i64>::default();
        for &(x, y) in pairs {
            let (x, y) = if swapped(i) { (y, x) } else { (x, y) };
            diff[x] += 1;
            diff[y] -= 1;
            i += 1;
        }
        stat += diff.iter().map(|(_, d)| d.unsigned_abs()).sum::<u64>();
    }
    stat
}

/// Exact symmetry test: under the hypothesis that both sets come from the same solver
/// statistics, each discordant pair (a, b) is as likely to have been (b, a). The p-value is the
/// share of the 2^D swap patterns of the D discordant pairs whose statistic (`l1_distance`)
/// reaches the observed one (exact up to 20 pairs, else `DRAWS` seeded random patterns). With
/// two outcomes and one point this is McNemar's exact test. No discordant pair: p = 1.
pub fn symmetry_test(points: &[Vec<(End, End)>]) -> f64 {
    let d: usize = points.iter().map(Vec::len).sum();
    let observed = l1_distance(points, |_| false);
    if d <= EXACT_UP_TO {
        let reach = (0u64..1 << d)
            .filter(|mask| l1_distance(points, |i| mask >> i & 1 == 1) >= observed)
            .count();
        return reach as f64 / (1u64 << d) as f64;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let mut reach = 0u32;
    for _ in 0..DRAWS {
        let flips: Vec<bool> = (0..d).map(|_| rng.random()).collect();
        if l1_distance(points, |i| flips[i]) >= observed {
            reach += 1;
        }
    }
    (1 + reach) as f64 / (1 + DRAWS) as f64
}

/// Pearson's chi-square statistic of the 2 x K table (outcomes with no replicate on either
/// side left out).
fn chi_square(a: &Tally, b: &Tally) -> f64 {
    let (na, nb) = (a.total() as f64, b.total() as f64);
    let n = na + nb;
    let mut x2 = 0.0;
    for c in End::ALL {
        let col = (a[c] + b[c]) as f64;
        if col == 0.0 {
            continue;
        }
        for (obs, side) in [(a[c] as f64, na), (b[c] as f64, nb)] {
            let e = side * col / n;
            x2 += (obs - e) * (obs - e) / e;
        }
    }
    x2
}

/// Permutation test for two independent samples of one point: the share of `DRAWS` seeded
/// random relabellings of the pooled replicates (sides keeping their sizes) whose chi-square
/// statistic reaches the observed one.
pub fn permutation_test(a: &Tally, b: &Tally) -> f64 {
    let na = a.total() as usize;
    let observed = chi_square(a, b);
    if observed == 0.0 || na == 0 || b.total() == 0 {
        return 1.0;
    }
    let mut pool: Vec<End> = Vec::new();
    for c in End::ALL {
        pool.extend(std::iter::repeat_n(c, (a[c] + b[c]) as usize));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let mut reach = 0u32;
    for _ in 0..DRAWS {
        // A random na-subset goes to side a (partial Fisher-Yates).
        for i in 0..na {
            let j = rng.random_range(i..pool.len());
            pool.swap(i, j);
        }
        let mut pa = Tally::default();
        let mut pb = Tally::default();
        for (i, &c) in pool.iter().enumerate() {
            if i < na {
                pa[c] += 1;
            } else {
                pb[c] += 1;
            }
        }
        // A relative tolerance, so that ties with the observed table count as reaching it.
        if chi_square(&pa, &pb) >= observed * (1.0 - 1e-12) {
            reach += 1;
        }
    }
    (1 + reach) as f64 / (1 + DRAWS) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rep(beta: f64, replicate: u32, seed: u64, end: End, t: Option<f64>) -> Replicate {
        Replicate {
            alpha: 0.1,
            beta,
            L: 90,
            sigma: 5.0,
            others: Default::default(),
            point: 0,
            replicate,
            seed,
            prep_seed: 7,
            end,
            decision_time: t,
        }
    }

    #[test]
    fn the_permutation_test_counts_every_end_collision_breakups_included() {
        // Side a all broke up in the collision, side b all trained: the two differ as much as
        // two samples can (it panicked when the pool left out the seventh kind of end).
        let mut a = Tally::default();
        let mut b = Tally::default();
        a[End::CollisionBreakup] = 16;
        b[End::Train] = 16;
        let p = permutation_test(&a, &b);
        assert!(p < 0.001, "{p}");
        assert!(chi_square(&a, &b) > 30.0);
        // Two samples of the same mix are alike.
        assert_eq!(permutation_test(&a, &a), 1.0);
    }

    #[test]
    fn mcnemar_exact_for_two_outcomes() {
        // Five discordant pairs, all train in a and walk-past in b: |diff| = 10 reached only by
        // "none swapped" and "all swapped": p = 2 / 32, McNemar's exact two-sided value.
        let d = vec![(End::Train, End::WalkPast); 5];
        assert_eq!(symmetry_test(&[d]), 2.0 / 32.0);
        // Four one way and one the other: |4 - 1| = 3 each side, statistic 6; patterns with
        // |k - (5 - k)| >= 3 are k in {0, 1, 4, 5}: (1 + 5 + 5 + 1) / 32.
        let mut d = vec![(End::Train, End::WalkPast); 4];
        d.push((End::WalkPast, End::Train));
        assert_eq!(symmetry_test(&[d]), 12.0 / 32.0);
        // No discordant pair: nothing to explain.
        assert_eq!(symmetry_test(&[vec![]]), 1.0);
    }

    #[test]
    fn the_pooled_statistic_does_not_let_points_cancel() {
        // Point 1 moved train -> walk-past, point 2 walk-past -> train: pooled marginals would
        // hide both, the sum of per-point distances does not.
        let d1 = vec![(End::Train, End::WalkPast); 4];
        let d2 = vec![(End::WalkPast, End::Train); 4];
        let both = symmetry_test(&[d1.clone(), d2]);
        assert_eq!(both, symmetry_test(std::slice::from_ref(&d1)).powi(2));
        assert!(both < 0.02, "{both}");
    }

    #[test]
    fn monte_carlo_beyond_twenty_pairs_agrees_with_the_binomial_tail() {
        // 30 discordant pairs, 22 one way: two-sided binomial(30, 1/2) tail P(|k - 15| >= 7)
        // = 2 * P(k >= 22) = 0.01612.
        let mut d = vec![(End::Train, End::WalkPast); 22];
        d.extend(vec![(End::WalkPast, End::Train); 8]);
        let p = symmetry_test(&[d]);
        assert!((p - 0.01612).abs() < 0.004, "{p}");
    }

    #[test]
    fn independent_samples_tell_equal_from_different_counts() {
        let same = permutation_test(&[8, 8, 0, 0, 0, 0, 0].into(), &[8, 8, 0, 0, 0, 0, 0].into());
        assert_eq!(same, 1.0);
        let close = permutation_test(&[8, 8, 0, 0, 0, 0, 0].into(), &[9, 7, 0, 0, 0, 0, 0].into());
        assert!(close > 0.5, "{close}");
        // 16/0 against 0/16: Fisher's exact two-sided p = 2 / C(32, 16) ~ 1.7e-9, far below
        // what the draws resolve: the smallest value they give.
        let apart = permutation_test(
            &[16, 0, 0, 0, 0, 0, 0].into(),
            &[0, 16, 0, 0, 0, 0, 0].into(),
        );
        assert_eq!(apart, 1.0 / (1 + DRAWS) as f64);
    }

    #[test]
    fn pairs_match_by_replicate_and_seed() {
        let a = vec![
            rep(10.0, 0, 100, End::Train, Some(200.0)),
            rep(10.0, 1, 101, End::Train, Some(210.0)),
            rep(10.0, 2, 102, End::WalkPast, Some(150.0)),
            rep(14.0, 0, 200, End::WalkPast, Some(120.0)),
            rep(18.0, 0, 300, End::Train, None),
        ];
        let b = vec![
            rep(10.0, 2, 102, End::Train, Some(160.0)),
            rep(10.0, 0, 100, End::Train, Some(200.5)),
            rep(10.0, 1, 101, End::Train, Some(209.0)),
            // Same replicate, another seed: not a matched pair.
            rep(14.0, 0, 999, End::WalkPast, Some(120.0)),
            rep(22.0, 0, 400, End::Train, None),
        ];
        let c = compare(&a, &b);
        assert_eq!((c.only_a, c.only_b), (1, 1));
        assert_eq!(c.points.len(), 2);
        let p10 = &c.points[0];
        assert_eq!((p10.beta, p10.matched, p10.alike), (10.0, 3, 2));
        assert_eq!(p10.test, Test::Paired);
        assert_eq!(p10.counts_a, [2, 1, 0, 0, 0, 0, 0].into());
        assert_eq!(p10.counts_b, [3, 0, 0, 0, 0, 0, 0].into());
        assert_eq!(p10.decision_shift_mean, Some(0.75));
        assert_eq!(p10.decision_shift_max, Some(1.0));
        assert_eq!(p10.p_value, 1.0, "one discordant pair can go either way");
        let p14 = &c.points[1];
        assert_eq!((p14.matched, p14.test), (0, Test::Independent));
        assert_eq!(p14.p_value, 1.0);
        assert_eq!((c.matched, c.alike), (3, 2));
        assert_eq!(c.labels_differ, 0);
        assert_eq!(c.p_value_paired, Some(1.0));
    }

    #[test]
    fn labels_follow_spec_section_6() {
        let a: Vec<Replicate> = (0..4)
            .map(|i| rep(10.0, i, i as u64, End::Train, None))
            .collect();
        let mut b = a.clone();
        for r in &mut b[..3] {
            r.end = End::WalkPast;
        }
        let c = compare(&a, &b);
        assert_eq!(c.points[0].label_a, Some(Label::Train));
        assert_eq!(c.points[0].label_b, Some(Label::WalkPast));
        assert_eq!(c.labels_differ, 1);
    }
}
