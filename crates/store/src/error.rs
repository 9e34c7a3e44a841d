//! Typed errors of the store; each names the database file or the sweep concerned.

use std::path::PathBuf;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum StoreError {
    #[error("no database at {0} (run a sweep first, or pass --db PATH)")]
    Missing(PathBuf),
    #[error("{0} is a directory, not a database file (pass --db DIR/NAME.sqlite)")]
    IsDirectory(PathBuf),
    #[error("cannot create the database {path}: the directory {dir} does not exist")]
    NoDirectory { path: PathBuf, dir: PathBuf },
    #[error("{path} is not a cellsweep database ({reason}); it was left untouched")]
    NotOurs { path: PathBuf, reason: String },
    #[error("{path} is corrupt or not a database ({reason}); it was left untouched")]
    Corrupt { path: PathBuf, reason: String },
    #[error("{path} has schema version {found}, this build reads versions 1 to {expected} (a newer cellsweep wrote it?)")]
    SchemaVersion {
        path: PathBuf,
        found: String,
        expected: u32,
    },
    #[error(
        "a different sweep named {name:?} is already registered ({differs}); rename the new \
         one, or pass --replace to keep the old one's results under {archived:?} and register \
         this one"
    )]
    SweepConflict {
        name: String,
        archived: String,
        differs: String,
    },
    #[error(
        "sweep {name:?} is registered with {stored} replicates per point and the file asks for \
         {asked}: a sweep can grow but not shrink (its results stay); ask for {stored} or more, \
         or give the smaller sweep another name"
    )]
    SweepShrinks {
        name: String,
        stored: u32,
        asked: u32,
    },
    #[error(
        "sweep {name:?} holds {added} points its refinement added, and this definition has no \
         [refine] to hold them: keep its [refine] table, or give the sweep another name"
    )]
    RefinementDropped { name: String, added: usize },
    #[error("no sweeps in {0}")]
    NoSweeps(PathBuf),
    #[error("{path} holds several sweeps ({names}); pass --sweep NAME")]
    SeveralSweeps { path: PathBuf, names: String },
    #[error("no sweep named {0:?} in the store")]
    UnknownSweep(String),
    #[error("{what} {id} is {found}, not {expected} (the store refuses the transition)")]
    BadTransition {
        what: &'static str,
        id: i64,
        found: String,
        expected: &'static str,
    },
    #[error("the jobs of point {point_id} cannot be planned: {why}")]
    Unplannable { point_id: i64, why: String },
    #[error("database error: {0}")]
    Sql(#[from] rusqlite::Error),
    #[error("stored JSON is malformed: {0}")]
    Json(#[from] serde_json::Error),
}

pub type Result<T, E = StoreError> = std::result::Result<T, E>;
