//! Slurm's queue as `squeue` reports it for one sweep, and the one rule that reads it: no answer
//! is not an empty answer.
//!
//! The sweep's arrays are asked for by job name (`cellsweep-NAME-prep`, `cellsweep-NAME-collide`),
//! not by id: `squeue -j ID` fails outright once any one of the ids has been purged from the
//! controller (MinJobAge), which would make every old sweep's queue unknowable. Each task line
//! carries its array's id, its state and the script it runs, so an array whose id the store
//! never learned (a kill between sbatch and the store) is found again by its script.

use super::ArrayKind;
use crate::error::QueueError;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long `squeue` may take before it counts as not answering.
pub const SQUEUE_TIMEOUT: Duration = Duration::from_secs(60);

/// One array task in the queue.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QueuedTask {
    /// The array's job id (squeue's `%F`).
    pub array_id: String,
    /// Slurm's state word (PENDING, RUNNING, COMPLETING, ...).
    pub state: String,
    /// The batch script the task runs (`%o`).
    pub script: String,
}

/// What squeue said of a sweep's arrays.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Queue {
    pub tasks: Vec<QueuedTask>,
}

/// The job names of a sweep's arrays (as the sbatch scripts set them).
pub fn job_name(sweep: &str, kind: ArrayKind) -> String {
    format!("cellsweep-{sweep}-{kind}")
}

impl Queue {
    /// Ask squeue for the tasks of `sweep`'s arrays.
    pub fn ask(sweep: &str) -> Result<Queue, QueueError> {
        let names = format!(
            "{},{}",
            job_name(sweep, ArrayKind::Prep),
            job_name(sweep, ArrayKind::Collide)
        );
        let out = run_with_timeout(
            Command::new("squeue").args(["-h", "-r", "--name", &names, "-o", "%F|%T|%o"]),
            SQUEUE_TIMEOUT,
        )?;
        Queue::parse(&out)
    }

    /// squeue's output, one `ARRAY_ID|STATE|SCRIPT` line per task.
    pub fn parse(text: &str) -> Result<Queue, QueueError> {
        let mut tasks = Vec::new();
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let mut parts = line.trim().splitn(3, '|');
            let (Some(id), Some(state), Some(script)) = (parts.next(), parts.next(), parts.next())
            else {
                return Err(QueueError::Unparsable(line.to_string()));
            };
            let word =
                |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !word(id) || !word(state) || !id.chars().all(|c| c.is_ascii_digit()) {
                return Err(QueueError::Unparsable(line.to_string()));
            }
            tasks.push(QueuedTask {
                array_id: id.to_string(),
                state: state.to_string(),
                script: script.to_string(),
            });
        }
        Ok(Queue { tasks })
    }

    /// Whether any task of array `id` is still in the queue.
    pub fn holds(&self, id: &str) -> bool {
        self.tasks.iter().any(|t| t.array_id == id)
    }

    /// Counts of the tasks of arrays `ids` by state, in order of first appearance.
    pub fn states_of(&self, ids: &[&str]) -> Vec<(String, usize)> {
        let mut counts: Vec<(String, usize)> = Vec::new();
        for t in self
            .tasks
            .iter()
            .filter(|t| ids.contains(&t.array_id.as_str()))
        {
            match counts.iter_mut().find(|(k, _)| *k == t.state) {
                Some((_, n)) => *n += 1,
                None => counts.push((t.state.clone(), 1)),
            }
        }
        counts
    }

    /// The array that runs `script`, if it is in the queue.
    pub fn array_of_script(&self, script: &Path) -> Option<String> {
        let s = script.display().to_string();
        self.tasks
            .iter()
            .find(|t| t.script == s)
            .map(|t| t.array_id.clone())
    }
}

/// The states of the tasks of a sweep's arrays not yet seen to end, as squeue reports them
/// (what `status` and the live page show); an error where squeue does not answer, never
/// "nothing queued".
pub fn queue_of(
    sweep: &str,
    arrays: &[cellsweep_store::SlurmArray],
) -> Result<Vec<(String, usize)>, QueueError> {
    let ids: Vec<&str> = arrays
        .iter()
        .filter(|a| a.ended_at.is_none())
        .filter_map(|a| a.slurm_job_id.as_deref())
        .collect();
    if ids.is_empty() {
        return Ok(Vec::new());
    }
    Ok(Queue::ask(sweep)?.states_of(&ids))
}

/// Run a Slurm command and return its standard output, or why there is none: it could not be
/// started, it exited non-zero (its standard error quoted), or it ran past `limit` (killed).
pub fn run_with_timeout(cmd: &mut Command, limit: Duration) -> Result<String, QueueError> {
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| QueueError::NotRun(e.to_string()))?;
    // Read both pipes on threads, so that a chatty command cannot fill one and stall.
    let mut out = child.stdout.take().expect("piped");
    let mut err = child.stderr.take().expect("piped");
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut out, &mut s);
        s
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut err, &mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if start.elapsed() < limit => std::thread::sleep(Duration::from_millis(20)),
            Ok(None) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(QueueError::TimedOut(limit));
            }
            Err(e) => return Err(QueueError::NotRun(e.to_string())),
        }
    };
    let stdout = out.join().unwrap_or_default();
    let stderr = err.join().unwrap_or_default();
    if !status.success() {
        return Err(QueueError::Failed {
            status: status.to_string(),
            stderr: first_line(&stderr),
        });
    }
    Ok(stdout)
}

/// The first non-empty line of a command's message (the rest goes to its own log).
pub(crate) fn first_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .unwrap_or("(no message)")
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn task_lines_are_read_and_anything_else_is_unknown() {
        let q = Queue::parse("149|RUNNING|/r/sub-0001-7/collide.sbatch\n149|PENDING|/r/sub-0001-7/collide.sbatch\n150|PENDING|/r/x y|z.sbatch\n").unwrap();
        assert!(q.holds("149") && q.holds("150") && !q.holds("14"));
        assert_eq!(
            q.states_of(&["149"]),
            vec![("RUNNING".to_string(), 1), ("PENDING".to_string(), 1)]
        );
        assert_eq!(
            q.array_of_script(Path::new("/r/x y|z.sbatch")).as_deref(),
            Some("150")
        );
        assert_eq!(Queue::parse("").unwrap(), Queue::default());
        for bad in [
            "slurm_load_jobs error: Socket timed out",
            "149 RUNNING",
            "abc|RUNNING|/s",
            "149||/s",
        ] {
            assert!(
                matches!(Queue::parse(bad), Err(QueueError::Unparsable(_))),
                "{bad}"
            );
        }
    }

    #[test]
    fn a_failing_slow_or_missing_command_is_an_error_not_an_empty_answer() {
        let e = run_with_timeout(
            Command::new("sh").args(["-c", "echo 'Socket timed out' >&2; exit 1"]),
            SQUEUE_TIMEOUT,
        )
        .unwrap_err();
        assert!(
            matches!(&e, QueueError::Failed { stderr, .. } if stderr == "Socket timed out"),
            "{e}"
        );
        let e = run_with_timeout(
            Command::new("sh").args(["-c", "sleep 5"]),
            Duration::from_millis(200),
        )
        .unwrap_err();
        assert_eq!(e, QueueError::TimedOut(Duration::from_millis(200)));
        let e =
            run_with_timeout(&mut Command::new("/nonexistent/squeue"), SQUEUE_TIMEOUT).unwrap_err();
        assert!(matches!(e, QueueError::NotRun(_)), "{e}");
        assert_eq!(
            run_with_timeout(Command::new("sh").args(["-c", "echo ok"]), SQUEUE_TIMEOUT).unwrap(),
            "ok\n"
        );
    }
}
