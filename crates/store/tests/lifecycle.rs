//! The store: files it refuses, and the job lifecycle that never finishes a job twice.

use cellsweep_stats::End;
use cellsweep_store::{
    JobState, NewJob, NewPoint, NewPrep, NewSweep, ResultRecord, Store, StoreError,
};
use std::path::Path;

#[path = "../../../tests/common/scratch.rs"]
mod scratch;

/// A store's path in a fresh scratch directory, removed when the test is done with it.
fn tmp(name: &str) -> scratch::Scratch {
    scratch::Scratch::file("store", name, "db.sqlite")
}

fn sweep(spec: &str, version: &str) -> NewSweep {
    sweep_of(spec, version, 3)
}

/// A one-point sweep with `replicates` jobs whose seeds depend on the replicate index only.
fn sweep_of(spec: &str, version: &str, replicates: u32) -> NewSweep {
    NewSweep {
        name: "s".into(),
        spec: spec.into(),
        source: "s.toml".into(),
        solver_version: version.into(),
        preps_per_point: 1,
        preps: vec![NewPrep {
            key: "k".into(),
            seed: u64::MAX - 3,
            config: "{}".into(),
        }],
        points: vec![NewPoint {
            alpha: 0.1,
            beta: 10.0,
            spacing: 90,
            sigma: 5.0,
            others: Default::default(),
            config: "{}".into(),
            jobs: (0..replicates)
                .map(|r| NewJob {
                    replicate: r,
                    seed: 1000 + r as u64,
                    prep: 0,
                })
                .collect(),
        }],
    }
}

/// The sweep's pending jobs under `version`, its planned ones written as rows first (as a run
/// does before it dispatches them).
fn pending(store: &mut Store, sweep_id: i64, version: &str) -> Vec<cellsweep_store::JobTask> {
    store
        .materialize_next(sweep_id, version, usize::MAX)
        .unwrap();
    store.pending_jobs(sweep_id, version).unwrap()
}

fn record(outcome: &str) -> ResultRecord {
    ResultRecord {
        verdict: cellsweep_stats::PrepVerdict::Ok,
        outcome: Some(cellsweep_stats::End::of_outcome(outcome).unwrap()),
        contact_time: Some(1.0),
        decision_time: Some(2.0),
        free_speed: Some(0.5),
        threshold_speed: Some(0.125),
        attachment: Some(["both".into(), "both".into()]),
        collision_steps: 10,
        breakup_reason: None,
        wall_s: 0.1,
        classifier: "{}".into(),
        record: "{}".into(),
    }
}

#[test]
fn missing_corrupt_and_foreign_files_are_refused_untouched() {
    let path = tmp("files");
    assert!(matches!(Store::open(&path), Err(StoreError::Missing(_))));
    assert!(!path.exists(), "opening must not create");

    std::fs::write(
        &path,
        b"this is not a database, just some bytes that must survive......",
    )
    .unwrap();
    let before = std::fs::read(&path).unwrap();
    for r in [Store::open(&path), Store::open_or_create(&path)] {
        let e = r.err().expect("refused");
        assert!(matches!(e, StoreError::Corrupt { .. }), "{e}");
        assert!(e.to_string().contains("left untouched"));
    }
    assert_eq!(std::fs::read(&path).unwrap(), before);

    // A real SQLite file of another application.
    let other = tmp("other");
    let c = rusqlite::Connection::open(&other).unwrap();
    c.execute_batch("CREATE TABLE t (x); INSERT INTO t VALUES (1);")
        .unwrap();
    drop(c);
    let e = Store::open_or_create(&other).err().expect("refused");
    assert!(matches!(e, StoreError::NotOurs { .. }), "{e}");
}

#[test]
fn a_job_goes_pending_running_done_exactly_once() {
    let path = tmp("life");
    let mut store = Store::open_or_create(&path).unwrap();
    let reg = store.register(&sweep("{\"a\":1}", "v1"), false).unwrap();
    assert!(reg.created);
    let jobs = pending(&mut store, reg.sweep_id, "v1");
    assert_eq!(jobs.len(), 3);
    assert_eq!(jobs[0].seed, 1000);
    let preps = store.preps_of(reg.sweep_id, "v1").unwrap();
    assert_eq!(
        preps[0].seed,
        u64::MAX - 3,
        "u64 seeds survive SQLite's i64"
    );

    let id = jobs[0].id;
    store.claim_job(id).unwrap();
    assert!(
        store.claim_job(id).is_err(),
        "a running job cannot be claimed again"
    );
    assert!(store.record_result(id, "v1", &record("train")).unwrap());
    assert!(
        !store.record_result(id, "v1", &record("walk_past")).unwrap(),
        "never twice"
    );
    assert!(
        !store
            .record_result(jobs[1].id, "v0", &record("train"))
            .unwrap(),
        "never under another solver version"
    );
    assert_eq!(pending(&mut store, reg.sweep_id, "v1").len(), 2);

    // Failures: retried until the limit, then failed with the error. Each attempt counts
    // once, however often its record is read (a Slurm results file is read at every collect),
    // and a running (local) or pending (Slurm) job records it alike.
    let id2 = jobs[1].id;
    store.claim_job(id2).unwrap();
    assert_eq!(
        store.fail_job(id2, 1, "crash 1", Some(2)).unwrap(),
        Some(JobState::Pending)
    );
    assert_eq!(store.fail_job(id2, 1, "crash 1", Some(2)).unwrap(), None);
    assert_eq!(
        store.fail_job(id2, 3, "a later attempt", Some(2)).unwrap(),
        None,
        "attempt 2 is the next one"
    );
    assert_eq!(
        store.fail_job(id2, 2, "crash 2", Some(2)).unwrap(),
        Some(JobState::Failed)
    );
    assert_eq!(store.fail_job(id2, 2, "crash 2", Some(2)).unwrap(), None);
    // A retry gives it two attempts anew; the old records still count for nothing.
    assert_eq!(store.retry_failed(reg.sweep_id, "v1").unwrap(), 1);
    for old in [1, 2] {
        assert_eq!(store.fail_job(id2, old, "old", Some(2)).unwrap(), None);
    }
    assert_eq!(
        store.fail_job(id2, 3, "crash 3", Some(2)).unwrap(),
        Some(JobState::Pending)
    );
    assert_eq!(
        store.fail_job(id2, 4, "crash 4", Some(2)).unwrap(),
        Some(JobState::Failed)
    );

    // A killed coordinator leaves a job running; recovery makes it pending again.
    let id3 = jobs[2].id;
    store.claim_job(id3).unwrap();
    drop(store);
    let mut store = Store::open(&path).unwrap();
    assert_eq!(store.recover_running(reg.sweep_id, "v1").unwrap(), 1);
    let st = &store.status().unwrap()[0];
    assert_eq!(
        (
            st.jobs.done,
            st.jobs.pending,
            st.jobs.failed,
            st.jobs.running
        ),
        (1, 1, 1, 0)
    );
    assert_eq!(st.outcomes[End::Train], 1);
}

#[test]
fn sweeps_and_solver_versions_stay_apart() {
    let path = tmp("versions");
    let mut store = Store::open_or_create(&path).unwrap();
    let a = store.register(&sweep("{\"a\":1}", "v1"), false).unwrap();
    // Same definition again: found, nothing duplicated.
    let again = store.register(&sweep("{\"a\":1}", "v1"), false).unwrap();
    assert_eq!((again.sweep_id, again.created), (a.sweep_id, false));
    assert_eq!(pending(&mut store, a.sweep_id, "v1").len(), 3);
    let j = pending(&mut store, a.sweep_id, "v1")[0].id;
    store.claim_job(j).unwrap();
    assert!(store.record_result(j, "v1", &record("train")).unwrap());

    // A new solver version gets its own jobs and preps; the old results are reported, not mixed.
    let v2 = store.register(&sweep("{\"a\":1}", "v2"), false).unwrap();
    assert_eq!(v2.other_versions, vec![("v1".to_string(), 1)]);
    assert_eq!(pending(&mut store, a.sweep_id, "v2").len(), 3);
    let counts = store.point_counts(a.sweep_id, "v2").unwrap();
    assert_eq!(counts[0].outcomes[End::Train], 0);
    assert_eq!(
        store.point_counts(a.sweep_id, "v1").unwrap()[0].outcomes[End::Train],
        1
    );

    // A different definition under the same name: refused, unless replacing (old results kept).
    let e = store
        .register(&sweep("{\"a\":2}", "v1"), false)
        .unwrap_err();
    assert!(matches!(e, StoreError::SweepConflict { .. }), "{e}");
    let r = store.register(&sweep("{\"a\":2}", "v1"), true).unwrap();
    assert!(r.created);
    let archived = r.archived_as.unwrap();
    let old = store.sweep_id(&archived).unwrap();
    assert_eq!(
        store.point_counts(old, "v1").unwrap()[0].outcomes[End::Train],
        1
    );
}

#[test]
fn a_sweep_grows_its_replicates_but_never_shrinks() {
    let path = tmp("grow");
    let mut store = Store::open_or_create(&path).unwrap();
    let spec = |n: u32| format!("{{\"name\":\"s\",\"replicates\":{n},\"seed\":7}}");
    let a = store.register(&sweep_of(&spec(3), "v1", 3), false).unwrap();
    assert_eq!(a.grown_from, None);
    let jobs = pending(&mut store, a.sweep_id, "v1");
    for j in &jobs[..2] {
        store.claim_job(j.id).unwrap();
        assert!(store.record_result(j.id, "v1", &record("train")).unwrap());
    }

    // 3 -> 5: the same sweep, its two results kept, and only replicates 3 and 4 added.
    let g = store.register(&sweep_of(&spec(5), "v1", 5), false).unwrap();
    assert_eq!(
        (g.sweep_id, g.created, g.grown_from),
        (a.sweep_id, false, Some(3))
    );
    assert!(g.archived_as.is_none());
    let pending = pending(&mut store, a.sweep_id, "v1");
    let mut seeds: Vec<u64> = pending.iter().map(|j| j.seed).collect();
    seeds.sort_unstable();
    assert_eq!(seeds, vec![1002, 1003, 1004]);
    let st = &store.status().unwrap()[0];
    assert_eq!((st.jobs.done, st.jobs.pending), (2, 3));
    assert_eq!(st.outcomes[End::Train], 2);
    // Registering the grown definition again is a plain resume.
    let again = store.register(&sweep_of(&spec(5), "v1", 5), false).unwrap();
    assert_eq!((again.created, again.grown_from), (false, None));

    // 5 -> 4: refused, naming both counts, and nothing changes.
    let e = store
        .register(&sweep_of(&spec(4), "v1", 4), false)
        .unwrap_err();
    assert!(
        matches!(
            e,
            StoreError::SweepShrinks {
                stored: 5,
                asked: 4,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("grow but not shrink"), "{e}");
    let st = &store.status().unwrap()[0];
    assert_eq!((st.jobs.done, st.jobs.pending), (2, 3));

    // Growing and changing anything else is another sweep: a conflict, as before.
    let other = r#"{"name":"s","replicates":6,"seed":8}"#;
    let e = store
        .register(&sweep_of(other, "v1", 6), false)
        .unwrap_err();
    assert!(matches!(e, StoreError::SweepConflict { .. }), "{e}");
}

#[test]
fn a_version_2_store_is_read_as_it_is_and_migrated_by_a_writer() {
    let path = tmp("migrate");
    let mut store = Store::open_or_create(&path).unwrap();
    let reg = store.register(&sweep("{\"a\":1}", "v1"), false).unwrap();
    let id = pending(&mut store, reg.sweep_id, "v1")[0].id;
    assert!(store.record_result(id, "v1", &record("train")).unwrap());
    drop(store);
    // The layout of version 2: no attempts_at_retry, no point_progress.
    let sql = |q: &str| {
        let c = rusqlite::Connection::open(&path).unwrap();
        c.execute_batch(q).unwrap();
    };
    sql("DROP TRIGGER jobs_progress_update;
         DROP TRIGGER jobs_progress_delete; DROP INDEX jobs_done_by_finish;
         DROP TABLE point_progress; DROP TRIGGER results_outcomes_insert;
         DROP TRIGGER results_outcomes_delete; DROP TABLE point_outcomes;
         ALTER TABLE jobs DROP COLUMN attempts_at_retry;
         ALTER TABLE preps DROP COLUMN attempts_at_retry;
         DROP INDEX point_plans_open; DROP TABLE point_plans;
         UPDATE meta SET value = '2' WHERE key = 'schema_version';");
    let version = |p: &Path| -> String {
        let c = rusqlite::Connection::open(p).unwrap();
        c.query_row(
            "SELECT value FROM meta WHERE key = 'schema_version'",
            [],
            |r| r.get(0),
        )
        .unwrap()
    };
    let read = Store::open_read(&path).unwrap();
    let before = read.status().unwrap();
    assert_eq!(before[0].outcomes[End::Train], 1);
    assert_eq!(before[0].jobs.done, 1);
    drop(read);
    assert_eq!(version(&path), "2", "a reader changes nothing");
    let mut store = Store::open(&path).unwrap();
    assert_eq!(version(&path), "6");
    // The counts kept since version 4 start from the jobs as they were.
    assert_eq!(store.status().unwrap(), before);
    let j = pending(&mut store, reg.sweep_id, "v1")[0].id;
    store.claim_job(j).unwrap();
    assert_eq!(
        store.fail_job(j, 1, "crash", Some(1)).unwrap(),
        Some(JobState::Failed)
    );
    assert_eq!(store.retry_failed(reg.sweep_id, "v1").unwrap(), 1);
    assert_eq!(store.status().unwrap()[0].outcomes[End::Train], 1);
}

#[test]
fn a_version_5_store_keeps_its_slurm_arrays_when_migrated_and_records_the_next_before_sbatch() {
    let path = tmp("migrate-arrays");
    let mut store = Store::open_or_create(&path).unwrap();
    let reg = store.register(&sweep("{\"a\":1}", "v1"), false).unwrap();
    drop(store);
    // The layout of version 5: slurm_arrays with a job id always, no sub_dir, no ended_at.
    let c = rusqlite::Connection::open(&path).unwrap();
    c.execute_batch(&format!(
        "DROP TABLE slurm_arrays;
         CREATE TABLE slurm_arrays (id INTEGER PRIMARY KEY, sweep_id INTEGER NOT NULL,
             solver_version TEXT NOT NULL, kind TEXT NOT NULL, slurm_job_id TEXT NOT NULL,
             run_dir TEXT NOT NULL, tasks INTEGER NOT NULL, jobs INTEGER NOT NULL,
             submitted_at REAL NOT NULL);
         INSERT INTO slurm_arrays VALUES (1, {}, 'v1', 'collide', '149', '/runs/x', 3, 8, 5.0);
         UPDATE meta SET value = '5' WHERE key = 'schema_version';",
        reg.sweep_id
    ))
    .unwrap();
    drop(c);
    // A reader sees the old array as it is.
    let read = Store::open_read(&path).unwrap();
    let old = read.arrays_of(reg.sweep_id, "v1").unwrap();
    assert_eq!(old.len(), 1);
    assert_eq!(old[0].slurm_job_id.as_deref(), Some("149"));
    assert_eq!((old[0].sub_dir.clone(), old[0].ended_at), (None, None));
    drop(read);
    let mut store = Store::open(&path).unwrap();
    assert_eq!(store.arrays_of(reg.sweep_id, "v1").unwrap(), old);
    // A new array: recorded without an id, then completed; another refused and forgotten.
    let mut a = old[0].clone();
    a.sub_dir = Some("/runs/x/sub-0002-1".into());
    let row = store.begin_array(reg.sweep_id, "v1", &a).unwrap();
    let refused = store.begin_array(reg.sweep_id, "v1", &a).unwrap();
    assert_eq!(
        store.open_arrays_of(reg.sweep_id, "v1").unwrap()[1].slurm_job_id,
        None
    );
    store.array_submitted(row, "150").unwrap();
    store.forget_array(refused).unwrap();
    store.array_ended(old[0].id, 9.0).unwrap();
    let now = store.arrays_of(reg.sweep_id, "v1").unwrap();
    assert_eq!(now.len(), 2);
    assert_eq!(now[0].ended_at, Some(9.0));
    assert_eq!(now[1].slurm_job_id.as_deref(), Some("150"));
    assert_eq!(now[1].sub_dir.as_deref(), Some("/runs/x/sub-0002-1"));
    let open = store.open_arrays_of(reg.sweep_id, "v1").unwrap();
    assert_eq!(open.len(), 1);
    assert_eq!(open[0].id, row);
}

/// The rows of `sql` (its first `cols` columns), each as one line of text.
fn rows_of(path: &Path, sql: &str, cols: usize) -> Vec<String> {
    let c = rusqlite::Connection::open(path).unwrap();
    let mut q = c.prepare(sql).unwrap();
    q.query_map([], |r| {
        let mut v = Vec::new();
        for i in 0..cols {
            v.push(format!("{:?}", r.get::<_, rusqlite::types::Value>(i)?));
        }
        Ok(v.join(" "))
    })
    .unwrap()
    .map(|r| r.unwrap())
    .collect()
}

/// `point_progress` against a count of the jobs themselves: (point, version) -> (pending,
/// running, done, failed, latest finish of a done job).
fn progress_and_jobs(path: &Path) -> (Vec<String>, Vec<String>) {
    (
        rows_of(
            path,
            "SELECT point_id, solver_version, pending, running, done, failed, last_finished
             FROM point_progress WHERE pending + running + done + failed > 0
             ORDER BY point_id, solver_version",
            7,
        ),
        rows_of(
            path,
            "SELECT j.point_id, j.solver_version,
                    SUM(j.state = 'pending') + COALESCE((SELECT pl.planned - pl.materialized
                        FROM point_plans pl WHERE pl.point_id = j.point_id
                          AND pl.solver_version = j.solver_version), 0),
                    SUM(j.state = 'running'), SUM(j.state = 'done'), SUM(j.state = 'failed'),
                    MAX(CASE WHEN j.state = 'done' THEN j.finished_at END)
             FROM jobs j GROUP BY j.point_id, j.solver_version
             ORDER BY j.point_id, j.solver_version",
            7,
        ),
    )
}

/// `point_outcomes` against a count of the results themselves.
fn outcomes_and_results(path: &Path) -> (Vec<String>, Vec<String>) {
    (
        rows_of(
            path,
            "SELECT point_id, solver_version, verdict, outcome, n FROM point_outcomes
             WHERE n > 0 ORDER BY 1, 2, 3, 4",
            5,
        ),
        rows_of(
            path,
            "SELECT j.point_id, r.solver_version, r.verdict, COALESCE(r.outcome, ''), COUNT(*)
             FROM results r JOIN jobs j ON j.id = r.job_id GROUP BY 1, 2, 3, 4 ORDER BY 1, 2, 3, 4",
            5,
        ),
    )
}

#[test]
fn the_counts_kept_by_triggers_follow_every_change_of_a_job() {
    let path = tmp("progress");
    let mut store = Store::open_or_create(&path).unwrap();
    let reg = store
        .register(&sweep_of("{\"a\":1}", "v1", 12), false)
        .unwrap();
    store
        .register(&sweep_of("{\"a\":1}", "v2", 5), false)
        .unwrap();
    let check = |what: &str| {
        let (kept, counted) = progress_and_jobs(&path);
        assert_eq!(kept, counted, "after {what}");
        let (kept, counted) = outcomes_and_results(&path);
        assert_eq!(kept, counted, "outcomes after {what}");
    };
    check("registration");
    let jobs = pending(&mut store, reg.sweep_id, "v1");
    for (i, j) in jobs.iter().enumerate() {
        store.claim_job(j.id).unwrap();
        match i % 4 {
            0 => {
                store.record_result(j.id, "v1", &record("train")).unwrap();
            }
            1 => {
                store.fail_job(j.id, 1, "crash", Some(1)).unwrap();
            }
            2 => {
                store.fail_job(j.id, 1, "crash", Some(3)).unwrap();
            }
            _ => {}
        }
        check("a job's step");
    }
    store.recover_running(reg.sweep_id, "v1").unwrap();
    check("recovery");
    store.retry_failed(reg.sweep_id, "v1").unwrap();
    check("a retry");
    let point: i64 = rusqlite::Connection::open(&path)
        .unwrap()
        .query_row("SELECT id FROM points", [], |r| r.get(0))
        .unwrap();
    store.reset_points("v1", &[point]).unwrap();
    check("a reset");
    // Grown: more replicates for the same sweep.
    store
        .register(&sweep_of("{\"a\":1}", "v1", 20), false)
        .unwrap();
    check("growing");
}

/// Two points with `replicates` jobs each, from three preps per point in turn (SPEC section 4),
/// replicate r of point i seeded 1000 i + r.
fn three_prep_sweep(replicates: u32) -> NewSweep {
    let prep = |i: u64| NewPrep {
        key: format!("k{}", i / 3),
        seed: 50 + i,
        config: "{}".into(),
    };
    let point = |i: usize, beta: f64| NewPoint {
        alpha: 0.1,
        beta,
        spacing: 90,
        sigma: 5.0,
        others: Default::default(),
        config: "{}".into(),
        jobs: (0..replicates)
            .map(|r| NewJob {
                replicate: r,
                seed: 1000 * i as u64 + r as u64,
                prep: 3 * i + (r % 3) as usize,
            })
            .collect(),
    };
    NewSweep {
        name: "plans".into(),
        spec: format!("{{\"replicates\":{replicates},\"preps_per_point\":3}}"),
        source: "plans.toml".into(),
        solver_version: "v1".into(),
        preps_per_point: 3,
        preps: (0..6).map(prep).collect(),
        points: vec![point(0, 10.0), point(1, 14.0)],
    }
}

#[test]
fn planned_jobs_are_pending_from_registration_and_become_the_very_rows_registered() {
    let path = tmp("plans");
    let mut store = Store::open_or_create(&path).unwrap();
    let reg = store.register(&three_prep_sweep(10), false).unwrap();
    let count = |sql: &str| -> i64 {
        rusqlite::Connection::open(&path)
            .unwrap()
            .query_row(sql, [], |r| r.get(0))
            .unwrap()
    };
    // One row per prep slot of each point; the other 14 jobs planned, and pending all the same.
    assert_eq!(count("SELECT COUNT(*) FROM jobs"), 6);
    assert_eq!(store.planned_jobs(reg.sweep_id, "v1").unwrap(), 14);
    assert_eq!(store.status().unwrap()[0].jobs.pending, 20);
    assert_eq!(store.preps_of(reg.sweep_id, "v1").unwrap().len(), 6);
    let (kept, counted) = progress_and_jobs(&path);
    assert_eq!(kept, counted);

    // A run asks for a few: the first point's whole tail is written, the second stays planned.
    assert_eq!(store.materialize_next(reg.sweep_id, "v1", 1).unwrap(), 7);
    assert_eq!(store.planned_jobs(reg.sweep_id, "v1").unwrap(), 7);
    assert_eq!(count("SELECT COUNT(*) FROM jobs"), 13);
    // A prep's verdict reaches its jobs at every point: the second point's tail is written too.
    let prep_of_point_1: i64 = count("SELECT MIN(id) FROM preps WHERE key = 'k1'");
    let failed = store
        .fail_jobs_of_prep(reg.sweep_id, prep_of_point_1, "v1", "boom")
        .unwrap();
    assert_eq!(failed, 4, "replicates 0, 3, 6 and 9 of the second point");
    assert_eq!(store.planned_jobs(reg.sweep_id, "v1").unwrap(), 0);
    assert_eq!(store.materialize_next(reg.sweep_id, "v1", 1).unwrap(), 0);

    // Every row is the job registered: its seed, and the prep of its slot.
    let rows = rows_of(
        &path,
        "SELECT p.beta, j.replicate, j.seed, pr.seed FROM jobs j JOIN points p ON p.id = j.point_id
         JOIN preps pr ON pr.id = j.prep_id ORDER BY p.idx, j.replicate",
        4,
    );
    let expected: Vec<String> = (0..2u64)
        .flat_map(|i| {
            (0..10u64).map(move |r| {
                format!(
                    "Real({:?}) Integer({}) Integer({}) Integer({})",
                    10.0 + 4.0 * i as f64,
                    r,
                    1000 * i + r,
                    50 + 3 * i + r % 3
                )
            })
        })
        .collect();
    assert_eq!(rows, expected);
    let (kept, counted) = progress_and_jobs(&path);
    assert_eq!(kept, counted);

    // Grown to 14: four more per point, planned, then written with the same rule.
    store.register(&three_prep_sweep(14), false).unwrap();
    assert_eq!(store.planned_jobs(reg.sweep_id, "v1").unwrap(), 8);
    assert_eq!(store.status().unwrap()[0].jobs.pending, 20 - 4 + 8);
    assert_eq!(
        store
            .materialize_next(reg.sweep_id, "v1", usize::MAX)
            .unwrap(),
        8
    );
    assert_eq!(
        rows_of(
            &path,
            "SELECT j.seed, pr.seed FROM jobs j JOIN preps pr ON pr.id = j.prep_id
             WHERE j.replicate = 13 ORDER BY j.point_id",
            2,
        ),
        vec!["Integer(13) Integer(51)", "Integer(1013) Integer(54)"]
    );
    let (kept, counted) = progress_and_jobs(&path);
    assert_eq!(kept, counted);

    // Jobs that are not replicates 0..n in the round-robin of their preps are refused.
    let mut odd = three_prep_sweep(14);
    odd.name = "odd".into();
    odd.points[0].jobs[5].prep = 0;
    let e = store.register(&odd, false).unwrap_err();
    assert!(matches!(e, StoreError::Unplannable { .. }), "{e}");
}
