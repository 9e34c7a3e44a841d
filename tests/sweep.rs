//! Sweeps through real worker processes: end to end, killed and resumed, crashed and hung
//! workers, interrupted runs, and bad databases.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn exe() -> &'static str {
    env!("CARGO_BIN_EXE_cellsweep")
}

fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellsweep-sweep-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A sweep of the real model on small lattices: 2 alphas x 2 sigmas x `replicates`.
fn write_sweep(dir: &Path, name: &str, replicates: u32, collide_time: f64) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            r#"name = "{name}"
seed = 5
replicates = {replicates}
[grid]
alpha = [0.1, 0.12]
beta = [10]
L = [48]
sigma = [5, 0]
[params]
R0 = 24
[protocol]
single_lattice = [96, 96]
relax_time = 5
free_time = 10
collide_time = {collide_time}
"#
        ),
    )
    .unwrap();
    path
}

fn cellsweep(args: &[&str], envs: &[(&str, String)]) -> Output {
    let mut c = Command::new(exe());
    c.args(args);
    for (k, v) in envs {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn db_query(db: &Path, sql: &str) -> i64 {
    let c = rusqlite::Connection::open_with_flags(db, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
        .unwrap();
    c.busy_timeout(Duration::from_secs(5)).unwrap();
    c.query_row(sql, [], |r| r.get(0)).unwrap()
}

/// Every job done with exactly one result.
fn assert_each_job_counted_once(db: &Path) {
    let jobs = db_query(db, "SELECT COUNT(*) FROM jobs");
    assert!(jobs > 0);
    assert_eq!(
        db_query(db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        jobs
    );
    assert_eq!(db_query(db, "SELECT COUNT(*) FROM results"), jobs);
    assert_eq!(
        db_query(db, "SELECT COUNT(DISTINCT job_id) FROM results"),
        jobs
    );
    assert_eq!(
        db_query(db, "SELECT COUNT(*) FROM results r JOIN jobs j ON j.id = r.job_id WHERE r.solver_version != j.solver_version"),
        0
    );
}

#[test]
fn a_small_sweep_runs_end_to_end_through_worker_processes() {
    let dir = workdir("e2e");
    let sweep = write_sweep(&dir, "e2e", 3, 2.0);
    let db = dir.join("r.sqlite");
    let out = cellsweep(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
        ],
        &[],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("registered sweep \"e2e\": 4 points x 3 replicates = 12 jobs, 2 preps"),
        "{text}"
    );
    assert!(text.contains("outcome counts"), "{text}");
    assert_each_job_counted_once(&db);
    // Two preps computed once each, shared by sigma = 5 and sigma = 0.
    assert_eq!(
        db_query(&db, "SELECT COUNT(*) FROM preps WHERE state = 'done'"),
        2
    );
    assert_eq!(db_query(&db, "SELECT COUNT(DISTINCT prep_id) FROM jobs"), 2);
    // Results record the solver version and every parameter, classifier included.
    let rec: String = rusqlite::Connection::open(&db)
        .unwrap()
        .query_row("SELECT record FROM results LIMIT 1", [], |r| r.get(0))
        .unwrap();
    let v: serde_json::Value = serde_json::from_str(&rec).unwrap();
    assert!(v["solver_version"].is_string());
    assert_eq!(v["config"]["params"]["R0"], 24.0);
    assert!(v["config"]["classifier"]["sustain_window"].is_number());

    // Running it again finds nothing to do and changes nothing.
    let again = cellsweep(
        &["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()],
        &[],
    );
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stdout).contains("resuming sweep"));
    assert_eq!(db_query(&db, "SELECT COUNT(*) FROM results"), 12);

    // status, as text and JSON.
    let st = cellsweep(&["status", "--db", db.to_str().unwrap(), "--json"], &[]);
    assert!(st.status.success());
    let v: serde_json::Value = serde_json::from_slice(&st.stdout).unwrap();
    assert_eq!(v[0]["sweep"], "e2e");
    assert_eq!(v[0]["jobs"]["done"], 12);
    assert_eq!(v[0]["preps_done"], 2);
    let o = &v[0]["outcomes"];
    let sum: i64 = [
        "train",
        "walk_past",
        "reversal",
        "undetermined",
        "unstable",
        "breakup",
    ]
    .iter()
    .map(|k| o[k].as_i64().unwrap())
    .sum();
    assert_eq!(sum, 12);

    // A different sweep under the same name is refused, and the store is unchanged.
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace("seed = 5", "seed = 6")
            .replace("alpha = [0.1, 0.12]", "alpha = [0.12, 0.1]"),
    )
    .unwrap();
    let clash = cellsweep(
        &["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()],
        &[],
    );
    assert!(!clash.status.success());
    let err = String::from_utf8_lossy(&clash.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("--replace"), "{err}");
    // It says what differs: the grid's order and the seed, each with both values.
    assert!(
        err.contains("grid.alpha is [0.1,0.12] in the store and [0.12,0.1] in this file"),
        "{err}"
    );
    assert!(
        err.contains("seed is 5 in the store and 6 in this file"),
        "{err}"
    );
    assert_eq!(db_query(&db, "SELECT COUNT(*) FROM sweeps"), 1);
}

fn wait_for(db: &Path, sql: &str, at_least: i64, limit: Duration) {
    let start = Instant::now();
    while start.elapsed() < limit {
        if db.exists() {
            let ok = std::panic::catch_unwind(|| db_query(db, sql)).is_ok_and(|n| n >= at_least);
            if ok {
                return;
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    panic!("timed out waiting for {sql} >= {at_least}");
}

fn spawn_run(sweep: &Path, db: &Path) -> Child {
    Command::new(exe())
        .args([
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}

#[test]
fn a_coordinator_killed_mid_run_resumes_with_every_job_counted_once() {
    let dir = workdir("kill");
    let sweep = write_sweep(&dir, "kill", 3, 20.0);
    let db = dir.join("r.sqlite");
    let mut child = spawn_run(&sweep, &db);
    wait_for(
        &db,
        "SELECT COUNT(*) FROM results",
        2,
        Duration::from_secs(120),
    );
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let done = db_query(&db, "SELECT COUNT(*) FROM results");
    assert!(done < 12, "killed too late to test anything ({done} done)");
    assert!(
        db_query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'") > 0,
        "jobs were in flight"
    );

    let out = cellsweep(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
        ],
        &[],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("recovered"), "{text}");
    assert_each_job_counted_once(&db);
}

#[test]
fn an_interrupted_run_leaves_a_consistent_store_and_resumes() {
    let dir = workdir("int");
    let sweep = write_sweep(&dir, "int", 3, 20.0);
    let db = dir.join("r.sqlite");
    let mut child = spawn_run(&sweep, &db);
    wait_for(
        &db,
        "SELECT COUNT(*) FROM results",
        1,
        Duration::from_secs(120),
    );
    common::send_signal(&child, libc::SIGINT);
    let code = child.wait().unwrap();
    assert_eq!(code.code(), Some(130), "interrupted runs exit with 130");
    assert_eq!(
        db_query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'"),
        0
    );
    assert_eq!(
        db_query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        db_query(&db, "SELECT COUNT(*) FROM results")
    );
    let out = cellsweep(
        &["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()],
        &[],
    );
    assert!(out.status.success());
    assert_each_job_counted_once(&db);
}

#[test]
fn a_crashed_worker_is_retried_and_a_persistent_crash_is_recorded() {
    let dir = workdir("crash");
    let sweep = write_sweep(&dir, "crash", 2, 2.0);
    let db = dir.join("r.sqlite");
    // Job 3 crashes its worker on the first attempt only: retried, then done.
    let envs = [("CELLSWEEP_TEST_CRASH_TASK", "3".to_string())];
    let out = cellsweep(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
        ],
        &envs,
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("crashed (signal 6)"),
        "the crash is reported: {text}"
    );
    assert_each_job_counted_once(&db);
    assert_eq!(db_query(&db, "SELECT attempts FROM jobs WHERE id = 3"), 1);

    // Job 2 of a second store crashes every time: failed after 2 attempts, with its error.
    let db2 = dir.join("r2.sqlite");
    let envs = [
        ("CELLSWEEP_TEST_CRASH_TASK", "2".to_string()),
        ("CELLSWEEP_TEST_CRASH_ATTEMPTS", "99".to_string()),
    ];
    let out = cellsweep(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db2.to_str().unwrap(),
            "--workers",
            "1",
            "--max-attempts",
            "2",
        ],
        &envs,
    );
    // A run with failures exits 1 and says how to see and retry them.
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("1 jobs of \"crash\" failed") && err.contains("--retry-failed"),
        "{err}"
    );
    assert_eq!(
        db_query(&db2, "SELECT COUNT(*) FROM jobs WHERE state = 'failed'"),
        1
    );
    assert_eq!(db_query(&db2, "SELECT attempts FROM jobs WHERE id = 2"), 2);
    let err: String = rusqlite::Connection::open(&db2)
        .unwrap()
        .query_row("SELECT error FROM jobs WHERE id = 2", [], |r| r.get(0))
        .unwrap();
    assert!(
        err.contains("crashed") && err.contains("test hook"),
        "{err}"
    );
    assert_eq!(
        db_query(&db2, "SELECT COUNT(*) FROM results WHERE job_id = 2"),
        0
    );
    assert_eq!(db_query(&db2, "SELECT COUNT(*) FROM results"), 7);
    // status --failed lists it with its error (text and JSON).
    let st = cellsweep(&["status", "--db", db2.to_str().unwrap(), "--failed"], &[]);
    let text = String::from_utf8_lossy(&st.stdout);
    assert!(
        text.contains("failed   job 2") && text.contains("test hook"),
        "{text}"
    );
    let st = cellsweep(
        &[
            "status",
            "--db",
            db2.to_str().unwrap(),
            "--failed",
            "--json",
        ],
        &[],
    );
    let v: serde_json::Value = serde_json::from_slice(&st.stdout).unwrap();
    assert_eq!(v[0]["failures"][0]["id"], 2);
    assert_eq!(
        v[0]["failures"][0]["replicate"],
        db_query(&db2, "SELECT replicate FROM jobs WHERE id = 2")
    );
    // --retry-failed runs it again (without the fault now): every job counted once, exit 0.
    let out = cellsweep(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db2.to_str().unwrap(),
            "--retry-failed",
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("retrying 1 failed"));
    assert_each_job_counted_once(&db2);
}

#[test]
fn a_hung_worker_is_killed_at_the_timeout_and_its_job_retried() {
    let dir = workdir("hang");
    let sweep = write_sweep(&dir, "hang", 1, 2.0);
    let db = dir.join("r.sqlite");
    let envs = [("CELLSWEEP_TEST_HANG_TASK", "2".to_string())];
    let out = cellsweep(
        &[
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
            "--job-timeout",
            "3",
        ],
        &envs,
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(text.contains("timed out after 3 s"), "{text}");
    assert_each_job_counted_once(&db);
    assert_eq!(db_query(&db, "SELECT attempts FROM jobs WHERE id = 2"), 1);
}

#[test]
fn missing_and_corrupt_databases_get_a_clear_error_and_are_never_overwritten() {
    let dir = workdir("db");
    let missing = dir.join("missing.sqlite");
    let out = cellsweep(&["status", "--db", missing.to_str().unwrap()], &[]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no database at") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    assert!(!missing.exists());

    let corrupt = dir.join("corrupt.sqlite");
    let bytes: Vec<u8> = (0..4096u32).map(|i| (i * 7 + 3) as u8).collect();
    std::fs::write(&corrupt, &bytes).unwrap();
    let sweep = write_sweep(&dir, "db", 1, 2.0);
    for args in [
        vec!["status", "--db", corrupt.to_str().unwrap()],
        vec![
            "run",
            sweep.to_str().unwrap(),
            "--db",
            corrupt.to_str().unwrap(),
        ],
    ] {
        let out = cellsweep(&args, &[]);
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(
            err.contains("corrupt") && err.contains("left untouched"),
            "{err}"
        );
        assert_eq!(
            std::fs::read(&corrupt).unwrap(),
            bytes,
            "the file must not change"
        );
    }
}

#[test]
fn a_malformed_sweep_file_is_one_line_naming_file_and_key() {
    let dir = workdir("bad");
    let sweep = write_sweep(&dir, "bad", 1, 2.0);
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace("L = [48]", "L = [47]"),
    )
    .unwrap();
    let db = dir.join("r.sqlite");
    let out = cellsweep(
        &["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()],
        &[],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("bad.toml: grid.L: 47 is odd"), "{err}");
    assert!(!db.exists(), "nothing is created for a bad sweep");
}

#[test]
fn compare_pairs_the_replicates_of_two_sweeps_by_seed() {
    let dir = workdir("compare");
    let db = dir.join("r.sqlite");
    let db_s = db.to_str().unwrap();
    // "a" and "b" are the same sweep under two names (same seed: the same preps and noise,
    // replicate by replicate); "c" differs only in its seed.
    let a = write_sweep(&dir, "a", 2, 2.0);
    let b = write_sweep(&dir, "b", 2, 2.0);
    let c = write_sweep(&dir, "c", 2, 2.0);
    let text = std::fs::read_to_string(&c).unwrap();
    std::fs::write(&c, text.replace("seed = 5", "seed = 6")).unwrap();
    for sweep in [&a, &b, &c] {
        let out = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db_s], &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let json = |x: &str, y: &str| -> serde_json::Value {
        let out = cellsweep(&["compare", x, y, "--db", db_s, "--format", "json"], &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };

    // Identical computations: every replicate matched, every pair alike to the bit (decision
    // times too, where there are any), nothing to test.
    let ab = json("a", "b");
    assert_eq!(ab["points"].as_array().unwrap().len(), 4);
    assert_eq!(
        (ab["matched"].as_u64(), ab["alike"].as_u64()),
        (Some(8), Some(8))
    );
    assert_eq!(ab["labels_differ"], 0);
    assert_eq!(ab["p_value_paired"], 1.0);
    for p in ab["points"].as_array().unwrap() {
        assert_eq!(p["test"], "paired");
        assert_eq!(p["counts_a"], p["counts_b"]);
        assert!(p["decision_shift_max"].is_null() || p["decision_shift_max"] == 0.0);
    }
    assert_eq!(ab["a"]["sweep"], "a");

    // Another seed: the same points, but no replicate pairs with its namesake, so each point's
    // counts are compared as independent samples.
    let ac = json("a", "c");
    assert_eq!(ac["matched"], 0);
    assert!(ac["p_value_paired"].is_null());
    for p in ac["points"].as_array().unwrap() {
        assert_eq!(p["test"], "independent");
        let p_value = p["p_value"].as_f64().unwrap();
        assert!(p_value > 0.0 && p_value <= 1.0);
    }

    let text = cellsweep(&["compare", "a", "b", "--db", db_s], &[]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("8 of 8 matched pairs end alike"), "{text}");
    assert!(text.contains("labels differ at 0 of 4 points"), "{text}");

    // A version with no results: one line that names the versions there are.
    let out = cellsweep(
        &[
            "compare",
            "a",
            "b",
            "--db",
            db_s,
            "--version-a",
            "cellsweep-solver 0.0.1",
        ],
        &[],
    );
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("has no results under") && err.contains("cellsweep-solver"),
        "{err}"
    );
}

#[test]
fn a_sweep_grows_its_replicates_in_place_and_refuses_to_shrink() {
    let dir = workdir("grow");
    let db = dir.join("r.sqlite");
    let db_s = db.to_str().unwrap();
    let run = |sweep: &Path, db: &str| {
        let out = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db], &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    // A pilot of 1 replicate per point, then the same sweep grown to 2.
    let sweep = write_sweep(&dir, "g", 1, 2.0);
    run(&sweep, db_s);
    let pilot_jobs = db_query(&db, "SELECT SUM(job_id) FROM results");
    let pilot_done = db_query(
        &db,
        "SELECT CAST(MAX(finished_at) * 1e6 AS INTEGER) FROM results",
    );
    write_sweep(&dir, "g", 2, 2.0);
    let text = run(&sweep, db_s);
    assert!(
        text.contains("grew sweep \"g\": 4 points x 2 replicates = 8 jobs")
            && text.contains("from 1 replicates per point"),
        "{text}"
    );
    assert_each_job_counted_once(&db);
    assert_eq!(db_query(&db, "SELECT COUNT(*) FROM sweeps"), 1);
    // The pilot's results are the same rows as before; only replicate 1 was computed now.
    let replicate = |r: u32, what: &str| {
        db_query(
            &db,
            &format!(
                "SELECT {what} FROM results r JOIN jobs j ON j.id = r.job_id WHERE j.replicate = {r}"
            ),
        )
    };
    assert_eq!(replicate(0, "SUM(r.job_id)"), pilot_jobs);
    assert_eq!(
        replicate(0, "CAST(MAX(r.finished_at) * 1e6 AS INTEGER)"),
        pilot_done
    );
    assert!(replicate(1, "CAST(MIN(r.finished_at) * 1e6 AS INTEGER)") > pilot_done);

    // Grown in place, it is the sweep a fresh 2-replicate run gives: every pair alike.
    let fresh = dir.join("fresh.sqlite");
    run(&sweep, fresh.to_str().unwrap());
    let out = cellsweep(
        &[
            "compare",
            "g",
            "g",
            "--db",
            db_s,
            "--db-b",
            fresh.to_str().unwrap(),
            "--format",
            "json",
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (v["matched"].as_u64(), v["alike"].as_u64()),
        (Some(8), Some(8))
    );
    for p in v["points"].as_array().unwrap() {
        assert!(p["decision_shift_max"].is_null() || p["decision_shift_max"] == 0.0);
    }

    // Shrinking: one line naming both counts, and the store untouched.
    write_sweep(&dir, "g", 1, 2.0);
    let out = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db_s], &[]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("2 replicates per point") && err.contains("grow but not shrink"),
        "{err}"
    );
    assert_eq!(db_query(&db, "SELECT COUNT(*) FROM jobs"), 8);
    assert_eq!(db_query(&db, "SELECT COUNT(*) FROM results"), 8);
}
