//! Bad flags, and stores that cannot be written.

use crate::common::{cellsweep_in, workdir};
use crate::{all_ok, check, refused, store};

/// (arguments, what the error must name).
const FLAGS: &[(&[&str], &str)] = &[
    // clap's own message, its lines joined where one ends in a colon (issue 50, 6).
    (
        &["run", "--db", "r.sqlite"],
        "the following required arguments were not provided: <SWEEP>",
    ),
    (
        &[
            "run",
            "good.toml",
            "--db",
            "r.sqlite",
            "--job-timeout",
            "inf",
        ],
        "--job-timeout",
    ),
    (
        &[
            "run",
            "good.toml",
            "--db",
            "r.sqlite",
            "--job-timeout",
            "1e20",
        ],
        "--job-timeout",
    ),
    (
        &[
            "run",
            "good.toml",
            "--db",
            "r.sqlite",
            "--job-timeout",
            "nan",
        ],
        "--job-timeout",
    ),
    (
        &["run", "good.toml", "--db", "r.sqlite", "--job-timeout", "0"],
        "--job-timeout",
    ),
    (
        &[
            "run",
            "good.toml",
            "--db",
            "r.sqlite",
            "--job-timeout",
            "-1",
        ],
        "'-1'",
    ),
    (
        &["run", "good.toml", "--db", "r.sqlite", "--workers", "0"],
        "--workers",
    ),
    (
        &[
            "run",
            "good.toml",
            "--db",
            "r.sqlite",
            "--workers",
            "100000",
        ],
        "--workers",
    ),
    (
        &[
            "run",
            "good.toml",
            "--db",
            "r.sqlite",
            "--max-attempts",
            "0",
        ],
        "--max-attempts",
    ),
    (
        &["run", "good.toml", "--db", "r.sqlite", "--grace", "nan"],
        "--grace",
    ),
    (
        &["run", "good.toml", "--db", "r.sqlite", "--grace", "-1"],
        "'-1'",
    ),
    (
        &["run", "good.toml", "--db", "r.sqlite", "--frobnicate"],
        "--frobnicate",
    ),
    (&["run", "missing.toml", "--db", "r.sqlite"], "missing.toml"),
    (&["run", "good.toml", "--db", "nodir/r.sqlite"], "nodir"),
    (&["run", "good.toml", "--db", "."], "is a directory"),
    (&["status", "--db", "none.sqlite"], "none.sqlite"),
    (&["status", "--db", "."], "is a directory"),
    (&["status", "--db", "good.toml"], "good.toml"),
    (&["table", "--db", "r.sqlite", "--sweep", "nope"], "nope"),
    (&["fit", "--db", "r.sqlite", "--format", "csv"], "--format"),
    (&["fit", "--db", "r.sqlite", "--bootstrap", "-1"], "'-1'"),
    (&["fit", "--db", "r.sqlite", "--method", "spline"], "spline"),
    (
        &[
            "submit",
            "good.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--jobs-per-task",
            "0",
        ],
        "--jobs-per-task",
    ),
    (
        &[
            "submit",
            "good.toml",
            "--backend",
            "pbs",
            "--db",
            "r.sqlite",
        ],
        "--backend",
    ),
    (
        &[
            "submit",
            "good.toml",
            "--backend",
            "slurm",
            "--db",
            "r.sqlite",
            "--poll",
            "0",
        ],
        "--poll",
    ),
    (&["export", "--db", "r.sqlite"], "--out"),
    (
        &["import", "good.toml", "--db", "r.sqlite"],
        "good.toml: line 1",
    ),
    (&["simulate", "--alpha", "nan"], "alpha"),
    (&["bogus"], "bogus"),
];

#[test]
fn bad_flags_and_stores_get_one_line_and_change_nothing() {
    let dir = workdir("flags");
    let before = store(&dir);
    let mut failures = Vec::new();
    for (k, (args, what)) in FLAGS.iter().enumerate() {
        let out = cellsweep_in(&dir, args);
        if let Err(why) = check(&out, what, &format!("flag case {k} {args:?}")) {
            failures.push(why);
        }
    }
    // An export whose sweep definition carries a name that could escape is refused too.
    // (The committed export's own header, with the name changed.)
    let export = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/paper/adaptive-L90-sigma5.csv"
    ))
    .unwrap();
    let head: String = export.lines().take(2).map(|l| format!("{l}\n")).collect();
    assert!(head.contains("\"name\":\"adaptive-L90-sigma5\""));
    std::fs::write(
        dir.join("x.csv"),
        head.replace("\"name\":\"adaptive-L90-sigma5\"", "\"name\":\"../x$(id)\""),
    )
    .unwrap();
    let out = cellsweep_in(&dir, &["import", "x.csv", "--db", "r.sqlite"]);
    if let Err(why) = check(&out, "x.csv: line 2: name:", "import with a bad spec name") {
        failures.push(why);
    }
    all_ok(failures);
    assert_eq!(std::fs::read(dir.join("r.sqlite")).unwrap(), before);
    // A corrupt page inside the store: writers refuse it and leave it as it is.
    let mut bytes = before.clone();
    let page = 4096 * 2;
    for b in &mut bytes[page..page + 200] {
        *b = 0xAB;
    }
    std::fs::write(dir.join("c.sqlite"), &bytes).unwrap();
    let out = cellsweep_in(&dir, &["run", "good.toml", "--db", "c.sqlite"]);
    refused(&out, "c.sqlite", "corrupt store");
    assert_eq!(std::fs::read(dir.join("c.sqlite")).unwrap(), bytes);
    println!("{} flag and store cases, and a corrupt page", FLAGS.len());
}

#[test]
fn a_store_on_read_only_media_can_be_read_and_is_refused_for_writing() {
    let dir = workdir("readonly");
    store(&dir);
    // A read-only filesystem of our own (a tmpfs remounted read-only; the tests run as root).
    let mnt = dir.join("ro");
    std::fs::create_dir_all(&mnt).unwrap();
    let sh = |cmd: &str| {
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg(cmd)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{cmd}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    sh(&format!("mount -t tmpfs tmpfs {}", mnt.display()));
    sh(&format!(
        "cp {} {}/",
        dir.join("r.sqlite").display(),
        mnt.display()
    ));
    sh(&format!("mount -o remount,ro {}", mnt.display()));
    let db = mnt.join("r.sqlite");
    let db = db.to_str().unwrap();
    let mut failures = Vec::new();
    for args in [
        vec!["status", "--db", db],
        vec!["table", "--db", db, "--format", "csv"],
        vec!["fit", "--db", db],
        vec!["export", "--db", db, "--out", "e.csv"],
    ] {
        let out = cellsweep_in(&dir, &args);
        // `fit` has nothing to fit in one point, and says so; the others succeed.
        let err = String::from_utf8_lossy(&out.stderr);
        let ok = out.status.success() || (args[0] == "fit" && err.contains("a line needs two"));
        if !ok || err.contains("unable to open") || err.contains("panicked") {
            failures.push(format!("{args:?}: {err}"));
        }
    }
    let out = cellsweep_in(&dir, &["run", "good.toml", "--db", db]);
    let refused = check(&out, "r.sqlite", "run on read-only media");
    sh(&format!("umount {}", mnt.display()));
    all_ok(failures);
    refused.unwrap();
}
