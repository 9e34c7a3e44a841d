//! Submitting, collecting exactly once, repairing and refusing: one sweep's arrays on the
//! local Slurm.

use crate::common;
use crate::*;

#[test]
fn a_sweep_submitted_through_sbatch_is_collected_exactly_once() {
    slurm_up();
    let dir = workdir("e2e");
    write_sweep(&dir, "slurm-e2e");
    let out = cellsweep(
        &dir,
        &[
            "submit",
            "s.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--jobs-per-task",
            "3",
            "--max-array",
            "2",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ids = slurm_ids(&out.stdout);
    assert_eq!(
        ids.len(),
        2,
        "a prep array and a collision array: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(
        db_count(&dir.join("r.sqlite"), "SELECT COUNT(*) FROM slurm_arrays"),
        2
    );
    wait_for(&ids);

    let c = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
    assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));
    assert!(
        String::from_utf8_lossy(&c.stdout).contains("2 preps and 8 results new"),
        "{}",
        String::from_utf8_lossy(&c.stdout)
    );
    assert_each_job_counted_once(&dir.join("r.sqlite"));
    // Collecting twice changes nothing.
    let again = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
    assert!(String::from_utf8_lossy(&again.stdout).contains("0 preps and 0 results new, 8 already"));
    assert_each_job_counted_once(&dir.join("r.sqlite"));
    let st = cellsweep(&dir, &["status", "--db", "r.sqlite"]);
    assert!(String::from_utf8_lossy(&st.stdout).contains("slurm    arrays"));
    let js: serde_json::Value =
        serde_json::from_slice(&cellsweep(&dir, &["status", "--db", "r.sqlite", "--json"]).stdout)
            .unwrap();
    assert_eq!(js[0]["slurm"]["arrays"].as_array().unwrap().len(), 2);
    assert_eq!(js[0]["slurm"]["arrays"][1]["kind"], "collide");

    // A torn last record (a task killed mid-write) is reported with its path and skipped.
    let results = std::fs::read_dir(dir.join("cellsweep-runs/slurm-e2e"))
        .unwrap()
        .flatten()
        .find(|e| e.file_name().to_string_lossy().starts_with("sub-"))
        .unwrap()
        .path()
        .join("results/collide-0.jsonl");
    let mut bytes = std::fs::read(&results).unwrap();
    bytes.extend_from_slice(b"{\"type\":\"collide\",\"task\":1,\"res");
    std::fs::write(&results, bytes).unwrap();
    let torn = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
    assert!(torn.status.success());
    let err = String::from_utf8_lossy(&torn.stderr);
    assert!(
        err.contains("collide-0.jsonl") && err.contains("torn record"),
        "{err}"
    );
    assert_each_job_counted_once(&dir.join("r.sqlite"));
}

#[test]
fn a_cancelled_task_is_repaired_by_submitting_again() {
    slurm_up();
    let dir = workdir("cancel");
    write_sweep(&dir, "slurm-cancel");
    let out = cellsweep(
        &dir,
        &[
            "submit",
            "s.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--jobs-per-task",
            "2",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ids = slurm_ids(&out.stdout);
    // Cancel one collision task while it waits for the preps.
    let cancel = Command::new("scancel")
        .arg(format!("{}_1", ids[1]))
        .status()
        .unwrap();
    assert!(cancel.success());
    wait_for(&ids);
    let c = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
    assert!(
        String::from_utf8_lossy(&c.stdout).contains("6 results new"),
        "{}",
        String::from_utf8_lossy(&c.stdout)
    );
    let db = dir.join("r.sqlite");
    assert_eq!(
        db_count(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'pending'"),
        2
    );

    // Submit again: only the two jobs without a result go out, the preps are reused.
    let again = cellsweep(
        &dir,
        &["submit", "s.toml", "--backend", "slurm", "--db", "r.sqlite"],
    );
    let text = String::from_utf8_lossy(&again.stdout);
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(
        text.contains("0 preps in 0 array tasks, 2 collisions"),
        "{text}"
    );
    wait_for(&slurm_ids(&again.stdout));
    assert!(cellsweep(&dir, &["collect", "--db", "r.sqlite"])
        .status
        .success());
    assert_each_job_counted_once(&db);
}

#[test]
fn a_sweep_grown_after_its_arrays_ran_submits_only_the_new_replicates() {
    slurm_up();
    let dir = workdir("grow");
    let db = dir.join("r.sqlite");
    let submit = || {
        let out = cellsweep(
            &dir,
            &["submit", "s.toml", "--backend", "slurm", "--db", "r.sqlite"],
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let ids = slurm_ids(&out.stdout);
        wait_for(&ids);
        let c = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
        assert!(c.status.success(), "{}", String::from_utf8_lossy(&c.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    write_sweep_of(&dir, "slurm-grow", 1);
    submit();
    assert_eq!(db_count(&db, "SELECT COUNT(*) FROM results"), 4);

    write_sweep_of(&dir, "slurm-grow", 2);
    let text = submit();
    assert!(
        text.contains("grew from 1 to 2 replicates per point"),
        "{text}"
    );
    assert!(
        text.contains("0 preps in 0 array tasks, 4 collisions"),
        "{text}"
    );
    assert_each_job_counted_once(&db);
}

#[test]
fn dry_run_prints_valid_sbatch_scripts_and_submits_nothing() {
    slurm_up();
    let dir = workdir("dry");
    write_sweep(&dir, "slurm-dry");
    let out = cellsweep(
        &dir,
        &[
            "submit",
            "s.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--dry-run",
            "--time",
            "01:00:00",
            "--max-array",
            "4",
            "--sbatch-arg=--comment=cellsweep",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(!dir.join("r.sqlite").exists(), "a dry run creates no store");
    let scripts: Vec<&str> = text
        .split("#!/bin/bash")
        .filter(|s| !s.trim().is_empty())
        .collect();
    assert_eq!(scripts.len(), 2);
    for (k, body) in scripts.iter().enumerate() {
        assert!(
            body.contains("#SBATCH --array=0-") && body.contains("%4"),
            "{body}"
        );
        assert!(
            body.contains("#SBATCH --time=01:00:00")
                && body.contains("#SBATCH --signal=B:USR1@120")
        );
        assert!(body.contains("#SBATCH --comment=cellsweep"));
        let path = dir.join(format!("script-{k}.sbatch"));
        std::fs::write(&path, format!("#!/bin/bash{body}")).unwrap();
        let check = Command::new("sbatch")
            .arg("--test-only")
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            check.status.success(),
            "sbatch --test-only: {}",
            String::from_utf8_lossy(&check.stderr)
        );
    }
}

#[test]
fn a_prep_that_blows_up_on_slurm_is_collected_as_breakup_and_not_resent() {
    slurm_up();
    let dir = workdir("nan");
    std::fs::write(
        dir.join("s.toml"),
        common::NAN_SWEEP.replace("{name}", "slurm-nan"),
    )
    .unwrap();
    let out = cellsweep(
        &dir,
        &["submit", "s.toml", "--backend", "slurm", "--db", "r.sqlite"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    wait_for(&slurm_ids(&out.stdout));
    let db = dir.join("r.sqlite");
    let again = cellsweep(
        &dir,
        &["submit", "s.toml", "--backend", "slurm", "--db", "r.sqlite"],
    );
    let text = String::from_utf8_lossy(&again.stdout);
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(text.contains("nothing to submit"), "{text}");
    assert_eq!(
        db_count(&db, "SELECT COUNT(*) FROM preps WHERE verdict = 'breakup'"),
        1
    );
    assert_eq!(
        db_count(
            &db,
            "SELECT COUNT(*) FROM results WHERE verdict = 'breakup'"
        ),
        2
    );
    // The collide tasks' records of those jobs agree with the prep: collecting them again is
    // quiet, not a refusal on every call.
    let c = cellsweep(&dir, &["collect", "--db", "r.sqlite"]);
    let err = String::from_utf8_lossy(&c.stderr);
    assert!(c.status.success(), "{err}");
    assert!(
        !err.contains("refused") && !err.contains("prep is"),
        "{err}"
    );
}

#[test]
fn a_stale_run_directory_of_another_sweep_is_refused_by_submit_and_collect() {
    slurm_up();
    let dir = workdir("stale");
    write_sweep_of(&dir, "stale", 1);
    let out = cellsweep(
        &dir,
        &["submit", "s.toml", "--backend", "slurm", "--db", "a.sqlite"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    wait_for(&slurm_ids(&out.stdout));
    let run_dir = dir.join("cellsweep-runs/stale");
    let listing = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    let before = listing(&run_dir);
    assert!(before.contains(&"sweep.uid".to_string()), "{before:?}");
    // A new store and a same-name sweep with another grid, into the default run directory:
    // refused before anything is written, and nothing of the old files is ingested.
    std::fs::write(
        dir.join("s.toml"),
        std::fs::read_to_string(dir.join("s.toml"))
            .unwrap()
            .replace("alpha = [0.1, 0.12]", "alpha = [0.12, 0.14]"),
    )
    .unwrap();
    let out = cellsweep(
        &dir,
        &["submit", "s.toml", "--backend", "slurm", "--db", "b.sqlite"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("holds the files of another sweep"), "{err}");
    assert_eq!(listing(&run_dir), before);
    assert_eq!(
        db_count(&dir.join("b.sqlite"), "SELECT COUNT(*) FROM results"),
        0
    );
    // The first store still collects its own directory.
    let c = cellsweep(&dir, &["collect", "--db", "a.sqlite"]);
    assert!(
        String::from_utf8_lossy(&c.stdout).contains("4 results new"),
        "{}",
        String::from_utf8_lossy(&c.stdout)
    );
}
