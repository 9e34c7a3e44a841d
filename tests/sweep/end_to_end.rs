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

/// A sweep on a finer lattice (SPEC section 6, `resolution = 2`) runs to the end: its preps are
/// k times larger in sites than the lattice the sweep file gives in l0, and the ledger takes
/// them (it once refused every such prep as "lattice [96, 96] is not the prep's [48, 48]" and
/// retried it until it gave up). Its export imports into a fresh store, preps recomputed.
#[test]
fn a_sweep_on_a_finer_lattice_runs_and_its_export_imports() {
    let dir = workdir("k2");
    let sweep = dir.join("k2.toml");
    std::fs::write(
        &sweep,
        "name = \"k2\"\nseed = 5\nreplicates = 2\n[grid]\nalpha = [0.1]\nbeta = [10]\nL = [24]\n\
         sigma = [5]\n[params]\nR0 = 12\nd = 2.23606797749979\n[protocol]\nresolution = 2\n\
         single_lattice = [48, 48]\nrelax_time = 2\nfree_time = 4\ncollide_time = 1\n",
    )
    .unwrap();
    let db = dir.join("r.sqlite");
    let out = cellsweep(
        &["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()],
        &[],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{text}\n{err}");
    assert!(!err.contains("not the prep's"), "{text}\n{err}");
    assert_each_job_counted_once(&db);
    // The prep is stored on the lattice the solver ran: 96 x 96 sites.
    assert_eq!(
        db_query(&db, "SELECT nx * 1000 + ny FROM preps WHERE state = 'done'"),
        96_096
    );
    let csv = dir.join("k2.csv");
    let ex = cellsweep(
        &[
            "export",
            "--db",
            db.to_str().unwrap(),
            "--out",
            csv.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        ex.status.success(),
        "{}",
        String::from_utf8_lossy(&ex.stderr)
    );
    let fresh = dir.join("fresh.sqlite");
    let im = cellsweep(
        &[
            "import",
            csv.to_str().unwrap(),
            "--db",
            fresh.to_str().unwrap(),
        ],
        &[],
    );
    assert!(
        im.status.success(),
        "{}",
        String::from_utf8_lossy(&im.stderr)
    );
    assert_eq!(db_query(&fresh, "SELECT COUNT(*) FROM results"), 2);
    // And each stored replicate replays identically on the finer lattice.
    let v = cellsweep(&["verify", "--db", fresh.to_str().unwrap(), "--all"], &[]);
    let text = String::from_utf8_lossy(&v.stdout);
    assert!(
        v.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&v.stderr)
    );
    assert!(
        text.contains("2 identical, 0 identical to round-off in a speed, 0 differ"),
        "{text}"
    );
}
