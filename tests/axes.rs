//! Any SPEC parameter as a grid axis (SPEC section 2): a sweep with `E0 = [1000, 3000]` in
//! `[grid]` runs, resumes after a kill, exports and imports, and its E0 = 1000 points give the
//! very preps and outcomes of a sweep with `E0 = 1000` fixed in `[params]` and the same seed.
//! (Both engines: `tests/slurm/rounds.rs` runs the same sweep through Slurm.)

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{cellsweep_in, query, try_query, workdir};

/// The real model on small lattices at 2 alphas, with `grid` and `params` lines added.
pub fn write(dir: &Path, name: &str, grid: &str, params: &str, collide_time: f64) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(
        &path,
        format!(
            "name = \"{name}\"\nseed = 5\nreplicates = 3\n[grid]\nalpha = [0.1, 0.12]\nbeta = [10]\n\
             L = [48]\nsigma = [5]\n{grid}\n[params]\nR0 = 24\n{params}\n[protocol]\n\
             single_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = {collide_time}\n"
        ),
    )
    .unwrap();
    path
}

/// Every exported row's columns but the sweep's name and the wall times, by the row's point
/// (its parameters included) and replicate.
fn rows(dir: &Path, db: &str, out: &str) -> Vec<Vec<String>> {
    let o = cellsweep_in(dir, &["export", "--db", db, "--out", out]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(dir.join(out)).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let skip = ["sweep", "wall_s", "prep_wall_s"];
    let mut rows: Vec<Vec<String>> = lines
        .map(|l| {
            // (No field holds a comma but the quoted JSON ones, kept whole, their quotes
            // dropped: `{"E0":1000.0}` reads `{E0:1000.0}`.)
            let mut cells = Vec::new();
            let mut cell = String::new();
            let mut quoted = false;
            for ch in l.chars() {
                match ch {
                    '"' => quoted = !quoted,
                    ',' if !quoted => cells.push(std::mem::take(&mut cell)),
                    c => cell.push(c),
                }
            }
            cells.push(cell);
            header
                .iter()
                .zip(cells)
                .filter(|(h, _)| !skip.contains(h))
                .map(|(h, c)| format!("{h}={c}"))
                .collect()
        })
        .collect();
    rows.sort();
    rows
}

fn run(dir: &Path, sweep: &Path, db: &str) -> String {
    let o = cellsweep_in(
        dir,
        &["run", sweep.to_str().unwrap(), "--db", db, "--workers", "2"],
    );
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    text
}

#[test]
fn a_sweep_over_e0_runs_resumes_exports_imports_and_matches_e0_fixed() {
    let dir = workdir("e0");
    let grid = write(&dir, "e0-grid", "E0 = [1000, 3000]", "", 20.0);
    let fixed = write(&dir, "e0-fixed", "", "E0 = 1000", 20.0);

    // Killed once a result is in, then resumed: every job exactly once.
    let db = dir.join("grid.sqlite");
    let mut child = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(&dir)
        .args([
            "run",
            grid.to_str().unwrap(),
            "--db",
            "grid.sqlite",
            "--workers",
            "2",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while try_query(&db, "SELECT COUNT(*) FROM results").unwrap_or(0) < 1 {
        assert!(start.elapsed() < Duration::from_secs(300), "no result came");
        std::thread::sleep(Duration::from_millis(50));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done = query(&db, "SELECT COUNT(*) FROM results");
    assert!(
        done < 12,
        "killed too late to test a resume ({done} of 12 done)"
    );
    run(&dir, &grid, "grid.sqlite");
    assert_eq!(query(&db, "SELECT COUNT(*) FROM points"), 4);
    assert_eq!(
        query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'"),
        12
    );
    assert_eq!(query(&db, "SELECT COUNT(DISTINCT job_id) FROM results"), 12);
    assert_eq!(
        query(
            &db,
            "SELECT COUNT(*) FROM points WHERE params LIKE '%\"E0\":3000.0%'"
        ),
        2
    );

    // The E0 = 1000 points are the fixed sweep's, replicate by replicate: seeds, prep hashes,
    // outcomes, times and steps.
    run(&dir, &fixed, "fixed.sqlite");
    let grid_rows = rows(&dir, "grid.sqlite", "grid.csv");
    assert_eq!(grid_rows.len(), 12);
    let at_1000: Vec<Vec<String>> = grid_rows
        .iter()
        .filter(|r| {
            r.iter()
                .any(|c| c.starts_with("params=") && c.contains("E0:1000.0"))
        })
        .cloned()
        .collect();
    assert_eq!(at_1000.len(), 6, "{grid_rows:?}");
    assert_eq!(at_1000, rows(&dir, "fixed.sqlite", "fixed.csv"));
    let at_3000: Vec<&Vec<String>> = grid_rows.iter().filter(|r| !at_1000.contains(r)).collect();
    let prep = |r: &Vec<String>| r.iter().find(|c| c.starts_with("prep_hash=")).cloned();
    assert!(
        at_3000
            .iter()
            .all(|r| !at_1000.iter().any(|s| prep(s) == prep(r))),
        "another E0 is another prepped cell"
    );

    // The export imports into a fresh store, whole, and reads back the same table.
    let o = cellsweep_in(&dir, &["import", "--db", "back.sqlite", "grid.csv"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        query(&dir.join("back.sqlite"), "SELECT COUNT(*) FROM results"),
        12
    );
    assert_eq!(rows(&dir, "back.sqlite", "back.csv"), grid_rows);
    // Again into the store that holds it: every row is already there (each matched to its own
    // E0's job, not to the other E0's row at the same alpha, beta and replicate).
    let o = cellsweep_in(&dir, &["import", "--db", "back.sqlite", "grid.csv"]);
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        said.contains("imported 0 results") && said.contains("(12 already"),
        "{said}"
    );
    let table = |args: &[&str]| {
        let o = cellsweep_in(&dir, args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    let from_store = table(&["table", "--db", "grid.sqlite", "--format", "json"]);
    assert_eq!(
        from_store,
        table(&["table", "--data", "grid.csv", "--format", "json"])
    );
    assert_eq!(
        from_store,
        table(&["table", "--db", "back.sqlite", "--format", "json"])
    );
    assert_eq!(from_store.matches("\"E0\"").count(), 4, "{from_store}");
    let text = table(&["table", "--db", "grid.sqlite"]);
    assert!(
        text.contains("E0 = 1000") && text.contains("E0 = 3000"),
        "{text}"
    );
    // Each E0 is its own diagram, drawn apart, its title naming it.
    table(&["plot", "--db", "grid.sqlite", "--out", "plots"]);
    assert!(!dir.join("plots/phase-L48-sigma5.svg").exists());
    for (e0, other) in [(1000, 3000), (3000, 1000)] {
        let svg = std::fs::read_to_string(dir.join(format!("plots/phase-L48-sigma5-E0_{e0}.svg")))
            .unwrap();
        assert!(svg.contains(&format!("E0 = {e0}")), "{svg}");
        assert!(!svg.contains(&format!("E0 = {other}")), "{svg}");
    }
    // --where selects on any axis; an axis the sweep lacks, or a value none has, is refused
    // in one line.
    let only = table(&[
        "table",
        "--db",
        "grid.sqlite",
        "--where",
        "E0=3000",
        "--format",
        "json",
    ]);
    let rows: Vec<serde_json::Value> = serde_json::from_str(&only).unwrap();
    assert_eq!(rows.len(), 2, "{only}");
    assert!(rows.iter().all(|r| r["E0"] == 3000.0), "{only}");
    for (sel, says) in [
        ("R0=32", "has no such axis"),
        ("E0=7", "no points match E0 = 7"),
    ] {
        let o = cellsweep_in(&dir, &["table", "--db", "grid.sqlite", "--where", sel]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "{sel}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

/// `reset` on a sweep with another axis (issue 50, 1): a point is named on any axis, an axis
/// left out matches every value of it, and a name that is not an axis is refused (ignoring it
/// put back points the user did not ask for).
#[test]
fn reset_puts_back_exactly_the_points_named_on_any_axis() {
    let dir = workdir("reset");
    write(&dir, "e0", "E0 = [2000, 2400]", "", 2.0);
    let run = cellsweep_in(
        &dir,
        &["run", "e0.toml", "--db", "r.sqlite", "--workers", "2"],
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let db = dir.join("r.sqlite");
    let done = || query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'done'");
    assert_eq!(done(), 12);
    // The point at E0 = 2400 only: 3 jobs at 1 point.
    let out = cellsweep_in(
        &dir,
        &[
            "reset",
            "--db",
            "r.sqlite",
            "--point",
            "alpha=0.1,beta=10,E0=2400",
        ],
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(said.contains("put back 3 jobs at 1 points"), "{said}");
    assert_eq!(done(), 9);
    // The same through a CSV of points.
    std::fs::write(dir.join("pts.csv"), "alpha,beta,E0\n0.12,10,2000\n").unwrap();
    let out = cellsweep_in(&dir, &["reset", "--db", "r.sqlite", "--points", "pts.csv"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("put back 3 jobs at 1 points"));
    assert_eq!(done(), 6);
    // A name that is not an axis, on the flag or as a column: refused, nothing changed.
    for args in [
        vec!["reset", "--db", "r.sqlite", "--point", "alpha=0.1,foo=3"],
        vec!["reset", "--db", "r.sqlite", "--points", "bad.csv"],
    ] {
        std::fs::write(dir.join("bad.csv"), "alpha,beta,foo\n0.1,10,1\n").unwrap();
        let out = cellsweep_in(&dir, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(
            err.contains(
                "\"foo\" is not an axis of the sweep (its axes: alpha, beta, L, sigma, E0)"
            ),
            "{err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert_eq!(done(), 6);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Diagrams on any two axes (issue 50): `table` and `plot` with `--x R0 --y beta --by xt,sigma`
/// over the committed collapse sweeps and the paper's R0 = 40 diagram (several `--data` read as
/// one; the paper's sweep fixes R0 and gains it as an axis) set cells of three sizes side by
/// side at each alpha~/L~; a cell that two points would share, an unknown axis, or one axis
/// twice is one line and a non-zero exit, with nothing written.
#[test]
fn diagrams_on_any_two_axes_from_the_collapse_exports() {
    let dir = workdir("plane");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let data = |f: &str| root.join(f).display().to_string();
    let (r32, r48, r40) = (
        data("data/collapse/R0-32.csv"),
        data("data/collapse/R0-48.csv"),
        data("data/paper/refined-L90-sigma5.csv"),
    );
    let plane = ["--x", "R0", "--y", "beta", "--by", "xt,sigma"];
    let mut args = vec!["table", "--data", &r32, "--data", &r48, "--data", &r40];
    args.extend(plane);
    let out = cellsweep_in(&dir, &args);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // alpha~/L~ = 2 pi d alpha R0^2 / L: R0 32 (alpha 0.125, L 72), 40 (alpha 0.10, L 90) and
    // 48 (alpha 0.0833, L 108) all sit at 49.95.
    let first = text.split("\n\n").next().unwrap();
    assert!(first.starts_with("xt = 49.95, sigma = 5"), "{text}");
    assert!(first.contains("beta \\ R0 |    32    40    48"), "{first}");
    // Each cell shows its point's label as the single sweep's own table gives it: R0 = 32 at
    // alpha 0.125 and 40 at alpha 0.10, beta 10 and 26.
    for (file, alpha, col) in [(&r32, 0.125, 0), (&r40, 0.1, 1)] {
        let one = cellsweep_in(&dir, &["table", "--data", file, "--format", "json"]);
        let points: serde_json::Value = serde_json::from_slice(&one.stdout).unwrap();
        for beta in [10.0, 26.0] {
            let p = points
                .as_array()
                .unwrap()
                .iter()
                .find(|p| p["alpha"] == alpha && p["beta"] == beta)
                .unwrap();
            let label: cellsweep_stats::Label = serde_json::from_value(p["label"].clone()).unwrap();
            let symbol = label.symbol();
            let row = first
                .lines()
                .find(|l| l.trim_start().starts_with(&format!("{beta} |")))
                .unwrap();
            let cells: Vec<&str> = row.split('|').nth(1).unwrap().split_whitespace().collect();
            assert_eq!(cells[col], symbol, "{file} beta {beta}: {row}");
        }
    }

    // plot writes one figure per alpha~/L~, the axis named R0.
    let pics = dir.join("pics");
    let mut args = vec![
        "plot", "--data", &r32, "--data", &r48, "--data", &r40, "--out",
    ];
    let pics_arg = pics.display().to_string();
    args.push(&pics_arg);
    args.extend(plane);
    let out = cellsweep_in(&dir, &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = std::fs::read_to_string(pics.join("plane-beta-R0-xt_49.95-sigma_5.svg")).unwrap();
    assert!(
        svg.contains(">R0<") && svg.contains("xt = 49.95"),
        "axis or title missing"
    );

    // Refusals: one line each, nothing written.
    let none = dir.join("none").display().to_string();
    for (extra, says) in [
        (vec!["--x", "R0", "--by", "sigma"], "add it to --by"),
        (vec!["--x", "E0"], "E0 is not an axis of these points"),
        (vec!["--x", "beta"], "--x and --y are both beta"),
    ] {
        for cmd in ["table", "plot"] {
            let mut args = vec![cmd, "--data", &r32];
            if cmd == "plot" {
                args.extend(["--out", &none]);
            }
            args.extend(extra.iter().copied());
            let out = cellsweep_in(&dir, &args);
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                !out.status.success() && err.contains(says),
                "{args:?}: {err}"
            );
            assert_eq!(err.trim().lines().count(), 1, "{err}");
        }
    }
    assert!(!dir.join("none").exists());
    // The same export twice would count every replicate twice: refused.
    let out = cellsweep_in(&dir, &["fit", "--data", &r32, "--data", &r32]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("would count twice"),
        "{err}"
    );
}

/// The report draws the planes a sweep asks for (`[report] planes` in sweeps/collapse/*.toml,
/// carried by their exports): beta against R0 at each alpha~/L~ of the collapse sweeps and
/// L~ = 2.25, with the paper's R0 = 40 columns beside them where both agree, and none of the
/// paper's columns that no asking sweep shares. A report of sweeps that ask for none has no
/// such section.
#[test]
fn the_report_draws_the_planes_the_collapse_sweeps_ask_for() {
    let dir = workdir("report-planes");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let data = |f: &str| root.join(f).display().to_string();
    let (collapse, r40) = (
        data("data/collapse"),
        data("data/paper/refined-L90-sigma5.csv"),
    );
    let out = cellsweep_in(
        &dir,
        &[
            "report", "--data", &collapse, "--data", &r40, "--out", "r.html",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(dir.join("r.html")).unwrap();
    let start = html.find("<h2 id=\"planes\">").expect("no planes section");
    let section = &html[start..];
    let section = &section[..section[4..].find("<h2").map_or(section.len(), |i| i + 4)];
    assert!(section.contains("<h3>beta against R0, one diagram per xt and Lt and sigma</h3>"));
    assert!(
        section.contains("Asked for by collapse-R0-32, collapse-R0-48."),
        "{}",
        &section[..600.min(section.len())]
    );
    let figures: Vec<&str> = section.split("<figure>").skip(1).collect();
    let captions: Vec<&str> = figures
        .iter()
        .map(|f| {
            let c = &f[f.find("<figcaption>").unwrap() + 12..];
            &c[..c.find("</figcaption>").unwrap()]
        })
        .collect();
    // alpha_40 = 0.10, 0.14, 0.18 at R0 = 40, L = 90 and the same alpha~/L~ at 32 and 48;
    // the paper's alpha 0.12, 0.16, 0.20 (59.95, 79.93, 99.91) have no collapse column.
    assert_eq!(
        captions,
        [
            "xt = 49.95, Lt = 2.25, sigma = 5",
            "xt = 69.94, Lt = 2.25, sigma = 5",
            "xt = 89.92, Lt = 2.25, sigma = 5"
        ]
    );
    for f in &figures {
        for r0 in [">32<", ">40<", ">48<", ">R0<"] {
            assert!(f.contains(r0), "{r0} missing from a figure");
        }
    }
    assert!(html.contains("<a href=\"#planes\">Other planes</a>"));
    // No sweep of the paper's asks for a plane: no section, no link.
    let out = cellsweep_in(&dir, &["report", "--data", &r40, "--out", "p.html"]);
    assert!(out.status.success());
    let html = std::fs::read_to_string(dir.join("p.html")).unwrap();
    assert!(!html.contains("id=\"planes\"") && !html.contains("#planes"));
}
