//! Sweeps through real worker processes: end to end, killed and resumed, crashed and hung
//! workers, interrupted runs, and bad databases.

#[path = "../common/mod.rs"]
mod common;

mod bad_stores;
mod compare;
mod end_to_end;
mod failing_workers;
mod growth;
mod interrupts;

pub(crate) use common::{cellsweep_env as cellsweep, exe, workdir};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A sweep of the real model on small lattices: 2 alphas x 2 sigmas x `replicates`.
pub(crate) fn write_sweep(dir: &Path, name: &str, replicates: u32, collide_time: f64) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            r#"name = "{name}"
seed = 5
replicates = {replicates}
[grid]
alpha = [0.1, 0.12]
beta = [10]
L = [48]
sigma = [5, 0]
[params]
R0 = 24
[protocol]
single_lattice = [96, 96]
relax_time = 5
free_time = 10
collide_time = {collide_time}
"#
        ),
    )
    .unwrap();
    path
}

pub(crate) fn db_query(db: &Path, sql: &str) -> i64 {
    let c = rusqlite::Connection::open_with_flags(db, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
        .unwrap();
    c.busy_timeout(Duration::from_secs(5)).unwrap();
    c.query_row(sql, [], |r| r.get(0)).unwrap()
}

/// Every job done with exactly one result.
pub(crate) fn assert_each_job_counted_once(db: &Path) {
    let jobs = db_query(db, "SELECT COUNT(*) FROM jobs");
    assert!(jobs > 0);
    assert_eq!(
        db_query(db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        jobs
    );
    assert_eq!(db_query(db, "SELECT COUNT(*) FROM results"), jobs);
    assert_eq!(
        db_query(db, "SELECT COUNT(DISTINCT job_id) FROM results"),
        jobs
    );
    assert_eq!(
        db_query(db, "SELECT COUNT(*) FROM results r JOIN jobs j ON j.id = r.job_id WHERE r.solver_version != j.solver_version"),
        0
    );
}

pub(crate) fn wait_for(db: &Path, sql: &str, at_least: i64, limit: Duration) {
    let start = Instant::now();
    while start.elapsed() < limit {
        if db.exists() {
            let ok = std::panic::catch_unwind(|| db_query(db, sql)).is_ok_and(|n| n >= at_least);
            if ok {
                return;
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    panic!("timed out waiting for {sql} >= {at_least}");
}

pub(crate) fn spawn_run(sweep: &Path, db: &Path) -> Child {
    Command::new(exe())
        .args([
            "run",
            sweep.to_str().unwrap(),
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap()
}
