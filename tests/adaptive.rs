//! Adaptive sweeps through real worker processes: rounds until every point is settled, and an
//! adaptive point's results are exactly the first n replicates of the fixed sweep.

mod common;

use std::path::{Path, PathBuf};

use std::process::{Command, Output};

use common::{result_rows, write_sweep, ADAPTIVE};

fn workdir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("cellsweep-adaptive-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn cellsweep(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .args(args)
        .output()
        .unwrap()
}

fn count(db: &Path, sql: &str) -> i64 {
    rusqlite::Connection::open(db)
        .unwrap()
        .query_row(sql, [], |r| r.get(0))
        .unwrap()
}

#[test]
fn an_adaptive_sweep_runs_rounds_until_settled_and_matches_the_fixed_sweep() {
    let dir = workdir("local");
    let db = dir.join("r.sqlite");
    let sweep = write_sweep(&dir, "adapt", 16, ADAPTIVE);
    let out = cellsweep(&[
        "run",
        sweep.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
        "--workers",
        "2",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("adaptive"), "{text}");
    // Three rounds of 4 per point, then settled: 12 of the 16-replicate budget.
    assert_eq!(count(&db, "SELECT COUNT(*) FROM jobs"), 48);
    assert_eq!(
        count(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        48
    );
    assert_eq!(count(&db, "SELECT COUNT(*) FROM results"), 48);
    assert_eq!(count(&db, "SELECT MAX(replicate) FROM jobs"), 11);

    // The table says so, per point.
    let t = cellsweep(&["table", "--db", db.to_str().unwrap(), "--format", "json"]);
    assert!(t.status.success(), "{}", String::from_utf8_lossy(&t.stderr));
    let v: serde_json::Value = serde_json::from_slice(&t.stdout).unwrap();
    for p in v.as_array().unwrap() {
        assert_eq!(p["n"], 12, "{p}");
        assert_eq!(p["standing"], "settled", "{p}");
        assert_eq!(p["label"], "undetermined", "{p}");
        let lo = p["bounds"]["undetermined"][0].as_f64().unwrap();
        assert!(lo >= 0.55, "{p}");
    }

    // So does status.
    let st = cellsweep(&["status", "--db", db.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&st.stdout).unwrap();
    assert_eq!(v[0]["adaptive"]["settled"], 4, "{v}");

    // Export: one row per replicate, each naming the seed its job has in the store.
    let csv = dir.join("adapt.csv");
    let out = cellsweep(&[
        "export",
        "--db",
        db.to_str().unwrap(),
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("# cellsweep export format 1"));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 48);
    for r in &rows {
        let seed: u64 = r[col("collision_seed")].parse().unwrap();
        let sql = format!(
            "SELECT COUNT(*) FROM jobs j JOIN points p ON p.id = j.point_id WHERE j.seed = {} \
             AND j.replicate = {} AND p.alpha = {}",
            seed as i64,
            r[col("replicate")],
            r[col("alpha")]
        );
        assert_eq!(count(&db, &sql), 1, "{r:?}");
        assert_eq!(r[col("outcome")], "undetermined");
        assert_eq!(r[col("prep_hash")].len(), 16);
        assert_eq!(r[col("params")], "\"{\"\"R0\"\":24.0}\"");
    }

    // Resuming a settled sweep runs nothing and changes nothing.
    let before = result_rows(&db, "adapt");
    let again = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()]);
    assert!(again.status.success());
    assert_eq!(count(&db, "SELECT COUNT(*) FROM jobs"), 48);
    assert_eq!(result_rows(&db, "adapt"), before);

    // The fixed sweep of the same seed and grid, 12 replicates: the same rows, pair by pair.
    let fixed = write_sweep(&dir, "fixed", 12, "");
    let out = cellsweep(&[
        "run",
        fixed.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
        "--workers",
        "2",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(result_rows(&db, "fixed"), before);
    assert_eq!(before.len(), 48);
}

#[test]
fn a_fixed_sweep_becomes_adaptive_under_its_name_and_keeps_its_results() {
    let dir = workdir("switch");
    let db = dir.join("r.sqlite");
    let sweep = write_sweep(&dir, "pilot", 4, "");
    let out = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let pilot = result_rows(&db, "pilot");
    let sweep = write_sweep(&dir, "pilot", 16, ADAPTIVE);
    let out = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("grew"), "{text}");
    let grown = result_rows(&db, "pilot");
    assert_eq!(grown.len(), 48);
    // The pilot's rows are the first 4 replicates of each point, unchanged.
    for row in &pilot {
        assert!(grown.contains(row), "{row:?}");
    }
    // A bad [adaptive] table is one line naming the key, and changes nothing.
    let bad = write_sweep(&dir, "pilot", 16, "[adaptive]\nbatch = 0\n");
    let out = cellsweep(&["run", bad.to_str().unwrap(), "--db", db.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("adaptive.batch") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    assert_eq!(result_rows(&db, "pilot"), grown);
}
