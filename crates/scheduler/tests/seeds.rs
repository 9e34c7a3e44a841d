//! Expansion into preps and jobs, and seeds that depend on parameters, never on order.

use cellsweep_scheduler::plan::{job_seed, prep_key, prep_seed};
use cellsweep_scheduler::{plan, Sweep};
use std::collections::HashSet;

fn sweep(extra: &str) -> Sweep {
    let text = format!(
        r#"
name = "s"
seed = 42
replicates = 6
preps_per_point = 2
[grid]
alpha = [0.1, 0.12]
beta = {{ from = 10, to = 18, step = 4 }}
L = [90, 70]
sigma = [5, 0]
{extra}
"#
    );
    Sweep::parse(&text, "s.toml").unwrap()
}

#[test]
fn the_grid_expands_into_points_preps_and_seeded_jobs() {
    let s = sweep("");
    let new = plan(&s, "s.toml");
    assert_eq!(new.points.len(), 2 * 3 * 2 * 2);
    // Preps: one per (alpha, beta, L) and prep index; sigma shares them.
    assert_eq!(new.preps.len(), 2 * 3 * 2 * 2);
    let jobs: Vec<_> = new.points.iter().flat_map(|p| p.jobs.iter()).collect();
    assert_eq!(jobs.len(), 24 * 6);
    let seeds: HashSet<u64> = jobs.iter().map(|j| j.seed).collect();
    assert_eq!(seeds.len(), jobs.len(), "every job has its own seed");
    // Replicates alternate between the point's two preps.
    let p0 = &new.points[0];
    assert_eq!(p0.jobs[0].prep, p0.jobs[2].prep);
    assert_ne!(p0.jobs[0].prep, p0.jobs[1].prep);
}

#[test]
fn points_differing_only_in_sigma_share_their_preps() {
    let new = plan(&sweep(""), "s.toml");
    let key = |i: usize| {
        (
            new.points[i].alpha,
            new.points[i].beta,
            new.points[i].spacing,
        )
    };
    for (i, a) in new.points.iter().enumerate() {
        for (j, b) in new.points.iter().enumerate() {
            if key(i) == key(j) && a.sigma != b.sigma {
                let pa: Vec<usize> = a.jobs.iter().map(|j| j.prep).collect();
                let pb: Vec<usize> = b.jobs.iter().map(|j| j.prep).collect();
                assert_eq!(pa, pb);
            }
        }
    }
    // ... but not their collision seeds.
    let s = sweep("");
    let pts = s.points();
    let (a, b) = (
        &pts[0],
        pts.iter()
            .find(|p| {
                p.sigma != pts[0].sigma
                    && p.alpha == pts[0].alpha
                    && p.beta == pts[0].beta
                    && p.L == pts[0].L
            })
            .unwrap(),
    );
    assert_ne!(job_seed(42, a, 0), job_seed(42, b, 0));
    assert_eq!(prep_key(a, &s.protocol), prep_key(b, &s.protocol));
}

#[test]
fn seeds_are_stable_and_independent_of_grid_order() {
    let a = sweep("");
    // The same points written in another order and as lists give the same seeds.
    let text = r#"
name = "s"
seed = 42
replicates = 6
preps_per_point = 2
[grid]
alpha = [0.12, 0.10]
beta = [18, 10, 14]
L = [70, 90]
sigma = [0, 5]
"#;
    let b = Sweep::parse(text, "b.toml").unwrap();
    let seeds = |s: &Sweep| -> HashSet<(String, u64)> {
        plan(s, "x")
            .points
            .iter()
            .flat_map(|p| {
                p.jobs.iter().map(move |j| {
                    (
                        format!(
                            "{} {} {} {} {}",
                            p.alpha, p.beta, p.spacing, p.sigma, j.replicate
                        ),
                        j.seed,
                    )
                })
            })
            .collect()
    };
    assert_eq!(seeds(&a), seeds(&b));
    let p = &a.points()[0];
    assert_ne!(job_seed(42, p, 0), job_seed(43, p, 0));
    assert_ne!(job_seed(42, p, 0), job_seed(42, p, 1));
    let key = prep_key(p, &a.protocol);
    assert_ne!(prep_seed(42, &key, 0), prep_seed(42, &key, 1));
    // A different protocol for the prep is a different prep.
    let c = sweep("[protocol]\nfree_time = 200");
    assert_ne!(prep_key(&c.points()[0], &c.protocol), key);
}

/// Pinned values: a change to seed derivation reshuffles the noise of every stored sweep (and
/// of `data/paper/`, whose rows carry these very seeds), so it must fail here and be deliberate.
#[test]
fn the_seeds_of_the_paper_sweep_are_pinned() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../sweeps/paper-L90-sigma5.toml"
    ))
    .unwrap();
    let s = Sweep::parse(&text, "paper-L90-sigma5.toml").unwrap();
    let p = &s.points()[0];
    assert_eq!((p.alpha, p.beta, p.L, p.sigma), (0.1, 10.0, 90, 5.0));
    // As in data/paper/adaptive-L90-sigma5.csv (the same seed and grid, f32 collisions).
    assert_eq!(job_seed(1, p, 0), 14385219847570742048);
    assert_eq!(job_seed(1, p, 1), 9416160944751426525);
    assert_eq!(
        prep_seed(1, &prep_key(p, &s.protocol), 0),
        475611912845846853
    );
    // Through the planner, as the store receives them.
    let new = plan(&s, "x");
    assert_eq!(new.points[0].jobs[1].seed, 9416160944751426525);
    assert_eq!(new.preps[0].seed, 475611912845846853);
}

/// Every committed export (`data/paper/*.csv`) read with this build: its definition is the
/// very text it was exported with (so it registers as the same sweep), and every row's prep
/// and collision seeds are the ones this build plans for that point and replicate, so
/// importing it changes no seed and runs no other trajectory.
#[test]
fn every_committed_export_keeps_its_definition_and_its_seeds() {
    use cellsweep_scheduler::export_file::read_export;
    use std::collections::HashMap;
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/paper");
    let mut files = 0;
    let mut rows_checked = 0;
    for f in std::fs::read_dir(&data).unwrap() {
        let path = f.unwrap().path();
        if path.extension().is_none_or(|e| e != "csv") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let spec = text
            .lines()
            .nth(1)
            .unwrap()
            .strip_prefix("# spec ")
            .unwrap();
        let (sweep, rows) = read_export(&path).unwrap();
        assert_eq!(sweep.canonical_json(), spec, "{}", path.display());
        let axes: Vec<_> = rows.iter().map(|r| sweep.axes_of_row(r).unwrap()).collect();
        let points = sweep.points_with(axes.iter().cloned()).unwrap();
        let index: HashMap<_, usize> = points
            .iter()
            .enumerate()
            .map(|(i, p)| (sweep.axes_of(p).key(), i))
            .collect();
        let new =
            cellsweep_scheduler::plan::plan_targets(&sweep, "x", &points, &|_| sweep.replicates);
        assert_eq!(new.spec, spec);
        for (r, a) in rows.iter().zip(&axes) {
            let point = &new.points[index[&a.key()]];
            let job = &point.jobs[r.replicate as usize];
            assert_eq!(job.replicate, r.replicate);
            assert_eq!(
                job.seed,
                r.collision_seed,
                "{}: {a} #{}",
                path.display(),
                r.replicate
            );
            assert_eq!(
                new.preps[job.prep].seed,
                r.prep_seed,
                "{}: {a}",
                path.display()
            );
            rows_checked += 1;
        }
        files += 1;
    }
    assert!(files >= 8, "{files} exports");
    assert!(rows_checked > 10_000, "{rows_checked} rows");
}
