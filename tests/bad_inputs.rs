//! A corpus of bad inputs through the real binary: sweep files, counts files, flags and stores.
//! Each must exit 1 with one line on stderr naming the file and key (or the flag), never a
//! panic or an abort, and leave an existing store byte for byte as it was.

mod common;

use std::path::Path;

use common::{cellsweep_in, workdir};

/// A valid tiny sweep; each case edits it.
const BASE: &str = "name = \"bad\"\nseed = 1\nreplicates = 2\ngeometry = \"two\"\n\
[grid]\nalpha = [0.1]\nbeta = [10]\nL = [48]\nsigma = [5]\n\
[params]\nR0 = 24\n\
[protocol]\nsingle_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 2\n\
[classifier]\nsustain_window = 25\n\
[run]\njob_timeout = 3600\n";

/// (what to replace in BASE, its replacement, the key the error must name).
const SWEEPS: &[(&str, &str, &str)] = &[
    // Panics and aborts found before.
    (
        "replicates = 2",
        "replicates = 4294967297\npreps_per_point = 4294967296",
        "replicates",
    ),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.1, to = 0.2, step = 1e-300 }",
        "grid.alpha",
    ),
    (
        "job_timeout = 3600",
        "job_timeout = 1e300",
        "run.job_timeout",
    ),
    ("job_timeout = 3600", "job_timeout = inf", "run.job_timeout"),
    ("job_timeout = 3600", "job_timeout = nan", "run.job_timeout"),
    ("job_timeout = 3600", "job_timeout = 0", "run.job_timeout"),
    ("job_timeout = 3600", "job_timeout = -5", "run.job_timeout"),
    (
        "job_timeout = 3600",
        "job_timeout = \"1h\"",
        "run.job_timeout",
    ),
    ("replicates = 2", "replicates = 1000000000000", "replicates"),
    ("replicates = 2", "replicates = 4294967296", "replicates"),
    ("replicates = 2", "replicates = 4294967299", "replicates"),
    ("replicates = 2", "replicates = 10001", "replicates"),
    ("replicates = 2", "replicates = 0", "replicates"),
    ("replicates = 2", "replicates = -3", "replicates"),
    ("replicates = 2", "replicates = 2.5", "replicates"),
    ("replicates = 2", "replicates = \"two\"", "replicates"),
    (
        "replicates = 2",
        "replicates = 2\npreps_per_point = 3",
        "preps_per_point",
    ),
    (
        "replicates = 2",
        "replicates = 2\npreps_per_point = 0",
        "preps_per_point",
    ),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.1, to = 1000, step = 0.0001 }",
        "grid.alpha",
    ),
    (
        "beta = [10]",
        "beta = { from = 0, to = 99999, step = 1 }",
        "grid.beta",
    ),
    ("L = [48]", "L = [10000000000]", "grid.L"),
    ("L = [48]", "L = [47]", "grid.L"),
    ("L = [48]", "L = [48.5]", "grid.L"),
    ("L = [48]", "L = [-48]", "grid.L"),
    ("L = [48]", "L = []", "grid.L"),
    ("L = [48]", "L = [48, 48]", "grid.L"),
    ("L = [48]", "L = \"48\"", "grid.L"),
    (
        "sustain_window = 25",
        "velocity_window = 0",
        "classifier.velocity_window",
    ),
    (
        "sustain_window = 25",
        "sustain_window = 0",
        "classifier.sustain_window",
    ),
    (
        "sustain_window = 25",
        "sustain_window = -1",
        "classifier.sustain_window",
    ),
    (
        "sustain_window = 25",
        "sustain_window = nan",
        "classifier.sustain_window",
    ),
    (
        "sustain_window = 25",
        "sustain_window = inf",
        "classifier.sustain_window",
    ),
    (
        "sustain_window = 25",
        "speed_fraction = -0.1",
        "classifier.speed_fraction",
    ),
    (
        "sustain_window = 25",
        "threshold = 1",
        "classifier.threshold",
    ),
    // Names.
    (
        "name = \"bad\"",
        "name = \"x$(touch${IFS}/tmp/PWNED)\"",
        "name",
    ),
    ("name = \"bad\"", "name = \"../../../x\"", "name"),
    ("name = \"bad\"", "name = \"/etc/x\"", "name"),
    ("name = \"bad\"", "name = \"\"", "name"),
    ("name = \"bad\"", "name = \".x\"", "name"),
    ("name = \"bad\"", "name = \"a b\"", "name"),
    ("name = \"bad\"", "name = \"a\\nb\"", "name"),
    ("name = \"bad\"", "name = 5", "name"),
    ("name = \"bad\"\n", "", "name"),
    // Seeds.
    ("seed = 1", "seed = -1", "seed"),
    ("seed = 1", "seed = 1.5", "seed"),
    ("seed = 1", "seed = \"1\"", "seed"),
    ("seed = 1\n", "", "seed"),
    // Unknown keys and types.
    ("seed = 1", "seed = 1\nreplicate = 3", "replicate"),
    ("[params]", "[param]", "param"),
    ("R0 = 24", "R0 = 24\nradius = 3", "params.radius"),
    ("R0 = 24", "R0 = 24\nalpha = 0.1", "params.alpha"),
    ("R0 = 24", "R0 = 24\ngeometry = \"one\"", "params.geometry"),
    ("R0 = 24", "R0 = \"big\"", "params.R0"),
    ("R0 = 24", "R0 = nan", "params.R0"),
    ("R0 = 24", "R0 = -24", "params.R0"),
    ("R0 = 24", "R0 = 1e300", "protocol.single_lattice"),
    ("R0 = 24", "R0 = 24\ndt = 0", "params.dt"),
    ("R0 = 24", "R0 = 24\ndt = -0.002", "params.dt"),
    ("R0 = 24", "R0 = 24\nt_sample = 0.003", "params.t_sample"),
    ("geometry = \"two\"", "geometry = \"three\"", "geometry"),
    ("geometry = \"two\"", "geometry = 2", "geometry"),
    ("[grid]", "[grids]", "grids"),
    ("alpha = [0.1]", "alpha = [0.1]\ngamma = [1]", "grid.gamma"),
    // Unstable at every alpha of the grid: the step is what to lower.
    ("alpha = [0.1]", "alpha = [0.9]", "params.dt"),
    ("alpha = [0.1]", "alpha = [\"a\"]", "grid.alpha"),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.2, to = 0.1, step = 0.02 }",
        "grid.alpha",
    ),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.1, to = 0.2, step = 0 }",
        "grid.alpha",
    ),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.1, to = 0.2, step = 0.03 }",
        "grid.alpha",
    ),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.1, to = 0.2 }",
        "grid.alpha",
    ),
    (
        "alpha = [0.1]",
        "alpha = { from = 0.1, to = 0.2, step = 0.02, by = 1 }",
        "grid.alpha",
    ),
    ("alpha = [0.1]\n", "", "grid.alpha"),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [95, 96]",
        "protocol.single_lattice",
    ),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [1000000, 1000000]",
        "protocol.single_lattice",
    ),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [96]",
        "protocol.single_lattice",
    ),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [40, 40]",
        "protocol.single_lattice",
    ),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [96, 96]\npair_lattice = [100, 96]",
        "protocol.pair_lattice",
    ),
    ("relax_time = 5", "relax_time = -5", "protocol.relax_time"),
    ("relax_time = 5", "relax_time = nan", "protocol.relax_time"),
    (
        "collide_time = 2",
        "collide_time = 0.0001",
        "protocol.collide_time",
    ),
    (
        "collide_time = 2",
        "collide_time = 2\nrecord_interval = 0",
        "protocol.record_interval",
    ),
    (
        "collide_time = 2",
        "collide_time = 2\nprecision = \"f16\"",
        "protocol.precision",
    ),
    (
        "collide_time = 2",
        "collide_time = 2\nstop_early = \"yes\"",
        "protocol.stop_early",
    ),
    (
        "collide_time = 2",
        "collide_time = 2\nwindows = 3",
        "protocol.windows",
    ),
    (
        "job_timeout = 3600",
        "job_timeout = 3600\nmax_attempts = 0",
        "run.max_attempts",
    ),
    (
        "job_timeout = 3600",
        "job_timeout = 3600\nmax_attempts = 1000",
        "run.max_attempts",
    ),
    (
        "job_timeout = 3600",
        "job_timeout = 3600\nretries = 2",
        "run.retries",
    ),
    // Refinement.
    ("[run]", "[refine]\naxis = \"alpha\"\n[run]", "refine.axis"),
    ("[run]", "[refine]\nstep = 0\n[run]", "refine.step"),
    ("[run]", "[refine]\nwidth = -1\n[run]", "refine.width"),
    ("[run]", "[refine]\nwidth = nan\n[run]", "refine.width"),
    (
        "[run]",
        "[refine]\nmax_new_per_column = 0\n[run]",
        "refine.max_new_per_column",
    ),
    (
        "[run]",
        "[refine]\nper_round = 7\n[run]",
        "refine.per_round",
    ),
    ("[run]", "[refine]\nbudget = 3\n[run]", "refine.budget"),
    ("[run]", "[refine]\n[run]", "grid.beta: 1 values"),
    ("[run]", "[refine]\nstep = 1e-300\n[run]", "refine.step"),
    // Messages that named the wrong thing (issue 26).
    ("L = [48]", "L = [-44]", "grid.L: -44 is negative"),
    (
        "seed = 1",
        "seed = 99999999999999999999",
        "line 2: the integer 99999999999999999999 is too large",
    ),
    (
        "[run]",
        "[adaptive]\nmin_replicates = 16\n[run]",
        "adaptive.min_replicates: 16 is above the budget of replicates = 2",
    ),
    // Adaptive.
    ("[run]", "[adaptive]\nbatch = 0\n[run]", "adaptive.batch"),
    (
        "[run]",
        "[adaptive]\nmin_replicates = 0\n[run]",
        "adaptive.min_replicates",
    ),
    ("[run]", "[adaptive]\nerror = 1.5\n[run]", "adaptive.error"),
    ("[run]", "[adaptive]\nerror = 0\n[run]", "adaptive.error"),
    (
        "[run]",
        "[adaptive]\nmax_replicates = 3\n[run]",
        "adaptive.max_replicates",
    ),
    (
        "[run]",
        "[adaptive]\nbatches = 3\n[run]",
        "adaptive.batches",
    ),
    // Shapes that only a typed parser catches.
    ("alpha = [0.1]", "alpha = [0.1, \"a\"]", "grid.alpha"),
    ("beta = [10]", "beta = [10, inf]", "grid.beta"),
    ("[grid]", "grid = 3\n[grids]", "grid"),
    ("[params]", "[params.x]", "params.x"),
    ("R0 = 24", "R0 = 24\nL = 48", "params.L"),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [96, \"96\"]",
        "protocol.single_lattice",
    ),
    (
        "single_lattice = [96, 96]",
        "single_lattice = [96, 96, 96]",
        "protocol.single_lattice",
    ),
    (
        "collide_time = 2",
        "collide_time = 2\npatch_bound = nan",
        "protocol.patch_bound",
    ),
    (
        "sustain_window = 25",
        "sustain_window = [25]",
        "classifier.sustain_window",
    ),
    (
        "[run]",
        "[adaptive]\nerror = \"small\"\n[run]",
        "adaptive.error",
    ),
    (
        "[run]",
        "[adaptive]\nbatch = 100000\n[run]",
        "adaptive.batch",
    ),
    ("seed = 1", "seed = 1\ndescription = 5", "description"),
    (
        "job_timeout = 3600",
        "job_timeout = 3600\nmax_attempts = 1e2",
        "run.max_attempts",
    ),
    // Not TOML at all.
    ("[grid]", "[grid", "line"),
    ("seed = 1", "seed = = 1", "line"),
];

/// A store made by a valid run, and its bytes.
fn store(dir: &Path) -> Vec<u8> {
    std::fs::write(
        dir.join("good.toml"),
        BASE.replace("name = \"bad\"", "name = \"good\""),
    )
    .unwrap();
    let out = cellsweep_in(dir, &["run", "good.toml", "--db", "r.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::read(dir.join("r.sqlite")).unwrap()
}

/// One line, exit 1, no panic, naming `what`; else the reason it is not.
fn check(out: &std::process::Output, what: &str, case: &str) -> Result<(), String> {
    let err = String::from_utf8_lossy(&out.stderr);
    if out.status.code() != Some(1) {
        return Err(format!("{case}: exit {:?}: {err}", out.status));
    }
    if err.trim_end().lines().count() != 1 || err.contains("panicked") {
        return Err(format!("{case}: not one clean line: {err}"));
    }
    if !err.contains(what) {
        return Err(format!("{case}: {err:?} does not name {what:?}"));
    }
    Ok(())
}

fn refused(out: &std::process::Output, what: &str, case: &str) {
    if let Err(why) = check(out, what, case) {
        panic!("{why}");
    }
}

/// Every case's failure at once, so that the corpus reads as a list.
fn all_ok(failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "{} cases failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn bad_sweep_files_get_one_line_naming_file_and_key_and_change_nothing() {
    let dir = workdir("bad", "sweeps");
    let before = store(&dir);
    let mut failures = Vec::new();
    for (k, (from, to, key)) in SWEEPS.iter().enumerate() {
        assert!(BASE.contains(from), "case {k}: {from:?} is not in BASE");
        let file = format!("s{k}.toml");
        std::fs::write(dir.join(&file), BASE.replacen(from, to, 1)).unwrap();
        for cmd in ["run", "submit"] {
            let mut args = vec![cmd, file.as_str(), "--db", "r.sqlite"];
            if cmd == "submit" {
                args.extend(["--backend", "slurm"]);
            }
            let out = cellsweep_in(&dir, &args);
            if let Err(why) = check(
                &out,
                &format!("{file}: {key}"),
                &format!("{cmd} case {k} ({to:?})"),
            ) {
                failures.push(why);
            }
        }
    }
    all_ok(failures);
    assert_eq!(std::fs::read(dir.join("r.sqlite")).unwrap(), before);
    assert!(!Path::new("/tmp/PWNED").exists());
    println!(
        "{} sweep-file cases, each through run and submit",
        SWEEPS.len()
    );
}

const HEADER: &str = "alpha,beta,L,sigma,n_train,n_walk,n_reversal,n_undetermined\n";

/// (counts file body after the header, or a whole file if it starts with '!', what to name).
const COUNTS: &[(&str, &str)] = &[
    ("1e308,10,90,5,1,2,0,0\n0.12,10,90,5,2,1,0,0\n", "alpha"),
    ("0.1,10,90,5,18446744073709551615,1,0,0\n", "n_train"),
    ("0.1,10,90,5,1000000001,1,0,0\n", "n_train"),
    ("0.1,10,90,5,-1,1,0,0\n", "n_train"),
    ("0.1,10,90,5,1.5,1,0,0\n", "n_train"),
    ("0.1,10,90,5,1,2,0,0\n0.1,10,90,5,2,1,0,0\n", "appears twice"),
    ("nan,10,90,5,1,2,0,0\n", "alpha"),
    ("inf,10,90,5,1,2,0,0\n", "alpha"),
    ("0.1,10,90.5,5,1,2,0,0\n", "L"),
    ("0.1,10,1e10,5,1,2,0,0\n", "L"),
    ("0.1,10,90,-5,1,2,0,0\n", "sigma"),
    ("0.1,x,90,5,1,2,0,0\n", "beta"),
    ("0.1,10,90,5,1,2,0\n", "n_undetermined"),
    ("", "no data rows"),
    ("!alpha,beta,L,sigma\n0.1,10,90,5\n", "missing column \"n_train\""),
    ("!", "empty file"),
    ("!\u{feff}alpha,beta,L,sigma,n_train,n_walk,n_reversal,n_undetermined,label\n0.1,10,90,5,1,2,0,0,sideways\n", "unknown label"),
    ("!\"alpha,beta,L,sigma,n_train,n_walk,n_reversal,n_undetermined\n", "line"),
];

#[test]
fn bad_counts_files_get_one_line_naming_the_problem() {
    let dir = workdir("bad", "counts");
    for (k, (body, what)) in COUNTS.iter().enumerate() {
        let text = match body.strip_prefix('!') {
            Some(whole) => whole.to_string(),
            None => format!("{HEADER}{body}"),
        };
        let file = format!("c{k}.csv");
        std::fs::write(dir.join(&file), text).unwrap();
        for cmd in ["table", "fit", "plot"] {
            let mut args = vec![cmd, "--counts", file.as_str()];
            if cmd == "plot" {
                args.extend(["--out", "plots"]);
            }
            let out = cellsweep_in(&dir, &args);
            refused(&out, what, &format!("{cmd} counts case {k}"));
            refused(&out, &file, &format!("{cmd} counts case {k}"));
        }
    }
    // A byte-order mark and quoted cells are fine.
    std::fs::write(
        dir.join("ok.csv"),
        format!("\u{feff}{HEADER}\"0.1\",10,90,5,1,2,0,0\n0.12,10,90,5,2,1,0,0\n"),
    )
    .unwrap();
    let out = cellsweep_in(&dir, &["table", "--counts", "ok.csv", "--format", "json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    println!(
        "{} counts-file cases, each through table, fit and plot",
        COUNTS.len()
    );
}

/// (arguments, what the error must name).
const FLAGS: &[(&[&str], &str)] = &[
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
    let dir = workdir("bad", "flags");
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
    let dir = workdir("bad", "readonly");
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

#[test]
fn bad_exports_read_with_data_get_one_line_naming_the_file() {
    let dir = workdir("bad", "data");
    let export = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/paper/adaptive-L90-sigma5.csv"
    ))
    .unwrap();
    let lines: Vec<&str> = export.lines().collect();
    let head = lines[..3].join("\n");
    let row = lines[3];
    let cases: Vec<(String, &str)> = vec![
        ("alpha,beta\n0.1,10\n".into(), "not a cellsweep export"),
        (format!("{head}\n{row}\n{row}\n"), "appears twice"),
        (
            format!(
                "{head}\n{}\n",
                row.replacen(",train,", ",sideways,", 1)
                    .replacen(",walk_past,", ",sideways,", 1)
            ),
            "is not a result",
        ),
        (
            format!(
                "{head}\n{}\n",
                row.replacen("adaptive-L90-sigma5,0.1,", "adaptive-L90-sigma5,0.7,", 1)
            ),
            "is not a point",
        ),
        (
            format!("{head}\n{}\n", row.replacen(",0,", ",999,", 1)),
            "beyond",
        ),
        (format!("{}\n# spec {{\n", lines[0]), "line 2"),
    ];
    let mut failures = Vec::new();
    for (k, (text, what)) in cases.iter().enumerate() {
        let file = format!("d{k}.csv");
        std::fs::write(dir.join(&file), text).unwrap();
        for cmd in ["table", "fit", "plot"] {
            let mut args = vec![cmd, "--data", file.as_str()];
            if cmd == "plot" {
                args.extend(["--out", "p"]);
            }
            let out = cellsweep_in(&dir, &args);
            for need in [file.as_str(), what] {
                if let Err(why) = check(&out, need, &format!("{cmd} data case {k}")) {
                    failures.push(why);
                }
            }
        }
    }
    all_ok(failures);
}
