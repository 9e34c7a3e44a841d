//! Sweep files that are wrong in one key each, through `run` and `submit`.

use crate::common::{cellsweep_in, workdir};
use crate::{all_ok, check, store, BASE};
use std::path::Path;

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
    // (Issue 50, 6: no multiple of 100 lies between two of the grid's betas.)
    (
        "beta = [10]\nL = [48]\nsigma = [5]\n",
        "beta = [10, 14, 18]\nL = [48]\nsigma = [5]\n[refine]\nstep = 100\n",
        "refine.step: 100: no multiple of it lies between",
    ),
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

#[test]
fn bad_sweep_files_get_one_line_naming_file_and_key_and_change_nothing() {
    let dir = workdir("sweeps");
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
