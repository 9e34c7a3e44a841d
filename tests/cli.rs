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
