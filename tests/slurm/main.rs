//! `submit --backend slurm` and `collect` against a real Slurm: the one-node cluster of
//! scripts/slurm-local.sh (Debian's slurm-wlm, started here if it is not up; `.ci/run` starts it
//! before the tests).

#[path = "../common/mod.rs"]
mod common;

mod array_tasks;
mod collect;
mod failures;
mod rounds;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Once;
use std::time::{Duration, Instant};

static SLURM: Once = Once::new();

pub(crate) fn slurm_up() {
    SLURM.call_once(|| {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm-local.sh");
        let out = Command::new("bash")
            .arg(script)
            // A cluster started here goes down once this test binary has exited.
            .args(["up", "--until-exit", &std::process::id().to_string()])
            .output()
            .expect("run slurm-local.sh");
        assert!(
            out.status.success(),
            "local Slurm did not come up: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    });
}

pub(crate) use common::{cellsweep_in as cellsweep, workdir};

pub(crate) fn write_sweep(dir: &Path, name: &str) -> PathBuf {
    write_sweep_of(dir, name, 2)
}

pub(crate) fn write_sweep_of(dir: &Path, name: &str, replicates: u32) -> PathBuf {
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

pub(crate) fn db_count(db: &Path, sql: &str) -> i64 {
    rusqlite::Connection::open(db)
        .unwrap()
        .query_row(sql, [], |r| r.get(0))
        .unwrap()
}

pub(crate) fn slurm_ids(stdout: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(stdout)
        .lines()
        .filter_map(|l| l.split("Slurm job ").nth(1).map(|s| s.trim().to_string()))
        .collect()
}

pub(crate) fn wait_for(ids: &[String]) {
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

pub(crate) fn assert_each_job_counted_once(db: &Path) {
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
