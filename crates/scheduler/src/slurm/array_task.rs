//! The array task's side of a Slurm run: `cellsweep worker --slurm` on one task's requests.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use super::read_responses;
use crate::error::SlurmError;
use crate::run_dir::{io, write_atomic};
use crate::wire::{PrepPayload, Request, Response};

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_usr1(_: libc::c_int) {
    STOP.store(true, Ordering::SeqCst);
}

/// The array task's side: run the requests of `SUB_DIR/tasks/<kind>/<SLURM_ARRAY_TASK_ID>.jsonl`
/// that have no result yet, appending each response to `SUB_DIR/results/<kind>-<task>.jsonl`.
/// On SIGUSR1 (Slurm's warning before the time limit) it stops after the current record.
pub fn serve_array_task(sub_dir: &Path, kind: &str) -> Result<(), SlurmError> {
    // SAFETY: the handler only stores to an atomic.
    unsafe {
        libc::signal(libc::SIGUSR1, on_usr1 as *const () as libc::sighandler_t);
    }
    let task = array_task_id()?;
    let tasks = sub_dir.join(format!("tasks/{kind}/{task}.jsonl"));
    let results = sub_dir.join(format!("results/{kind}-{task}.jsonl"));
    let preps_dir = sub_dir
        .parent()
        .ok_or("run directory has no parent")?
        .join("preps");
    let done: std::collections::HashSet<i64> = read_responses(&results)
        .0
        .iter()
        .map(|r| r.task())
        .collect();
    let text = std::fs::read_to_string(&tasks).map_err(|e| io(e, &tasks))?;
    let mut out = open_records(&results)?;
    let mut cache = crate::worker::PrepCache::new();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    for (k, line) in lines.iter().enumerate() {
        if STOP.load(Ordering::SeqCst) {
            eprintln!("SIGUSR1: stopping before the time limit; the rest is resubmitted by `cellsweep submit`");
            break;
        }
        let mut req: Request =
            serde_json::from_str(line).map_err(|e| format!("{}: {e}", tasks.display()))?;
        if done.contains(&req.task()) {
            continue;
        }
        // In the task's Slurm log: which record runs now (after the stop check above).
        eprintln!(
            "{kind} task {task}: record {} of {} started",
            k + 1,
            lines.len()
        );
        if let Request::Collide { prep_id, prep, .. } = &mut req {
            match read_prep(&preps_dir.join(format!("{prep_id}.json"))) {
                Ok(p) => *prep = Some(Box::new(p)),
                Err(error) => {
                    // The job could not start: that is its prep's failure (recorded from the
                    // prep task), not an attempt of its own. It stays pending, and the next
                    // `submit` sends it again with its prep.
                    eprintln!("{kind} task {task}: job {} skipped: {error}", req.task());
                    continue;
                }
            }
        }
        let resp = crate::worker::answer(req, &mut cache);
        if let Response::Prep { task, prep, .. } = &resp {
            let path = preps_dir.join(format!("{task}.json"));
            // The prep file itself is the result.
            write_atomic(&path, serde_json::to_string(prep)?.as_bytes())?;
        } else {
            let mut line = serde_json::to_vec(&resp)?;
            line.push(b'\n');
            out.write_all(&line).map_err(|e| io(e, &results))?;
            out.sync_data().map_err(|e| io(e, &results))?;
        }
    }
    Ok(())
}

/// This array task's index, from Slurm.
fn array_task_id() -> Result<usize, SlurmError> {
    std::env::var("SLURM_ARRAY_TASK_ID")
        .map_err(|_| {
            "SLURM_ARRAY_TASK_ID is not set (this mode runs inside a Slurm array task)".to_string()
        })?
        .parse()
        .map_err(|e| format!("bad SLURM_ARRAY_TASK_ID: {e}").into())
}

/// The task's record file, opened to append; a torn last line (a task killed mid-write) is
/// ended first, so that the torn record stays alone (and is skipped by `collect`) instead of
/// swallowing the next.
fn open_records(results: &Path) -> Result<std::fs::File, SlurmError> {
    let mut out = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(results)
        .map_err(|e| io(e, results))?;
    let torn = std::fs::read(results)
        .map(|b| b.last().is_some_and(|&c| c != b'\n'))
        .unwrap_or(false);
    if torn {
        out.write_all(b"\n").map_err(|e| io(e, results))?;
    }
    Ok(out)
}

/// The prep file a collide record needs.
fn read_prep(path: &Path) -> Result<PrepPayload, SlurmError> {
    let text = std::fs::read_to_string(path).map_err(|e| io(e, path))?;
    serde_json::from_str::<PrepPayload>(&text)
        .map_err(|e| format!("{}: {e}", path.display()).into())
}
