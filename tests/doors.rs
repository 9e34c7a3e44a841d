//! Nothing wrong enters at any door (issue 26), through the real binary: one writer per database
//! file whatever name reaches it, an import that lands whole or not at all (conflicts and
//! impossible fields refused and named), and a full disk that leaves no job `running`.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{cellsweep_in, query, workdir, write_sweep};

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).to_string()
}

/// Run `cmd` in sh; it must succeed (mounting and filling the small disks of the full-disk
/// tests).
fn sh(cmd: &str) {
    let out = Command::new("sh").arg("-c").arg(cmd).output().unwrap();
    assert!(
        out.status.success(),
        "{cmd}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Refused: non-zero, and stderr's last line names `needle`.
fn refused(out: &Output, needle: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(!out.status.success(), "accepted, wanted {needle:?}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains(needle), "{needle:?} not in {err}");
    err
}

/// A finished tiny sweep (2 points x 2 sigmas x 2 replicates) in `dir/r.sqlite`, exported to
/// `dir/e.csv`; returns the export's text.
fn exported(dir: &Path) -> String {
    write_sweep(dir, "door", 2, "");
    ok(&cellsweep_in(
        dir,
        &["run", "door.toml", "--db", "r.sqlite"],
    ));
    ok(&cellsweep_in(
        dir,
        &["export", "--db", "r.sqlite", "--out", "e.csv"],
    ));
    std::fs::read_to_string(dir.join("e.csv")).unwrap()
}

/// The export with one field of its first data row set to `value`.
fn with_field(text: &str, field: &str, value: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let header: Vec<&str> = lines[2].split(',').collect();
    let k = header.iter().position(|h| *h == field).unwrap();
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(lines[3].as_bytes());
    let mut row: Vec<String> = reader
        .records()
        .next()
        .unwrap()
        .unwrap()
        .iter()
        .map(String::from)
        .collect();
    row[k] = value.to_string();
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(&row).unwrap();
    let row = String::from_utf8(w.into_inner().unwrap()).unwrap();
    let mut out: Vec<String> = lines[..3].iter().map(|l| l.to_string()).collect();
    out.push(row.trim_end().to_string());
    out.extend(lines[4..].iter().map(|l| l.to_string()));
    out.join("\n") + "\n"
}

#[test]
fn an_import_is_all_or_nothing_and_names_each_problem() {
    let dir = workdir("import");
    let text = exported(&dir);
    let cases: Vec<(String, &str)> = vec![
        (
            with_field(&text, "collision_seed", "12345"),
            "collision seed",
        ),
        (with_field(&text, "decision_time", "-1"), "decision_time"),
        (
            with_field(&text, "attachment_1", "nonsense"),
            "attachment_1",
        ),
        (with_field(&text, "free_speed", "NaN"), "free_speed"),
        (
            with_field(&text, "collision_steps", "-1"),
            "collision_steps",
        ),
        (with_field(&text, "outcome", "breakup"), "breakup_reason"),
    ];
    for (k, (bad, needle)) in cases.iter().enumerate() {
        let file = format!("bad{k}.csv");
        std::fs::write(dir.join(&file), bad).unwrap();
        // Into a fresh store: refused, and no store is left behind.
        let out = cellsweep_in(&dir, &["import", &file, "--db", "fresh.sqlite"]);
        refused(&out, needle);
        assert!(
            !dir.join("fresh.sqlite").exists(),
            "case {k}: a store was left"
        );
        assert!(
            !dir.join("fresh.sqlite.lock").exists(),
            "case {k}: its lock file was left (issue 50, 6)"
        );
        // Into the store that holds these jobs: refused, byte for byte as it was.
        let before = std::fs::read(dir.join("r.sqlite")).unwrap();
        let out = cellsweep_in(&dir, &["import", &file, "--db", "r.sqlite"]);
        refused(&out, needle);
        assert_eq!(
            std::fs::read(dir.join("r.sqlite")).unwrap(),
            before,
            "case {k}"
        );
    }
    // One replicate twice in a file, with two outcomes: refused, naming both.
    let lines: Vec<&str> = text.lines().collect();
    let twice = format!(
        "{}\n{}\n",
        text.trim_end(),
        with_field(&text, "contact_time", "1.25")
            .lines()
            .nth(3)
            .unwrap()
    );
    assert!(twice.lines().count() == lines.len() + 1);
    std::fs::write(dir.join("twice.csv"), &twice).unwrap();
    let out = cellsweep_in(&dir, &["import", "twice.csv", "--db", "fresh.sqlite"]);
    let err = refused(&out, "contact_time");
    assert!(
        err.contains("replicate 0") && err.contains("(the same job)"),
        "{err}"
    );
    assert!(!dir.join("fresh.sqlite").exists());
    // A sound export imports whole into a fresh store, and again as already there.
    let out = ok(&cellsweep_in(
        &dir,
        &["import", "e.csv", "--db", "fresh.sqlite"],
    ));
    assert!(out.contains("imported 8 results"), "{out}");
    let out = ok(&cellsweep_in(
        &dir,
        &["import", "e.csv", "--db", "fresh.sqlite"],
    ));
    assert!(
        out.contains("imported 0 results") && out.contains("8 already"),
        "{out}"
    );
    // Another sweep under the same name (its seed changed in the definition line): refused
    // without offering a --replace that import does not have, the store as it was.
    let other = text.replacen("\"seed\":", "\"seed\":1", 1);
    assert_ne!(other, text);
    std::fs::write(dir.join("other.csv"), other).unwrap();
    let before = std::fs::read(dir.join("fresh.sqlite")).unwrap();
    let out = cellsweep_in(&dir, &["import", "other.csv", "--db", "fresh.sqlite"]);
    let err = refused(&out, "a different sweep named");
    assert!(
        err.contains("import it into another store") || err.contains("into another store"),
        "{err}"
    );
    assert!(!err.contains("pass --replace"), "{err}");
    assert_eq!(std::fs::read(dir.join("fresh.sqlite")).unwrap(), before);
}

/// Points whose prep breaks up (beta = 200 on the small lattice) hold a result the prep itself
/// decides, which import writes when it recomputes the prep: into a fresh store every row is
/// new, none "already in the store"; the second time every row is.
/// The tiny sweep `name` with a second beta, 200, at which every prep breaks up on the small
/// lattice: its file's path.
fn sweep_with_broken_preps(dir: &Path, name: &str) -> String {
    let toml = write_sweep(dir, name, 2, "").to_str().unwrap().to_string();
    let text = std::fs::read_to_string(&toml)
        .unwrap()
        .replace("beta = [10]", "beta = [10, 200]");
    std::fs::write(&toml, text).unwrap();
    toml
}

/// `reset --breakups` puts back only what a change of the breakup rule can change: the preps
/// that broke up (beta = 200 on the small lattice) with every job that starts from them, and
/// no other result; the next run computes them again with the same seeds, to the same rows.
#[test]
fn reset_breakups_puts_back_only_the_stored_breakups_and_the_rerun_gives_them_again() {
    let dir = workdir("reset-breakups");
    let toml = sweep_with_broken_preps(&dir, "broke");
    ok(&cellsweep_in(&dir, &["run", &toml, "--db", "r.sqlite"]));
    let export = |name: &str| -> Vec<String> {
        ok(&cellsweep_in(
            &dir,
            &["export", "--db", "r.sqlite", "--out", name],
        ));
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let header: Vec<String> = text
            .lines()
            .nth(2)
            .unwrap()
            .split(',')
            .map(String::from)
            .collect();
        let wall: Vec<usize> = ["wall_s", "prep_wall_s"]
            .iter()
            .map(|w| header.iter().position(|h| h == w).unwrap())
            .collect();
        // Every row without its wall times (where it ran, not what it is).
        let mut rows: Vec<String> = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_reader(text.as_bytes())
            .records()
            .map(|r| {
                let r = r.unwrap();
                r.iter()
                    .enumerate()
                    .filter(|(k, _)| !wall.contains(k))
                    .map(|(_, c)| c.to_string())
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect();
        rows.sort();
        rows
    };
    let before = export("before.csv");
    let broke = before.iter().filter(|r| r.contains(",breakup,")).count();
    assert!(
        broke >= 2 && broke < before.len(),
        "{broke} of {}",
        before.len()
    );
    // A dry run counts and changes nothing.
    let bytes = std::fs::read(dir.join("r.sqlite")).unwrap();
    let out = ok(&cellsweep_in(
        &dir,
        &["reset", "--db", "r.sqlite", "--breakups", "--dry-run"],
    ));
    assert!(
        out.contains(&format!("would put back {broke} jobs")),
        "{out}"
    );
    assert_eq!(std::fs::read(dir.join("r.sqlite")).unwrap(), bytes);
    let out = ok(&cellsweep_in(
        &dir,
        &["reset", "--db", "r.sqlite", "--breakups"],
    ));
    assert!(
        out.contains(&format!("put back {broke} jobs")) && out.contains("preps to compute again"),
        "{out}"
    );
    // The rest of the sweep is untouched: its results are all still there.
    let kept = export("kept.csv");
    assert_eq!(kept.len(), before.len() - broke);
    assert!(kept.iter().all(|r| before.contains(r)));
    // The run computes the put-back preps and jobs again: the very rows of before.
    ok(&cellsweep_in(&dir, &["run", &toml, "--db", "r.sqlite"]));
    assert_eq!(export("after.csv"), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn rows_decided_by_their_prep_import_as_new_into_a_fresh_store() {
    let dir = workdir("by-prep");
    let toml = sweep_with_broken_preps(&dir, "byprep");
    ok(&cellsweep_in(&dir, &["run", &toml, "--db", "r.sqlite"]));
    ok(&cellsweep_in(
        &dir,
        &["export", "--db", "r.sqlite", "--out", "e.csv"],
    ));
    let export = std::fs::read_to_string(dir.join("e.csv")).unwrap();
    let rows = export.lines().count() - 3;
    let by_prep = export.lines().filter(|l| l.contains(",breakup,")).count();
    assert!(
        by_prep >= 2 && by_prep < rows,
        "{by_prep} of {rows}\n{export}"
    );
    let out = ok(&cellsweep_in(
        &dir,
        &["import", "e.csv", "--db", "fresh.sqlite"],
    ));
    assert!(
        out.contains(&format!("imported {rows} results")) && out.contains("(0 already"),
        "{out}"
    );
    let out = ok(&cellsweep_in(
        &dir,
        &["import", "e.csv", "--db", "fresh.sqlite"],
    ));
    assert!(
        out.contains("imported 0 results") && out.contains(&format!("({rows} already")),
        "{out}"
    );
    // An export written before prep_extent was a column (format 3) imports too: the rows its
    // preps decide are not refused for the extent the store now gives them.
    let lines: Vec<&str> = export.lines().collect();
    let header: Vec<&str> = lines[2].split(',').collect();
    let k = header.iter().position(|h| *h == "prep_extent").unwrap();
    assert_eq!(k, header.len() - 1, "prep_extent is the last column");
    let old: Vec<String> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| match i {
            0 | 1 => l.to_string(),
            _ => l.rsplit_once(',').unwrap().0.to_string(),
        })
        .collect();
    std::fs::write(dir.join("old.csv"), old.join("\n") + "\n").unwrap();
    let out = ok(&cellsweep_in(
        &dir,
        &["import", "old.csv", "--db", "old.sqlite"],
    ));
    assert!(out.contains(&format!("imported {rows} results")), "{out}");
}

#[test]
fn an_archived_sweeps_export_imports_into_a_fresh_store() {
    let dir = workdir("archived");
    let text = exported(&dir);
    // A different sweep under the same name, with --replace: the old one is "door@1".
    let changed = std::fs::read_to_string(dir.join("door.toml"))
        .unwrap()
        .replace("seed = 5", "seed = 6");
    std::fs::write(dir.join("door.toml"), changed).unwrap();
    ok(&cellsweep_in(
        &dir,
        &["run", "door.toml", "--db", "r.sqlite", "--replace"],
    ));
    ok(&cellsweep_in(
        &dir,
        &[
            "export", "--db", "r.sqlite", "--sweep", "door@1", "--out", "old.csv",
        ],
    ));
    let old = std::fs::read_to_string(dir.join("old.csv")).unwrap();
    assert!(old.lines().nth(3).unwrap().starts_with("door@1,"));
    let out = ok(&cellsweep_in(
        &dir,
        &["import", "old.csv", "--db", "f.sqlite"],
    ));
    assert!(out.contains("imported 8 results"), "{out}");
    // The same rows as the original sweep's export.
    ok(&cellsweep_in(
        &dir,
        &["export", "--db", "f.sqlite", "--out", "back.csv"],
    ));
    let body = |t: &str| -> Vec<String> {
        t.lines()
            .skip(3)
            .map(|l| l.split(',').take(18).collect::<Vec<_>>().join(","))
            .collect()
    };
    let back = std::fs::read_to_string(dir.join("back.csv")).unwrap();
    assert_eq!(body(&back), body(&text));
}

#[test]
fn a_killed_import_leaves_no_store_at_its_path_and_a_clean_run_no_lock_file() {
    let dir = workdir("killed-import");
    // One point whose prep takes a while (a long free motion): the import recomputes it.
    std::fs::write(
        dir.join("slow.toml"),
        "name = \"slow\"\nseed = 5\nreplicates = 1\n[grid]\nalpha = [0.1]\nbeta = [10]\nL = [48]\nsigma = [5]\n\
         [params]\nR0 = 24\n[protocol]\nsingle_lattice = [96, 96]\nrelax_time = 5\nfree_time = 150\ncollide_time = 2\n",
    )
    .unwrap();
    let said = ok(&cellsweep_in(
        &dir,
        &["run", "slow.toml", "--db", "r.sqlite"],
    ));
    // One of each is said in the singular (issue 50, 6).
    assert!(
        said.contains("registered sweep \"slow\": 1 point x 1 replicate = 1 job, 1 prep"),
        "{said}"
    );
    // A run that ended leaves its store and nothing else (issue 50, 9).
    assert!(
        !dir.join("r.sqlite.lock").exists(),
        "the run left its lock file"
    );
    ok(&cellsweep_in(
        &dir,
        &["export", "--db", "r.sqlite", "--out", "e.csv"],
    ));
    let mut child = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(&dir)
        .args(["import", "e.csv", "--db", "new.sqlite"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Killed while it computes the prep (its store under construction is on disk by then).
    let building = dir.join("new.sqlite.importing");
    let t0 = std::time::Instant::now();
    while !building.exists() {
        assert!(
            t0.elapsed().as_secs() < 60,
            "the import never started its store"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the import ended before the kill"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    common::send_signal(&child, libc::SIGKILL);
    let _ = child.wait();
    assert!(
        !dir.join("new.sqlite").exists(),
        "a killed import left a store at the path asked for (issue 50, 6)"
    );
    // The next import clears what the killed one left and lands whole.
    ok(&cellsweep_in(
        &dir,
        &["import", "e.csv", "--db", "new.sqlite"],
    ));
    assert!(!building.exists() && !dir.join("new.sqlite.lock").exists());
    assert_eq!(
        query(&dir.join("new.sqlite"), "SELECT COUNT(*) FROM results"),
        1
    );
}

#[test]
fn one_writer_per_database_file_whatever_name_reaches_it() {
    let dir = workdir("lock");
    write_sweep(&dir, "lk", 2, "");
    ok(&cellsweep_in(&dir, &["run", "lk.toml", "--db", "c.sqlite"]));
    std::os::unix::fs::symlink("c.sqlite", dir.join("l.sqlite")).unwrap();
    let abs = dir.join("c.sqlite").canonicalize().unwrap();
    let lock = format!("{}.lock", abs.display());
    // Hold the writer lock as a running writer would (flock(2), as cellsweep takes it).
    let mut holder = Command::new("flock")
        .args([&lock, "sleep", "60"])
        .spawn()
        .unwrap();
    // Held once a non-blocking shared lock of the same file is refused (no sleep and hope).
    let t0 = std::time::Instant::now();
    while Command::new("flock")
        .args(["-n", "-s", &lock, "true"])
        .status()
        .unwrap()
        .success()
    {
        assert!(t0.elapsed().as_secs() < 30, "flock never took the lock");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let names = ["c.sqlite", "./c.sqlite", "l.sqlite", abs.to_str().unwrap()];
    for name in names {
        let out = cellsweep_in(&dir, &["run", "lk.toml", "--db", name]);
        refused(&out, "held by another cellsweep writer");
    }
    holder.kill().unwrap();
    let _ = holder.wait();
    // A hard link: refused for writing (two names, two journals), readable as ever.
    std::fs::hard_link(dir.join("c.sqlite"), dir.join("h.sqlite")).unwrap();
    let out = cellsweep_in(&dir, &["run", "lk.toml", "--db", "h.sqlite"]);
    refused(&out, "hard links");
    ok(&cellsweep_in(&dir, &["status", "--db", "h.sqlite"]));
}

#[test]
fn a_full_disk_puts_the_jobs_in_flight_back_and_names_the_store() {
    let dir = workdir("full");
    // Collisions long enough to be in flight when the disk fills.
    write_sweep(&dir, "full", 3, "");
    let text = std::fs::read_to_string(dir.join("full.toml"))
        .unwrap()
        .replace("collide_time = 2", "collide_time = 30");
    std::fs::write(dir.join("full.toml"), text).unwrap();
    let mnt = dir.join("mnt");
    std::fs::create_dir_all(&mnt).unwrap();
    sh(&format!(
        "mount -t tmpfs -o size=4m tmpfs {}",
        mnt.display()
    ));
    let db = mnt.join("c.sqlite");
    let child = Command::new(env!("CARGO_BIN_EXE_cellsweep"))
        .current_dir(&dir)
        .args([
            "run",
            "full.toml",
            "--db",
            db.to_str().unwrap(),
            "--workers",
            "2",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while common::try_query(&db, "SELECT COUNT(*) FROM preps WHERE state = 'done'") != Some(2) {
        assert!(t0.elapsed().as_secs() < 120, "the preps did not finish");
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    sh(&format!(
        "dd if=/dev/zero of={}/fill bs=64k 2>/dev/null || true",
        mnt.display()
    ));
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    sh(&format!("rm {}/fill", mnt.display()));
    let running = query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'running'");
    let pending = query(&db, "SELECT COUNT(*) FROM jobs WHERE state = 'pending'");
    sh(&format!("umount {}", mnt.display()));
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("c.sqlite") && err.contains("full"), "{err}");
    assert_eq!(running, 0, "{err}");
    assert!(pending > 0);
}

/// Pictures on a full disk: refused in one line naming the file, and no empty or half
/// picture left under any name (issue 50, 6).
#[test]
fn plot_on_a_full_disk_leaves_no_empty_picture() {
    let dir = workdir("full-plot");
    let mnt = dir.join("mnt");
    std::fs::create_dir_all(&mnt).unwrap();
    sh(&format!(
        "mount -t tmpfs -o size=1m tmpfs {}",
        mnt.display()
    ));
    std::fs::create_dir_all(mnt.join("p")).unwrap();
    sh(&format!(
        "dd if=/dev/zero of={}/fill bs=4k 2>/dev/null || true",
        mnt.display()
    ));
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/paper/refined-L90-sigma5.csv");
    let out = cellsweep_in(
        &dir,
        &["plot", "--data", data.to_str().unwrap(), "--out", "mnt/p"],
    );
    let left: Vec<String> = std::fs::read_dir(mnt.join("p"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    sh(&format!("umount {}", mnt.display()));
    let err = refused(&out, "mnt/p/");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(left.is_empty(), "left behind: {left:?}");
}

#[test]
fn every_committed_row_passes_the_import_field_checks() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/paper");
    let mut rows = 0;
    for f in std::fs::read_dir(&data).unwrap() {
        let path = f.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .from_reader(text.as_bytes());
        for (i, r) in reader.deserialize().enumerate() {
            let r: cellsweep_store::export::ExportRow = r.unwrap();
            let problems = r.field_problems();
            assert!(
                problems.is_empty(),
                "{}: row {}: {problems:?}",
                path.display(),
                i + 1
            );
            rows += 1;
        }
    }
    assert!(rows > 10_000, "{rows} rows");
}

#[test]
fn a_reset_point_runs_again_to_the_very_same_rows() {
    let dir = workdir("reset");
    exported(&dir);
    let db = dir.join("r.sqlite");
    let before = common::result_rows(&db, "door");
    let bytes = std::fs::read(&db).unwrap();
    for (args, needle) in [
        (
            vec!["--point", "alpha=0.3"],
            "no point of sweep \"door\" matches",
        ),
        (
            vec!["--point", "alpha=$(touch x)"],
            "is not a finite number",
        ),
        (
            vec!["--point", "gamma=1"],
            "\"gamma\" is not an axis of the sweep",
        ),
        (vec!["--point", "alpha=NaN"], "is not a finite number"),
        (
            vec!["--point", "alpha=0.1,alpha=0.12"],
            "alpha is given twice",
        ),
        (vec![], "say what to put back"),
    ] {
        let mut a = vec!["reset", "--db", "r.sqlite"];
        a.extend(args);
        refused(&cellsweep_in(&dir, &a), needle);
    }
    // A store that is not there is named, and nothing is made beside it.
    refused(
        &cellsweep_in(
            &dir,
            &["reset", "--db", "none.sqlite", "--point", "alpha=0.1"],
        ),
        "no database at none.sqlite",
    );
    assert!(!dir.join("none.sqlite").exists() && !dir.join("none.sqlite.lock").exists());
    // A column that is not an axis is refused, not ignored (issue 50: a mistyped axis would
    // put back every value of the axis it meant).
    std::fs::write(dir.join("pts.csv"), "beta,alpha,note\n10,0.1,x\n").unwrap();
    refused(
        &cellsweep_in(&dir, &["reset", "--db", "r.sqlite", "--points", "pts.csv"]),
        "column \"note\" is not an axis of the sweep",
    );
    std::fs::write(dir.join("pts.csv"), "beta,alpha\n10,0.1\n").unwrap();
    let dry = ok(&cellsweep_in(
        &dir,
        &[
            "reset",
            "--db",
            "r.sqlite",
            "--points",
            "pts.csv",
            "--dry-run",
        ],
    ));
    assert!(dry.contains("would put back 4 jobs at 2 points"), "{dry}");
    assert_eq!(
        std::fs::read(&db).unwrap(),
        bytes,
        "a refused or dry reset wrote"
    );

    let out = ok(&cellsweep_in(
        &dir,
        &["reset", "--db", "r.sqlite", "--point", "alpha=0.1,sigma=5"],
    ));
    assert!(out.contains("put back 2 jobs at 1 points"), "{out}");
    let left = "SELECT COUNT(*) FROM results r JOIN jobs j ON j.id = r.job_id \
                JOIN points p ON p.id = j.point_id";
    assert_eq!(query(&db, left), 6);
    assert_eq!(
        query(
            &db,
            "SELECT COUNT(*) FROM jobs j JOIN points p ON p.id = j.point_id \
             WHERE p.alpha = 0.1 AND p.sigma = 5 AND j.state = 'pending' AND j.attempts = 0"
        ),
        2
    );
    let status = ok(&cellsweep_in(&dir, &["status", "--db", "r.sqlite"]));
    assert!(status.contains("6 done / 8 total"), "{status}");
    ok(&cellsweep_in(
        &dir,
        &["run", "door.toml", "--db", "r.sqlite"],
    ));
    assert_eq!(common::result_rows(&db, "door"), before);
}

/// Box-limited points (SPEC 4.5; issue 48, 1) are counted and listed by `status` (text and
/// JSON) as `table` marks them: a cell prepped in a box too narrow for it.
#[test]
fn status_lists_the_box_limited_points() {
    let dir = workdir("box");
    std::fs::write(dir.join("bx.toml"), common::BOX_SWEEP).unwrap();
    ok(&cellsweep_in(&dir, &["run", "bx.toml", "--db", "b.sqlite"]));
    let table = ok(&cellsweep_in(&dir, &["table", "--db", "b.sqlite"]));
    assert!(
        table.contains("[box]") && table.contains("(1 point)"),
        "{table}"
    );
    let status = ok(&cellsweep_in(&dir, &["status", "--db", "b.sqlite"]));
    assert!(
        status.contains("box      1 box-limited point (SPEC 4.5")
            && status.contains("alpha = 0.1, beta = 10, L = 48, sigma = 5"),
        "{status}"
    );
    let json = ok(&cellsweep_in(
        &dir,
        &["status", "--db", "b.sqlite", "--json"],
    ));
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(
        v[0]["box_limited"],
        serde_json::json!(["alpha = 0.1, beta = 10, L = 48, sigma = 5"])
    );
}
