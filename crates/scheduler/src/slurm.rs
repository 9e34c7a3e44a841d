//! Slurm as the distributed engine: `submit` writes task files and sbatch scripts into a run
//! directory on the cluster's shared filesystem and submits two job arrays (preps, then
//! collisions with a dependency); array tasks run `cellsweep worker --slurm` on their slice and
//! append one JSON line per result to a file of their own; `collect` ingests those files into
//! the store, idempotently. Compute nodes never open the SQLite database.
//!
//! Run directory layout:
//! ```text
//! RUN_DIR/preps/<prep id>.json            prepped cells (written atomically: tmp + rename)
//! RUN_DIR/sub-<n>/tasks/<kind>/<task>.jsonl    requests of one array task
//! RUN_DIR/sub-<n>/results/<kind>-<task>.jsonl  one response per line, appended and flushed
//! RUN_DIR/sub-<n>/{prep,collide}.sbatch, logs/
//! ```

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use cellsweep_store::{JobState, SlurmArray, Store};

use crate::error::SlurmError;
use crate::ledger::{Failure, Ledger, Opening, Settlement, TaskRef};
use crate::run_dir::{claim_run_dir, io, run_dir_is, write_atomic};
use crate::wire::{PrepPayload, Request, Response};

/// How to submit.
#[derive(Debug, Clone)]
pub struct SubmitOptions {
    pub run_dir: PathBuf,
    pub partition: Option<String>,
    pub account: Option<String>,
    pub time: Option<String>,
    pub jobs_per_task: usize,
    /// Most array tasks running at once (`%N`).
    pub max_running: Option<usize>,
    pub sbatch_args: Vec<String>,
    /// The cellsweep executable the array tasks run (on the shared filesystem).
    pub exe: PathBuf,
    /// Failed attempts after which a task is failed for good (applied when submitting: a
    /// task out of attempts is not sent again).
    pub max_attempts: u32,
    pub dry_run: bool,
}

/// What a submission did.
#[derive(Debug, Clone, Default)]
pub struct Submission {
    /// What the ledger did before anything was sent.
    pub opening: Opening,
    pub sub_dir: PathBuf,
    pub prep_tasks: usize,
    pub preps: usize,
    pub collide_tasks: usize,
    pub jobs: usize,
    pub jobs_per_task: usize,
    pub scripts: Vec<(String, String)>,
    pub slurm_ids: Vec<(String, String)>,
}

/// MaxArraySize of the cluster (`scontrol show config`); array indices must stay below it.
pub fn max_array_size() -> Option<usize> {
    let out = std::process::Command::new("scontrol")
        .args(["show", "config"])
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines()
        .find(|l| l.trim_start().starts_with("MaxArraySize"))
        .and_then(|l| l.split('=').nth(1))
        .and_then(|v| v.trim().parse().ok())
}

/// A word for the shell, in single quotes (a quote inside becomes '\'').
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

impl SubmitOptions {
    /// Every value that reaches a script must stay on its line: no newline, carriage return
    /// or NUL (an `#SBATCH` value with a newline would end the header and run as a command);
    /// the Slurm values must be in Slurm's own syntax.
    pub fn validate(&self) -> Result<(), SlurmError> {
        let mut values: Vec<(&str, String)> = vec![
            ("--run-dir", self.run_dir.display().to_string()),
            (
                "the cellsweep executable's path",
                self.exe.display().to_string(),
            ),
        ];
        values.extend(self.partition.iter().map(|p| ("--partition", p.clone())));
        values.extend(self.account.iter().map(|a| ("--account", a.clone())));
        values.extend(self.time.iter().map(|t| ("--time", t.clone())));
        values.extend(self.sbatch_args.iter().map(|a| ("--sbatch-arg", a.clone())));
        for (flag, v) in values {
            if v.chars().any(|c| matches!(c, '\n' | '\r' | '\0')) {
                return Err(format!(
                    "{flag} {v:?} contains a newline, carriage return or NUL; nothing was written"
                )
                .into());
            }
        }
        use crate::slurm_syntax::{account, partition, sbatch_arg, time_limit};
        type Check = fn(&str) -> Result<(), String>;
        let checks: [(&str, Option<&String>, Check); 3] = [
            ("--partition", self.partition.as_ref(), partition),
            ("--account", self.account.as_ref(), account),
            ("--time", self.time.as_ref(), time_limit),
        ];
        for (flag, value, check) in checks {
            if let Some(v) = value {
                check(v).map_err(|e| format!("{flag}: {e}; nothing was written"))?;
            }
        }
        for a in &self.sbatch_args {
            sbatch_arg(a).map_err(|e| format!("--sbatch-arg: {e}; nothing was written"))?;
        }
        Ok(())
    }
}

/// The sbatch script of one array.
pub fn script(
    opts: &SubmitOptions,
    sub_dir: &Path,
    kind: &str,
    tasks: usize,
    name: &str,
) -> String {
    let mut s = String::from("#!/bin/bash\n");
    s += &format!("#SBATCH --job-name=cellsweep-{name}-{kind}\n");
    let throttle = opts.max_running.map_or(String::new(), |n| format!("%{n}"));
    s += &format!("#SBATCH --array=0-{}{throttle}\n", tasks.saturating_sub(1));
    s += &format!(
        "#SBATCH --output={}/logs/{kind}-%a.out\n",
        sub_dir.display()
    );
    s += "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n";
    // Two minutes' warning before the time limit: the task stops after its current record.
    s += "#SBATCH --signal=B:USR1@120\n";
    if let Some(p) = &opts.partition {
        s += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(a) = &opts.account {
        s += &format!("#SBATCH --account={a}\n");
    }
    if let Some(t) = &opts.time {
        s += &format!("#SBATCH --time={t}\n");
    }
    for a in &opts.sbatch_args {
        s += &format!("#SBATCH {a}\n");
    }
    s += &format!(
        "exec {} worker --slurm {} --kind {kind}\n",
        shell_quote(&opts.exe.display().to_string()),
        shell_quote(&sub_dir.display().to_string())
    );
    s
}

fn write_tasks(dir: &Path, reqs: &[Request], per_task: usize) -> Result<usize, SlurmError> {
    std::fs::create_dir_all(dir).map_err(|e| io(e, dir))?;
    let mut n = 0;
    for (k, chunk) in reqs.chunks(per_task.max(1)).enumerate() {
        let mut text = String::new();
        for r in chunk {
            text += &serde_json::to_string(r)?;
            text.push('\n');
        }
        write_atomic(&dir.join(format!("{k}.jsonl")), text.as_bytes())?;
        n += 1;
    }
    Ok(n)
}

fn sbatch(script: &Path, dependency: Option<&str>) -> Result<String, SlurmError> {
    let mut cmd = std::process::Command::new("sbatch");
    cmd.arg("--parsable");
    if let Some(d) = dependency {
        cmd.arg(format!("--dependency=afterany:{d}"));
    }
    let out = cmd
        .arg(script)
        .output()
        .map_err(|e| format!("cannot run sbatch: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "sbatch {} failed: {}",
            script.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        )
        .into());
    }
    let id = String::from_utf8_lossy(&out.stdout)
        .trim()
        .split(';')
        .next()
        .unwrap_or("")
        .to_string();
    if id.is_empty() {
        return Err("sbatch printed no job id".into());
    }
    Ok(id)
}

/// Submit the sweep's preps and jobs that have no result yet.
pub fn submit(
    store: &mut Store,
    sweep_id: i64,
    name: &str,
    version: &str,
    opts: &SubmitOptions,
) -> Result<Submission, SlurmError> {
    let preps_dir = opts.run_dir.join("preps");
    // (A dry run of a sweep never submitted has no uid yet: nothing to compare with.)
    if let Some(uid) = store.sweep_uid(sweep_id, !opts.dry_run)? {
        claim_run_dir(&opts.run_dir, &uid, opts.dry_run)?;
    }
    let mut opening = Opening::default();
    if !opts.dry_run {
        // The start every engine makes: work a killed local run left `running` is submitted
        // too, tasks out of attempts fail for good, decided preps settle their jobs, an
        // adaptive sweep plans its next round.
        opening = Ledger::open(store, sweep_id, version, opts.max_attempts)?.1;
    }
    let preps = store.preps_of(sweep_id, version)?;
    let jobs = store.pending_jobs(sweep_id, version)?;
    // Preps decided earlier: a verdict that is not ok settled its jobs (the ledger, above);
    // ok preps are written out for the collision tasks.
    let mut prep_reqs = Vec::new();
    let mut blocked = std::collections::HashSet::new();
    for p in &preps {
        match (p.state, p.verdict.as_deref()) {
            (JobState::Done, Some("ok")) => {
                let path = preps_dir.join(format!("{}.json", p.id));
                if !path.exists() && !opts.dry_run {
                    std::fs::create_dir_all(&preps_dir).map_err(|x| io(x, &preps_dir))?;
                    let payload = payload_from_store(store, p.id, p.seed)?;
                    write_atomic(&path, serde_json::to_string(&payload)?.as_bytes())?;
                }
            }
            (JobState::Done | JobState::Failed, _) => {
                blocked.insert(p.id);
            }
            _ => prep_reqs.push(Request::prep(p)?),
        }
    }
    let job_reqs = jobs
        .iter()
        .filter(|j| !blocked.contains(&j.prep_id))
        .map(|j| Request::collide(j, None))
        .collect::<Result<Vec<_>, _>>()?;
    let max_index = max_array_size().unwrap_or(1001).saturating_sub(1).max(1);
    let per_task = opts
        .jobs_per_task
        .max(1)
        .max(job_reqs.len().div_ceil(max_index));
    let prep_per_task = 1usize.max(prep_reqs.len().div_ceil(max_index));
    let n = std::fs::read_dir(&opts.run_dir)
        .map(|d| d.count())
        .unwrap_or(0);
    let sub_dir = opts
        .run_dir
        .join(format!("sub-{n:04}-{}", std::process::id()));
    let mut sub = Submission {
        opening,
        sub_dir: sub_dir.clone(),
        jobs_per_task: per_task,
        preps: prep_reqs.len(),
        jobs: job_reqs.len(),
        ..Default::default()
    };
    sub.prep_tasks = prep_reqs.len().div_ceil(prep_per_task);
    sub.collide_tasks = job_reqs.len().div_ceil(per_task);
    if sub.prep_tasks > 0 {
        sub.scripts.push((
            "prep".into(),
            script(opts, &sub_dir, "prep", sub.prep_tasks, name),
        ));
    }
    if sub.collide_tasks > 0 {
        sub.scripts.push((
            "collide".into(),
            script(opts, &sub_dir, "collide", sub.collide_tasks, name),
        ));
    }
    if opts.dry_run || sub.scripts.is_empty() {
        return Ok(sub);
    }
    for d in ["logs", "results"] {
        std::fs::create_dir_all(sub_dir.join(d)).map_err(|x| io(x, &sub_dir))?;
    }
    std::fs::create_dir_all(&preps_dir).map_err(|x| io(x, &preps_dir))?;
    write_tasks(&sub_dir.join("tasks/prep"), &prep_reqs, prep_per_task)?;
    write_tasks(&sub_dir.join("tasks/collide"), &job_reqs, per_task)?;
    let mut previous: Option<String> = None;
    for (kind, text) in sub.scripts.clone() {
        let path = sub_dir.join(format!("{kind}.sbatch"));
        write_atomic(&path, text.as_bytes())?;
        let id = sbatch(&path, previous.as_deref())?;
        let (tasks, count) = if kind == "prep" {
            (sub.prep_tasks, sub.preps)
        } else {
            (sub.collide_tasks, sub.jobs)
        };
        store.record_array(
            sweep_id,
            version,
            &SlurmArray {
                kind: kind.clone(),
                slurm_job_id: id.clone(),
                run_dir: opts.run_dir.display().to_string(),
                tasks: tasks as i64,
                jobs: count as i64,
                submitted_at: cellsweep_store::now(),
            },
        )?;
        sub.slurm_ids.push((kind, id.clone()));
        previous = Some(id);
    }
    Ok(sub)
}

fn payload_from_store(store: &Store, prep_id: i64, seed: u64) -> Result<PrepPayload, SlurmError> {
    Ok(PrepPayload::from_record(store.load_prep(prep_id)?, seed)?)
}

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
    let task: usize = std::env::var("SLURM_ARRAY_TASK_ID")
        .map_err(|_| {
            "SLURM_ARRAY_TASK_ID is not set (this mode runs inside a Slurm array task)".to_string()
        })?
        .parse()
        .map_err(|e| format!("bad SLURM_ARRAY_TASK_ID: {e}"))?;
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
    let mut out = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&results)
        .map_err(|e| io(e, &results))?;
    // A task killed mid-write left a torn last line: start on a fresh one, so that the torn
    // record stays alone (and is skipped by `collect`) instead of swallowing the next.
    let torn = std::fs::read(&results)
        .map(|b| b.last().is_some_and(|&c| c != b'\n'))
        .unwrap_or(false);
    if torn {
        out.write_all(b"\n").map_err(|e| io(e, &results))?;
    }
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
            let path = preps_dir.join(format!("{prep_id}.json"));
            match std::fs::read_to_string(&path)
                .map_err(|e| io(e, &path))
                .and_then(|t| {
                    serde_json::from_str::<PrepPayload>(&t)
                        .map_err(|e| format!("{}: {e}", path.display()).into())
                }) {
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

/// Complete responses of a results file, and the problems met (a torn or malformed line).
pub fn read_responses(path: &Path) -> (Vec<Response>, Vec<String>) {
    let Ok(bytes) = std::fs::read(path) else {
        return (Vec::new(), Vec::new());
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
        return Err(format!("sweep {sweep_id} has no uid in the store").into());
    };
    if let Err(why) = run_dir_is(run_dir, &uid) {
        c.problems.push(why.to_string());
        return Ok(c);
    }
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
    let mut files = Vec::new();
    if let Ok(subs) = std::fs::read_dir(run_dir) {
        for sub in subs.flatten() {
            if let Ok(rs) = std::fs::read_dir(sub.path().join("results")) {
                files.extend(rs.flatten().map(|f| f.path()));
            }
        }
    }
    files.sort();
    for f in files {
        // A prep task's file holds only its failures (a prep's result is its prep file).
        let prep_file = f
            .file_name()
            .is_some_and(|n| n.to_string_lossy().starts_with("prep-"));
        let (responses, problems) = read_responses(&f);
        c.problems.extend(problems);
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
    }
    c.planned = ledger.plan_rounds(store)?;
    Ok(c)
}

/// Counts of the sweep's array tasks by Slurm state (squeue), where Slurm answers.
pub fn queue_states(job_ids: &[String]) -> Option<Vec<(String, usize)>> {
    if job_ids.is_empty() {
        return Some(Vec::new());
    }
    let out = std::process::Command::new("squeue")
        .args(["-h", "-r", "-o", "%T", "-j", &job_ids.join(",")])
        .output()
        .ok()?;
    let mut counts: Vec<(String, usize)> = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let s = line.trim().to_string();
        match counts.iter_mut().find(|(k, _)| *k == s) {
            Some((_, n)) => *n += 1,
            None => counts.push((s, 1)),
        }
    }
    Some(counts)
}
