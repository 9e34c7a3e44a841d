//! The worker side: `cellsweep worker` reads requests line by line, runs the solver, writes one
//! response line per request, and keeps the last few preps it saw or made.
//! With the `fault-injection` feature (the test suite's build only) the worker also obeys the
//! faults of [`crate::fault_injection`].

use std::collections::VecDeque;
use std::io::{BufRead, Write};
use std::time::Instant;

use cellsweep_solver::{collide, prepare, Prep, Silent, TrajectoryResult, Verdict};

use crate::wire::{PrepPayload, Request, Response};

/// Preps kept per worker.
pub const CACHE: usize = 4;

/// The preps a worker keeps, newest last.
pub type PrepCache = VecDeque<(i64, Prep)>;

/// Serve requests from `input` until it closes.
pub fn serve(input: impl BufRead, mut output: impl Write) -> std::io::Result<()> {
    let mut cache = PrepCache::new();
    for line in input.lines() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let response = match serde_json::from_str::<Request>(&line) {
            Ok(req) => answer(req, &mut cache),
            Err(e) => Response::Failed {
                task: -1,
                attempt: 0,
                error: format!("malformed request: {e}"),
            },
        };
        writeln!(output, "{}", serde_json::to_string(&response)?)?;
        output.flush()?;
    }
    Ok(())
}

/// The response to one request (a solver panic becomes a failure, never a crash).
pub fn answer(req: Request, cache: &mut PrepCache) -> Response {
    #[cfg(feature = "fault-injection")]
    crate::fault_injection::crash_or_hang(&req);
    let (task, attempt) = (req.task(), req.attempt());
    let failed = |error: String| Response::Failed {
        task,
        attempt,
        error,
    };
    #[cfg(feature = "fault-injection")]
    if let Some(error) = crate::fault_injection::failure(&req) {
        return failed(error);
    }
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| handle(req, cache)))
        .unwrap_or_else(|panic| {
            let msg = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            Err(JobError::Panicked(msg))
        })
        .unwrap_or_else(|e| failed(e.to_string()))
}

/// Keep `value` as prep `id` in a worker's cache of at most [`CACHE`] preps, the oldest
/// inserted going first. The coordinator keeps its copy of each worker's cache (ids only) by
/// this same function, so it knows exactly which preps a worker still holds.
pub fn remember<T>(cache: &mut VecDeque<(i64, T)>, id: i64, value: T) {
    cache.retain(|(k, _)| *k != id);
    if cache.len() == CACHE {
        cache.pop_front();
    }
    cache.push_back((id, value));
}

/// Why a job or prep gave no result (sent back as the failed attempt's error).
#[derive(Debug, thiserror::Error)]
enum JobError {
    #[error(transparent)]
    Solver(#[from] cellsweep_solver::SolverError),
    #[error(transparent)]
    Payload(#[from] crate::error::PayloadError),
    #[error("prep {0} was not sent to this worker")]
    MissingPrep(i64),
    #[error("solver panicked: {0}")]
    Panicked(String),
}

fn handle(req: Request, cache: &mut VecDeque<(i64, Prep)>) -> Result<Response, JobError> {
    let started = Instant::now();
    match req {
        Request::Prep {
            task, config, seed, ..
        } => match prepare(&config.params, &config.protocol, seed, &mut Silent) {
            Ok(prep) => {
                let payload = Box::new(PrepPayload::from_prep(&prep));
                remember(cache, task, prep);
                Ok(Response::Prep {
                    task,
                    prep: payload,
                    wall_s: started.elapsed().as_secs_f64(),
                })
            }
            Err(e) => Err(e.into()),
        },
        Request::Collide {
            task,
            config,
            seed,
            prep_id,
            prep,
            ..
        } => {
            if let Some(payload) = prep {
                remember(cache, prep_id, payload.to_prep()?);
            }
            let Some((_, prep)) = cache.iter().find(|(k, _)| *k == prep_id) else {
                return Err(JobError::MissingPrep(prep_id));
            };
            if prep.verdict != Verdict::Ok {
                // No collision starts from a cell that is not `ok` (SPEC section 4): a Slurm
                // collide task can meet one, since its array is submitted before the preps'
                // verdicts are known. The record says the prep decided the job.
                return Ok(Response::Collide {
                    task,
                    result: Box::new(TrajectoryResult::new(&config, prep, seed, None)),
                    wall_s: started.elapsed().as_secs_f64(),
                });
            }
            collide(
                &config.params,
                &config.protocol,
                &config.classifier,
                prep,
                seed,
                &mut Silent,
                false,
            )
            .map(|c| Response::Collide {
                task,
                result: Box::new(TrajectoryResult::new(&config, prep, seed, Some(&c))),
                wall_s: started.elapsed().as_secs_f64(),
            })
            .map_err(JobError::from)
        }
    }
}
