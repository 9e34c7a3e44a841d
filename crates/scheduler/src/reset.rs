//! Putting chosen points of a sweep back to pending (`cellsweep reset`): the points named by
//! selectors ([`PointChoice`], from `--point` or a CSV file of points) are found in the store,
//! and their jobs, or only what a change of the breakup rule can change at them, are put back
//! so that the next run computes them again with the same seeds. Main types: [`ResetRequest`],
//! [`ResetDone`] and [`ResetError`]; the store's side is [`cellsweep_store::Reset`].
//!
//! Every selector is checked against the sweep's axes before anything is locked or written (an
//! unknown axis is refused, never ignored: ignoring it would put back every value of that
//! axis), and a selector that matches no point is refused with the store as it was.

use std::path::{Path, PathBuf};

use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::{Axes, Condition, SelectError, Selector};
use cellsweep_store::{PointRef, Reset, Store, StoreError};

use crate::error::StoredSweepError;
use crate::lock::{LockError, StoreLock};
use crate::sweep::Sweep;

/// The paper's axes; a sweep may have others (R0, E0, ...), which a selector may name too.
const KEYS: [&str; 4] = ["alpha", "beta", "L", "sigma"];

/// Why a reset was refused; nothing was written.
#[derive(Debug, thiserror::Error)]
pub enum ResetError {
    #[error("say what to put back: --point alpha=0.1,beta=46, --points FILE.csv or --breakups")]
    NothingAsked,
    #[error("{place}: {source}")]
    Selector { place: String, source: SelectError },
    #[error("{place}: no point of sweep {sweep:?} matches")]
    NoMatch { place: String, sweep: String },
    #[error("cannot read {file}: {source}")]
    Read {
        file: String,
        source: std::io::Error,
    },
    #[error("{place}: {source}")]
    Csv { place: String, source: csv::Error },
    #[error("{file}: column {column:?} is not an axis of the sweep (its axes: {axes})")]
    NotAnAxis {
        file: String,
        column: String,
        axes: String,
    },
    #[error("{file}: no points listed")]
    NoPoints { file: String },
    #[error("{db}: {source}")]
    Sweep {
        db: String,
        source: StoredSweepError,
    },
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error(transparent)]
    Lock(#[from] LockError),
}

/// A selector of points and the words that name it in errors (`--point ...`, `FILE: row 3`).
#[derive(Debug)]
pub struct PointChoice {
    place: String,
    selector: Selector,
}

impl PointChoice {
    /// A selector over the axes `axes` of the sweep, named `place` in errors.
    fn new(
        place: String,
        selector: Result<Selector, SelectError>,
        axes: &[String],
    ) -> Result<PointChoice, ResetError> {
        let axes: Vec<&str> = axes.iter().map(String::as_str).collect();
        match selector.and_then(|s| s.check_axes(&axes, "the sweep").map(|_| s)) {
            Ok(selector) => Ok(PointChoice { place, selector }),
            Err(source) => Err(ResetError::Selector { place, source }),
        }
    }

    /// `--point alpha=0.1,beta=46` (any axis of the sweep).
    fn parse(text: &str, axes: &[String]) -> Result<PointChoice, ResetError> {
        PointChoice::new(format!("--point {text}"), Selector::parse(text), axes)
    }

    /// `--points FILE.csv`: one selector per row; every column must name an axis of the sweep.
    fn read(path: &Path, axes: &[String]) -> Result<Vec<PointChoice>, ResetError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| ResetError::Read {
            file: file.clone(),
            source,
        })?;
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header = reader
            .headers()
            .map_err(|source| ResetError::Csv {
                place: format!("{file}: unreadable header"),
                source,
            })?
            .clone();
        let columns: Vec<(usize, &str)> = header.iter().enumerate().collect();
        if let Some((_, h)) = columns.iter().find(|(_, h)| !axes.iter().any(|a| a == h)) {
            return Err(ResetError::NotAnAxis {
                file,
                column: h.to_string(),
                axes: axes.join(", "),
            });
        }
        let mut out = Vec::new();
        for (i, row) in reader.records().enumerate() {
            let place = format!("{file}: row {}", i + 1);
            let row = row.map_err(|source| ResetError::Csv {
                place: place.clone(),
                source,
            })?;
            let conditions = columns
                .iter()
                .map(|&(c, key)| Condition::new(key, row.get(c).unwrap_or("")))
                .collect::<Result<Vec<_>, _>>();
            out.push(PointChoice::new(
                place,
                conditions.and_then(Selector::of),
                axes,
            )?);
        }
        if out.is_empty() {
            return Err(ResetError::NoPoints { file });
        }
        Ok(out)
    }

    fn matches(&self, p: &PointRef) -> bool {
        let names: Vec<&str> = self
            .selector
            .conditions
            .iter()
            .map(|c| c.name.as_str())
            .filter(|k| !KEYS.contains(k))
            .collect();
        let mut axes = Axes::new(p.alpha, p.beta, p.L, p.sigma);
        axes.others = cellsweep_store::point_others(&p.config, &names);
        self.selector.matches(|name| axes.value(name))
    }
}

/// What to put back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResetKind {
    /// Every job of the chosen points, its result deleted.
    Jobs,
    /// Only what a change of the breakup rule can change at the chosen points (every point
    /// where no selector is given): stored breakups, the collisions and the preps they rest on.
    Breakups,
}

/// A reset as asked for on the command line.
#[derive(Debug)]
pub struct ResetRequest<'a> {
    pub db: &'a Path,
    /// The sweep (needed where the store holds several).
    pub sweep: Option<&'a str>,
    /// `--point` selectors.
    pub points: &'a [String],
    /// `--points FILE.csv`.
    pub points_file: Option<&'a Path>,
    pub kind: ResetKind,
    /// Count what would be put back, and change nothing.
    pub dry_run: bool,
}

/// What a reset put back (or, in a dry run, would have).
#[derive(Debug, Clone)]
pub struct ResetDone {
    pub db: PathBuf,
    pub sweep: String,
    pub kind: ResetKind,
    pub dry_run: bool,
    pub reset: Reset,
}

/// Put the chosen points back (under the store's lock, after its integrity check), or count
/// what would be put back in a dry run.
pub fn reset(req: &ResetRequest) -> Result<ResetDone, ResetError> {
    if req.points.is_empty() && req.points_file.is_none() && req.kind == ResetKind::Jobs {
        return Err(ResetError::NothingAsked);
    }
    let db = req.db;
    // The sweep and its axes, read before anything is locked or written: a selector that does
    // not fit the sweep is refused with the store as it was.
    let (sweep, axes) = {
        let store = Store::open_read(db)?;
        let name = store.choose_sweep(req.sweep)?;
        let id = store.sweep_id(&name)?;
        let stored = Sweep::stored(&store, id).map_err(|source| ResetError::Sweep {
            db: db.display().to_string(),
            source,
        })?;
        let mut axes: Vec<String> = KEYS.iter().map(|k| k.to_string()).collect();
        axes.extend(stored.grid.others.iter().map(|a| a.name.clone()));
        (name, axes)
    };
    let mut choices: Vec<PointChoice> = req
        .points
        .iter()
        .map(|p| PointChoice::parse(p, &axes))
        .collect::<Result<_, _>>()?;
    if let Some(path) = req.points_file {
        choices.extend(PointChoice::read(path, &axes)?);
    }
    // No run may be live while its jobs are put back (a dry run only reads).
    let _lock = match req.dry_run {
        true => None,
        false => Some(StoreLock::acquire(db)?),
    };
    let mut store = match req.dry_run {
        true => Store::open_read(db)?,
        false => Store::open(db)?,
    };
    let points = store.sweep_points(store.sweep_id(&sweep)?)?;
    let mut chosen: Vec<i64> = Vec::new();
    if choices.is_empty() {
        // --breakups alone: every point of the sweep.
        chosen.extend(points.iter().map(|p| p.id));
    }
    for c in &choices {
        let hits = points.iter().filter(|p| c.matches(p)).map(|p| p.id);
        let before = chosen.len();
        chosen.extend(hits);
        if chosen.len() == before {
            return Err(ResetError::NoMatch {
                place: c.place.clone(),
                sweep,
            });
        }
    }
    chosen.sort_unstable();
    chosen.dedup();
    if !req.dry_run {
        store.check_integrity()?;
    }
    let reset = match (req.kind, req.dry_run) {
        (ResetKind::Jobs, true) => Reset {
            points: chosen.len(),
            jobs: store.jobs_of_points(&chosen, SOLVER_VERSION)?,
            ..Reset::default()
        },
        (ResetKind::Jobs, false) => store.reset_points(SOLVER_VERSION, &chosen)?,
        (ResetKind::Breakups, true) => store.count_breakups(SOLVER_VERSION, &chosen)?,
        (ResetKind::Breakups, false) => store.reset_breakups(SOLVER_VERSION, &chosen)?,
    };
    Ok(ResetDone {
        db: db.to_path_buf(),
        sweep,
        kind: req.kind,
        dry_run: req.dry_run,
        reset,
    })
}

impl std::fmt::Display for ResetDone {
    /// The one line `cellsweep reset` prints.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (r, name, db) = (&self.reset, &self.sweep, self.db.display());
        match (self.kind, self.dry_run) {
            (ResetKind::Jobs, true) => write!(
                f,
                "would put back {} jobs at {} points of {name:?} in {db} (dry run: nothing \
                 changed)",
                r.jobs, r.points
            ),
            (ResetKind::Jobs, false) => write!(
                f,
                "put back {} jobs at {} points of {name:?} in {db} ({} results deleted); \
                 `cellsweep run` of the sweep computes them again",
                r.jobs, r.points, r.results
            ),
            (ResetKind::Breakups, true) => write!(
                f,
                "would put back {} jobs at {} points of {name:?} in {db} ({} results, {} preps \
                 to compute again; dry run: nothing changed)",
                r.jobs, r.points, r.results, r.preps
            ),
            (ResetKind::Breakups, false) => write!(
                f,
                "put back {} jobs at {} points of {name:?} in {db} ({} results deleted, {} \
                 preps to compute again): every stored breakup; `cellsweep run` of the sweep \
                 computes them again",
                r.jobs, r.points, r.results, r.preps
            ),
        }
    }
}
