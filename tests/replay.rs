//! `cellsweep replay` and `cellsweep verify` as a user runs them: a stored replicate computed
//! again from its record comes out identical, with its movie; a tampered record is named field
//! by field; a record of another solver version is not compared; bad points get one line.

mod common;

use std::path::Path;

use common::{cellsweep_in, workdir};

/// The real model on small lattices, long enough collisions to end in an outcome.
fn write_sweep(dir: &Path) {
    std::fs::write(
        dir.join("s.toml"),
        "name = \"replayed\"\nseed = 5\nreplicates = 2\n[grid]\nalpha = [0.1]\nbeta = [10, 22]\nL = [48]\nsigma = [5]\n\
         [params]\nR0 = 24\n[protocol]\nsingle_lattice = [96, 96]\nrelax_time = 5\nfree_time = 10\ncollide_time = 30\n",
    )
    .unwrap();
}

fn text(out: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

#[test]
fn a_stored_replicate_replays_identically_from_a_store_and_from_its_export_with_its_movie() {
    let dir = workdir("identical");
    write_sweep(&dir);
    let run = cellsweep_in(
        &dir,
        &["run", "s.toml", "--db", "r.sqlite", "--workers", "2"],
    );
    assert!(run.status.success(), "{}", text(&run));
    let export = cellsweep_in(&dir, &["export", "--db", "r.sqlite", "--out", "r.csv"]);
    assert!(export.status.success(), "{}", text(&export));

    for source in [["--db", "r.sqlite"], ["--data", "r.csv"]] {
        let mut args = vec!["replay", source[0], source[1]];
        args.extend(["--point", "alpha=0.1,beta=22", "--replicate", "1"]);
        let out = cellsweep_in(&dir, &args);
        let said = text(&out);
        assert!(out.status.success(), "{said}");
        assert_eq!(
            said.lines().filter(|l| *l == "identical").count(),
            1,
            "{said}"
        );
    }
    // Its movie and its observables.
    let out = cellsweep_in(
        &dir,
        &[
            "replay",
            "--data",
            "r.csv",
            "--point",
            "beta=10,alpha=0.1",
            "--replicate",
            "0",
            "--frames",
            "movie",
            "--frame-every",
            "5",
            "--track",
            "track.jsonl",
        ],
    );
    // The movie runs on past the decision to show it; the replay still compares the steps
    // the record counts (it said "differs: collision_steps" before).
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    assert!(said.lines().any(|l| l == "identical"), "{said}");
    let frames: Vec<String> = std::fs::read_dir(dir.join("movie"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(frames.iter().any(|f| f.ends_with(".gif")), "{frames:?}");
    assert!(
        frames.iter().filter(|f| f.ends_with(".png")).count() >= 3,
        "{frames:?}"
    );
    let track = std::fs::read_to_string(dir.join("track.jsonl")).unwrap();
    assert!(track.lines().count() >= 10);
    serde_json::from_str::<serde_json::Value>(track.lines().next().unwrap()).unwrap();

    // verify --all: every row identical.
    let v = cellsweep_in(&dir, &["verify", "--data", "r.csv", "--all"]);
    let said = text(&v);
    assert!(v.status.success(), "{said}");
    assert!(
        said.contains("4 identical, 0 identical to round-off in a speed, 0 differ, 0 of another solver version"),
        "{said}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The sweep run and exported into `dir/r.csv`: the export's text and its header's line.
fn exported(dir: &Path) -> (String, usize) {
    write_sweep(dir);
    let run: &[&str] = &["run", "s.toml", "--db", "r.sqlite"];
    let export: &[&str] = &["export", "--db", "r.sqlite", "--out", "r.csv"];
    for args in [run, export] {
        let out = cellsweep_in(dir, args);
        assert!(out.status.success(), "{}", text(&out));
    }
    let original = std::fs::read_to_string(dir.join("r.csv")).unwrap();
    let header_at = original
        .lines()
        .position(|l| l.starts_with("sweep,"))
        .unwrap();
    (original, header_at)
}

#[test]
fn a_tampered_row_is_named_field_by_field_and_another_version_is_not_compared() {
    let dir = workdir("tampered");
    let (original, header_at) = exported(&dir);
    let header: Vec<&str> = original
        .lines()
        .nth(header_at)
        .unwrap()
        .split(',')
        .collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // Row 1 (alpha 0.1, beta 10, replicate 1) with one more collision step.
    let tamper = |field: &str, f: &dyn Fn(&str) -> String| -> String {
        let mut lines: Vec<String> = original.lines().map(String::from).collect();
        let row = &mut lines[header_at + 2];
        let mut cells: Vec<String> = row.split(',').map(String::from).collect();
        let c = col(field);
        cells[c] = f(&cells[c]);
        *row = cells.join(",");
        lines.join("\n") + "\n"
    };
    std::fs::write(
        dir.join("steps.csv"),
        tamper("collision_steps", &|v| {
            (v.parse::<i64>().unwrap() + 1).to_string()
        }),
    )
    .unwrap();
    let out = cellsweep_in(
        &dir,
        &[
            "replay",
            "--data",
            "steps.csv",
            "--point",
            "alpha=0.1,beta=10",
            "--replicate",
            "1",
        ],
    );
    let said = text(&out);
    assert_eq!(out.status.code(), Some(1), "{said}");
    assert!(said.contains("differs: collision_steps: stored"), "{said}");
    assert!(!said.contains("\nidentical"), "{said}");
    // verify counts it.
    let v = cellsweep_in(&dir, &["verify", "--data", "steps.csv", "--all"]);
    assert_eq!(v.status.code(), Some(1));
    assert!(
        text(&v).contains("3 identical, 0 identical to round-off in a speed, 1 differ"),
        "{}",
        text(&v)
    );

    // A free speed one ulp off (as rows stored before floats crossed JSON exactly): round-off.
    std::fs::write(
        dir.join("ulp.csv"),
        tamper("free_speed", &|v| {
            let x: f64 = v.parse().unwrap();
            format!("{:?}", f64::from_bits(x.to_bits() + 1))
        }),
    )
    .unwrap();
    let out = cellsweep_in(
        &dir,
        &[
            "replay",
            "--data",
            "ulp.csv",
            "--point",
            "alpha=0.1,beta=10",
            "--replicate",
            "1",
        ],
    );
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    assert!(
        said.contains("round-off: free_speed: stored") && said.contains("identical to round-off"),
        "{said}"
    );

    std::fs::write(
        dir.join("version.csv"),
        tamper("solver_version", &|_| "cellsweep-solver 0.0.1".to_string()),
    )
    .unwrap();
    let out = cellsweep_in(
        &dir,
        &[
            "replay",
            "--data",
            "version.csv",
            "--point",
            "alpha=0.1,beta=10",
            "--replicate",
            "1",
        ],
    );
    let said = text(&out);
    if out.status.code() == Some(2) {
        assert!(
            said.contains("not compared: recorded by solver cellsweep-solver 0.0.1"),
            "{said}"
        );
    } else {
        // An export whose rows disagree on their version is refused as a whole: also fine,
        // as long as it says so in one line and nothing is compared.
        assert!(!out.status.success(), "{said}");
        assert!(!said.contains("identical"), "{said}");
    }

    // Points that are not one point: one line each, non-zero.
    for (point, words) in [
        (
            "alpha=0.1,foo=3",
            "\"foo\" is not an axis of sweep \"replayed\"",
        ),
        ("alpha=0.1", "matches 2 points"),
        ("alpha=0.3,beta=10", "no finished replicate"),
        ("alpha=nan", "not a finite number"),
    ] {
        let out = cellsweep_in(
            &dir,
            &[
                "replay",
                "--data",
                "r.csv",
                "--point",
                point,
                "--replicate",
                "0",
            ],
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(err.contains(words), "{point}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    let out = cellsweep_in(
        &dir,
        &[
            "replay",
            "--data",
            "r.csv",
            "--point",
            "alpha=0.1,beta=10",
            "--replicate",
            "7",
        ],
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("replicate 7 has no result"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A row of the committed paper data: a prep the paper's L = 90 diagram found unstable,
/// recomputed from its seed with the paper's lattices, gives the same verdict, free speed
/// and prep hash.
#[test]
fn a_replicate_of_the_committed_paper_data_replays_identically() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let data = root.join("data/paper/refined-L90-sigma5.csv");
    let out = cellsweep_in(
        root,
        &[
            "replay",
            "--data",
            data.to_str().unwrap(),
            "--point",
            "alpha=0.1,beta=30",
            "--replicate",
            "0",
            "--parallel",
        ],
    );
    let said = text(&out);
    assert!(out.status.success(), "{said}");
    assert!(said.contains("stored   unstable"), "{said}");
    assert!(said.lines().any(|l| l == "identical"), "{said}");
}

/// Import checks a row's speeds against the prep it recomputes (issue 50, 3): a free speed the
/// prep does not have, or a threshold the classifier would not give for it, is refused with
/// the store as it was.
#[test]
fn import_refuses_speeds_that_contradict_the_prep_it_recomputes() {
    let dir = workdir("import-speeds");
    let (original, header_at) = exported(&dir);
    let header: Vec<&str> = original
        .lines()
        .nth(header_at)
        .unwrap()
        .split(',')
        .collect();
    for (field, value, words) in [
        ("free_speed", "0.1", "free_speed 0.1 contradicts its prep's"),
        (
            "threshold_speed",
            "0.2",
            "threshold_speed 0.2 contradicts the classifier's",
        ),
    ] {
        let c = header.iter().position(|h| *h == field).unwrap();
        let mut lines: Vec<String> = original.lines().map(String::from).collect();
        let mut cells: Vec<String> = lines[header_at + 1].split(',').map(String::from).collect();
        cells[c] = value.to_string();
        lines[header_at + 1] = cells.join(",");
        std::fs::write(dir.join("bad.csv"), lines.join("\n") + "\n").unwrap();
        let db = format!("fresh-{field}.sqlite");
        let out = cellsweep_in(&dir, &["import", "bad.csv", "--db", &db]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{field}: {}", text(&out));
        assert!(err.contains(words), "{err}");
        let rows = rusqlite::Connection::open(dir.join(&db))
            .ok()
            .and_then(|c| {
                c.query_row("SELECT COUNT(*) FROM results", [], |r| r.get::<_, i64>(0))
                    .ok()
            })
            .unwrap_or(0);
        assert_eq!(rows, 0, "nothing imported");
    }
    // Speeds one ulp off (another machine sums the prep's trajectory in another order) are
    // round-off, not a contradiction: the file imports.
    let c = header.iter().position(|h| *h == "free_speed").unwrap();
    let nudged: Vec<String> = original
        .lines()
        .enumerate()
        .map(|(i, line)| {
            let mut cells: Vec<String> = line.split(',').map(String::from).collect();
            if i > header_at {
                if let Ok(v) = cells[c].parse::<f64>() {
                    cells[c] = f64::from_bits(v.to_bits() + 1).to_string();
                }
            }
            cells.join(",")
        })
        .collect();
    std::fs::write(dir.join("ulp.csv"), nudged.join("\n") + "\n").unwrap();
    let out = cellsweep_in(&dir, &["import", "ulp.csv", "--db", "ulp.sqlite"]);
    assert!(out.status.success(), "{}", text(&out));
    // The untouched export imports.
    let out = cellsweep_in(&dir, &["import", "r.csv", "--db", "good.sqlite"]);
    assert!(out.status.success(), "{}", text(&out));
    std::fs::remove_dir_all(&dir).unwrap();
}
