//! Slurm's own commands and syntax: the cluster's MaxArraySize, the sbatch scripts (every value
//! checked to stay on its line) and `sbatch` itself; the queue is [`super::Queue`].

use std::path::Path;

use super::queue::{run_with_timeout, SQUEUE_TIMEOUT};
use super::{ArrayKind, SubmitOptions};
use crate::error::QueueError;
use crate::error::SlurmError;

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

/// `s` as one word for a POSIX shell: bare when it is plainly safe, else in single quotes (a
/// quote inside becomes '\''). The one quoting of the project: sbatch scripts and the commands
/// the live page offers.
pub fn shell_quote(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c));
    match plain {
        true => s.to_string(),
        false => format!("'{}'", s.replace('\'', "'\\''")),
    }
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
                return Err(SlurmError::Refused(format!(
                    "{flag} {v:?} contains a newline, carriage return or NUL; nothing was written"
                )));
            }
        }
        use crate::slurm_syntax::{account, partition, sbatch_arg, time_limit};
        type Check = fn(&str) -> Result<(), crate::slurm_syntax::SyntaxError>;
        let checks: [(&str, Option<&String>, Check); 3] = [
            ("--partition", self.partition.as_ref(), partition),
            ("--account", self.account.as_ref(), account),
            ("--time", self.time.as_ref(), time_limit),
        ];
        for (flag, value, check) in checks {
            if let Some(v) = value {
                check(v).map_err(|e| {
                    SlurmError::Refused(format!("{flag}: {e}; nothing was written"))
                })?;
            }
        }
        for a in &self.sbatch_args {
            sbatch_arg(a).map_err(|e| {
                SlurmError::Refused(format!("--sbatch-arg: {e}; nothing was written"))
            })?;
        }
        Ok(())
    }
}

/// The sbatch script of one array.
pub fn script(
    opts: &SubmitOptions,
    sub_dir: &Path,
    kind: ArrayKind,
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

/// Submit one array; its Slurm job id. A refusal, a failure to run and a controller that does
/// not answer within [`SQUEUE_TIMEOUT`] are all [`SlurmError::Sbatch`]: nothing was queued.
pub(super) fn sbatch(script: &Path, dependency: Option<&str>) -> Result<String, SlurmError> {
    let mut cmd = std::process::Command::new("sbatch");
    cmd.arg("--parsable");
    if let Some(d) = dependency {
        cmd.arg(format!("--dependency=afterany:{d}"));
    }
    let failed = |message: String| SlurmError::Sbatch {
        script: script.display().to_string(),
        message,
    };
    let out = run_with_timeout(cmd.arg(script), SQUEUE_TIMEOUT).map_err(|e| {
        failed(match e {
            QueueError::Failed { stderr, .. } => stderr,
            other => other.to_string().replacen("squeue", "sbatch", 1),
        })
    })?;
    let id = out.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(failed(format!("it printed no job id ({:?})", out.trim())));
    }
    Ok(id)
}

#[cfg(test)]
mod tests {
    use super::shell_quote;

    #[test]
    fn a_quoted_word_survives_the_shell() {
        assert_eq!(shell_quote("sweeps/a.toml"), "sweeps/a.toml");
        assert_eq!(shell_quote("a b"), "'a b'");
        assert_eq!(shell_quote("it's $(x)"), "'it'\\''s $(x)'");
        assert_eq!(shell_quote(""), "''");
        // The shell gives the word back unchanged.
        for s in ["it's $(touch x) `y` \"z\"", "plain", "a\nb"] {
            let out = std::process::Command::new("sh")
                .arg("-c")
                .arg(format!("printf %s {}", shell_quote(s)))
                .output()
                .unwrap();
            assert_eq!(String::from_utf8_lossy(&out.stdout), s);
        }
    }
}
