//! Helpers shared by the integration tests that compare stored results.

#![allow(dead_code)]

pub mod browser;
mod scratch;
pub mod world;

pub use scratch::Scratch;

use std::path::{Path, PathBuf};

/// An adaptive rule for tiny sweeps whose 2 tau0 collisions are always `undetermined`: with
/// batch 4, min 4, a budget of 16 and error 0.05 (delta = 0.05 / 20 per interval: 5 outcome kinds, 4 looks), a point of n
/// undetermined replicates is settled once (delta/2)^(1/n) >= 0.55, at n = 12.
pub const ADAPTIVE: &str = "[adaptive]\nbatch = 4\nmin_replicates = 4\nerror = 0.05\n";

/// Every result row of a sweep, keyed by point and replicate, without wall times and
/// timestamps: (alpha, beta, L, sigma, replicate) -> the other columns as text, ordered by
/// point (its parameters too, which tell apart the points of a sweep's other axes).
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
             ORDER BY p.L, p.sigma, p.alpha, p.beta, p.params, j.replicate",
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

/// The real model on small lattices, 2 alphas x 2 sigmas, seed 5, `replicates` per point, with
/// `tail` (TOML tables) appended. Its 2 tau0 collisions are always `undetermined`.
pub fn write_sweep(dir: &Path, name: &str, replicates: u32, tail: &str) -> PathBuf {
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

/// A fresh scratch directory for one test, named after the test binary and `name`, removed
/// when the test is done with it (see [`Scratch`]): the tests leave nothing behind.
pub fn workdir(name: &str) -> Scratch {
    Scratch::dir(env!("CARGO_CRATE_NAME"), name)
}

/// The cellsweep binary under test.
pub fn exe() -> &'static str {
    env!("CARGO_BIN_EXE_cellsweep")
}

/// The cellsweep binary, run with `args`.
pub fn cellsweep(args: &[&str]) -> std::process::Output {
    cellsweep_env(args, &[])
}

/// The cellsweep binary, run with `args` and the environment variables `envs` added.
pub fn cellsweep_env(args: &[&str], envs: &[(&str, String)]) -> std::process::Output {
    let mut command = std::process::Command::new(exe());
    command.args(args);
    for (k, v) in envs {
        command.env(k, v);
    }
    command.output().unwrap()
}

/// `cellsweep export` of the store at `db` into `out`, which must succeed.
pub fn export(db: &Path, out: &Path) {
    let o = cellsweep(&[
        "export",
        "--db",
        db.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The cellsweep binary, run in `dir`.
pub fn cellsweep_in(dir: &Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(exe())
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// One value of a query.
pub fn query(db: &Path, sql: &str) -> i64 {
    try_query(db, sql).unwrap_or_else(|| panic!("{}: {sql} failed", db.display()))
}

/// One value of a query, or None while the store is not there yet (for polling a live run).
pub fn try_query(db: &Path, sql: &str) -> Option<i64> {
    let c = rusqlite::Connection::open_with_flags(db, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
        .ok()?;
    c.busy_timeout(std::time::Duration::from_secs(5)).ok()?;
    c.query_row(sql, [], |r| r.get(0)).ok()
}

/// A sweep whose one prep blows up to NaN: alpha 0.18 with dt = t_sample = 0.01 on a small
/// cell (R0 = 20, d = sqrt 5) is within the explicit step's stability guard, but the field
/// diverges within the relaxation. `{name}` is replaced by the sweep's name.
pub const NAN_SWEEP: &str = "name = \"{name}\"\nseed = 1\nreplicates = 2\n[grid]\nalpha = [0.18]\nbeta = [10]\nL = [40]\nsigma = [5]\n\
     [params]\ndt = 0.01\nt_sample = 0.01\nR0 = 20\nd = 2.23606797749979\n\
     [protocol]\nsingle_lattice = [100, 100]\nrelax_time = 5\nfree_time = 20\ncollide_time = 2\n";

/// A one-point sweep (1 replicate) whose prepped cell fills its 72-wide box: box-limited
/// (SPEC 4.5), as `table`, `status` and the live page flag it.
pub const BOX_SWEEP: &str = "name = \"bx\"\nseed = 5\nreplicates = 1\n[grid]\nalpha = [0.1]\nbeta = [10]\nL = [48]\nsigma = [5]\n\
     [params]\nR0 = 24\n[protocol]\nsingle_lattice = [72, 96]\npair_lattice = [144, 96]\n\
     relax_time = 5\nfree_time = 10\ncollide_time = 2\n";

/// Send `sig` (libc::SIGINT, ...) to a child process: no `kill` binary needed (a minimal system
/// has none: procps is not essential).
pub fn send_signal(child: &std::process::Child, sig: i32) {
    let pid = i32::try_from(child.id()).expect("pid fits");
    // SAFETY: kill(2) with a live child's pid and a valid signal number.
    let rc = unsafe { libc::kill(pid, sig) };
    assert_eq!(rc, 0, "kill({pid}, {sig}) failed");
}
