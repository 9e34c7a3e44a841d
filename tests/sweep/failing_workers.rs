//! Workers that crash or hang: retried, killed at the timeout, and recorded when they persist.

use crate::{assert_each_job_counted_once, cellsweep, db_query, workdir, write_sweep};

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
