//! Adaptive sweeps through real worker processes: rounds until every point is settled, and an
//! adaptive point's results are exactly the first n replicates of the fixed sweep.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

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

/// The real model on small lattices, 2 alphas x 2 sigmas. A 2 tau0 collision is always
/// `undetermined`: with batch 4, min 4, max 16 and error 0.05 (delta = 0.05 / 16 per interval),
/// a point of n undetermined replicates is settled once (delta/2)^(1/n) >= 0.55, at n = 12.
fn write_sweep(dir: &Path, name: &str, replicates: u32, tail: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            "name = \"{name}\"\nseed = 5\nreplicates = {replicates}\n[grid]\nalpha = [0.1, 0.12]\nbeta = [10]\nL = [48]\nsigma = [5, 0]\n\
             [params]\nR0 = 24\n[protocol]\nsingle_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 2\n{tail}"
        ),
    )
    .unwrap();
    path
}

pub const ADAPTIVE: &str = "[adaptive]\nbatch = 4\nmin_replicates = 4\nerror = 0.05\n";

/// Every result row of a sweep, keyed by point and replicate, without wall times and
/// timestamps: (alpha, beta, L, sigma, replicate) -> the other columns as text.
pub fn result_rows(db: &Path, sweep: &str) -> Vec<(String, String)> {
    let c = rusqlite::Connection::open(db).unwrap();
    let mut q = c
        .prepare(
            "SELECT p.alpha, p.beta, p.L, p.sigma, j.replicate, j.seed, r.solver_version,
                    r.verdict, r.outcome, r.contact_time, r.decision_time, r.free_speed,
                    r.threshold_speed, r.attachment_1, r.attachment_2, r.collision_steps,
                    r.classifier, r.record
             FROM results r JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
             JOIN sweeps s ON s.id = p.sweep_id WHERE s.name = ?1
             ORDER BY p.L, p.sigma, p.alpha, p.beta, j.replicate",
        )
        .unwrap();
    let rows = q
        .query_map([sweep], |r| {
            let mut cols = Vec::new();
            for i in 0..18 {
                cols.push(format!("{:?}", r.get::<_, rusqlite::types::Value>(i)?));
            }
            Ok((cols[..5].join(" "), cols[5..].join(" ")))
        })
        .unwrap();
    rows.map(|r| r.unwrap()).collect()
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
