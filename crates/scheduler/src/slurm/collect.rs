//! `collect`: the records of a run directory read back into the store through the ledger.

use std::path::{Path, PathBuf};

use cellsweep_store::{JobState, Store};

use crate::error::SlurmError;
use crate::ledger::{Failure, Ledger, Settlement, TaskRef};
use crate::run_dir::run_dir_is;
use crate::wire::{PrepPayload, Response};

/// Complete responses of a results file, and the problems met (a torn or malformed line).
pub fn read_responses(path: &Path) -> (Vec<Response>, Vec<String>) {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return (Vec::new(), Vec::new()),
        Err(e) => {
            return (
                Vec::new(),
                vec![format!("{}: cannot be read, skipped: {e}", path.display())],
            )
        }
    };
    let mut good = Vec::new();
    let mut bad = Vec::new();
    let text = String::from_utf8_lossy(&bytes);
    let complete = text.ends_with('\n');
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let last = i + 1 == lines.len();
        match serde_json::from_str::<Response>(line) {
            Ok(r) if !last || complete => good.push(r),
            Ok(_) | Err(_) if last && !complete => bad.push(format!(
                "{}: line {}: torn record (no newline), skipped",
                path.display(),
                i + 1
            )),
            Err(e) => bad.push(format!(
                "{}: line {}: malformed record, skipped: {e}",
                path.display(),
                i + 1
            )),
            Ok(_) => unreachable!(),
        }
    }
    (good, bad)
}

/// What `collect` did.
#[derive(Debug, Clone, Default)]
pub struct Collected {
    pub preps: usize,
    pub results: usize,
    pub already: usize,
    /// Failed attempts recorded now (each kept with its error and number).
    pub failures: usize,
    pub problems: Vec<String>,
    /// Jobs of an adaptive sweep's next rounds, added after collecting.
    pub planned: usize,
}

/// Ingest the result files under `run_dir` into the store through the ledger, which checks
/// every record against the job or prep it claims; collecting twice changes nothing. Then an
/// adaptive sweep's next rounds are planned (`planned` jobs).
pub fn collect(
    store: &mut Store,
    sweep_id: i64,
    version: &str,
    run_dir: &Path,
) -> Result<Collected, SlurmError> {
    let ledger = Ledger::load(store, sweep_id, version)?;
    let mut c = Collected::default();
    let Some(uid) = store.sweep_uid(sweep_id, true)? else {
        return Err(SlurmError::Refused(format!(
            "sweep {sweep_id} has no uid in the store"
        )));
    };
    if let Err(why) = run_dir_is(run_dir, &uid) {
        c.problems.push(why.to_string());
        return Ok(c);
    }
    collect_preps(&ledger, store, sweep_id, version, run_dir, &mut c)?;
    for f in result_files(run_dir, &mut c.problems) {
        collect_file(&ledger, store, &f, &mut c)?;
    }
    c.planned = ledger.plan_rounds(store)?;
    Ok(c)
}

/// Take in the prep files of preps not yet done (each settles the jobs of its prep).
fn collect_preps(
    ledger: &Ledger,
    store: &mut Store,
    sweep_id: i64,
    version: &str,
    run_dir: &Path,
    c: &mut Collected,
) -> Result<(), SlurmError> {
    let preps = store.preps_of(sweep_id, version)?;
    let preps_dir = run_dir.join("preps");
    for p in preps.iter().filter(|p| p.state != JobState::Done) {
        let path = preps_dir.join(format!("{}.json", p.id));
        if !path.exists() {
            continue;
        }
        let payload = match std::fs::read_to_string(&path)
            .map_err(|x| x.to_string())
            .and_then(|t| serde_json::from_str::<PrepPayload>(&t).map_err(|x| x.to_string()))
        {
            Ok(p) => p,
            Err(x) => {
                c.problems
                    .push(format!("{}: malformed prep, skipped: {x}", path.display()));
                continue;
            }
        };
        let s = ledger.settle_prep(store, p.id, &payload, 0.0)?;
        match s.settlement {
            Settlement::New => c.preps += 1,
            Settlement::Already => {}
            Settlement::Refused(why) => {
                c.problems
                    .push(format!("{}: refused: {why}", path.display()));
            }
        }
        c.results += s.jobs_settled;
    }
    Ok(())
}

/// Every record file of every submission under the run directory, in order; an entry that is
/// not a plain file (a directory named like one) is reported and skipped.
fn result_files(run_dir: &Path, problems: &mut Vec<String>) -> Vec<PathBuf> {
    let mut files = Vec::new();
    if let Ok(subs) = std::fs::read_dir(run_dir) {
        for sub in subs.flatten() {
            if let Ok(rs) = std::fs::read_dir(sub.path().join("results")) {
                for f in rs.flatten() {
                    let path = f.path();
                    match std::fs::metadata(&path) {
                        Ok(m) if m.is_file() => files.push(path),
                        Ok(_) => problems.push(format!(
                            "{}: not a results file (a directory or device), skipped",
                            path.display()
                        )),
                        Err(e) => problems
                            .push(format!("{}: cannot be read, skipped: {e}", path.display())),
                    }
                }
            }
        }
    }
    files.sort();
    problems.sort();
    files
}

/// Take in one record file: its results, and its failures as attempts of their task.
fn collect_file(
    ledger: &Ledger,
    store: &mut Store,
    f: &Path,
    c: &mut Collected,
) -> Result<(), SlurmError> {
    // A prep task's file holds only its failures (a prep's result is its prep file).
    let prep_file = f
        .file_name()
        .is_some_and(|n| n.to_string_lossy().starts_with("prep-"));
    let (responses, problems) = read_responses(f);
    c.problems.extend(problems);
    // One transaction per file, not per record: each record is still checked against its job
    // on its own and committed whole, and a commit per record capped `collect` at about 5,000
    // records a second. An error (not a refusal) rolls the file back; collecting again redoes
    // it, since a record already taken changes nothing.
    let mut counted = Collected::default();
    store.atomically(|store| {
        settle_responses(ledger, store, f, prep_file, responses, &mut counted)
    })?;
    c.results += counted.results;
    c.already += counted.already;
    c.failures += counted.failures;
    c.problems.extend(counted.problems);
    Ok(())
}

/// Settle a file's records through the ledger, counting into `c`.
fn settle_responses(
    ledger: &Ledger,
    store: &mut Store,
    f: &Path,
    prep_file: bool,
    responses: Vec<Response>,
    c: &mut Collected,
) -> Result<(), SlurmError> {
    for r in responses {
        match r {
            Response::Collide {
                task,
                result,
                wall_s,
            } => match ledger.settle_job(store, task, &result, wall_s)? {
                Settlement::New => c.results += 1,
                Settlement::Already => c.already += 1,
                Settlement::Refused(why) => {
                    c.problems.push(format!("{}: refused: {why}", f.display()))
                }
            },
            Response::Failed {
                task,
                attempt,
                error,
            } => {
                let of = if prep_file {
                    TaskRef::Prep(task)
                } else {
                    TaskRef::Job(task)
                };
                match ledger.fail(store, of, attempt, &error)? {
                    Failure::Retry | Failure::GaveUp { .. } => c.failures += 1,
                    Failure::Already | Failure::PrepNotReady => {}
                }
            }
            Response::Prep { .. } => {}
        }
    }
    Ok(())
}
