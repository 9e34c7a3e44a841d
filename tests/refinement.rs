//! Refinement (SPEC section 6; a sweep's `[refine]`): rounds that add beta values where each
//! column's crossing lies, through the ledger in a world whose crossing is known
//! ([`common::world`]), and through the local engine, export and import.

mod common;

use std::collections::BTreeSet;

use cellsweep_scheduler::{plan, Ledger, Sweep};
use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_stats::refine::{plan_round, ColumnNeed};
use cellsweep_stats::PointEnds;
use common::world::{added, beta_star, drive, open, rows, store_at, sweep_text, STEP};

#[test]
fn rounds_add_values_inside_the_interval_until_narrow_or_spent_and_match_a_fixed_sweep() {
    let text = sweep_text("refined", "{ from = 10, to = 30, step = 4 }", true);
    let sweep = Sweep::parse(&text, "refined.toml").unwrap();
    let (_store_dir, mut store) = store_at("rounds");
    let ledger = open(&mut store, &sweep);
    drive(&mut store, &ledger, false, usize::MAX);

    // Every added value: on the step lattice, between the grid's betas, not on the grid, at
    // most 6 a column, and each with its 40 replicates.
    let points = ledger.points(&store).unwrap();
    assert_eq!(&points[..12], &sweep.points()[..], "the grid comes first");
    let extra: Vec<&Params> = points[12..].iter().collect();
    assert!(!extra.is_empty(), "no value added");
    for alpha in [0.1, 0.12] {
        let betas: Vec<f64> = extra
            .iter()
            .filter(|p| p.alpha == alpha)
            .map(|p| p.beta)
            .collect();
        assert!(!betas.is_empty() && betas.len() <= 6, "{alpha}: {betas:?}");
        for b in &betas {
            assert_eq!((b / STEP).round() * STEP, *b);
            assert!(*b > 10.0 && *b < 30.0 && !sweep.grid.beta.contains(b));
            // Near the true crossing (inside the intervals of the rounds that added it).
            assert!((b - beta_star(alpha)).abs() < 3.0, "{alpha}: {b}");
        }
    }
    assert_eq!(
        store
            .jobs_per_point(ledger.sweep_id, SOLVER_VERSION)
            .unwrap()
            .iter()
            .map(|j| (j.jobs, j.open))
            .collect::<Vec<_>>(),
        vec![(40, 0); points.len()]
    );
    // No column wants more: each is narrow, out of budget or out of lattice.
    let ends = ledger.point_ends(&store).unwrap();
    let counts: Vec<_> = ends
        .iter()
        .map(|e: &PointEnds| e.counts(u32::MAX))
        .collect();
    let rule = sweep.refine.unwrap();
    let betas_added = |key: &cellsweep_stats::ColumnKey| {
        extra
            .iter()
            .filter(|p| sweep.axes_of(p).column() == *key)
            .count() as u32
    };
    for c in plan_round(&counts, &rule, &betas_added) {
        assert!(
            matches!(
                c.need,
                ColumnNeed::Narrow { .. } | ColumnNeed::Budget { .. } | ColumnNeed::Lattice { .. }
            ),
            "{c:?}"
        );
    }

    // A fixed sweep listing the grid and every added value stores the very same rows there.
    let mut listed: Vec<f64> = sweep.grid.beta.clone();
    listed.extend(extra.iter().map(|p| p.beta));
    listed.sort_by(f64::total_cmp);
    listed.dedup();
    let list = format!(
        "[{}]",
        listed
            .iter()
            .map(|b| b.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let fixed = Sweep::parse(&sweep_text("refined", &list, false), "fixed.toml").unwrap();
    let (_fixed_store_dir, mut fixed_store) = store_at("fixed");
    let fixed_ledger = open(&mut fixed_store, &fixed);
    drive(&mut fixed_store, &fixed_ledger, false, usize::MAX);
    let wanted: BTreeSet<(u64, u64)> = points
        .iter()
        .map(|p| (p.alpha.to_bits(), p.beta.to_bits()))
        .collect();
    let fixed_rows: Vec<String> = rows(&fixed_store, &fixed_ledger)
        .into_iter()
        .filter(|r| {
            wanted.iter().any(|(a, b)| {
                r.contains(&format!(
                    "alpha: {:?}, beta: {:?},",
                    f64::from_bits(*a),
                    f64::from_bits(*b)
                ))
            })
        })
        .collect();
    assert_eq!(rows(&store, &ledger), fixed_rows);
}

#[test]
fn a_killed_refinement_resumes_and_the_order_of_results_changes_nothing() {
    let text = sweep_text("resumed", "{ from = 10, to = 30, step = 4 }", true);
    let sweep = Sweep::parse(&text, "resumed.toml").unwrap();

    let (_straight_dir, mut straight) = store_at("straight");
    let l1 = open(&mut straight, &sweep);
    drive(&mut straight, &l1, false, usize::MAX);

    // Results in the reverse order, killed twice: once between results, once with a job
    // claimed and never answered (left running). Each restart reopens the ledger as a run does.
    let (_killed_dir, mut killed) = store_at("killed");
    let l2 = open(&mut killed, &sweep);
    drive(&mut killed, &l2, true, 500);
    let l2 = open(&mut killed, &sweep);
    killed
        .materialize_next(l2.sweep_id, SOLVER_VERSION, 1)
        .unwrap();
    let job = killed.pending_jobs(l2.sweep_id, SOLVER_VERSION).unwrap()[0].clone();
    killed.claim_job(job.id).unwrap();
    drop(l2);
    let (l2, opening) = {
        let reg = killed.register(&plan(&sweep, "test"), false).unwrap();
        Ledger::open(&mut killed, reg.sweep_id, SOLVER_VERSION, 3).unwrap()
    };
    assert_eq!(opening.recovered, 1);
    drive(&mut killed, &l2, true, usize::MAX);

    assert_eq!(added(&l1, &straight), added(&l2, &killed));
    assert_eq!(rows(&straight, &l1), rows(&killed, &l2));
}

#[test]
fn a_run_goes_on_with_the_rounds_of_an_imported_refined_sweep_and_its_export_reads_back() {
    let dir = common::workdir("engine");
    let (toml, csv) = common::world::refined_export(&dir, "engine");
    let (toml, csv) = (toml.to_str().unwrap(), csv.to_str().unwrap());
    let import = common::cellsweep_in(&dir, &["import", csv, "--db", "r.sqlite"]);
    assert!(
        import.status.success(),
        "{}",
        String::from_utf8_lossy(&import.stderr)
    );
    let db = dir.join("r.sqlite");
    assert_eq!(common::query(&db, "SELECT COUNT(*) FROM points"), 12);

    // The dry run says what the next round adds, column by column, and what it costs.
    let dry = common::cellsweep_in(&dir, &["run", toml, "--db", "r.sqlite", "--dry-run"]);
    let said = String::from_utf8_lossy(&dry.stdout);
    assert!(dry.status.success(), "{said}");
    assert!(
        said.contains("refine now: ") && said.contains("the next round of refinement: "),
        "{said}"
    );
    for alpha in ["0.1", "0.12"] {
        assert!(
            said.contains(&format!("alpha = {alpha}, L = 48, sigma = 5: beta ")),
            "{said}"
        );
    }
    assert_eq!(common::query(&db, "SELECT COUNT(*) FROM points"), 12);

    // The run plans each column's values from the imported crossings and runs them. Its own
    // 2 tau0 collisions end undetermined, which tells the model nothing: rounds go on until
    // the column's budget (or lattice) is spent.
    let run = common::cellsweep_in(&dir, &["run", toml, "--db", "r.sqlite", "--workers", "2"]);
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(text.contains("refine"), "{text}");
    let added = common::query(&db, "SELECT COUNT(*) FROM points") - 12;
    // Its progress lines count the added points; the last has them all.
    let last = text.lines().rfind(|l| l.starts_with("progress: "));
    assert!(
        last.is_some_and(|l| l.contains(&format!("refined +{added} betas"))),
        "{text}"
    );
    assert!(added >= 2, "{added} points added\n{text}");
    for alpha in [0.1, 0.12] {
        let n = common::query(
            &db,
            &format!(
                "SELECT COUNT(*) FROM points WHERE alpha = {alpha} AND beta NOT IN (10, 14, 18, 22, 26, 30)"
            ),
        );
        assert!(n <= 6, "alpha {alpha}: {n} added");
    }
    assert_eq!(
        common::query(&db, "SELECT COUNT(*) FROM jobs WHERE state != 'done'"),
        0
    );
    assert_eq!(
        common::query(&db, "SELECT COUNT(*) FROM jobs"),
        (12 + added) * 40
    );
    // Nothing is owed: a second run has nothing to do and adds nothing.
    let again = common::cellsweep_in(&dir, &["run", toml, "--db", "r.sqlite"]);
    assert!(again.status.success());
    assert_eq!(
        common::query(&db, "SELECT COUNT(*) FROM points") - 12,
        added
    );

    // Its export carries the added points through import into a fresh store, row for row,
    // and every reader takes the uneven column.
    let out = common::cellsweep_in(&dir, &["export", "--db", "r.sqlite", "--out", "all.csv"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let back = common::cellsweep_in(&dir, &["import", "all.csv", "--db", "b.sqlite"]);
    assert!(
        back.status.success(),
        "{}",
        String::from_utf8_lossy(&back.stderr)
    );
    let again = common::cellsweep_in(&dir, &["export", "--db", "b.sqlite", "--out", "back.csv"]);
    assert!(again.status.success());
    assert_eq!(
        export_rows(&dir.join("all.csv")),
        export_rows(&dir.join("back.csv"))
    );
    // Status tells where refinement stands: every column finished, each at its budget or
    // lattice (its 2 tau0 collisions decide nothing), nothing more to add.
    let status = common::cellsweep_in(&dir, &["status", "--db", "r.sqlite"]);
    let said = String::from_utf8_lossy(&status.stdout);
    assert!(
        said.contains(&format!("refine   {added} beta values added"))
            && said.contains("next round: 0 values in 0 columns now"),
        "{said}"
    );
    for args in [
        vec!["table", "--data", "all.csv"],
        vec!["fit", "--data", "all.csv", "--format", "json"],
        vec!["plot", "--data", "all.csv", "--out", "figs"],
        vec!["status", "--db", "r.sqlite"],
    ] {
        let o = common::cellsweep_in(&dir, &args);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    // What the export says it cost: the grid's 12 points and the added ones apart, row for
    // row, and the same read from the store.
    let from_export = cellsweep_report::load::from_export(&dir.join("all.csv")).unwrap();
    let from_store = cellsweep_report::load::from_store(&db, None).unwrap();
    for p in [from_export.provenance, from_store.provenance] {
        let p = p.expect("a provenance");
        assert_eq!((p.grid_points, p.added_points), (12, added as u64));
        assert_eq!(p.grid.rows, 12 * 40);
        assert_eq!(p.added.rows, added as u64 * 40);
        assert_eq!(p.fixed_grid_replicates(), 12 * 40);
        assert!(
            p.added.collision_s > 0.0 && p.grid.collision_s > 0.0,
            "{p:?}"
        );
        assert_eq!(p.refine, sweep_refine(toml));
    }
    // A row at a point no refinement of this sweep could add is refused by import.
    let text = std::fs::read_to_string(dir.join("all.csv")).unwrap();
    let forged = text.replacen("\nengine,0.1,10.0,", "\nengine,0.1,10.25,", 1);
    assert_ne!(forged, text);
    std::fs::write(dir.join("forged.csv"), forged).unwrap();
    let o = common::cellsweep_in(&dir, &["import", "forged.csv", "--db", "f.sqlite"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("not on the refinement's step"), "{err}");
    assert!(!dir.join("f.sqlite").exists());
}

/// The committed refinement of the paper's L = 70, sigma = 5 diagram, against a fixed sweep
/// that lists two of the beta values refinement added (at alpha = 0.14, on the 0.125 lattice)
/// and nothing else: the real model at full size, so the rows must agree field for field
/// (but the sweep's name and wall times), trajectories and all. Two replicates per point keep
/// it to four collisions.
#[test]
fn the_paper_refinement_stores_the_rows_a_fixed_sweep_listing_its_added_betas_stores() {
    let dir = common::workdir("paper");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let refined = root.join("data/paper/refined-L70-sigma5.csv");
    let toml = std::fs::read_to_string(root.join("sweeps/refined/L70-sigma5.toml")).unwrap();
    let (betas, alpha) = (["42.125", "42.375"], "0.14");
    // The same sweep file with another name, a fixed grid of the two values, no rounds.
    let head = toml.split("[grid]").next().unwrap();
    let protocol = toml.split("[protocol]").nth(1).unwrap();
    let protocol = protocol.split("[adaptive]").next().unwrap();
    let fixed = head
        .replace("name = \"adaptive-L70-sigma5\"", "name = \"fixed\"")
        .replace("replicates = 96", "replicates = 2")
        + &format!(
            "[grid]\nalpha = [{alpha}]\nbeta = [{}]\nL = [70]\nsigma = [5]\n[protocol]{protocol}",
            betas.join(", ")
        );
    assert!(fixed.contains("name = \"fixed\"") && fixed.contains("replicates = 2"));
    std::fs::write(dir.join("fixed.toml"), &fixed).unwrap();
    let run = common::cellsweep_in(
        &dir,
        &["run", "fixed.toml", "--db", "f.sqlite", "--workers", "2"],
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = common::cellsweep_in(&dir, &["export", "--db", "f.sqlite", "--out", "f.csv"]);
    assert!(out.status.success());

    // Both files' rows at those points and replicates, without the sweep's name.
    let pick = |path: &std::path::Path| -> Vec<Vec<String>> {
        let (head, rows) = export_table(path);
        assert_eq!(
            head[..7],
            [
                "sweep",
                "alpha",
                "beta",
                "L",
                "sigma",
                "params",
                "replicate"
            ]
        );
        rows.into_iter()
            .filter(|r| {
                r[1] == alpha && betas.contains(&r[2].as_str()) && (r[6] == "0" || r[6] == "1")
            })
            .map(|r| r[1..].to_vec())
            .collect()
    };
    let (mut ours, mut committed) = (pick(&dir.join("f.csv")), pick(&refined));
    assert_eq!(ours.len(), 4, "{ours:?}");
    // The columns both files have (a newer export format appends its new columns).
    let shared = ours[0].len().min(committed[0].len());
    for r in ours.iter_mut().chain(committed.iter_mut()) {
        r.truncate(shared);
    }
    // The speeds to round-off, the rest exactly: the committed rows were stored before JSON
    // carried floats exactly between processes (serde_json's float_roundtrip), and some of
    // their free and threshold speeds are one ulp off the value the worker computed.
    let (head, _) = export_table(&refined);
    let speeds: Vec<usize> = ["free_speed", "threshold_speed"]
        .iter()
        .map(|h| head.iter().position(|x| x == h).unwrap() - 1)
        .collect();
    let blank = |rows: &[Vec<String>]| -> Vec<Vec<String>> {
        rows.iter()
            .map(|r| {
                let mut r = r.clone();
                for &c in &speeds {
                    r[c] = String::new();
                }
                r
            })
            .collect()
    };
    assert_eq!(blank(&ours), blank(&committed));
    for (a, b) in ours.iter().zip(&committed) {
        for &c in &speeds {
            let (x, y): (f64, f64) = (a[c].parse().unwrap(), b[c].parse().unwrap());
            assert!((x - y).abs() <= 1e-12 * x.abs(), "{x} against {y}");
        }
    }
}

/// The `[refine]` rule of the sweep file at `toml`.
fn sweep_refine(toml: &str) -> Option<cellsweep_stats::RefineRule> {
    Sweep::load(std::path::Path::new(toml)).unwrap().refine
}

/// An export's rows without their wall times, sorted.
fn export_rows(path: &std::path::Path) -> Vec<Vec<String>> {
    export_table(path).1
}

/// An export's header and rows, both without the wall times, the rows sorted.
fn export_table(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .unwrap();
    let head = r.headers().unwrap().clone();
    let names = head
        .iter()
        .filter(|h| !h.ends_with("wall_s"))
        .map(String::from)
        .collect();
    let mut rows: Vec<Vec<String>> = r
        .records()
        .map(|rec| {
            rec.unwrap()
                .iter()
                .zip(&head)
                .filter(|(_, h)| !h.ends_with("wall_s"))
                .map(|(v, _)| v.to_string())
                .collect()
        })
        .collect();
    rows.sort();
    assert!(!rows.is_empty());
    (names, rows)
}

/// Retuning `[refine]` (issue 50, 2): a rule that could not have added the values earlier
/// rounds added (another step, a smaller budget) is refused before anything is written; one that holds them (a larger budget) is taken, and the store's
/// export then imports.
#[test]
fn a_retuned_refine_rule_must_hold_the_values_earlier_rounds_added() {
    let dir = common::workdir("retune");
    let (toml, csv) = common::world::refined_export(&dir, "retune");
    let import = common::cellsweep_in(&dir, &["import", csv.to_str().unwrap(), "--db", "r.sqlite"]);
    assert!(
        import.status.success(),
        "{}",
        String::from_utf8_lossy(&import.stderr)
    );
    let db = dir.join("r.sqlite");
    // The rounds add values on the rule's step from the imported crossings.
    let run = common::cellsweep_in(&dir, &["run", toml.to_str().unwrap(), "--db", "r.sqlite"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(common::query(&db, "SELECT COUNT(*) FROM points") > 12);
    let text = std::fs::read_to_string(&toml).unwrap();
    let step = format!("step = {}", common::world::STEP);
    assert!(text.contains(&step) && text.contains("max_new_per_column = 6"));
    for (k, (from, to, needle)) in [
        (
            step.as_str(),
            "step = 0.3",
            "not on the refinement's step 0.3",
        ),
        (
            "max_new_per_column = 6",
            "max_new_per_column = 2",
            "max_new_per_column = 2",
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let file = dir.join(format!("retuned{k}.toml"));
        std::fs::write(&file, text.replace(from, to)).unwrap();
        let before = std::fs::read(&db).unwrap();
        let out = common::cellsweep_in(&dir, &["run", file.to_str().unwrap(), "--db", "r.sqlite"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "retune {k} accepted");
        assert!(
            err.contains("could not have added them") && err.contains(needle),
            "{err}"
        );
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert_eq!(
            std::fs::read(&db).unwrap(),
            before,
            "retune {k} changed the store"
        );
    }
    // A larger budget holds every added value: taken, and the export imports afresh.
    std::fs::write(
        &toml,
        text.replace("max_new_per_column = 6", "max_new_per_column = 8"),
    )
    .unwrap();
    let out = common::cellsweep_in(&dir, &["run", toml.to_str().unwrap(), "--db", "r.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Growing the replicates grows the added points too, not the grid's alone (issue 50, 4).
    let grown = text
        .replace("max_new_per_column = 6", "max_new_per_column = 8")
        .replace("replicates = 40", "replicates = 42");
    assert!(grown.contains("replicates = 42"));
    std::fs::write(&toml, grown).unwrap();
    let out = common::cellsweep_in(&dir, &["run", toml.to_str().unwrap(), "--db", "r.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        common::query(
            &db,
            "SELECT COUNT(*) FROM (SELECT point_id FROM jobs GROUP BY point_id \
             HAVING COUNT(*) != 42 OR SUM(state = 'done') != 42)"
        ),
        0,
        "a point was left at its old replicates"
    );
    let out = common::cellsweep_in(&dir, &["export", "--db", "r.sqlite", "--out", "back.csv"]);
    assert!(out.status.success());
    let out = common::cellsweep_in(&dir, &["import", "back.csv", "--db", "fresh.sqlite"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// An extension (SPEC section 6, `[refine] extend_to`): columns whose crossing lies above the
/// grid (training everywhere it was sampled, or open at its last beta) take the grid's spacing
/// above it until the crossing is bounded, then are refined as any other; nothing goes past
/// extend_to, and adding an extension to a stored sweep is a different sweep (a new name).
#[test]
fn an_extension_finds_crossings_above_the_grid_and_is_a_sweep_of_its_own() {
    let text = sweep_text("ext", "[10, 12, 14]", false)
        + "[refine]\nwidth = 1.2\nstep = 0.5\nmax_new_per_column = 12\nper_round = 2\n\
           extend_to = 30\n";
    let sweep = Sweep::parse(&text, "ext.toml").unwrap();
    let rule = sweep.refine.unwrap();
    assert_eq!((rule.extend_to, rule.extend_step), (Some(30.0), Some(2.0)));
    let (_store_dir, mut store) = store_at("extension");
    let ledger = open(&mut store, &sweep);
    drive(&mut store, &ledger, false, usize::MAX);

    let points = ledger.points(&store).unwrap();
    let ends = ledger.point_ends(&store).unwrap();
    let counts: Vec<_> = ends
        .iter()
        .map(|e: &PointEnds| e.counts(u32::MAX))
        .collect();
    let fit = cellsweep_stats::fit_line(
        &counts,
        &Default::default(),
        0,
        1,
        cellsweep_stats::Method::Model,
    )
    .unwrap();
    for alpha in [0.1, 0.12] {
        let added: Vec<f64> = points
            .iter()
            .filter(|p| p.alpha == alpha && !sweep.grid.beta.contains(&p.beta))
            .map(|p| p.beta)
            .collect();
        assert!(added.len() <= 12, "{alpha}: {added:?}");
        for b in &added {
            assert!(
                *b > 14.0 && *b <= 30.0 && (b / 0.5).round() * 0.5 == *b,
                "{b}"
            );
        }
        // The ladder reached past the true crossing, and the column now has one near it.
        assert!(
            added.iter().any(|&b| b > beta_star(alpha)),
            "{alpha}: {added:?}"
        );
        let c = fit.columns.iter().find(|c| c.alpha == alpha).unwrap();
        let star = c.beta_star.unwrap_or_else(|| panic!("{alpha}: {c:?}"));
        assert!((star - beta_star(alpha)).abs() < 1.5, "{alpha}: {star}");
    }

    // The same name without the extension in a store that holds it: a different sweep.
    let plain = Sweep::parse(
        &(sweep_text("ext", "[10, 12, 14]", false)
            + "[refine]\nwidth = 1.2\nstep = 0.5\nmax_new_per_column = 12\nper_round = 2\n"),
        "plain.toml",
    )
    .unwrap();
    let err = store.register(&plan(&plain, "test"), false).unwrap_err();
    assert!(err.to_string().contains("extend_to"), "{err}");

    // extend_to at or below the grid's top, or an extend_step off the step, is refused.
    for (tail, key) in [
        ("extend_to = 14\n", "refine.extend_to"),
        ("extend_to = 30\nextend_step = 0.3\n", "refine.extend_step"),
        ("extend_step = 2\n", "refine.extend_step"),
    ] {
        let t = sweep_text("bad", "[10, 12, 14]", false) + "[refine]\nstep = 0.5\n" + tail;
        let e = Sweep::parse(&t, "bad.toml").unwrap_err().to_string();
        assert!(e.contains(key), "{tail}: {e}");
    }
}

/// An extension beside its sweep (the same seed and parameters, another name and grid) runs
/// the very same trajectories where their betas meet (seeds never depend on a sweep's name):
/// `--data A --data B` refuses to count them twice, `--pool` reads each run once, and a row
/// that is not the same run (another seed) is refused rather than added.
#[test]
fn pooling_reads_the_runs_an_extension_shares_with_its_sweep_once() {
    let dir = common::workdir("pool");
    let export = |name: &str, beta: &str| -> std::path::PathBuf {
        let sweep = Sweep::parse(&sweep_text(name, beta, false), "pool.toml").unwrap();
        let (db, mut store) = store_at(&format!("pool-{name}"));
        let ledger = open(&mut store, &sweep);
        drive(&mut store, &ledger, false, usize::MAX);
        drop(store);
        let csv = dir.join(format!("{name}.csv"));
        common::export(&db, &csv);
        csv
    };
    let grid = export("grid", "[10, 14, 18, 22]");
    let extension = export("extension", "[18, 22, 26]");
    let (a, b) = (grid.to_str().unwrap(), extension.to_str().unwrap());
    let table = |args: &[&str]| {
        let out = common::cellsweep(&[&["table", "--format", "json"], args].concat());
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        let points: Option<Vec<serde_json::Value>> = out
            .status
            .success()
            .then(|| serde_json::from_slice(&out.stdout).unwrap());
        (points, err)
    };
    let (none, err) = table(&["--data", a, "--data", b]);
    assert!(none.is_none() && err.contains("would count twice"), "{err}");

    let (pooled, err) = table(&["--pool", "--data", a, "--data", b]);
    let pooled = pooled.unwrap_or_else(|| panic!("{err}"));
    let (alone, _) = table(&["--data", a]);
    let alone = alone.unwrap();
    let key = |p: &serde_json::Value| (p["alpha"].to_string(), p["beta"].as_f64().unwrap());
    let mut keys: Vec<_> = pooled.iter().map(key).collect();
    keys.sort_by(|x, y| x.partial_cmp(y).unwrap());
    let n_keys = keys.len();
    keys.dedup();
    assert_eq!(keys.len(), n_keys, "a point read twice");
    assert_eq!(
        n_keys,
        2 * 5,
        "betas 10-22 of the grid and 26 of the extension, two alphas"
    );
    for p in &pooled {
        assert_eq!(p["n"], 40, "{p}");
        // Where both hold a point, its counts are the grid's own: the same runs, once.
        if let Some(q) = alone.iter().find(|q| key(q) == key(p)) {
            for k in ["n_walk", "n_train", "n_reversal"] {
                assert_eq!(p[k], q[k], "{k} at {:?}", key(p));
            }
        }
    }

    // One row of the extension at beta 22 that is another run: refused, not added.
    let text = std::fs::read_to_string(&extension).unwrap();
    let mut changed = false;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            // sweep,alpha,beta,...,params,replicate,prep_seed,collision_seed,verdict,...: the
            // collision seed is the number before the first ",ok," (params may hold commas).
            match (l.starts_with("extension,0.1,22.0,"), l.find(",ok,")) {
                (true, Some(at)) if !changed => {
                    changed = true;
                    let (head, tail) = l.split_at(at);
                    let cut = head.rfind(',').unwrap();
                    format!("{},12345{tail}", &head[..cut])
                }
                _ => l.to_string(),
            }
        })
        .collect();
    assert!(changed, "no row at beta 22 to change");
    std::fs::write(&extension, lines.join("\n") + "\n").unwrap();
    let (none, err) = table(&["--pool", "--data", a, "--data", b]);
    assert!(none.is_none() && err.contains("is not a run of"), "{err}");
}
