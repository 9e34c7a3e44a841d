//! The array task's side of a Slurm run: `cellsweep worker --slurm` on one task's requests.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use super::{read_responses, ArrayKind};
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
/// A task that stops before its last record says why in its exit marker
/// (`SUB_DIR/exits/<kind>-<task>.txt`, one line, best effort: the run directory may be what
/// failed), which `collect` gives as the reason of the jobs left without a result.
pub fn serve_array_task(sub_dir: &Path, kind: ArrayKind) -> Result<(), SlurmError> {
    // SAFETY: the handler only stores to an atomic.
    unsafe {
        libc::signal(libc::SIGUSR1, on_usr1 as *const () as libc::sighandler_t);
    }
    let task = array_task_id()?;
    let outcome = serve_task(sub_dir, kind, task);
    let why = match &outcome {
        Ok(Some(stopped)) => Some(stopped.clone()),
        Ok(None) => None,
        Err(e) => Some(format!("the worker failed: {e}")),
    };
    if let Some(why) = why {
        let dir = sub_dir.join("exits");
        let _ = std::fs::create_dir_all(&dir)
            .map_err(|e| io(e, &dir))
            .and_then(|_| write_atomic(&exit_marker(sub_dir, kind, task), why.as_bytes()));
    }
    outcome.map(|_| ())
}

/// Where an array task says why it stopped early.
pub(crate) fn exit_marker(sub_dir: &Path, kind: ArrayKind, task: usize) -> std::path::PathBuf {
    sub_dir.join(format!("exits/{kind}-{task}.txt"))
}

/// The task's records; `Some(why)` where it stopped before the last.
fn serve_task(sub_dir: &Path, kind: ArrayKind, task: usize) -> Result<Option<String>, SlurmError> {
    let tasks = sub_dir.join(format!("tasks/{kind}/{task}.jsonl"));
    let results = sub_dir.join(format!("results/{kind}-{task}.jsonl"));
    let preps_dir = sub_dir
        .parent()
        .ok_or_else(|| SlurmError::Refused("run directory has no parent".into()))?
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
            return Ok(Some(format!(
                "time limit: the task had Slurm's warning before its time limit (SIGUSR1) after {k} of its {} records",
                lines.len()
            )));
        }
        let mut req: Request = serde_json::from_str(line)
            .map_err(|e| SlurmError::Refused(format!("{}: {e}", tasks.display())))?;
        if done.contains(&req.task()) {
            continue;
        }
        // In the task's Slurm log: which record runs now (after the stop check above).
        eprintln!(
            "{kind} task {task}: record {} of {} started",
            k + 1,
            lines.len()
        );
        let mut unreadable = None;
        if let Request::Collide { prep_id, prep, .. } = &mut req {
            let path = preps_dir.join(format!("{prep_id}.json"));
            match read_prep(&path) {
                Ok(p) => *prep = Some(Box::new(p)),
                // No file: its prep task has not made it (it failed, or ran out of time). That
                // is the prep's failure, not an attempt of the job's: the job stays pending,
                // and the next `submit` sends it again with its prep.
                Err(error) if !path.exists() => {
                    eprintln!("{kind} task {task}: job {} skipped: {error}", req.task());
                    continue;
                }
                // A file that cannot be read is damaged: the job fails an attempt through the
                // ledger like any other, and the next `submit` writes the file again.
                Err(error) => unreadable = Some(format!("cannot read its prep file: {error}")),
            }
        }
        let resp = match unreadable {
            Some(error) => {
                eprintln!("{kind} task {task}: job {} failed: {error}", req.task());
                Response::Failed {
                    task: req.task(),
                    attempt: req.attempt(),
                    error,
                }
            }
            None => crate::worker::answer(req, &mut cache),
        };
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
    Ok(None)
}

/// This array task's index, from Slurm.
fn array_task_id() -> Result<usize, SlurmError> {
    std::env::var("SLURM_ARRAY_TASK_ID")
        .map_err(|_| {
            SlurmError::Refused(
                "SLURM_ARRAY_TASK_ID is not set (this mode runs inside a Slurm array task)".into(),
            )
        })?
        .parse()
        .map_err(|e| SlurmError::Refused(format!("bad SLURM_ARRAY_TASK_ID: {e}")))
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
pub(super) fn read_prep(path: &Path) -> Result<PrepPayload, SlurmError> {
    let text = std::fs::read_to_string(path).map_err(|e| io(e, path))?;
    serde_json::from_str::<PrepPayload>(&text)
        .map_err(|e| SlurmError::Refused(format!("{}: {e}", path.display())))
}
