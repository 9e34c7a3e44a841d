//! Flags of the commands that run a sweep: `run`, `submit`, `collect`, `reset` and the worker.

use clap::Args;

use super::DbArgs;

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Sweep file (see sweeps/*.toml).
    pub sweep: std::path::PathBuf,
    #[command(flatten)]
    pub db: DbArgs,
    /// Worker processes (default: the number of cores).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub workers: Option<u16>,
    /// Register this sweep even though a different sweep has its name; the old one keeps its
    /// results under a new name.
    #[arg(long)]
    pub replace: bool,
    /// Seconds one job may take before its worker is killed and the job retried (default: the
    /// sweep file's [run] job_timeout, else 3600).
    #[arg(long, value_parser = job_timeout_flag)]
    pub job_timeout: Option<f64>,
    /// Failed attempts before a job is marked failed (default: the sweep file's, else 3).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub max_attempts: Option<u32>,
    /// When the sweep is done, write its pictures into this folder (as `cellsweep plot`).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<std::path::PathBuf>,
    /// Seconds that jobs in flight may take to finish after Ctrl-C or SIGTERM (their results
    /// are kept); a second signal stops at once.
    #[arg(long, default_value_t = 10.0, value_name = "SECONDS", value_parser = grace_seconds)]
    pub grace: f64,
    /// Put the sweep's failed jobs and preps back to pending, each with its attempts anew, and
    /// run them.
    #[arg(long)]
    pub retry_failed: bool,
    /// Print the sweep's points, preps and jobs, what the store already holds, and what the
    /// rest would cost, writing nothing.
    #[arg(long, conflicts_with_all = ["retry_failed", "replace", "plot"])]
    pub dry_run: bool,
    /// Run even while the sweep has Slurm arrays queued or running (or squeue cannot tell):
    /// their jobs are computed here too, and what they send later is taken as already done.
    #[arg(long)]
    pub force: bool,
}

#[derive(Debug, Args)]
pub struct WorkerArgs {
    /// Run the array task SLURM_ARRAY_TASK_ID of this submission directory.
    #[arg(long, value_name = "SUB_DIR")]
    pub slurm: Option<std::path::PathBuf>,
    /// prep or collide.
    #[arg(long, default_value = "collide")]
    pub kind: cellsweep_scheduler::slurm::ArrayKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Backend {
    Slurm,
}

#[derive(Debug, Args)]
pub struct SubmitArgs {
    /// Sweep file.
    pub sweep: std::path::PathBuf,
    /// The cluster's scheduler.
    #[arg(long, value_enum)]
    pub backend: Backend,
    #[command(flatten)]
    pub db: DbArgs,
    /// Run directory on the cluster's shared filesystem (default: cellsweep-runs/NAME).
    #[arg(long, value_name = "DIR")]
    pub run_dir: Option<std::path::PathBuf>,
    /// Slurm partition (or several, comma-separated).
    #[arg(long)]
    pub partition: Option<String>,
    /// Slurm account to charge.
    #[arg(long)]
    pub account: Option<String>,
    /// Time limit of one array task, HH:MM:SS.
    #[arg(long)]
    pub time: Option<String>,
    /// Collision jobs per array task (raised if the array would exceed MaxArraySize).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub jobs_per_task: u32,
    /// Most array tasks running at once (Slurm's %N throttle).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub max_array: Option<u32>,
    /// Extra #SBATCH line, e.g. --sbatch-arg=--account=abc (repeatable).
    #[arg(long = "sbatch-arg", value_name = "ARG", allow_hyphen_values = true)]
    pub sbatch_args: Vec<String>,
    /// Print the scripts without writing or submitting anything.
    #[arg(long)]
    pub dry_run: bool,
    /// As for `run`: register even though a different sweep has the name.
    #[arg(long)]
    pub replace: bool,
    /// Keep going until the sweep is done: collect, plan an adaptive sweep's next round,
    /// submit it, wait for its arrays, and again.
    #[arg(long, conflicts_with = "dry_run")]
    pub watch: bool,
    /// As for `run`: put the sweep's failed jobs and preps back to pending and submit them.
    #[arg(long, conflicts_with = "dry_run")]
    pub retry_failed: bool,
    /// Failed attempts before a job is marked failed and no longer submitted (default: the
    /// sweep file's, else 3). `collect` records each failure; `submit` applies the limit.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub max_attempts: Option<u32>,
    /// Seconds between looks at the queue with --watch.
    #[arg(long, default_value_t = 30.0, value_name = "SECONDS", value_parser = poll_seconds)]
    pub poll: f64,
    /// With --watch, how long squeue or sbatch may keep failing (each failure waited out, the
    /// waits doubling from --poll up to 5 minutes) before the watch gives up.
    #[arg(long, default_value_t = 3600.0, value_name = "SECONDS", value_parser = poll_seconds)]
    pub give_up_after: f64,
}

fn job_timeout_flag(s: &str) -> Result<f64, String> {
    let x: f64 = s
        .parse()
        .map_err(|_| format!("{s:?} is not a number of seconds"))?;
    cellsweep_scheduler::sweep::job_timeout(x).map_err(|e| e.to_string())
}

fn grace_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && (0.0..=86_400.0).contains(&x) => Ok(x),
        _ => Err(format!("{s:?} is not a number of seconds in [0, 86400]")),
    }
}

fn poll_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && (0.1..=86_400.0).contains(&x) => Ok(x),
        _ => Err(format!("{s:?} is not a number of seconds in [0.1, 86400]")),
    }
}

#[derive(Debug, Args)]
pub struct ResetArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// The sweep (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// Points to put back, as `alpha=0.1,beta=46` (any axis of the sweep, E0 or R0 too; an
    /// axis left out matches every value): repeat it for several.
    #[arg(long, value_name = "KEY=VALUE,...")]
    pub point: Vec<String>,
    /// A CSV file of points to put back: a header naming axes of the sweep (a column that is
    /// not one is refused), one point per row.
    #[arg(long, value_name = "FILE.csv")]
    pub points: Option<std::path::PathBuf>,
    /// Put back only what a change of the breakup rule can change: collisions stored as
    /// breakup, and preps whose verdict is breakup with the jobs that start from them (at the
    /// points given, or at every point of the sweep).
    #[arg(long)]
    pub breakups: bool,
    /// Say what would be put back, changing nothing.
    #[arg(long)]
    pub dry_run: bool,
}

#[derive(Debug, Args)]
pub struct CollectArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// Only this sweep.
    #[arg(long)]
    pub sweep: Option<String>,
}
