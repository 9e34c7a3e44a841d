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

/// Failures of the Slurm engine: writing a run directory, calling sbatch, reading results.
#[derive(Debug, Error)]
pub enum SlurmError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
    #[error(transparent)]
    Run(#[from] RunError),
    #[error("malformed JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A value, directory or answer that cannot be used, with the reason.
    #[error("{0}")]
    Refused(String),
}

impl From<String> for SlurmError {
    fn from(why: String) -> Self {
        SlurmError::Refused(why)
    }
}

impl From<&str> for SlurmError {
    fn from(why: &str) -> Self {
        SlurmError::Refused(why.to_string())
    }
}
