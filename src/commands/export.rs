//! `cellsweep export`: one CSV row per finished replicate (format in the first line).

use anyhow::{bail, Context};
use cellsweep_scheduler::export_file::read_export;
use cellsweep_scheduler::wire::PrepPayload;
use cellsweep_scheduler::{plan_targets, Ledger, RowCheck, Settlement, StoreLock, Sweep};
use cellsweep_solver::{prepare, Config, Silent};
use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_stats::{Axes, PointKey};
use cellsweep_store::export::{ExportRow, EXPORT_FORMAT};
use cellsweep_store::JobState;
use cellsweep_store::{Store, StoreError};
use rayon::prelude::*;
use std::collections::HashMap;

use crate::cli::{ExportArgs, ImportArgs};

pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    let store = Store::open_read(&args.db.db)?;
    let name = store.choose_sweep(args.sweep.as_deref())?;
    let id = store.sweep_id(&name)?;
    let defaults = serde_json::to_value(Params::default())?;
    let rows = store.export_rows(id, SOLVER_VERSION, &defaults)?;
    let out = &args.out;
    crate::output::replace_file(out, |file| {
        use std::io::Write as _;
        writeln!(
            file,
            "# cellsweep export format {EXPORT_FORMAT}; sweep {name:?}; {SOLVER_VERSION}"
        )?;
        // The sweep's definition, so that `cellsweep import` can register it anywhere.
        writeln!(file, "# spec {}", store.sweep_spec(id)?)?;
        let mut w = csv::Writer::from_writer(file);
        for r in &rows {
            w.serialize(r)?;
        }
        w.flush()?;
        Ok(())
    })?;
    println!(
        "wrote {} replicates of {name:?} to {}",
        rows.len(),
        out.display()
    );
    Ok(())
}

/// `cellsweep import`: register the file's sweep, compute the preps its rows need, check every
/// row against the job it claims (and against the row the store already holds for it), and
/// commit it all in one transaction: refused, the store is as it was (a store the import would
/// have created is not left behind).
pub fn import(args: ImportArgs) -> anyhow::Result<()> {
    let file = args.file.display().to_string();
    let (sweep, mut rows) = read_export(&args.file)?;
    let (points, targets) = import_targets(&file, &sweep, &mut rows)?;
    let lock = StoreLock::acquire(&args.db.db)?;
    let db = &args.db.db;
    let existed = std::fs::metadata(db).is_ok_and(|m| m.len() > 0);
    // A new store is built under a name of its own and moved into place whole once committed:
    // an import killed on the way (its preps take minutes) leaves no store at the path asked
    // for. What a killed one left there is removed first (this import holds the path's lock).
    let building = (!existed).then(|| with_suffix(db, ".importing"));
    let target = building.as_deref().unwrap_or(db);
    if let Some(tmp) = &building {
        remove_store_files(tmp);
    }
    let mut store = Store::open_or_create(target)?;
    store.check_integrity()?;
    let done =
        store.atomically(|store| import_into(store, &file, &sweep, &rows, &points, &targets));
    if let Some(tmp) = &building {
        let placed = done.as_ref().map_err(|_| ()).and_then(|_| {
            store.close().map_err(|_| ())?;
            std::fs::rename(tmp, db).map_err(|_| ())
        });
        // Refused (or not moved): nothing of it stays, not even an empty store.
        if placed.is_err() {
            remove_store_files(tmp);
            done.as_ref().map_err(|e| anyhow::anyhow!("{e:#}"))?;
            bail!(
                "cannot move the imported store into place at {}",
                db.display()
            );
        }
    } else {
        drop(store);
    }
    drop(lock);
    let (new, already) = done?;
    println!(
        "imported {new} results of {:?} from {file} ({already} already in the store) into {}",
        sweep.name,
        db.display()
    );
    Ok(())
}

/// `path` with `suffix` appended to its file name.
fn with_suffix(path: &std::path::Path, suffix: &str) -> std::path::PathBuf {
    let mut p = path.as_os_str().to_owned();
    p.push(suffix);
    std::path::PathBuf::from(p)
}

/// A store's database file and SQLite's files beside it.
fn remove_store_files(db: &std::path::Path) {
    for tail in ["", "-wal", "-shm", "-journal"] {
        let _ = std::fs::remove_file(with_suffix(db, tail));
    }
}

/// Every row's field check and point, the sweep's points (its grid's, then any its refinement
/// added), and the replicates to register per point (at least its first round). Rows of an archived sweep (`NAME@ID`, a sweep set aside by `run --replace`)
/// are the rows of the sweep its definition names. Two rows of one job must agree.
fn import_targets(
    file: &str,
    sweep: &Sweep,
    rows: &mut [ExportRow],
) -> anyhow::Result<(Vec<Params>, Vec<u32>)> {
    for r in rows.iter_mut() {
        if let Some((name, id)) = r.sweep.rsplit_once('@') {
            if name == sweep.name && !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()) {
                r.sweep = sweep.name.clone();
            }
        }
    }
    // The grid's points, then those a refinement added (refused if this sweep could not have).
    let axes: Vec<Axes> = rows
        .iter()
        .map(|r| sweep.axes_of_row(r))
        .collect::<Result<_, _>>()
        .map_err(|why| anyhow::anyhow!("{file}: {why}"))?;
    let points = sweep
        .points_with(axes.iter().cloned())
        .map_err(|why| anyhow::anyhow!("{file}: {why}"))?;
    let index: HashMap<_, usize> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (sweep.axes_of(p).key(), i))
        .collect();
    let mut targets = vec![sweep.initial_replicates(); points.len()];
    let mut problems = Vec::new();
    let mut first_of: HashMap<(usize, u32), usize> = HashMap::new();
    for (n, r) in rows.iter().enumerate() {
        let at = format!("row {}", n + 1);
        for p in r.field_problems() {
            problems.push(format!("{at}: {p}"));
        }
        // (points_with holds every row's point.)
        let Some(&i) = index.get(&axes[n].key()) else {
            bail!(
                "{file}: {at}: {} is not a point of sweep {:?}",
                axes[n],
                sweep.name
            );
        };
        if r.replicate >= sweep.replicates {
            bail!(
                "{file}: {at}: replicate {} is beyond the sweep's {} per point",
                r.replicate,
                sweep.replicates
            );
        }
        targets[i] = targets[i].max(r.replicate + 1);
        match first_of.get(&(i, r.replicate)) {
            Some(&first) => problems.extend(conflicts(
                &format!("{at} and row {} (the same job)", first + 1),
                r,
                &rows[first],
            )),
            None => {
                first_of.insert((i, r.replicate), n);
            }
        }
    }
    refuse(file, rows.len(), &problems)?;
    Ok((points, targets))
}

/// Each result field in which `row` and `other` (of one job) differ, as a line naming the
/// replicate, the field and both values.
fn conflicts(what: &str, row: &ExportRow, other: &ExportRow) -> Vec<String> {
    let at = format!(
        "alpha = {}, beta = {}, L = {}, sigma = {}, replicate {}",
        row.alpha, row.beta, row.L, row.sigma, row.replicate
    );
    row.result_differences(other)
        .into_iter()
        .map(|(field, a, b)| format!("{what}, {at}: {field} is {a:?} here and {b:?} there"))
        .collect()
}

/// Refuse the file if anything is wrong with it: the first problems, one a line, then one line
/// that says nothing was imported.
fn refuse(file: &str, rows: usize, problems: &[String]) -> anyhow::Result<()> {
    if problems.is_empty() {
        return Ok(());
    }
    for why in problems.iter().take(10) {
        eprintln!("refused: {file}: {why}");
    }
    if problems.len() > 10 {
        eprintln!("refused: ... and {} more", problems.len() - 10);
    }
    bail!(
        "{file}: {} problems in its {rows} rows; nothing was imported and the store is as it was",
        problems.len()
    )
}

/// The import itself, inside the store's one transaction: register, compute and check the
/// preps, check every row, commit. Returns (results new, results already stored and equal).
/// The results of points whose prep is unstable or broke up are written by the prep itself, so
/// rows of a fresh store can be "already stored": they count as new unless the store held them
/// before the import.
fn import_into(
    store: &mut Store,
    file: &str,
    sweep: &Sweep,
    rows: &[ExportRow],
    points: &[Params],
    targets: &[u32],
) -> anyhow::Result<(usize, usize)> {
    sweep
        .stored_points(store)
        .map_err(|e| anyhow::anyhow!("{file}: {e}"))?;
    let retuned = match store.sweep_id(&sweep.name) {
        Ok(id) => matches!(
            cellsweep_store::spec_change(&store.sweep_spec(id)?, &sweep.canonical_json()),
            cellsweep_store::SpecChange::Retuned | cellsweep_store::SpecChange::Grows { .. }
        ),
        Err(_) => false,
    };
    if retuned {
        println!(
            "note: sweep {:?} in the store takes the file's replicates, [adaptive], [refine] and [report] \
             rules (its points and results are kept)",
            sweep.name
        );
    }
    let reg = store
        .register(&plan_targets(sweep, file, points, &|i| targets[i]), false)
        .map_err(|e| match e {
            // (The store's message offers `run --replace`; import never replaces a sweep.)
            StoreError::SweepConflict { name, differs, .. } => anyhow::anyhow!(
                "{file}: a different sweep named {name:?} is already registered in this store \
                 ({differs}); import never replaces a sweep: import the file into another store"
            ),
            e => e.into(),
        })?;
    // Rows are checked against the jobs they claim: every planned job becomes a row first.
    store.materialize_next(reg.sweep_id, SOLVER_VERSION, usize::MAX)?;
    let ledger = Ledger::load(store, reg.sweep_id, SOLVER_VERSION)?;
    let defaults = serde_json::to_value(Params::default())?;
    let held_before: std::collections::HashSet<JobKey> = store
        .export_rows(reg.sweep_id, SOLVER_VERSION, &defaults)?
        .iter()
        .map(|r| job_key(sweep, r))
        .collect::<anyhow::Result<_>>()?;
    compute_preps(store, &ledger, reg.sweep_id, rows)?;
    let mut stored: HashMap<JobKey, ExportRow> = HashMap::new();
    for r in store.export_rows(reg.sweep_id, SOLVER_VERSION, &defaults)? {
        stored.insert(job_key(sweep, &r)?, r);
    }
    let mut problems = Vec::new();
    let mut to_commit = Vec::new();
    let (mut already, mut by_prep) = (0, 0);
    let mut taken = std::collections::HashSet::new();
    for r in rows {
        match ledger.check_row(store, r)? {
            RowCheck::Commit(job) => {
                if taken.insert(job) {
                    to_commit.push((job, r));
                }
            }
            RowCheck::Already => {
                let key = job_key(sweep, r)?;
                let c = match stored.get(&key) {
                    Some(s) => conflicts("the file's row and the store's", r, s),
                    None => Vec::new(),
                };
                if c.is_empty() {
                    match held_before.contains(&key) {
                        true => already += 1,
                        false => by_prep += 1,
                    }
                }
                problems.extend(c);
            }
            RowCheck::Refused(why) => problems.push(why),
        }
    }
    refuse(file, rows.len(), &problems)?;
    let mut new = 0;
    for (job, r) in to_commit {
        if ledger.commit_row(store, job, r)? == Settlement::New {
            new += 1;
        }
    }
    Ok((new + by_prep, already))
}

/// A job: its point's axes (as bits, every other axis included) and replicate.
type JobKey = (PointKey, u32);

/// A row's job.
fn job_key(sweep: &Sweep, r: &ExportRow) -> anyhow::Result<JobKey> {
    let axes = sweep.axes_of_row(r).map_err(|why| anyhow::anyhow!(why))?;
    Ok((axes.key(), r.replicate))
}

/// The preps the rows need, computed here (in parallel) so that each row's prep hash can be
/// checked, and committed through the ledger.
fn compute_preps(
    store: &mut Store,
    ledger: &Ledger,
    sweep_id: i64,
    rows: &[ExportRow],
) -> anyhow::Result<()> {
    let missing: Vec<_> = store
        .preps_of(sweep_id, SOLVER_VERSION)?
        .into_iter()
        .filter(|p| p.state != JobState::Done)
        .collect();
    if !missing.is_empty() {
        // What the preps took where the rows were made, for an honest estimate of the wait.
        let recorded: Vec<f64> = missing
            .iter()
            .filter_map(|p| rows.iter().find(|r| r.prep_seed == p.seed))
            .filter_map(|r| r.prep_wall_s.filter(|w| w.is_finite() && *w > 0.0))
            .collect();
        let cores = rayon::current_num_threads().max(1);
        let estimate = match recorded.len() {
            0 => "each a whole free motion".to_string(),
            n => {
                let each = recorded.iter().sum::<f64>() / n as f64;
                let batches = missing.len().div_ceil(cores);
                format!(
                    "each a whole free motion, {each:.0} s where the rows were made: about {} on {cores} cores",
                    cellsweep_stats::throughput::fmt_duration(batches as f64 * each)
                )
            }
        };
        let n = missing.len();
        let preps = if n == 1 { "prep" } else { "preps" };
        eprintln!("computing {n} {preps} to check the rows against ({estimate})");
    }
    let computed: Vec<(i64, u64, f64, anyhow::Result<PrepPayload>)> = missing
        .par_iter()
        .map(|p| {
            let start = std::time::Instant::now();
            let run = || -> anyhow::Result<PrepPayload> {
                let config: Config = serde_json::from_str(&p.config)?;
                let prep = prepare(&config.params, &config.protocol, p.seed, &mut Silent)?;
                Ok(PrepPayload::from_prep(&prep))
            };
            let payload = run();
            (p.id, p.seed, start.elapsed().as_secs_f64(), payload)
        })
        .collect();
    for (id, seed, took, payload) in computed {
        let payload = payload.with_context(|| format!("prep {id}"))?;
        // The prep's cost where the rows were made, if they say; else this recomputation's.
        let wall_s = rows
            .iter()
            .find(|r| r.prep_seed == seed)
            .and_then(|r| r.prep_wall_s)
            .filter(|w| w.is_finite() && *w > 0.0)
            .unwrap_or(took);
        if let Settlement::Refused(why) =
            ledger.settle_prep(store, id, &payload, wall_s)?.settlement
        {
            bail!("{why}");
        }
    }
    Ok(())
}
