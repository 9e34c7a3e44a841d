//! Runs killed or interrupted mid-sweep, and their resumption.

use crate::common;
use crate::{
    assert_each_job_counted_once, cellsweep, db_query, spawn_run, wait_for, workdir, write_sweep,
};
use std::time::Duration;

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
    // While the run holds the store, status says its jobs run (issue 50, 5).
    let status = |json: bool| {
        let mut args = vec!["status", "--db", db.to_str().unwrap()];
        if json {
            args.push("--json");
        }
        String::from_utf8_lossy(&cellsweep(&args, &[]).stdout).into_owned()
    };
    let live = status(false);
    assert!(
        live.contains(" running ·") && !live.contains("interrupted"),
        "{live}"
    );
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let done = db_query(&db, "SELECT COUNT(*) FROM results");
    assert!(done < 12, "killed too late to test anything ({done} done)");
    assert!(
        db_query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'") > 0,
        "jobs were in flight"
    );
    // Once the run is dead, its jobs read as interrupted and no ETA is promised.
    let dead = status(false);
    assert!(
        dead.contains("interrupted (no run holds the store"),
        "{dead}"
    );
    assert!(!dead.contains("ETA"), "{dead}");
    assert!(status(true).contains("\"live\": false"));

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
