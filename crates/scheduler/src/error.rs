//! Errors of sweep files and of running sweeps.

use std::time::Duration;

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

/// A single value that cannot be used: a sweep name, a job timeout.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ValueError {
    #[error(
        "{0:?} is not a sweep name: 1 to 100 of the characters A-Z a-z 0-9 . _ -, not starting \
         with a dot"
    )]
    Name(String),
    #[error("{value} is not a number of seconds in (0, {max}] (30 days)")]
    Timeout { value: f64, max: f64 },
}

/// A grid axis that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AxisError {
    #[error("is empty")]
    Empty,
    #[error("{0} values: more than {max}", max = crate::limits::MAX_AXIS_POINTS)]
    TooMany(usize),
    #[error("{0} is not a finite number")]
    NotFinite(f64),
    #[error("from, to and step must be finite numbers")]
    RangeNotFinite,
    #[error("step = {0} must be > 0")]
    StepNotPositive(f64),
    #[error("to = {to} is below from = {from}")]
    Reversed { from: f64, to: f64 },
    #[error("(to - from) / step = {0:e}: more than {max} points", max = crate::limits::MAX_AXIS_POINTS)]
    RangeTooLong(f64),
    #[error("(to - from) / step = {steps} is not a whole number, so {to} is not on the range")]
    NotWhole { steps: f64, to: f64 },
    #[error("{0} appears twice")]
    Twice(f64),
}

/// A prep in transit (or as stored) that does not decode.
#[derive(Debug, Error)]
pub enum PayloadError {
    #[error("bad field encoding: {0}")]
    Encoding(#[from] base64::DecodeError),
    #[error("prep fields have {phi} and {p} values, lattice needs {n}")]
    Size { phi: usize, p: usize, n: usize },
    #[error("prep summary: {0}")]
    Summary(#[from] serde_json::Error),
    #[error("prep summary {key}: {source}")]
    SummaryField {
        key: &'static str,
        #[source]
        source: serde_json::Error,
    },
}

/// A worker call that got no valid answer; the job is retried.
#[derive(Debug, Error)]
pub enum CallError {
    #[error("cannot encode the request: {0}")]
    Encode(serde_json::Error),
    #[error("timed out after {0} s (worker killed)")]
    TimedOut(f64),
    #[error("worker answered task {got} instead of {sent}")]
    WrongTask { got: i64, sent: i64 },
    #[error("malformed reply from worker: {0}")]
    Malformed(serde_json::Error),
    /// The worker process ended: how, with the last line it wrote to stderr.
    #[error("{0}")]
    Exited(String),
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
    #[error("stored prep is malformed: {0}")]
    Prep(#[from] PayloadError),
    #[error(transparent)]
    Definition(#[from] StoredSweepError),
    /// A row committed without [`crate::Ledger::check_row`] passing it first.
    #[error("a row with verdict {verdict:?} and outcome {outcome:?} was not checked")]
    UncheckedRow { verdict: String, outcome: String },
}

/// A point found in a store or an export that the sweep could not hold (see
/// [`crate::Sweep::points_with`]).
#[derive(Debug, Clone, Error)]
pub enum AddedPointError {
    #[error("{axes} is not a point of sweep {sweep:?}: {why}")]
    NotOfSweep {
        axes: String,
        sweep: String,
        why: String,
    },
    #[error(
        "{axes}: more added values in its column than the sweep's max_new_per_column = {budget}"
    )]
    OverBudget { axes: String, budget: u32 },
}

/// A sweep file whose `[refine]` rule cannot hold the beta values earlier rounds added to the
/// sweep of its name in the store (another step, a smaller budget): refused before anything is
/// written, since the store's own export would then be refused by `import`.
#[derive(Debug, Error)]
pub enum RetuneError {
    #[error(
        "sweep {name:?} in the store holds beta values its earlier [refine] rounds added, and \
         this definition's [refine] could not have added them ({why}); keep the stored rule \
         ({stored}) or one that holds them (a step dividing theirs, a budget at least as \
         large), or give the sweep another name"
    )]
    Refused {
        name: String,
        why: AddedPointError,
        stored: String,
    },
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
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
    #[error(transparent)]
    Payload(#[from] PayloadError),
    /// A value, directory or answer that cannot be used, with the reason.
    #[error("{0}")]
    Refused(String),
    /// squeue did not answer: whether the sweep's arrays still run is unknown.
    #[error(transparent)]
    Queue(#[from] QueueError),
    /// sbatch did not take an array (nothing of it was queued).
    #[error("sbatch {script} failed: {message}")]
    Sbatch { script: String, message: String },
}

/// Why the queue's answer is unknown. Never read as "nothing queued".
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum QueueError {
    #[error("squeue could not be run: {0}")]
    NotRun(String),
    #[error("squeue failed ({status}): {stderr}")]
    Failed { status: String, stderr: String },
    #[error("squeue gave no answer within {} s", .0.as_secs_f64())]
    TimedOut(Duration),
    #[error("squeue's answer could not be read: line {0:?}")]
    Unparsable(String),
}

/// A stored sweep definition that cannot be read back.
#[derive(Debug, thiserror::Error)]
pub enum StoredSweepError {
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
    #[error("sweep {name:?}: malformed definition: {source}")]
    Malformed {
        name: String,
        #[source]
        source: serde_json::Error,
    },
}
