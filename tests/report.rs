//! `cellsweep report`: one self-contained HTML page, from a store or from exports, checked in
//! a real headless browser (Debian's chromium; `.ci/run` installs it).

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::browser::browser;
use common::{cellsweep, workdir, write_sweep};

fn ok(out: &Output) -> String {
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// A page that loads nothing from anywhere: no script, no external reference of any kind.
fn assert_self_contained(html: &str) {
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.trim_end().ends_with("</html>"));
    for bad in ["<script", "src=", "<link", "url(", "@import", "<iframe"] {
        assert!(!html.contains(bad), "the report contains {bad:?}");
    }
    // Every http(s) address is an SVG namespace, not something to fetch.
    for (i, _) in html.match_indices("http") {
        let rest = &html[i..];
        assert!(
            rest.starts_with("http://www.w3.org/2000/svg"),
            "an address in the report: {}",
            &rest[..rest.len().min(60)]
        );
    }
}

/// Load `page` headless: (the DOM it built, the console messages it logged, a screenshot).
fn load(browser: &Path, page: &Path, shot: &Path) -> (String, Vec<String>) {
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    let common = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
        "--enable-logging=stderr",
        "--v=0",
    ];
    let dom = Command::new(browser)
        .args(common)
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .unwrap();
    assert!(
        dom.status.success(),
        "{}",
        String::from_utf8_lossy(&dom.stderr)
    );
    let console: Vec<String> = String::from_utf8_lossy(&dom.stderr)
        .lines()
        .filter(|l| l.contains("CONSOLE"))
        .map(String::from)
        .collect();
    let out = Command::new(browser)
        .args(common)
        .arg("--window-size=1400,4000")
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (String::from_utf8_lossy(&dom.stdout).to_string(), console)
}

#[test]
fn the_report_of_the_committed_data_is_self_contained_and_loads_clean_in_a_browser() {
    let dir = workdir("data");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/paper");
    // A folder whose name is markup and a shell substitution: shown as text, never as markup.
    let odd = dir.join("d'<b>$(touch x)\"");
    std::fs::create_dir_all(&odd).unwrap();
    for f in std::fs::read_dir(&data).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, odd.join(f.file_name().unwrap())).unwrap();
    }
    let page = dir.join("report.html");
    let text = ok(&cellsweep(&[
        "report",
        "--data",
        odd.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]));
    assert!(text.contains("adaptive-L90-sigma5"), "{text}");
    let html = std::fs::read_to_string(&page).unwrap();
    assert_self_contained(&html);
    assert!(!html.contains("<b>$(touch"), "an unescaped folder name");
    assert!(html.contains("d&#39;&lt;b&gt;$(touch x)&quot;"));
    assert!(!dir.join("x").exists());
    // The collapse test: every shown diagram's columns at their alpha~/L~, a tooltip each.
    assert!(html.contains("One line in α̃/L̃?"));
    for (l, sigma) in [(90, 5), (80, 5), (70, 5), (90, 0), (80, 0), (70, 0)] {
        let tip = format!("<title>R0 = 40, L = {l}, σ = {sigma}, α = ");
        assert!(
            html.contains(&tip),
            "the collapse figure lacks L = {l}, sigma = {sigma}"
        );
    }
    // Folders add up: a second --data brings its sweeps in beside the first's.
    let extra = dir.join("extra");
    std::fs::create_dir_all(&extra).unwrap();
    let check =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/checks/check-breakup-wide-column.csv");
    std::fs::copy(&check, extra.join("check-breakup-wide-column.csv")).unwrap();
    let both = ok(&cellsweep(&[
        "report",
        "--data",
        odd.to_str().unwrap(),
        "--data",
        extra.to_str().unwrap(),
        "--out",
        dir.join("both.html").to_str().unwrap(),
    ]));
    let files = std::fs::read_dir(&data).unwrap().count() + 1;
    assert!(
        both.contains(&format!("({files} result sets of ")),
        "{both}"
    );
    assert!(both.contains("check-breakup-wide-column"), "{both}");
    // And a file is read as itself.
    let one = ok(&cellsweep(&[
        "report",
        "--data",
        check.to_str().unwrap(),
        "--out",
        dir.join("one.html").to_str().unwrap(),
    ]));
    assert!(
        one.contains("(1 result set of 1 sweep: check-breakup-wide-column)"),
        "{one}"
    );
    // What a reader needs: the claims with verdicts, the fit beside the paper's, the diagram
    // drawn inline, and where every number came from.
    for need in [
        "The paper's claims",
        "almost always form a train",
        "class=\"verdict reproduced\"",
        "a = 0.6, b = −12",
        "β* per column",
        "<svg xmlns=\"http://www.w3.org/2000/svg\"",
        "(a) outcome",
        "Provenance",
        "cellsweep-solver",
        "Precision and cost",
        "<b>The shift from σ = 5 to σ = 0</b>",
        "<b>Column by column</b>",
        "<th>δ_c [95%]</th>",
    ] {
        assert!(html.contains(need), "the report lacks {need:?}");
    }
    // Each of the six diagrams is shown once, from its sweep's largest export (a refined one
    // over the adaptive run it grew from), and its cost set against the paper's fixed grid of
    // 66 points x 96 replicates.
    let cost = html
        .split("id=\"cost\"")
        .nth(1)
        .and_then(|t| t.split("</table>").next())
        .expect("a cost table");
    assert!(cost.contains("<td class=\"num\">38016</td>"), "{cost}");
    assert_eq!(
        cost.matches("<td class=\"num\">6336</td>").count(),
        6,
        "{cost}"
    );
    // Each of the paper's diagrams is drawn, or (not in the data yet) named with the command
    // that makes it.
    for (l, sigma) in [(90, 5), (80, 5), (70, 5), (90, 0), (80, 0), (70, 0)] {
        let exported = data
            .join(format!("adaptive-L{l}-sigma{sigma}.csv"))
            .exists();
        let command = format!("cellsweep run sweeps/adaptive/L{l}-sigma{sigma}.toml");
        assert_eq!(
            html.contains(&command),
            !exported,
            "L = {l}, sigma = {sigma}"
        );
    }
    let b = browser().unwrap_or_else(|e| panic!("{e}"));
    let shot = dir.join("report.png");
    let (dom, console) = load(&b, &page, &shot);
    assert!(console.is_empty(), "console messages: {console:#?}");
    assert!(
        dom.contains("The paper's claims"),
        "the browser built no page"
    );
    assert!(
        dom.contains("<svg") && dom.contains("(a) outcome"),
        "the figures did not load"
    );
    let png = std::fs::read(&shot).unwrap();
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 50_000,
        "{} bytes",
        png.len()
    );

    // The console check can fail: a page that logs an error is caught.
    let bad = dir.join("bad.html");
    std::fs::write(
        &bad,
        "<!DOCTYPE html><html><body><script>console.error('broken')</script></body></html>",
    )
    .unwrap();
    let (_, console) = load(&b, &bad, &dir.join("bad.png"));
    assert!(
        console.iter().any(|l| l.contains("broken")),
        "the browser's console is not seen: {console:?}"
    );
}

#[test]
fn the_report_of_a_store_shows_its_diagrams_costs_and_refuses_bad_sources() {
    let dir = workdir("store");
    let sweep = write_sweep(&dir, "rep", 2, "");
    let db = dir.join("r.sqlite");
    ok(&cellsweep(&[
        "run",
        sweep.to_str().unwrap(),
        "--db",
        db.to_str().unwrap(),
        "--workers",
        "2",
    ]));
    let page = dir.join("r.html");
    ok(&cellsweep(&[
        "report",
        "--db",
        db.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]));
    let html = std::fs::read_to_string(&page).unwrap();
    assert_self_contained(&html);
    // Its diagrams are not the paper's: drawn apart, the paper's six named as not run.
    assert!(
        html.contains("L = 48, σ = 5 (not one of the paper's)"),
        "{html}"
    );
    assert!(html.contains("L = 48, σ = 0 (not one of the paper's)"));
    assert!(
        html.contains("Not run yet: <code>cellsweep run sweeps/adaptive/L90-sigma5.toml</code>")
    );
    assert!(html.contains("no data yet"));
    // Provenance: the sweep, its 8 replicates and their recorded core-hours.
    let row = html
        .lines()
        .find(|l| l.starts_with("<tr><td>rep</td>"))
        .expect("a provenance row for the sweep");
    assert!(row.contains("<td class=\"num\">8</td>"), "{row}");
    let hours: f64 = row
        .split("<td class=\"num\">")
        .nth(4)
        .and_then(|c| c.split('<').next())
        .and_then(|c| c.parse().ok())
        .expect("core-hours");
    assert!(hours > 0.0, "{row}");

    // Bad sources: one line naming the problem, non-zero exit, no page written.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    std::fs::write(empty.join("notes.txt"), "x").unwrap();
    let junk = dir.join("junk");
    std::fs::create_dir_all(&junk).unwrap();
    std::fs::write(junk.join("a.csv"), "alpha,beta\n0.1,10\n").unwrap();
    let out = dir.join("never.html");
    for (args, says) in [
        (vec!["--data", empty.to_str().unwrap()], "no export files"),
        (
            vec!["--data", junk.to_str().unwrap()],
            "a.csv: line 1: not a cellsweep export",
        ),
        (
            vec!["--data", "/no/such/dir"],
            "cannot read the folder /no/such/dir",
        ),
        (vec!["--db", "/no/such.sqlite"], "/no/such.sqlite"),
    ] {
        let mut a = vec!["report"];
        a.extend(args);
        a.extend(["--out", out.to_str().unwrap()]);
        let r = cellsweep(&a);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{a:?}");
        assert!(err.contains(says), "{a:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{a:?}: {err}");
        assert!(!err.contains("panicked"));
        assert!(!out.exists());
    }
    // An --out that is a folder is refused, and nothing is left beside it.
    let r = cellsweep(&[
        "report",
        "--db",
        db.to_str().unwrap(),
        "--out",
        empty.to_str().unwrap(),
    ]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stderr).contains("is a folder"));
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// "Is it converged?" (issue 48, 4): variants of the numerics passed with --variants are
/// compared column by column with the shown diagram, as `cellsweep converge` compares them,
/// and are never shown as diagrams themselves.
#[test]
fn the_report_compares_variants_of_the_numerics_with_the_shown_columns() {
    let dir = workdir("variants");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let base = root.join("data/paper/refined-L70-sigma5.csv");
    let variant = root.join("data/convergence/conv-dt-half-L70-sigma5.csv");
    let page = dir.join("r.html");
    let (b, v, p) = (
        base.to_str().unwrap(),
        variant.to_str().unwrap(),
        page.to_str().unwrap(),
    );
    ok(&cellsweep(&[
        "report",
        "--data",
        b,
        "--variants",
        v,
        "--out",
        p,
    ]));
    let html = std::fs::read_to_string(&page).unwrap();
    assert_self_contained(&html);
    let section = &html[html.find("id=\"converged\"").unwrap()..];
    let section = &section[..section.find("<h2").unwrap_or(section.len())];
    let row = section
        .lines()
        .find(|l| l.starts_with("<tr><td>conv-dt-half-L70-sigma5</td>"))
        .unwrap_or_else(|| panic!("no row for the variant: {section}"));
    // The same column both sides, with a verdict the difference's interval gives.
    assert!(
        row.contains("<td class=\"num\">70</td><td class=\"num\">5</td><td class=\"num\">0.1</td>"),
        "{row}"
    );
    let converge = cellsweep(&[
        "converge",
        "--baseline",
        b,
        "--variant",
        v,
        "--format",
        "csv",
    ]);
    let csv = ok(&converge);
    let line = csv.lines().find(|l| l.contains(",70,5,0.1,")).unwrap();
    let verdict = line.rsplit(',').next().unwrap();
    assert!(
        row.contains(&format!(" {verdict}</span>")),
        "{row} against {line}"
    );
    // The variant is not a diagram of the page.
    assert!(
        !html.contains("conv-dt-half-L70-sigma5: L = 70"),
        "shown as a diagram"
    );
    // Without variants the section says how to get them.
    ok(&cellsweep(&["report", "--data", b, "--out", p]));
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("No variant is loaded"));
}
