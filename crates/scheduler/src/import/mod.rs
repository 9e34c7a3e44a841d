//! Import: an export file (`cellsweep export`, [`crate::export_file`]) into a store, the sweep
//! registered, the preps its rows need computed, every row checked against the job it claims
//! (and against the row the store already holds for it), and it all committed in one
//! transaction: refused, the store is as it was, and a store the import would have created is
//! not left behind.
//!
//! Main items: [`import`], what it reports on the way ([`ImportEvent`]) and at its end
//! ([`Imported`]), and [`ImportError`] (a refused file carries each problem, one line each).

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_stats::PointKey;
use cellsweep_store::export::ExportRow;
use cellsweep_store::{SpecChange, Store, StoreError};

use crate::export_file::{read_export, ExportFileError};
use crate::{plan_targets, Ledger, LockError, RowCheck, RunError, Settlement, StoreLock, Sweep};

mod preps;
mod rows;

/// What an import added.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Imported {
    pub sweep: String,
    /// Results new to the store.
    pub new: usize,
    /// Rows whose result the store already held, equal.
    pub already: usize,
}

/// What an import tells on its way (the binary prints these).
#[derive(Debug, Clone, PartialEq)]
pub enum ImportEvent {
    /// The store's sweep of the file's name takes the file's rules (replicates, `[adaptive]`,
    /// `[refine]`, `[report]`); its points and results are kept.
    Retuned { sweep: String },
    /// Preps are computed to check the rows against: how many, and what they are thought to
    /// take ("each a whole free motion, 13 s where the rows were made: about 3m49s on 2 cores").
    ComputingPreps { count: usize, estimate: String },
}

/// Why an import was refused; nothing was written.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error(transparent)]
    File(#[from] ExportFileError),
    #[error("{file}: {why}")]
    Invalid { file: String, why: String },
    /// Rows wrong in themselves, against each other, against their jobs or against the store.
    #[error(
        "{file}: {} problems in its {rows} rows; nothing was imported and the store is as it was",
        problems.len()
    )]
    Refused {
        file: String,
        rows: usize,
        problems: Vec<String>,
    },
    #[error(
        "{file}: a different sweep named {name:?} is already registered in this store \
         ({differs}); import never replaces a sweep: import the file into another store"
    )]
    Conflict {
        file: String,
        name: String,
        differs: String,
    },
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error(transparent)]
    Lock(#[from] LockError),
    #[error(transparent)]
    Run(#[from] RunError),
    /// A prep the rows need could not be computed, or its result was refused.
    #[error("{0}")]
    Prep(String),
    #[error("cannot move the imported store into place at {0}")]
    Move(String),
}

impl ImportError {
    fn invalid(file: &str, why: impl std::fmt::Display) -> ImportError {
        ImportError::Invalid {
            file: file.to_string(),
            why: why.to_string(),
        }
    }
}

/// Import export file `file` into the store at `db` (created if missing), telling `on` what
/// happens on the way.
pub fn import(
    file: &Path,
    db: &Path,
    on: &mut dyn FnMut(ImportEvent),
) -> Result<Imported, ImportError> {
    let name = file.display().to_string();
    let (sweep, mut rows) = read_export(file)?;
    let (points, targets) = rows::targets(&name, &sweep, &mut rows)?;
    let lock = StoreLock::acquire(db)?;
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
    let done = store.atomically(|store| {
        let job = Job {
            file: &name,
            sweep: &sweep,
            rows: &rows,
            points: &points,
            targets: &targets,
        };
        job.commit_into(store, on)
    });
    if let Some(tmp) = &building {
        let placed = match &done {
            Ok(_) => store
                .close()
                .map_err(|_| ())
                .and_then(|_| std::fs::rename(tmp, db).map_err(|_| ())),
            Err(_) => Err(()),
        };
        // Refused (or not moved): nothing of it stays, not even an empty store.
        if placed.is_err() {
            remove_store_files(tmp);
            done?;
            return Err(ImportError::Move(db.display().to_string()));
        }
    } else {
        drop(store);
    }
    drop(lock);
    let (new, already) = done?;
    Ok(Imported {
        sweep: sweep.name,
        new,
        already,
    })
}

/// `path` with `suffix` appended to its file name.
fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut p = path.as_os_str().to_owned();
    p.push(suffix);
    PathBuf::from(p)
}

/// A store's database file and SQLite's files beside it.
fn remove_store_files(db: &Path) {
    for tail in ["", "-wal", "-shm", "-journal"] {
        let _ = std::fs::remove_file(with_suffix(db, tail));
    }
}

/// One file's rows on their way into a store.
struct Job<'a> {
    file: &'a str,
    sweep: &'a Sweep,
    rows: &'a [ExportRow],
    points: &'a [Params],
    targets: &'a [u32],
}

/// A job of the sweep: its point's axes (as bits, every other axis included) and replicate.
type JobKey = (PointKey, u32);

impl Job<'_> {
    /// A row's job.
    fn key(&self, r: &ExportRow) -> Result<JobKey, ImportError> {
        let axes = self
            .sweep
            .axes_of_row(r)
            .map_err(|why| ImportError::invalid(self.file, why))?;
        Ok((axes.key(), r.replicate))
    }

    /// The import itself, inside the store's one transaction: register, compute and check the
    /// preps, check every row, commit. Returns (results new, results already stored and
    /// equal). The results of points whose prep is unstable or broke up are written by the
    /// prep itself, so rows of a fresh store can be "already stored": they count as new unless
    /// the store held them before the import.
    fn commit_into(
        &self,
        store: &mut Store,
        on: &mut dyn FnMut(ImportEvent),
    ) -> Result<(usize, usize), ImportError> {
        let (file, sweep) = (self.file, self.sweep);
        sweep
            .stored_points(store)
            .map_err(|e| ImportError::invalid(file, e))?;
        let retuned = match store.sweep_id(&sweep.name) {
            Ok(id) => matches!(
                cellsweep_store::spec_change(&store.sweep_spec(id)?, &sweep.canonical_json()),
                SpecChange::Retuned | SpecChange::Grows { .. }
            ),
            Err(_) => false,
        };
        if retuned {
            on(ImportEvent::Retuned {
                sweep: sweep.name.clone(),
            });
        }
        let plan = plan_targets(sweep, file, self.points, &|i| self.targets[i]);
        let reg = store.register(&plan, false).map_err(|e| match e {
            // (The store's message offers `run --replace`; import never replaces a sweep.)
            StoreError::SweepConflict { name, differs, .. } => ImportError::Conflict {
                file: file.to_string(),
                name,
                differs,
            },
            e => e.into(),
        })?;
        // Rows are checked against the jobs they claim: every planned job becomes a row first.
        store.materialize_next(reg.sweep_id, SOLVER_VERSION, usize::MAX)?;
        let ledger = Ledger::load(store, reg.sweep_id, SOLVER_VERSION)?;
        let defaults =
            serde_json::to_value(Params::default()).map_err(|e| ImportError::invalid(file, e))?;
        let held_before: HashSet<JobKey> = store
            .export_rows(reg.sweep_id, SOLVER_VERSION, &defaults)?
            .iter()
            .map(|r| self.key(r))
            .collect::<Result<_, _>>()?;
        preps::compute(store, &ledger, reg.sweep_id, self.rows, on)?;
        let mut stored: HashMap<JobKey, ExportRow> = HashMap::new();
        for r in store.export_rows(reg.sweep_id, SOLVER_VERSION, &defaults)? {
            stored.insert(self.key(&r)?, r);
        }
        let mut problems = Vec::new();
        let mut to_commit = Vec::new();
        let (mut already, mut by_prep) = (0, 0);
        let mut taken = HashSet::new();
        for r in self.rows {
            match ledger.check_row(store, r)? {
                RowCheck::Commit(job) => {
                    if taken.insert(job) {
                        to_commit.push((job, r));
                    }
                }
                RowCheck::Already => {
                    let key = self.key(r)?;
                    let c = match stored.get(&key) {
                        Some(s) => rows::conflicts("the file's row and the store's", r, s),
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
        rows::refuse(file, self.rows.len(), problems)?;
        let mut new = 0;
        for (job, r) in to_commit {
            if ledger.commit_row(store, job, r)? == Settlement::New {
                new += 1;
            }
        }
        Ok((new + by_prep, already))
    }
}
