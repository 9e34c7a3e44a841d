//! Adaptive and refinement rounds, failures and other axes through Slurm, against the local
//! engine's rows.

use crate::common;
use crate::*;

#[test]
fn an_adaptive_sweep_runs_its_rounds_through_slurm_with_the_local_engine_s_rows() {
    slurm_up();
    let dir = workdir("adaptive");
    let sweep = common::write_sweep(&dir, "slurm-adaptive", 16, common::ADAPTIVE);
    let file = sweep.to_str().unwrap();
    let out = cellsweep(
        &dir,
        &[
            "submit",
            file,
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--watch",
            "--poll",
            "0.5",
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Three rounds of 4 replicates, each submitted after the previous one was collected.
    assert_eq!(text.matches("submitted").count(), 3, "{text}");
    assert!(text.contains("every point is settled"), "{text}");
    let db = dir.join("r.sqlite");
    assert_eq!(db_count(&db, "SELECT COUNT(*) FROM jobs"), 48);
    assert_eq!(db_count(&db, "SELECT COUNT(*) FROM results"), 48);
    // The same sweep on the local engine: identical rows but for wall times and timestamps.
    let local = cellsweep(&dir, &["run", file, "--db", "l.sqlite", "--workers", "2"]);
    assert!(
        local.status.success(),
        "{}",
        String::from_utf8_lossy(&local.stderr)
    );
    let rows = common::result_rows(&db, "slurm-adaptive");
    assert_eq!(rows.len(), 48);
    assert_eq!(
        rows,
        common::result_rows(&dir.join("l.sqlite"), "slurm-adaptive")
    );

    // Forged and foreign records in a result file are refused, each with its reason, and the
    // store does not change: a job of another sweep, a job that does not exist, another seed,
    // other parameters, and a collision claiming a verdict its prep does not have.
    let other = common::write_sweep(&dir, "other", 1, "");
    assert!(
        cellsweep(&dir, &["run", other.to_str().unwrap(), "--db", "r.sqlite"])
            .status
            .success()
    );
    let foreign = db_count(
        &db,
        "SELECT MIN(j.id) FROM jobs j JOIN points p ON p.id = j.point_id JOIN sweeps s ON s.id = p.sweep_id WHERE s.name = 'other'",
    );
    let results = std::fs::read_dir(dir.join("cellsweep-runs/slurm-adaptive"))
        .unwrap()
        .flatten()
        .find(|e| e.file_name().to_string_lossy().starts_with("sub-"))
        .unwrap()
        .path()
        .join("results/collide-0.jsonl");
    let text = std::fs::read_to_string(&results).unwrap();
    let line: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    let mut forged = Vec::new();
    let mut v = line.clone();
    v["task"] = foreign.into();
    forged.push(v);
    let mut v = line.clone();
    v["task"] = 999_999.into();
    forged.push(v);
    let mut v = line.clone();
    v["result"]["seeds"]["collision"] = 12345.into();
    forged.push(v);
    let mut v = line.clone();
    v["result"]["config"]["params"]["alpha"] = 0.3.into();
    forged.push(v);
    let mut v = line.clone();
    v["result"]["verdict"] = "unstable".into();
    forged.push(v);
    let mut bytes = text.into_bytes();
    for v in &forged {
        bytes.extend_from_slice(format!("{v}\n").as_bytes());
    }
    std::fs::write(&results, bytes).unwrap();
    let before = (
        common::result_rows(&db, "slurm-adaptive"),
        common::result_rows(&db, "other"),
    );
    let c = cellsweep(
        &dir,
        &["collect", "--db", "r.sqlite", "--sweep", "slurm-adaptive"],
    );
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));
    let err = String::from_utf8_lossy(&c.stderr);
    for why in [
        "belongs to another sweep",
        "no such job",
        "collision seed 12345",
        "parameters are not the job's",
        "verdict \"unstable\"",
    ] {
        assert!(err.contains(why), "{why}: {err}");
    }
    assert_eq!(err.matches("refused").count(), 5, "{err}");
    assert_eq!(
        (
            common::result_rows(&db, "slurm-adaptive"),
            common::result_rows(&db, "other")
        ),
        before
    );
}

#[test]
fn failed_attempts_are_recorded_alike_by_both_engines() {
    slurm_up();
    let dir = workdir("failures");
    let sweep = write_sweep(&dir, "failing");
    let mut text = std::fs::read_to_string(&sweep).unwrap();
    text += "[run]\nmax_attempts = 2\n";
    std::fs::write(&sweep, text).unwrap();
    // Prep 1 fails its first attempt (its jobs wait for the second); job 2 fails every one.
    let faults = [
        ("CELLSWEEP_TEST_FAIL_PREP", "1:1"),
        ("CELLSWEEP_TEST_FAIL_TASK", "2:99"),
    ];
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .current_dir(&dir)
            .args(args)
            .envs(faults)
            .output()
            .unwrap()
    };
    let local = run(&["run", "s.toml", "--db", "l.sqlite", "--workers", "2"]);
    let slurm = run(&[
        "submit",
        "s.toml",
        "--backend",
        "slurm",
        "--db",
        "r.sqlite",
        "--watch",
        "--poll",
        "0.5",
    ]);
    for (engine, out) in [("run", &local), ("submit", &slurm)] {
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{engine}: {err}");
        assert!(
            err.contains("1 jobs of \"failing\" failed after retries")
                && err.contains(&format!("cellsweep {engine} --retry-failed")),
            "{engine}: {err}"
        );
    }
    // The same rows, and the same errors and attempt counts, job by job and prep by prep.
    let book =
        |db: &str| -> Vec<String> {
            let c = rusqlite::Connection::open(dir.join(db)).unwrap();
            let mut rows = Vec::new();
            for sql in [
            "SELECT 'job', p.idx, j.replicate, j.state, j.attempts, COALESCE(j.error, '')
             FROM jobs j JOIN points p ON p.id = j.point_id ORDER BY p.idx, j.replicate",
            "SELECT 'prep', id, seed, state, attempts, COALESCE(error, '') FROM preps ORDER BY id",
        ] {
            let mut q = c.prepare(sql).unwrap();
            let found = q
                .query_map([], |r| {
                    Ok((0..6)
                        .map(|i| r.get::<_, rusqlite::types::Value>(i).map(|v| format!("{v:?}")))
                        .collect::<rusqlite::Result<Vec<_>>>()?
                        .join(" "))
                })
                .unwrap();
            rows.extend(found.map(Result::unwrap));
        }
            rows
        };
    let slurm_book = book("r.sqlite");
    assert_eq!(book("l.sqlite"), slurm_book);
    let text = slurm_book.join("\n");
    assert!(
        text.contains("Text(\"failed\") Integer(2) Text(\"test hook: injected failure of task 2, attempt 2\")"),
        "{text}"
    );
    assert_eq!(
        db_count(
            &dir.join("r.sqlite"),
            "SELECT attempts FROM preps WHERE id = 1"
        ),
        1
    );
    assert_eq!(
        common::result_rows(&dir.join("l.sqlite"), "failing"),
        common::result_rows(&dir.join("r.sqlite"), "failing")
    );
    // Collecting the same records again counts no attempt twice.
    let again = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
    assert!(again.status.success());
    assert_eq!(book("r.sqlite"), slurm_book);
    // A retry on Slurm: the job gets two attempts anew, which fail again (the fault stays),
    // and the records of the earlier ones are not counted again.
    let retry = run(&[
        "submit",
        "s.toml",
        "--backend",
        "slurm",
        "--db",
        "r.sqlite",
        "--watch",
        "--poll",
        "0.5",
        "--retry-failed",
    ]);
    assert_eq!(retry.status.code(), Some(1));
    assert_eq!(
        db_count(
            &dir.join("r.sqlite"),
            "SELECT attempts FROM jobs WHERE id = 2"
        ),
        4
    );
}

#[test]
fn a_refined_sweep_runs_its_rounds_through_slurm_with_the_local_engine_s_points_and_rows() {
    slurm_up();
    let dir = workdir("refined");
    let (toml, csv) = common::world::refined_export(&dir, "slurm-refined");
    let (toml, csv) = (toml.to_str().unwrap(), csv.to_str().unwrap());
    for db in ["r.sqlite", "l.sqlite"] {
        let o = cellsweep(&dir, &["import", csv, "--db", db]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let out = cellsweep(
        &dir,
        &[
            "submit",
            toml,
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--watch",
            "--poll",
            "0.5",
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Rounds one after another: each submitted once the previous one was collected.
    assert!(text.matches("submitted").count() >= 2, "{text}");
    let db = dir.join("r.sqlite");
    let added = db_count(&db, "SELECT COUNT(*) FROM points") - 12;
    assert!(added >= 2, "{text}");
    assert_eq!(
        db_count(&db, "SELECT COUNT(*) FROM jobs WHERE state != 'done'"),
        0
    );
    // The local engine adds the same points and stores the same rows.
    let local = cellsweep(&dir, &["run", toml, "--db", "l.sqlite", "--workers", "2"]);
    assert!(
        local.status.success(),
        "{}",
        String::from_utf8_lossy(&local.stderr)
    );
    let points = |db: &str| {
        let c = rusqlite::Connection::open(dir.join(db)).unwrap();
        let mut q = c
            .prepare("SELECT alpha, beta FROM points ORDER BY alpha, beta")
            .unwrap();
        let v: Vec<(f64, f64)> = q
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
            .unwrap()
            .map(|r| r.unwrap())
            .collect();
        v
    };
    assert_eq!(points("r.sqlite"), points("l.sqlite"));
    assert_eq!(
        common::result_rows(&db, "slurm-refined"),
        common::result_rows(&dir.join("l.sqlite"), "slurm-refined")
    );
}

#[test]
fn a_sweep_over_a_non_paper_axis_runs_through_slurm_with_the_local_engine_s_rows() {
    slurm_up();
    let dir = workdir("other-axis");
    let sweep = dir.join("e0.toml");
    std::fs::write(
        &sweep,
        "name = \"slurm-e0\"\nseed = 5\nreplicates = 2\n[grid]\nalpha = [0.1, 0.12]\nbeta = [10]\n\
         L = [48]\nsigma = [5]\nE0 = [1000, 3000]\n[params]\nR0 = 24\n[protocol]\n\
         single_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 2\n",
    )
    .unwrap();
    let file = sweep.to_str().unwrap();
    let out = cellsweep(
        &dir,
        &[
            "submit",
            file,
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--watch",
            "--poll",
            "0.5",
        ],
    );
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let db = dir.join("r.sqlite");
    assert_eq!(db_count(&db, "SELECT COUNT(*) FROM points"), 4);
    assert_each_job_counted_once(&db);
    let local = cellsweep(&dir, &["run", file, "--db", "l.sqlite", "--workers", "2"]);
    assert!(
        local.status.success(),
        "{}",
        String::from_utf8_lossy(&local.stderr)
    );
    let rows = common::result_rows(&db, "slurm-e0");
    assert_eq!(rows.len(), 8);
    assert_eq!(rows, common::result_rows(&dir.join("l.sqlite"), "slurm-e0"));
    // Each E0 has its own prepped cells.
    assert_eq!(db_count(&db, "SELECT COUNT(DISTINCT prep_id) FROM jobs"), 4);
}
