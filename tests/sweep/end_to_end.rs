//! A small sweep end to end through worker processes.

use crate::{assert_each_job_counted_once, cellsweep, db_query, workdir, write_sweep};

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
