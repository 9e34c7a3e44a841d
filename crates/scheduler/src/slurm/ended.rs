//! Arrays that have left the queue: every job or prep one of their tasks was sent and left
//! without a result gets a failed attempt through the ledger, with the reason the task's end
//! gives. Without this, a task killed as a whole (its time limit, a node, the out-of-memory
//! killer, a run directory it cannot write) leaves its jobs pending with no attempt counted, and
//! `submit --watch` sends the same work, with the same limit, for ever.
//!
//! The reason is read, best first, from the task's exit marker (written by the task itself when
//! it stops early: Slurm's warning before the time limit, its own error), Slurm's accounting
//! (`sacct`, where the cluster keeps it), and the task's log (slurmstepd's "CANCELLED ... DUE TO
//! TIME LIMIT", "DUE TO NODE FAILURE", an out-of-memory kill, the worker's `Error:` line).

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

use cellsweep_store::{JobState, SlurmArray, Store};
use serde::Deserialize;

use super::array_task::exit_marker;
use super::queue::{run_with_timeout, Queue, SQUEUE_TIMEOUT};
use super::ArrayKind;
use crate::error::SlurmError;
use crate::ledger::{Failure, Ledger, TaskRef};

/// What examining the ended arrays did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Ended {
    /// Arrays seen to have left the queue now.
    pub arrays: usize,
    /// Failed attempts recorded, by kind of reason (the words before its first colon: "time
    /// limit", "out of memory", "the worker failed", ...), each with how many and one reason
    /// in full (they differ by array and task).
    pub failures: Vec<EndedKind>,
}

/// Failed attempts of one kind of reason.
#[derive(Debug, Clone, PartialEq)]
pub struct EndedKind {
    pub kind: String,
    pub count: usize,
    pub example: String,
}

impl Ended {
    /// Failed attempts recorded in all.
    pub fn attempts(&self) -> usize {
        self.failures.iter().map(|k| k.count).sum()
    }

    fn count(&mut self, why: &str) {
        let kind = why.split(':').next().unwrap_or(why).trim().to_string();
        match self.failures.iter_mut().find(|k| k.kind == kind) {
            Some(k) => k.count += 1,
            None => self.failures.push(EndedKind {
                kind,
                count: 1,
                example: why.to_string(),
            }),
        }
    }
}

/// The fields of a task file's line that say which attempt of which job or prep it sent.
#[derive(Deserialize)]
struct Sent {
    task: i64,
    attempt: u32,
}

/// Examine every array of the ledger's sweep that `queue` no longer holds and that was not
/// examined before: record a failed attempt for each of its jobs (preps) still without a
/// result, then mark the array ended. Call it after collecting the run directory with the
/// queue asked *before* collecting, so that a task that ended in between is still counted as
/// queued (and examined next time, once its records are in).
pub fn settle_ended_arrays(
    ledger: &Ledger,
    store: &mut Store,
    queue: &Queue,
) -> Result<Ended, SlurmError> {
    let mut ended = Ended::default();
    for a in store.open_arrays_of(ledger.sweep_id, &ledger.version)? {
        // An array still being submitted is found again, or forgotten, by `submit`.
        let Some(id) = a.slurm_job_id.clone() else {
            continue;
        };
        if queue.holds(&id) {
            continue;
        }
        if let Some(sub) = &a.sub_dir {
            examine(ledger, store, &a, &id, Path::new(sub), &mut ended)?;
        }
        store.array_ended(a.id, cellsweep_store::now())?;
        ended.arrays += 1;
    }
    Ok(ended)
}

fn examine(
    ledger: &Ledger,
    store: &mut Store,
    a: &SlurmArray,
    slurm_id: &str,
    sub: &Path,
    ended: &mut Ended,
) -> Result<(), SlurmError> {
    // The store's CHECK holds `prep` or `collide`; anything else is not an array of ours.
    let Ok(kind) = a.kind.parse::<ArrayKind>() else {
        return Ok(());
    };
    let mut accounting: Option<HashMap<String, String>> = None;
    for k in 0..a.tasks.max(0) as usize {
        let file = sub.join(format!("tasks/{kind}/{k}.jsonl"));
        let Ok(text) = std::fs::read_to_string(&file) else {
            continue;
        };
        let mut reason: Option<String> = None;
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let Ok(sent) = serde_json::from_str::<Sent>(line) else {
                continue;
            };
            let (of, open) = match kind {
                ArrayKind::Prep => (
                    TaskRef::Prep(sent.task),
                    store
                        .prep_identity(sent.task, ledger.sweep_id)?
                        .is_some_and(|p| p.state != JobState::Done && p.state != JobState::Failed),
                ),
                _ => (
                    TaskRef::Job(sent.task),
                    store
                        .job_identity(sent.task)?
                        .is_some_and(|j| matches!(j.state, JobState::Pending | JobState::Running)),
                ),
            };
            if !open {
                continue;
            }
            let why = reason.get_or_insert_with(|| {
                let acct = accounting.get_or_insert_with(|| sacct_states(slurm_id));
                end_reason(store, ledger, sub, kind, k, slurm_id, acct)
            });
            match ledger.fail(store, of, sent.attempt, why)? {
                Failure::Retry | Failure::GaveUp { .. } => ended.count(why),
                Failure::Already | Failure::PrepNotReady => {}
            }
        }
    }
    Ok(())
}

/// Each task's final state in Slurm's accounting (`sacct`), by task index; empty where the
/// cluster keeps no accounting or sacct does not answer.
fn sacct_states(slurm_id: &str) -> HashMap<String, String> {
    let Ok(out) = run_with_timeout(
        Command::new("sacct").args(["-n", "-P", "-X", "-j", slurm_id, "-o", "JobID,State"]),
        SQUEUE_TIMEOUT,
    ) else {
        return HashMap::new();
    };
    out.lines()
        .filter_map(|l| {
            let (job, state) = l.trim().split_once('|')?;
            let task = job.strip_prefix(slurm_id)?.strip_prefix('_')?;
            Some((
                task.to_string(),
                state.split_whitespace().next()?.to_string(),
            ))
        })
        .collect()
}

/// Why task `k` of the array ended without a result for some of its jobs.
fn end_reason(
    store: &Store,
    ledger: &Ledger,
    sub: &Path,
    kind: ArrayKind,
    k: usize,
    slurm_id: &str,
    accounting: &HashMap<String, String>,
) -> String {
    let place = format!("array {slurm_id}, task {k}");
    if let Ok(text) = std::fs::read_to_string(exit_marker(sub, kind, k)) {
        let text = text.trim();
        if text.starts_with("time limit") {
            return format!(
                "{text} ({place}); {}",
                time_advice(store, ledger, sub, kind)
            );
        }
        return format!("{text} ({place})");
    }
    let log = sub.join(format!("logs/{kind}-{k}.out"));
    let tail = read_tail(&log);
    let state = accounting.get(&k.to_string()).map(String::as_str);
    let time = state == Some("TIMEOUT") || tail.contains("DUE TO TIME LIMIT");
    if time {
        return format!(
            "time limit: Slurm stopped the task at its time limit ({place}); {}",
            time_advice(store, ledger, sub, kind)
        );
    }
    let lower = tail.to_lowercase();
    if state == Some("OUT_OF_MEMORY")
        || lower.contains("oom-kill")
        || lower.contains("out of memory")
        || lower.contains("exceeded job memory limit")
    {
        return format!("out of memory: the task was killed for its memory ({place}); ask for more with --sbatch-arg=--mem=...");
    }
    if state == Some("NODE_FAIL") || tail.contains("DUE TO NODE FAILURE") {
        return format!("node failure: the task's node failed ({place})");
    }
    if let Some(line) = tail.lines().rev().find(|l| l.starts_with("Error: ")) {
        return format!(
            "the worker failed: {} ({place}; log {})",
            &line[7..],
            log.display()
        );
    }
    if state == Some("CANCELLED") || tail.contains("CANCELLED") {
        return format!("cancelled: the task was cancelled ({place})");
    }
    if let Some(s) = state {
        return format!(
            "the task ended {s} without a result for this job ({place}; log {})",
            log.display()
        );
    }
    if log.exists() {
        format!("the task ended without a result for this job and its log says no more ({place}; log {})", log.display())
    } else {
        format!("the task left the queue without starting (cancelled while pending?) ({place})")
    }
}

/// The last 64 KiB of a log (where slurmstepd's and the worker's last words are).
fn read_tail(path: &Path) -> String {
    let Ok(bytes) = std::fs::read(path) else {
        return String::new();
    };
    let from = bytes.len().saturating_sub(64 * 1024);
    String::from_utf8_lossy(&bytes[from..]).into_owned()
}

/// What a time limit that fits would be: the script's limit, the jobs per task, and the
/// sweep's measured time per collision.
fn time_advice(store: &Store, ledger: &Ledger, sub: &Path, kind: ArrayKind) -> String {
    let script = std::fs::read_to_string(sub.join(format!("{kind}.sbatch"))).unwrap_or_default();
    let limit = script
        .lines()
        .find_map(|l| l.strip_prefix("#SBATCH --time="))
        .map_or("the partition's default".to_string(), |t| {
            format!("--time {t}")
        });
    let per_task = std::fs::read_to_string(sub.join(format!("tasks/{kind}/0.jsonl")))
        .map(|t| t.lines().filter(|l| !l.trim().is_empty()).count())
        .unwrap_or(0);
    let measured = match kind {
        ArrayKind::Collide => store
            .mean_collision_wall_s(ledger.sweep_id, &ledger.version)
            .ok()
            .flatten(),
        _ => None,
    };
    match measured {
        Some(s) if per_task > 0 => {
            let need = s * per_task as f64 * 1.5 + 180.0;
            format!(
                "the limit was {limit}; this sweep's collisions took {s:.0} s each so far, so {per_task} per task need a limit of at least {} (or fewer --jobs-per-task)",
                slurm_duration(need)
            )
        }
        _ => format!("the limit was {limit}; no {kind} of this sweep has finished to measure: ask for more (--time) or fewer --jobs-per-task"),
    }
}

/// Seconds in Slurm's `D-HH:MM:SS`, rounded up to the minute.
fn slurm_duration(seconds: f64) -> String {
    let m = (seconds / 60.0).ceil().max(1.0) as u64;
    let (d, h, m) = (m / 1440, (m / 60) % 24, m % 60);
    if d > 0 {
        format!("{d}-{h:02}:{m:02}:00")
    } else {
        format!("{h:02}:{m:02}:00")
    }
}

#[cfg(test)]
mod tests {
    use super::slurm_duration;

    #[test]
    fn durations_are_written_as_slurm_reads_them() {
        assert_eq!(slurm_duration(1.0), "00:01:00");
        assert_eq!(slurm_duration(3601.0), "01:01:00");
        assert_eq!(slurm_duration(90_000.0), "1-01:00:00");
    }
}
