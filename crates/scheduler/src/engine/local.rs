//! The local engine: worker processes on this machine ([`crate::coordinator`]). It runs
//! everything owed, every adaptive round and refinement included, in one dispatch; nothing is
//! ever in flight between looks.

use cellsweep_store::Store;

use super::{Dispatch, Engine, EngineError, Event, Stock, Target};
use crate::coordinator::{run_sweep, Ending, Reporter, RunOptions};
use crate::ledger::Ledger;

/// Worker processes on this machine.
pub struct Local<'r> {
    opts: RunOptions,
    reporter: &'r mut dyn Reporter,
}

impl<'r> Local<'r> {
    pub fn new(opts: RunOptions, reporter: &'r mut dyn Reporter) -> Self {
        Local { opts, reporter }
    }
}

impl Engine for Local<'_> {
    fn take_stock(
        &mut self,
        _store: &mut Store,
        _target: Target<'_>,
        _on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Stock, EngineError> {
        // A local run leaves nothing in flight: a stop puts its running work back to pending
        // (and the ledger's opening recovers what a kill left `running`).
        Ok(Stock::default())
    }

    fn dispatch(
        &mut self,
        store: &mut Store,
        target: Target<'_>,
        _on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Dispatch, EngineError> {
        if !owes_work(store, target)? {
            return Ok(Dispatch::Nothing);
        }
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .map_err(EngineError::Runtime)?;
        let report = runtime.block_on(run_sweep(
            store,
            target.sweep_id,
            target.version,
            self.opts.clone(),
            self.reporter,
        ))?;
        Ok(Dispatch::Ran {
            interrupted: report.ending == Ending::Interrupted,
        })
    }
}

/// Whether the sweep has work to run: a job or prep not yet settled, after planning any
/// adaptive round or refinement it is owed.
fn owes_work(store: &mut Store, target: Target<'_>) -> Result<bool, EngineError> {
    Ledger::load(store, target.sweep_id, target.version)?.plan_rounds(store)?;
    let status = store
        .status()?
        .into_iter()
        .find(|s| s.sweep == target.name && s.solver_version == target.version);
    Ok(status.is_none_or(|s| s.jobs.pending + s.jobs.running > 0 || s.preps_done != s.preps_total))
}
