//! The ledger: the one owner of a run's bookkeeping, shared by the local engine
//! ([`crate::coordinator`]) and the Slurm engine ([`crate::slurm`]), which are then only
//! transport (worker processes; task and record files).
//!
//! A run starts with [`Ledger::open`] (recover what a killed run left `running`, settle jobs
//! whose prep is decided, fail the jobs of preps that failed for good, plan an adaptive sweep's
//! next round). Tasks become requests by [`crate::wire::Request::prep`] and
//! [`crate::wire::Request::collide`]. Every answer comes back here:
//! - a prep or collision record ([`Ledger::settle_prep`], [`Ledger::settle_job`]) is checked
//!   against what the store says of the prep or job it claims (its sweep, solver version, seed,
//!   parameters, and the prep a collision started from) before it is committed in one
//!   transaction; a record that does not match is refused with the reason and nothing is
//!   written. A prep whose verdict is not `ok` settles its jobs with that verdict;
//! - a failed attempt ([`Ledger::fail`]) keeps its error and its number: the task is pending
//!   again, or failed for good after the sweep's `max_attempts`;
//! - an adaptive sweep's rounds ([`Ledger::plan_rounds`]) add the next replicates of every open
//!   point whose round is complete;
//! - an exported row ([`Ledger::check_row`], [`Ledger::commit_row`]) is checked like a record.

use std::cell::RefCell;

use cellsweep_solver::Config;
use cellsweep_store::Store;

use crate::error::RunError;
use crate::sweep::Sweep;

mod failure;
mod import;
mod rounds;
mod settle;

pub use failure::{Failure, TaskRef};
pub use import::RowCheck;
pub use rounds::ColumnStanding;
pub use settle::PrepSettled;
pub(crate) use settle::{result_record, stored_verdict};

/// What became of a record.
#[derive(Debug, Clone, PartialEq)]
pub enum Settlement {
    /// Committed.
    New,
    /// The store already had it; nothing changed.
    Already,
    /// Not committed: the record does not belong to the job or prep it claims.
    Refused(String),
}

/// The ledger of one sweep under one solver version.
#[derive(Debug, Clone)]
pub struct Ledger {
    pub sweep_id: i64,
    pub version: String,
    pub sweep: Sweep,
    /// Failed attempts after which a task is failed for good: the run's (its flag, else the
    /// sweep file's `[run]`; the store does not keep it). `None` where no run gives it (a
    /// Slurm `collect`): failures are recorded, and the next run's [`Ledger::open`] gives up.
    pub max_attempts: Option<u32>,
    /// JSON of the sweep's classifier settings, stored with every result.
    classifier: String,
    /// The configuration of the point last checked, as stored and as parsed: records come
    /// point by point, and parsing it for each one was a fifth of `collect`'s time.
    last_config: RefCell<Option<(String, Config)>>,
}

/// What [`Ledger::open`] did to the store before any work is sent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Opening {
    /// Preps and jobs a killed run left `running`, pending again.
    pub recovered: usize,
    /// Jobs settled by the verdict of their prep, decided earlier.
    pub settled: usize,
    /// Preps and jobs failed for good: out of attempts (recorded by a Slurm collect), or
    /// jobs of a prep that failed for good earlier.
    pub failed: usize,
    /// Jobs of an adaptive sweep's next rounds.
    pub planned: usize,
}

impl Ledger {
    /// Whether `config` is the stored configuration `stored` (JSON) says.
    fn is_stored_config(&self, stored: &str, config: &Config) -> Result<bool, RunError> {
        let mut last = self.last_config.borrow_mut();
        if last.as_ref().map(|(text, _)| text.as_str()) != Some(stored) {
            *last = Some((stored.to_string(), serde_json::from_str(stored)?));
        }
        Ok(last.as_ref().is_some_and(|(_, c)| c == config))
    }

    /// The ledger of a registered sweep, its definition read back from the store.
    pub fn load(store: &Store, sweep_id: i64, version: &str) -> Result<Ledger, RunError> {
        let sweep = Sweep::stored(store, sweep_id)?;
        Ok(Ledger {
            sweep_id,
            version: version.to_string(),
            classifier: serde_json::to_string(&sweep.classifier)?,
            max_attempts: None,
            sweep,
            last_config: RefCell::new(None),
        })
    }

    /// Start a run of a registered sweep, whose tasks fail for good after `max_attempts`
    /// failed attempts: the ledger, after the bookkeeping every engine does first (see
    /// [`Opening`]).
    pub fn open(
        store: &mut Store,
        sweep_id: i64,
        version: &str,
        max_attempts: u32,
    ) -> Result<(Ledger, Opening), RunError> {
        let recovered = store.recover_running(sweep_id, version)?;
        let mut ledger = Ledger::load(store, sweep_id, version)?;
        ledger.max_attempts = Some(max_attempts);
        let gave_up = store.give_up_exhausted(sweep_id, version, max_attempts)?;
        let settled = ledger.settle_decided(store)?;
        let failed = gave_up + ledger.fail_jobs_of_failed_preps(store)?;
        let planned = ledger.plan_rounds(store)?;
        Ok((
            ledger,
            Opening {
                recovered,
                settled,
                failed,
                planned,
            },
        ))
    }
}
