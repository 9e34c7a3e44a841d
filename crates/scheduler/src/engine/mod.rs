//! Engines: where a sweep's jobs run. The [`Ledger`](crate::ledger::Ledger) owns what is owed
//! and settles every result; an engine only carries work out and results back. Two implement
//! [`Engine`]: [`Local`] (worker processes on this machine, [`crate::coordinator`]) and
//! [`SlurmArrays`] (job arrays on a cluster, [`crate::slurm`]). One loop drives either
//! ([`drive`]: take stock, dispatch, wait, with back-off while the engine does not answer), and
//! one sequence opens a sweep for either ([`Session`]: lock, check, plan, register, retry).
//!
//! A third engine (HTCondor, a Kubernetes job, another batch system) implements
//! [`Engine::take_stock`] (ask its queue first, then bring finished results in through the
//! ledger and give work that left the queue without a result a failed attempt) and
//! [`Engine::dispatch`] (send what the ledger owes, recording what it sent in the store), and
//! says which of its errors are transient; [`drive`], the session, the store and every printer
//! stay as they are.

mod drive;
mod local;
mod session;
mod slurm_arrays;

pub use drive::{drive, DriveOptions, Finish};
pub use local::Local;
pub use session::{queued_elsewhere, Session, SessionError, SessionOptions};
pub use slurm_arrays::SlurmArrays;

use cellsweep_store::Store;

use crate::error::{QueueError, RunError, SlurmError};
use crate::slurm::{Collected, EndedKind, Submission};

/// The states of a sweep's work queued on engines away from this machine (Slurm arrays not
/// yet seen to end), as their queues report them: what `status`, the live page and a local
/// run's refusal read. Empty where nothing is queued; an error where a queue does not answer,
/// never "nothing queued".
pub fn queue_states(
    store: &Store,
    sweep_id: i64,
    name: &str,
    version: &str,
) -> Result<Vec<(String, usize)>, EngineError> {
    let arrays = store.open_arrays_of(sweep_id, version)?;
    match arrays.is_empty() {
        true => Ok(Vec::new()),
        false => Ok(crate::slurm::queue_of(name, &arrays)?),
    }
}

/// The sweep an engine works on.
#[derive(Debug, Clone, Copy)]
pub struct Target<'a> {
    pub sweep_id: i64,
    pub name: &'a str,
    /// The solver version whose results count.
    pub version: &'a str,
}

/// What an engine found when it took stock.
#[derive(Debug, Clone, Copy, Default)]
pub struct Stock {
    /// Tasks it has sent that are still queued or running (0: nothing in flight).
    pub in_flight: usize,
}

/// What an engine did with the work owed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dispatch {
    /// Nothing was owed: every job has a result or failed for good.
    Nothing,
    /// Work was handed over; its results come back at a later take of stock.
    Sent,
    /// The work ran here to its end (`interrupted`: stopped by a signal, the rest pending).
    Ran { interrupted: bool },
}

/// What an engine tells its caller while it works (the binary prints these).
#[derive(Debug)]
pub enum Event<'a> {
    /// Arrays a kill left recorded without their engine id, found again in the queue.
    FoundAgain { arrays: usize },
    /// Results brought in from one run directory.
    Collected {
        dir: &'a str,
        collected: &'a Collected,
    },
    /// Work that left the queue without a result: a failed attempt each.
    EndedWithoutResult { kind: &'a EndedKind },
    /// Preps and jobs out of attempts (or needing a prep that is), failed for good.
    OutOfAttempts { count: usize, max_attempts: u32 },
    /// A submission was made.
    Submitted(&'a Submission),
    /// The engine did not answer; the drive waits `wait` seconds (the `failures`-th time).
    Retrying {
        error: &'a EngineError,
        wait: f64,
        failures: u32,
        give_up_after: f64,
    },
}

/// Why an engine could not go on.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    #[error(transparent)]
    Run(#[from] RunError),
    #[error(transparent)]
    Slurm(#[from] SlurmError),
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
    /// The queue did not answer (a watch waits; see [`EngineError::QueueUnknown`] otherwise).
    #[error(transparent)]
    Queue(#[from] QueueError),
    /// The queue did not answer, so whether earlier work still runs is unknown.
    #[error("{source}: it is unknown whether earlier arrays of {name:?} still run, so nothing was sent; submit again when squeue answers (or use --watch, which waits)")]
    QueueUnknown { name: String, source: QueueError },
    /// Work is still in flight and the caller does not wait for it.
    #[error("{active} array tasks of {name:?} are still queued or running (squeue); wait for them or scancel them, then submit again")]
    StillRunning { name: String, active: usize },
    /// The drive waited the engine out for `--give-up-after` and stops.
    #[error("{last}; it has failed for {failing:.0} s (--give-up-after {limit}), so the watch stops; nothing was sent for jobs that may still be queued: run submit --watch again when Slurm answers")]
    GaveUp {
        last: Box<EngineError>,
        failing: f64,
        limit: f64,
    },
    #[error("cannot start the async runtime: {0}")]
    Runtime(std::io::Error),
}

impl EngineError {
    /// The engine not answering now (its queue, or its submission command): a watch waits it
    /// out; anything else stops the drive.
    pub fn is_transient(&self) -> bool {
        matches!(
            self,
            EngineError::Queue(_)
                | EngineError::QueueUnknown { .. }
                | EngineError::Slurm(SlurmError::Queue(_) | SlurmError::Sbatch { .. })
        )
    }
}

/// An engine: carries the ledger's owed work somewhere and brings results back.
pub trait Engine {
    /// Take in what finished since the last look (through the ledger) and say what is still
    /// in flight. Asks the engine's queue first, so work that ends meanwhile is counted as in
    /// flight and taken in next time, never sent again; an engine whose queue does not answer
    /// returns an error rather than "nothing in flight".
    fn take_stock(
        &mut self,
        store: &mut Store,
        target: Target<'_>,
        on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Stock, EngineError>;

    /// Send (or run) what the ledger owes now. Called only with nothing in flight.
    fn dispatch(
        &mut self,
        store: &mut Store,
        target: Target<'_>,
        on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Dispatch, EngineError>;
}
