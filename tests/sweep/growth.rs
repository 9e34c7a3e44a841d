//! A sweep that grows its replicates in place, and refuses to shrink.

use crate::{assert_each_job_counted_once, cellsweep, db_query, workdir, write_sweep};
use std::path::Path;

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
