//! Errors of sweep files and of running sweeps.

use thiserror::Error;

/// A sweep file that cannot be used: names the file, the key and the problem, on one line.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}: {key}: {problem}")]
pub struct SweepError {
    pub file: String,
    pub key: String,
    pub problem: String,
}

impl SweepError {
    pub fn new(file: &str, key: impl Into<String>, problem: impl Into<String>) -> Self {
        SweepError {
            file: file.to_string(),
            key: key.into(),
            problem: problem.into(),
        }
    }
}

/// Failures of a run (not of single jobs: those are retried and recorded in the store).
#[derive(Debug, Error)]
pub enum RunError {
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
    #[error("cannot start worker process {exe}: {source}")]
    Spawn {
        exe: String,
        #[source]
        source: std::io::Error,
    },
    #[error("stored configuration is malformed: {0}")]
    Config(#[from] serde_json::Error),
}
