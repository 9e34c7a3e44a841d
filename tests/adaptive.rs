//! Adaptive sweeps through real worker processes: rounds until every point is settled, and an
//! adaptive point's results are exactly the first n replicates of the fixed sweep.

mod common;

use common::{cellsweep, query, result_rows, workdir, write_sweep, ADAPTIVE};

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
    assert_eq!(query(&db, "SELECT COUNT(*) FROM jobs"), 48);
    assert_eq!(
        query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        48
    );
    assert_eq!(query(&db, "SELECT COUNT(*) FROM results"), 48);
    assert_eq!(query(&db, "SELECT MAX(replicate) FROM jobs"), 11);

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
    common::export(&db, &csv);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("# cellsweep export format 4"));
    assert!(lines.next().unwrap().starts_with("# spec {"));
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
        assert_eq!(query(&db, &sql), 1, "{r:?}");
        assert_eq!(r[col("outcome")], "undetermined");
        assert_eq!(r[col("prep_hash")].len(), 16);
        assert_eq!(r[col("params")], "\"{\"\"R0\"\":24.0}\"");
    }

    // Read straight from the export (no store), the table is the store's, standings included.
    let from = |args: &[&str]| {
        let out = cellsweep(args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let stored = from(&["table", "--db", db.to_str().unwrap(), "--format", "json"]);
    let exported = from(&["table", "--data", csv.to_str().unwrap(), "--format", "json"]);
    assert_eq!(exported, stored);

    // Import into a new store: the sweep is registered from the file, its preps computed, and
    // every row checked; exporting that store gives the same file. Importing again adds nothing.
    let db2 = dir.join("imported.sqlite");
    let imp = cellsweep(&[
        "import",
        csv.to_str().unwrap(),
        "--db",
        db2.to_str().unwrap(),
    ]);
    assert!(
        imp.status.success(),
        "{}",
        String::from_utf8_lossy(&imp.stderr)
    );
    assert!(String::from_utf8_lossy(&imp.stdout).contains("imported 48 results"));
    let csv2 = dir.join("again.csv");
    common::export(&db2, &csv2);
    assert_eq!(std::fs::read_to_string(&csv2).unwrap(), text);
    let imp = cellsweep(&[
        "import",
        csv.to_str().unwrap(),
        "--db",
        db2.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&imp.stdout).contains("imported 0 results"));
    assert!(String::from_utf8_lossy(&imp.stdout).contains("48 already"));
    // A tampered row (another seed, another prep, another sweep's name) refuses the whole
    // file: one reason per row, exit 1, nothing imported.
    let seed_col = col("collision_seed");
    for (k, tamper) in [
        Box::new(move |r: &mut Vec<String>| r[seed_col] = "17".into())
            as Box<dyn Fn(&mut Vec<String>)>,
        Box::new(|r: &mut Vec<String>| r[20] = "0123456789abcdef".into()),
        Box::new(|r: &mut Vec<String>| r[0] = "other".into()),
    ]
    .into_iter()
    .enumerate()
    {
        let mut bad: Vec<String> = text.lines().map(String::from).collect();
        let mut cells: Vec<String> = bad[5].split(',').map(String::from).collect();
        tamper(&mut cells);
        bad[5] = cells.join(",");
        let file = dir.join(format!("bad{k}.csv"));
        std::fs::write(&file, bad.join("\n") + "\n").unwrap();
        let db3 = dir.join(format!("bad{k}.sqlite"));
        let out = cellsweep(&[
            "import",
            file.to_str().unwrap(),
            "--db",
            db3.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{k}: {err}");
        assert!(
            err.contains("refused") && err.contains("nothing was imported"),
            "{k}: {err}"
        );
        // All or nothing: not even the store the import would have created is left.
        assert!(
            !db3.exists(),
            "{k}: a refused import left {}",
            db3.display()
        );
    }
    assert_eq!(header[20], "prep_hash");

    // Resuming a settled sweep runs nothing and changes nothing.
    let before = result_rows(&db, "adapt");
    let again = cellsweep(&["run", sweep.to_str().unwrap(), "--db", db.to_str().unwrap()]);
    assert!(again.status.success());
    assert_eq!(query(&db, "SELECT COUNT(*) FROM jobs"), 48);
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

#[test]
fn later_rounds_reach_preps_a_worker_has_dropped_from_its_cache() {
    // Six preps (six alphas) on one worker, which keeps four: every second round returns to
    // preps it dropped long ago. Each must be sent again, and no job may fail for want of it.
    let dir = workdir("cache");
    let db = dir.join("r.sqlite");
    let sweep = write_sweep(&dir, "cache", 16, ADAPTIVE);
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace(
                "alpha = [0.1, 0.12]",
                "alpha = [0.1, 0.11, 0.12, 0.13, 0.14, 0.15]",
            )
            .replace("sigma = [5, 0]", "sigma = [5]"),
    )
    .unwrap();
    let out = cellsweep(&[
        "run",
        sweep.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
        "--workers",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'failed'"),
        0
    );
    assert_eq!(
        query(&db, "SELECT COUNT(*) FROM jobs WHERE attempts > 0"),
        0
    );
    assert_eq!(query(&db, "SELECT COUNT(*) FROM results"), 6 * 12);
}

/// The paper's speed figure from an export: several preps per point give a mean free speed
/// with its standard error per beta, and the export names each prep's seed.
#[test]
fn an_export_with_several_preps_per_point_plots_mean_speeds_with_error_bars() {
    let dir = common::workdir("export");
    std::fs::write(
        dir.join("sp.toml"),
        "name = \"sp\"\nseed = 1\nreplicates = 3\npreps_per_point = 3\n[grid]\nalpha = [0.1]\n\
         beta = [10, 14]\nL = [48]\nsigma = [5]\n[params]\nR0 = 24\n[protocol]\n\
         single_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 1\n",
    )
    .unwrap();
    for args in [
        &["run", "sp.toml", "--db", "s.sqlite"][..],
        &["export", "--db", "s.sqlite", "--out", "sp.csv"],
        &["plot", "--data", "sp.csv", "--out", "p"],
    ] {
        let out = common::cellsweep_in(&dir, args);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = std::fs::read_to_string(dir.join("sp.csv")).unwrap();
    let seeds: std::collections::HashSet<&str> = text
        .lines()
        .skip(3)
        .map(|l| l.split(',').nth(7).unwrap())
        .collect();
    assert_eq!(seeds.len(), 6, "three preps per point, each its own seed");
    let svg = std::fs::read_to_string(dir.join("p/free-speed.svg")).unwrap();
    assert!(svg.contains("mean free speed of the prepped cells ± standard error"));
}
