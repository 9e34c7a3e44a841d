//! The one loop that drives an engine: take stock, dispatch what is owed, and (watching) wait
//! for what was sent, waiting out an engine that does not answer with a back-off.

use std::time::{Duration, Instant};

use cellsweep_store::Store;

use super::{Dispatch, Engine, EngineError, Event, Target};

/// How to drive.
#[derive(Debug, Clone, Copy)]
pub struct DriveOptions {
    /// Stay until the sweep is finished: wait for what was sent, send the next rounds, wait
    /// out an engine that does not answer. Without it, one dispatch and back.
    pub watch: bool,
    /// Seconds between looks while work is in flight, and the first wait after a failure.
    pub poll: f64,
    /// Seconds of consecutive failures after which a watch gives up.
    pub give_up_after: f64,
}

/// How a drive ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Finish {
    /// Nothing is left to do: every job has a result or failed for good (`failed` of them).
    /// `ran`: work was dispatched on the way (false: there was nothing to do).
    Done { failed: u64, ran: bool },
    /// Work was sent and the caller does not watch: its results come back later.
    Sent,
    /// Stopped by Ctrl-C or SIGTERM; unfinished work is pending again.
    Interrupted,
}

/// One look, as the loop sees it.
enum Look {
    Finished(Finish),
    Wait,
}

/// Drive `engine` on `target` until the sweep is finished (or, without `watch`, once work is
/// sent). A look whose engine does not answer is tried again after a wait that doubles from
/// `poll` (at most 5 minutes) until it has failed for `give_up_after`.
pub fn drive(
    engine: &mut dyn Engine,
    store: &mut Store,
    target: Target<'_>,
    opts: DriveOptions,
    on: &mut dyn FnMut(Event<'_>),
) -> Result<Finish, EngineError> {
    let mut trouble: Option<(Instant, u32)> = None;
    let mut ran = false;
    loop {
        let wait = match look(engine, store, target, opts.watch, &mut ran, on) {
            Ok(Look::Finished(f)) => return Ok(f),
            Ok(Look::Wait) => {
                trouble = None;
                opts.poll
            }
            Err(e) if opts.watch && e.is_transient() => {
                let (since, n) = trouble.get_or_insert((Instant::now(), 0));
                *n += 1;
                let failing = since.elapsed().as_secs_f64();
                if failing >= opts.give_up_after {
                    return Err(EngineError::GaveUp {
                        last: Box::new(e),
                        failing,
                        limit: opts.give_up_after,
                    });
                }
                let wait = (opts.poll * 2f64.powi(*n as i32 - 1))
                    .min(300f64.max(opts.poll))
                    .min(opts.give_up_after - failing);
                on(Event::Retrying {
                    error: &e,
                    wait,
                    failures: *n,
                    give_up_after: opts.give_up_after,
                });
                wait
            }
            Err(EngineError::Queue(source)) => {
                return Err(EngineError::QueueUnknown {
                    name: target.name.to_string(),
                    source,
                })
            }
            Err(e) => return Err(e),
        };
        std::thread::sleep(Duration::from_secs_f64(wait.max(0.0)));
    }
}

/// One look: take in what finished, then dispatch what is owed if nothing is in flight.
fn look(
    engine: &mut dyn Engine,
    store: &mut Store,
    target: Target<'_>,
    watch: bool,
    ran: &mut bool,
    on: &mut dyn FnMut(Event<'_>),
) -> Result<Look, EngineError> {
    let stock = engine.take_stock(store, target, on)?;
    if stock.in_flight > 0 {
        return match watch {
            true => Ok(Look::Wait),
            false => Err(EngineError::StillRunning {
                name: target.name.to_string(),
                active: stock.in_flight,
            }),
        };
    }
    Ok(match engine.dispatch(store, target, on)? {
        Dispatch::Nothing => Look::Finished(Finish::Done {
            failed: failed_jobs(store, target)?,
            ran: *ran,
        }),
        Dispatch::Sent if watch => {
            *ran = true;
            Look::Wait
        }
        Dispatch::Sent => Look::Finished(Finish::Sent),
        Dispatch::Ran { interrupted: true } => Look::Finished(Finish::Interrupted),
        // Ran here to its end, every round included.
        Dispatch::Ran { interrupted: false } => Look::Finished(Finish::Done {
            failed: failed_jobs(store, target)?,
            ran: true,
        }),
    })
}

/// Jobs of the sweep that failed for good (after their attempts).
fn failed_jobs(store: &Store, target: Target<'_>) -> Result<u64, EngineError> {
    Ok(store
        .status()?
        .into_iter()
        .find(|s| s.sweep == target.name && s.solver_version == target.version)
        .map_or(0, |s| s.jobs.failed as u64))
}
