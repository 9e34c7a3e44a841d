//! Slurm as an engine: job arrays on a cluster ([`crate::slurm`]). A dispatch writes the owed
//! work into a run directory and submits it; a take of stock asks squeue, collects the run
//! directories and settles arrays that ended without results.

use cellsweep_store::Store;

use super::{Dispatch, Engine, EngineError, Event, Stock, Target};
use crate::slurm::{self, SubmitOptions};

/// Slurm job arrays.
pub struct SlurmArrays {
    pub opts: SubmitOptions,
}

impl SlurmArrays {
    /// Take stock without submitting anything (`cellsweep collect`): what
    /// [`Engine::take_stock`] does, and needs no submission options.
    pub fn collect(
        store: &mut Store,
        target: Target<'_>,
        on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Stock, EngineError> {
        // The queue is asked before the run directories are read (slurm::take_stock), so a
        // task that ends between the two is still counted as running and collected next time.
        let stock = slurm::take_stock(store, target.sweep_id, target.name, target.version)?;
        if stock.found_again > 0 {
            on(Event::FoundAgain {
                arrays: stock.found_again,
            });
        }
        for (dir, collected) in &stock.collected {
            on(Event::Collected { dir, collected });
        }
        for kind in &stock.ended.failures {
            on(Event::EndedWithoutResult { kind });
        }
        // Without an answer from the queue nothing may be sent: jobs still queued would look
        // lost.
        stock.queue?;
        Ok(Stock {
            in_flight: stock.active,
        })
    }
}

impl Engine for SlurmArrays {
    fn take_stock(
        &mut self,
        store: &mut Store,
        target: Target<'_>,
        on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Stock, EngineError> {
        SlurmArrays::collect(store, target, on)
    }

    fn dispatch(
        &mut self,
        store: &mut Store,
        target: Target<'_>,
        on: &mut dyn FnMut(Event<'_>),
    ) -> Result<Dispatch, EngineError> {
        let sub = slurm::submit(
            store,
            target.sweep_id,
            target.name,
            target.version,
            &self.opts,
        )?;
        if sub.opening.failed > 0 {
            on(Event::OutOfAttempts {
                count: sub.opening.failed,
                max_attempts: self.opts.max_attempts,
            });
        }
        if sub.scripts.is_empty() {
            return Ok(Dispatch::Nothing);
        }
        on(Event::Submitted(&sub));
        Ok(Dispatch::Sent)
    }
}
