//! Opening a sweep for an engine, the same way for every engine: take the store's lock, open
//! (or create) and check the store, refuse while another engine still holds the sweep's work,
//! plan against what the store holds, register, and put failed work back if asked.

use std::path::Path;

use cellsweep_store::{NewSweep, Registration, Store};

use crate::error::RetuneError;
use crate::lock::{LockError, StoreLock};
use crate::plan::{plan, plan_in};
use crate::sweep::Sweep;

/// How to open.
#[derive(Debug, Clone, Copy, Default)]
pub struct SessionOptions {
    /// Register this sweep even though a different one has its name (the old one is archived).
    pub replace: bool,
    /// Put the sweep's failed jobs and preps back to pending with their attempts anew.
    pub retry_failed: bool,
    /// Refuse while the sweep has work queued on another engine (Slurm arrays not seen to end).
    pub refuse_if_elsewhere: bool,
}

/// A sweep opened for an engine: the store, locked for as long as the session lives.
pub struct Session {
    pub store: Store,
    /// What registration did.
    pub registration: Registration,
    /// The rows planned for registration.
    pub planned: NewSweep,
    /// Failed jobs and preps put back to pending (with `retry_failed`).
    pub retried: Option<usize>,
    _lock: StoreLock,
}

/// Why a sweep could not be opened.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    #[error(transparent)]
    Lock(#[from] LockError),
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
    #[error(transparent)]
    Retune(#[from] RetuneError),
    #[error("{active} array tasks of {name:?} are still queued or running on Slurm (arrays {arrays}): a local run would compute their jobs again; wait for them (cellsweep submit --watch, or collect), scancel them, or pass --force")]
    QueuedElsewhere {
        name: String,
        active: usize,
        arrays: String,
    },
    #[error("{name:?} has Slurm arrays not yet seen to end ({arrays}) and {source}, so whether they still run is unknown; run where squeue answers, or pass --force")]
    ElsewhereUnknown {
        name: String,
        arrays: String,
        source: Box<super::EngineError>,
    },
}

impl Session {
    /// Open `sweep` (read from `source`) in the store at `db` for solver `version`.
    pub fn open(
        db: &Path,
        sweep: &Sweep,
        source: &str,
        version: &str,
        opts: SessionOptions,
    ) -> Result<Session, SessionError> {
        // One writer per store: a second run, submit, collect or import is refused here.
        let lock = StoreLock::acquire(db)?;
        let mut store = Store::open_or_create(db)?;
        store.check_integrity()?;
        if opts.refuse_if_elsewhere {
            queued_elsewhere(&store, &sweep.name, version)?;
        }
        let planned = match opts.replace {
            true => plan(sweep, source),
            false => plan_in(sweep, source, &store)?,
        };
        let registration = store.register(&planned, opts.replace)?;
        let retried = match opts.retry_failed {
            true => Some(store.retry_failed(registration.sweep_id, version)?),
            false => None,
        };
        Ok(Session {
            store,
            registration,
            planned,
            retried,
            _lock: lock,
        })
    }
}

/// Refuse where the sweep `name` has work on Slurm that has not been seen to end (queued,
/// running, or unknown because squeue does not answer): running it here would compute it twice.
pub fn queued_elsewhere(store: &Store, name: &str, version: &str) -> Result<(), SessionError> {
    let Ok(id) = store.sweep_id(name) else {
        return Ok(());
    };
    let arrays = store.open_arrays_of(id, version)?;
    if arrays.is_empty() {
        return Ok(());
    }
    let labels: Vec<String> = arrays.iter().map(|a| a.label()).collect();
    match super::queue_states(store, id, name, version) {
        Ok(states) if states.is_empty() => Ok(()),
        Ok(states) => Err(SessionError::QueuedElsewhere {
            name: name.to_string(),
            active: states.iter().map(|(_, n)| n).sum(),
            arrays: labels.join(", "),
        }),
        Err(super::EngineError::Store(e)) => Err(e.into()),
        Err(source) => Err(SessionError::ElsewhereUnknown {
            name: name.to_string(),
            arrays: labels.join(", "),
            source: Box::new(source),
        }),
    }
}
