//! Sweep files: the format, and one clear error line for each kind of mistake.

use cellsweep_scheduler::Sweep;

const GOOD: &str = r#"
name = "paper-L90"
seed = 1
replicates = 96
geometry = "two"
[grid]
alpha = { from = 0.10, to = 0.20, step = 0.02 }
beta  = { from = 10, to = 50, step = 4 }
L     = [90]
sigma = [5]
[params]
tau = 100
[protocol]
single_lattice = [200, 200]
pair_lattice = [400, 200]
relax_time = 40
free_time = 400
collide_time = 400
"#;

#[test]
fn the_documented_format_parses() {
    let s = Sweep::parse(GOOD, "good.toml").unwrap();
    assert_eq!(s.grid.alpha, vec![0.1, 0.12, 0.14, 0.16, 0.18, 0.2]);
    assert_eq!(s.grid.beta.len(), 11);
    assert_eq!(s.points().len(), 66);
    assert_eq!(s.replicates, 96);
    assert_eq!(s.protocol.pair_lattice, [400, 200]);
    assert_eq!(s.params.tau, 100.0);
}

/// The error for `text`, checked to be one line naming the file and the key.
fn error(text: &str, key: &str) -> String {
    let e = Sweep::parse(text, "sweeps/bad.toml")
        .unwrap_err()
        .to_string();
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(e.starts_with("sweeps/bad.toml: "), "{e}");
    assert!(e.contains(key), "{key:?} not in {e:?}");
    e
}

#[test]
fn malformed_files_get_one_line_naming_file_key_and_problem() {
    let e = error(&GOOD.replace("seed = 1", "seed = 1\ncolour = 3"), "colour");
    assert!(e.contains("unknown key"));
    error(&GOOD.replace("tau = 100", "gamma = 2"), "params.gamma");
    let e = error(&GOOD.replace("L     = [90]", "L     = []"), "grid.L");
    assert!(e.contains("empty"));
    let e = error(&GOOD.replace("step = 0.02", "step = 0.03"), "grid.alpha");
    assert!(e.contains("whole number"));
    error(&GOOD.replace("step = 4 }", "step = -4 }"), "grid.beta");
    let e = error(&GOOD.replace("L     = [90]", "L     = [90, 75]"), "grid.L");
    assert!(e.contains("75") && e.contains("odd"));
    let e = error(&GOOD.replace("to = 0.20", "to = 0.30"), "grid.alpha");
    assert!(e.contains("unstable"), "{e}");
    let e = error(
        &GOOD.replace("tau = 100", "dt = 0.006\nt_sample = 0.006"),
        "params.dt",
    );
    assert!(e.contains("unstable"), "{e}");
    // (Any SPEC parameter may be an axis: d may, a radius may not.)
    error(
        &GOOD.replace("[grid]", "[grid]\nradius = [1]"),
        "grid.radius",
    );
    error(&GOOD.replace("name = \"paper-L90\"", ""), "name");
    error(
        &GOOD.replace("relax_time = 40", "relax_time = 40.0001"),
        "protocol.relax_time",
    );
    error(&GOOD.replace("tau = 100", "alpha = 0.1"), "params.alpha");
    error(
        &GOOD.replace("replicates = 96", "replicates = 0"),
        "replicates",
    );
    error(
        &GOOD.replace("geometry = \"two\"", "geometry = \"three\""),
        "geometry",
    );
    let e = error("name = \"x\"\nseed = [", "line");
    assert!(!e.contains('\n'));
}

#[test]
fn a_missing_file_is_named() {
    let e = Sweep::load(std::path::Path::new("/nonexistent/sweep.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("/nonexistent/sweep.toml: file: cannot read"),
        "{e}"
    );
}

/// `[report] planes` (issue 50): diagrams on other axes the report draws, each axis a SPEC
/// parameter or a derived one (xt, Lt), checked when the file is read; stored with the
/// definition but not part of the sweep's identity.
#[test]
fn report_planes_are_checked_and_are_not_the_sweeps_identity() {
    let with = |planes: &str| format!("{GOOD}[report]\nplanes = [{planes}]\n");
    let s = Sweep::parse(
        &with(r#"{ x = "R0", y = "beta", by = ["xt", "Lt", "sigma"] }, { x = "beta", y = "E0" }"#),
        "good.toml",
    )
    .unwrap();
    assert_eq!(s.planes.len(), 2);
    assert_eq!(s.planes[0].x, "R0");
    assert_eq!(
        s.planes[0].by.as_deref(),
        Some(&["xt".to_string(), "Lt".into(), "sigma".into()][..])
    );
    assert_eq!(s.planes[1].by, None);
    // The definition carries them (an export's header does), and a stored sweep that differs
    // only in its planes is the same sweep, retuned.
    let plain = Sweep::parse(GOOD, "good.toml").unwrap().canonical_json();
    assert!(s.canonical_json().contains(r#""planes":[{"x":"R0""#));
    assert!(!plain.contains("planes"));
    assert_eq!(
        cellsweep_store::spec_change(&plain, &s.canonical_json()),
        cellsweep_store::SpecChange::Retuned
    );
    for (planes, says) in [
        (r#"{ x = "R1", y = "beta" }"#, "\"R1\" is not an axis"),
        (r#"{ x = "beta", y = "beta" }"#, "x and y are both beta"),
        (
            r#"{ x = "R0", y = "beta", by = ["R0"] }"#,
            "by names R0, which is x or y",
        ),
        (
            r#"{ x = "R0", y = "beta", by = ["xt", "xt"] }"#,
            "by names xt twice",
        ),
        (
            r#"{ x = "alpha", y = "beta" }"#,
            "the paper's: always drawn",
        ),
        (
            r#"{ x = "R0", y = "beta" }, { x = "R0", y = "beta" }"#,
            "asked for twice",
        ),
        (r#"{ x = "R0", y = "beta", colour = 1 }"#, "colour"),
        (r#"{ x = "$(rm -rf /)", y = "beta" }"#, "is not an axis"),
    ] {
        let e = error(&with(planes), "report.planes");
        assert!(e.contains(says), "{planes}: {e}");
    }
}
