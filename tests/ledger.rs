//! What the ledger and its engines refuse or keep, through the real binary: one writer per
//! store, sweep names that cannot escape or inject, script values that cannot end the #SBATCH
//! block, a prep that blows up stored as `breakup`, and a dry run that writes nothing.

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{cellsweep_in, query, try_query, workdir, write_sweep};

#[test]
fn a_second_writer_is_refused_while_readers_keep_working() {
    let dir = workdir("lock");
    // Long enough to be caught running: 30 tau0 collisions.
    let sweep = write_sweep(&dir, "held", 4, "");
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace("collide_time = 2", "collide_time = 30"),
    )
    .unwrap();
    let mut first = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(&dir)
        .args(["run", "held.toml", "--db", "r.sqlite", "--workers", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let db = dir.join("r.sqlite");
    let start = Instant::now();
    while try_query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'").unwrap_or(0) == 0 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the first run never ran a job"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let second = cellsweep_in(&dir, &["run", "held.toml", "--db", "r.sqlite"]);
    let err = String::from_utf8_lossy(&second.stderr);
    assert_eq!(second.status.code(), Some(1), "{err}");
    assert!(
        err.contains("r.sqlite.lock is held by another cellsweep writer (pid"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    // The first run's jobs were not touched.
    assert!(query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'") > 0);
    // Readers work meanwhile.
    assert!(cellsweep_in(&dir, &["status", "--db", "r.sqlite"])
        .status
        .success());
    // Killed outright, the holder leaves its lock behind with it: the next run takes over,
    // recovers the dead holder's jobs and finishes.
    first.kill().unwrap();
    first.wait().unwrap();
    let again = cellsweep_in(&dir, &["run", "held.toml", "--db", "r.sqlite"]);
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert_eq!(query(&db, "SELECT COUNT(*) FROM results"), 16);
}

#[test]
fn sweep_names_that_could_escape_or_inject_are_refused_before_anything_is_written() {
    let dir = workdir("names");
    for (k, name) in [
        "x$(touch${IFS}/tmp/cellsweep-PWNED)",
        "../../../x",
        "/abs/path",
        ".hidden",
        "with space",
        "quote'd",
        "",
        &"n".repeat(101),
    ]
    .iter()
    .enumerate()
    {
        let file = dir.join(format!("s{k}.toml"));
        std::fs::write(
            &file,
            format!("name = {name:?}\nseed = 1\n[grid]\nalpha = [0.1]\nbeta = [10]\nL = [48]\nsigma = [5]\n"),
        )
        .unwrap();
        for cmd in [
            vec!["run", file.to_str().unwrap(), "--db", "r.sqlite"],
            vec![
                "submit",
                file.to_str().unwrap(),
                "--backend",
                "slurm",
                "--db",
                "r.sqlite",
            ],
        ] {
            let out = cellsweep_in(&dir, &cmd);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{name:?}: {err}");
            assert!(
                err.contains(": name: ") && err.contains("is not a sweep name"),
                "{err}"
            );
        }
    }
    assert!(!std::path::Path::new("/tmp/cellsweep-PWNED").exists());
    assert!(!dir.join("r.sqlite").exists());
    assert!(!dir.join("cellsweep-runs").exists());
}

#[test]
fn script_values_with_a_newline_are_refused_and_paths_are_quoted() {
    let dir = workdir("inject");
    write_sweep(&dir, "inject", 1, "");
    for flag in [
        "--partition=debug\ntouch /tmp/cellsweep-PWNED2",
        "--time=1:00\n#",
        "--sbatch-arg=--account=x\necho hi",
        "--run-dir=runs\nx",
    ] {
        let out = cellsweep_in(
            &dir,
            &[
                "submit",
                "inject.toml",
                "--backend",
                "slurm",
                "--db",
                "r.sqlite",
                flag,
            ],
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{flag:?}: {err}");
        assert!(err.contains("contains a newline"), "{err}");
        assert!(!dir.join("r.sqlite").exists());
    }
    // A run directory with a quote and $(...) reaches the script only inside single quotes.
    let out = cellsweep_in(
        &dir,
        &[
            "submit",
            "inject.toml",
            "--backend",
            "slurm",
            "--db",
            "none.sqlite",
            "--dry-run",
            "--run-dir",
            "/tmp/it's $(touch x)",
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("--slurm '/tmp/it'\\''s $(touch x)/sub-0000'"),
        "{text}"
    );
}

#[test]
fn a_prep_that_blows_up_is_stored_as_breakup_with_its_nan_summaries() {
    let dir = workdir("nan");
    std::fs::write(
        dir.join("nan.toml"),
        common::NAN_SWEEP.replace("{name}", "nan"),
    )
    .unwrap();
    let out = cellsweep_in(&dir, &["run", "nan.toml", "--db", "r.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let db = dir.join("r.sqlite");
    assert_eq!(
        query(
            &db,
            "SELECT COUNT(*) FROM preps WHERE verdict = 'breakup' AND attempts = 0"
        ),
        1
    );
    assert_eq!(
        query(
            &db,
            "SELECT COUNT(*) FROM results WHERE verdict = 'breakup'"
        ),
        2
    );
    let summary: String = rusqlite::Connection::open(&db)
        .unwrap()
        .query_row("SELECT summary FROM preps", [], |r| r.get(0))
        .unwrap();
    assert!(summary.contains("\"area\":\"NaN\""), "{summary}");
    // With its reason, in the prep and in every result it decided.
    assert!(summary.contains("not finite"), "{summary}");
    let record: String = rusqlite::Connection::open(&db)
        .unwrap()
        .query_row("SELECT record FROM results LIMIT 1", [], |r| r.get(0))
        .unwrap();
    assert!(
        record.contains("\"reason\":\"the fields are not finite"),
        "{record}"
    );
    // The stored verdict record carries the sweep's classifier settings, as a collision does.
    let classifier: String = rusqlite::Connection::open(&db)
        .unwrap()
        .query_row("SELECT classifier FROM results LIMIT 1", [], |r| r.get(0))
        .unwrap();
    assert!(classifier.contains("sustain_window"), "{classifier}");
}

#[test]
fn submit_dry_run_leaves_the_store_byte_for_byte_as_it_was() {
    let dir = workdir("dry");
    write_sweep(&dir, "dry", 1, "");
    assert!(cellsweep_in(&dir, &["run", "dry.toml", "--db", "r.sqlite"])
        .status
        .success());
    // Grow it in the file: a dry run shows what it would submit and registers nothing.
    let grown = std::fs::read_to_string(dir.join("dry.toml"))
        .unwrap()
        .replace("replicates = 1", "replicates = 3");
    std::fs::write(dir.join("dry.toml"), grown).unwrap();
    let before = std::fs::read(dir.join("r.sqlite")).unwrap();
    let out = cellsweep_in(
        &dir,
        &[
            "submit",
            "dry.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--dry-run",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(std::fs::read(dir.join("r.sqlite")).unwrap(), before);
    assert!(!dir.join("cellsweep-runs").exists());
}

/// Start `run` of a sweep whose job 1 hangs its worker, and wait until other jobs are done.
fn hung_run(dir: &std::path::Path, grace: &str) -> std::process::Child {
    let sweep = write_sweep(dir, "hang", 3, "");
    std::fs::write(
        &sweep,
        std::fs::read_to_string(&sweep)
            .unwrap()
            .replace("collide_time = 2", "collide_time = 10"),
    )
    .unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(dir)
        .args([
            "run",
            "hang.toml",
            "--db",
            "r.sqlite",
            "--workers",
            "2",
            "--grace",
            grace,
        ])
        .env("CELLSWEEP_TEST_HANG_TASK", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let db = dir.join("r.sqlite");
    let start = Instant::now();
    let running = "SELECT COUNT(*) FROM jobs WHERE id = 1 AND state = 'running'";
    while !(try_query(&db, "SELECT COUNT(*) FROM results").unwrap_or(0) >= 2
        && try_query(&db, running) == Some(1))
    {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the run never got going"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    child
}

#[test]
fn ctrl_c_stops_dispatching_at_once_and_a_hung_worker_only_gets_the_grace() {
    let dir = workdir("grace");
    let mut child = hung_run(&dir, "2");
    let db = dir.join("r.sqlite");
    let asked = Instant::now();
    common::send_signal(&child, libc::SIGINT);
    let code = child.wait().unwrap();
    let took = asked.elapsed();
    assert_eq!(code.code(), Some(130));
    // The hung job had 2 s, not the hour of its job timeout.
    assert!(took < Duration::from_secs(10), "took {took:?}");
    let mut out = String::new();
    std::io::Read::read_to_string(&mut child.stdout.take().unwrap(), &mut out).unwrap();
    assert!(out.contains("no new jobs; waiting up to 2 s"), "{out}");
    assert!(out.contains("grace period over"), "{out}");
    assert_eq!(
        query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'"),
        0
    );
    assert_eq!(
        query(&db, "SELECT state = 'pending' FROM jobs WHERE id = 1"),
        1
    );
    assert_eq!(
        query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        query(&db, "SELECT COUNT(*) FROM results")
    );

    // A second signal does not wait for the grace.
    let dir = workdir("twice");
    let mut child = hung_run(&dir, "600");
    let asked = Instant::now();
    common::send_signal(&child, libc::SIGINT);
    // The second signal only once the run has taken the first (it says so), never after a
    // sleep that hopes it has.
    let mut lines = std::io::BufRead::lines(std::io::BufReader::new(child.stdout.take().unwrap()));
    let said = lines
        .by_ref()
        .map_while(Result::ok)
        .find(|l| l.contains("no new jobs"));
    assert!(
        said.is_some(),
        "the run never said it took the first signal"
    );
    common::send_signal(&child, libc::SIGTERM);
    assert_eq!(child.wait().unwrap().code(), Some(130));
    assert!(
        asked.elapsed() < Duration::from_secs(10),
        "{:?}",
        asked.elapsed()
    );
}
