//! `submit --backend slurm` and `collect` against a real Slurm: the one-node cluster of
//! scripts/slurm-local.sh (Debian's slurm-wlm, started here if it is not up; `.ci/run` starts it
//! before the tests).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Once;
use std::time::{Duration, Instant};

static SLURM: Once = Once::new();

fn slurm_up() {
    SLURM.call_once(|| {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm-local.sh");
        let out = Command::new("bash")
            .arg(script)
            .arg("up")
            .output()
            .expect("run slurm-local.sh");
        assert!(
            out.status.success(),
            "local Slurm did not come up: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    });
}

fn cellsweep(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellsweep-slurm-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_sweep(dir: &Path, name: &str) -> PathBuf {
    write_sweep_of(dir, name, 2)
}

fn write_sweep_of(dir: &Path, name: &str, replicates: u32) -> PathBuf {
    let path = dir.join("s.toml");
    std::fs::write(
        &path,
        format!(
            "name = \"{name}\"\nseed = 3\nreplicates = {replicates}\n[grid]\nalpha = [0.1, 0.12]\nbeta = [10]\nL = [48]\nsigma = [5, 0]\n\
             [params]\nR0 = 24\n[protocol]\nsingle_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 2\n"
        ),
    )
    .unwrap();
    path
}

fn db_count(db: &Path, sql: &str) -> i64 {
    rusqlite::Connection::open(db)
        .unwrap()
        .query_row(sql, [], |r| r.get(0))
        .unwrap()
}

fn slurm_ids(stdout: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(stdout)
        .lines()
        .filter_map(|l| l.split("Slurm job ").nth(1).map(|s| s.trim().to_string()))
        .collect()
}

fn wait_for(ids: &[String]) {
    let start = Instant::now();
    loop {
        let out = Command::new("squeue")
            .args(["-h", "-r", "-j", &ids.join(",")])
            .output()
            .unwrap();
        if String::from_utf8_lossy(&out.stdout).trim().is_empty() {
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "Slurm jobs {ids:?} did not finish"
        );
        std::thread::sleep(Duration::from_millis(500));
    }
}

fn assert_each_job_counted_once(db: &Path) {
    let jobs = db_count(db, "SELECT COUNT(*) FROM jobs");
    assert_eq!(jobs, 8);
    assert_eq!(
        db_count(db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        jobs
    );
    assert_eq!(db_count(db, "SELECT COUNT(*) FROM results"), jobs);
    assert_eq!(
        db_count(db, "SELECT COUNT(DISTINCT job_id) FROM results"),
        jobs
    );
}

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

/// Stand-ins for sbatch, squeue and scontrol (MaxArraySize = 5), so array tasks can be run by
/// hand: the worker side of Slurm runs, packing and signals, without waiting for a scheduler.
fn fake_slurm(dir: &Path) -> String {
    let bin = dir.join("fake-bin");
    std::fs::create_dir_all(&bin).unwrap();
    for (name, body) in [
        (
            "sbatch",
            "echo \"$@\" >> \"$(dirname \"$0\")/sbatch.log\"; echo $((RANDOM + 1000))",
        ),
        ("squeue", "exit 0"),
        ("scontrol", "echo 'MaxArraySize            = 5'"),
    ] {
        let path = bin.join(name);
        std::fs::write(&path, format!("#!/bin/bash\n{body}\n")).unwrap();
        Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    }
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

#[test]
fn array_tasks_respect_max_array_size_stop_cleanly_on_usr1_and_resume() {
    let dir = workdir("usr1");
    let sweep = write_sweep(&dir, "slurm-usr1");
    let text = std::fs::read_to_string(&sweep)
        .unwrap()
        .replace("collide_time = 2", "collide_time = 16")
        .replace("replicates = 2", "replicates = 3");
    std::fs::write(&sweep, text).unwrap();
    let path = fake_slurm(&dir);
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .current_dir(&dir)
            .env("PATH", &path)
            .args(args)
            .output()
            .unwrap()
    };

    // 12 jobs at 1 per task would need indices 0..11; MaxArraySize = 5 allows 0..4: packed 3 per task.
    let out = run(&[
        "submit",
        "s.toml",
        "--backend",
        "slurm",
        "--db",
        "r.sqlite",
        "--jobs-per-task",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("12 collisions in 4 array tasks (3 per task)"),
        "{stdout}"
    );
    let sub = std::fs::read_dir(dir.join("cellsweep-runs/slurm-usr1"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with("sub-"))
        .unwrap();
    let collide_script = std::fs::read_to_string(sub.join("collide.sbatch")).unwrap();
    assert!(
        collide_script.contains("#SBATCH --array=0-3\n"),
        "{collide_script}"
    );
    let log = std::fs::read_to_string(dir.join("fake-bin/sbatch.log")).unwrap();
    assert!(
        log.lines()
            .nth(1)
            .unwrap()
            .contains("--dependency=afterany:"),
        "collisions wait for the preps: {log}"
    );

    let task = |kind: &str, id: usize| {
        Command::new(env!("CARGO_BIN_EXE_cellsweep"))
            .args(["worker", "--slurm", sub.to_str().unwrap(), "--kind", kind])
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    for k in 0..2 {
        assert!(task("prep", k).wait().unwrap().success());
    }
    // Task 0 holds three jobs. USR1 while the second runs (the task says on stderr when a
    // record starts): it finishes that record, then stops.
    let results = sub.join("results/collide-0.jsonl");
    let mut child = task("collide", 0);
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut said = String::new();
    loop {
        let mut line = String::new();
        use std::io::BufRead as _;
        assert!(
            stderr.read_line(&mut line).unwrap() > 0,
            "the task ended: {said}"
        );
        said += &line;
        if line.contains("record 2 of 3 started") {
            break;
        }
    }
    common::send_signal(&child, libc::SIGUSR1);
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    assert!(child.wait().unwrap().success());
    assert!(rest.contains("SIGUSR1"), "{said}{rest}");
    assert!(!rest.contains("record 3 of 3"), "{rest}");
    let first = std::fs::read_to_string(&results).unwrap();
    assert_eq!(
        first.lines().count(),
        2,
        "the record in flight completes, the next is not started"
    );
    assert!(first.ends_with('\n'));

    // A task killed mid-write leaves a torn last line. Rerunning the task (as a requeue would)
    // skips the finished records and starts the next on a fresh line, so the torn fragment
    // stays alone (reported by collect) instead of swallowing the new record.
    let mut torn = first.clone().into_bytes();
    torn.extend_from_slice(b"{\"type\":\"collide\",\"task\":");
    std::fs::write(&results, torn).unwrap();
    assert!(task("collide", 0).wait().unwrap().success());
    assert_eq!(
        std::fs::read_to_string(&results).unwrap().lines().count(),
        4
    );
    let c = run(&["collect", "--db", "r.sqlite"]);
    assert!(
        String::from_utf8_lossy(&c.stdout).contains("2 preps and 3 results new"),
        "{}",
        String::from_utf8_lossy(&c.stdout)
    );
    assert!(
        String::from_utf8_lossy(&c.stderr).contains("collide-0.jsonl: line 3: malformed record"),
        "{}",
        String::from_utf8_lossy(&c.stderr)
    );
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
