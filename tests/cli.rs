//! The `cellsweep` binary as a user runs it: outputs, exit codes, one-line errors.

mod common;
use common::cellsweep;
use std::process::Output;

const SMALL: &[&str] = &["--lattice", "96x96", "--set", "R0=24", "--L", "48"];

fn with_small(args: &[&str]) -> Vec<String> {
    args.iter().chain(SMALL).map(|s| s.to_string()).collect()
}

fn run(args: Vec<String>) -> Output {
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    cellsweep(&refs)
}

#[test]
fn relax_prints_one_json_object_with_the_documented_keys() {
    let out = run(with_small(&["relax", "--steps", "400", "--json"]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.lines().count(), 1);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in [
        "steps",
        "sum_phi",
        "area",
        "adhesive_area",
        "adhesive_area_bottom",
        "adhesive_area_top",
        "xbar",
        "ybar",
        "max_phi",
    ] {
        assert!(v[key].is_number(), "missing {key}: {v}");
    }
    assert_eq!(v["steps"], 400);
    let total = v["adhesive_area"].as_f64().unwrap();
    let parts =
        v["adhesive_area_bottom"].as_f64().unwrap() + v["adhesive_area_top"].as_f64().unwrap();
    assert!((total - parts).abs() < 1e-9 * total);
    assert!((v["xbar"].as_f64().unwrap() - 47.5).abs() < 1e-9);
}

#[test]
fn relax_with_one_fiber_reports_the_single_fiber_twice() {
    let out = run(with_small(&[
        "relax",
        "--steps",
        "200",
        "--geometry",
        "one",
        "--json",
    ]));
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["adhesive_area_bottom"], v["adhesive_area_top"]);
    assert_eq!(v["adhesive_area"], v["adhesive_area_bottom"]);
}

#[test]
fn simulate_runs_a_whole_small_trajectory() {
    let out = run(with_small(&[
        "simulate",
        "--beta",
        "10",
        "--sigma",
        "5",
        "--seed",
        "3",
        "--relax-time",
        "5",
        "--free-time",
        "10",
        "--collide-time",
        "4",
        "--json",
    ]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["verdict"], "ok");
    assert!(v["outcome"].is_string());
    assert_eq!(v["config"]["params"]["beta"], 10.0);
    assert_eq!(v["config"]["params"]["R0"], 24.0);
    assert!(v["config"]["classifier"]["contact_overlap"].is_number());
    assert!(v["solver_version"]
        .as_str()
        .unwrap()
        .starts_with("cellsweep-solver"));
    assert!(v["seeds"]["prep"].is_u64() && v["seeds"]["collision"].is_u64());
    assert_eq!(v["collision_steps"], 2000);

    // The human-readable summary, without a progress bar when not on a terminal.
    let out = run(with_small(&[
        "simulate",
        "--seed",
        "3",
        "--relax-time",
        "5",
        "--free-time",
        "10",
        "--collide-time",
        "2",
    ]));
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("prep verdict") && text.contains("outcome"),
        "{text}"
    );
    assert!(out.stderr.is_empty(), "no progress output off a terminal");
}

/// Bad input: exit non-zero, one line on stderr that names the problem.
fn assert_refused(args: Vec<String>, needle: &str) {
    let out = run(args);
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    assert!(err.contains(needle), "{needle:?} not in {err:?}");
}

#[test]
fn bad_parameters_get_one_clear_error_line() {
    let odd_l = ["relax", "--lattice", "96x96", "--set", "R0=24", "--L", "35"];
    assert_refused(odd_l.iter().map(|s| s.to_string()).collect(), "L = 35");
    assert_refused(with_small(&["relax", "--alpha", "0.3"]), "unstable");
    assert_refused(
        with_small(&["relax", "--set", "gamma=3"]),
        "unknown parameter",
    );
    assert_refused(with_small(&["relax", "--set", "tau=-1"]), "tau");
    assert_refused(
        with_small(&["relax", "--set", "t_sample=0.003"]),
        "t_sample",
    );
    assert_refused(
        vec!["relax".into(), "--lattice".into(), "201x200".into()],
        "even",
    );
    assert_refused(
        with_small(&["simulate", "--classifier", "speed=1"]),
        "classifier setting",
    );
}

#[test]
fn completions_and_the_man_page_come_from_the_command_line_definition() {
    let out = cellsweep(&["completions", "bash"]);
    assert!(out.status.success());
    let script = String::from_utf8(out.stdout).unwrap();
    // Every user command is completed, with its flags.
    for word in [
        "simulate",
        "run",
        "status",
        "export",
        "import",
        "--dry-run",
        "--retry-failed",
    ] {
        assert!(script.contains(word), "bash completion lacks {word}");
    }
    for shell in ["zsh", "fish"] {
        assert!(cellsweep(&["completions", shell]).status.success());
    }
    let out = cellsweep(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(1));
    let man = String::from_utf8(cellsweep(&["man"]).stdout).unwrap();
    assert!(man.contains(".TH cellsweep 1"));
    assert!(man.contains("simulate") && man.contains("export"));
}

#[test]
fn bench_reports_rates_that_agree_with_its_own_lattice_sizes() {
    let out = run(vec![
        "bench".into(),
        "--quick".into(),
        "--no-yardstick".into(),
        "--json".into(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let f = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} missing: {v}"));
    for k in [
        "single_steps_per_s",
        "pair_steps_per_s",
        "pair_f32_steps_per_s",
    ] {
        assert!(f(k).is_finite() && f(k) > 0.0, "{k} = {}", f(k));
    }
    // Site updates are steps times the lattice's sites: 200 x 200 for one cell, two cells on
    // 400 x 200 for the pair; the step time is the rate's inverse.
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    assert!(close(
        f("single_site_updates_per_s"),
        f("single_steps_per_s") * 40_000.0
    ));
    assert!(close(
        f("pair_site_updates_per_s"),
        f("pair_steps_per_s") * 160_000.0
    ));
    assert!(close(f("pair_step_s") * f("pair_steps_per_s"), 1.0));
    assert_eq!(v["threads"], 1);
    assert!(v.get("trajectory").is_none(), "--quick times no trajectory");

    // A yardstick that cannot run is skipped with its reason, not an error.
    let out = run(vec![
        "bench".into(),
        "--quick".into(),
        "--python".into(),
        "/nonexistent/python3".into(),
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("NumPy yardstick")
            && text.contains("skipped: cannot run /nonexistent/python3"),
        "{text}"
    );
}

#[test]
fn simulate_frames_writes_the_snapshots_it_counts_and_a_gif() {
    let dir = common::workdir("frames");
    let frames = dir.join("movie");
    let out = run(with_small(&[
        "simulate",
        "--relax-time",
        "2",
        "--free-time",
        "2",
        "--collide-time",
        "6",
        "--frames",
        frames.to_str().unwrap(),
        "--frame-every",
        "2",
    ]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let pngs: Vec<_> = std::fs::read_dir(&frames)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".png"))
        .collect();
    // A snapshot at t = 0, 2, 4 and 6 tau0 (the last at the collision's end).
    assert_eq!(pngs.len(), 4, "{pngs:?}");
    assert!(
        text.contains(&format!("wrote {} snapshots", pngs.len())),
        "{text}"
    );
    let gif = std::fs::read(frames.join("collision.gif")).unwrap();
    assert!(gif.starts_with(b"GIF89a"));

    // A folder that cannot be made: one line naming it, nothing run.
    let blocked = dir.join("a-file");
    std::fs::write(&blocked, "").unwrap();
    let bad = blocked.join("movie");
    assert_refused(
        with_small(&["simulate", "--frames", bad.to_str().unwrap()]),
        "cannot create",
    );
}
