//! The command line's shape (clap). Each subcommand's behaviour lives in `commands/`.

use cellsweep_solver::Geometry;
use clap::{Args, Parser, Subcommand};

#[derive(Debug, Parser)]
#[command(name = "cellsweep", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the deterministic relaxation of one cell (SPEC stage 1) and summarize the field.
    Relax(RelaxArgs),
    /// Run one whole trajectory (prep and collision) and print its result.
    Simulate(SimulateArgs),
    /// Run (or resume) a sweep on this machine: register it in the store, expand it into seeded
    /// jobs and dispatch them to worker processes.
    Run(RunArgs),
    /// Progress of every sweep in the store: jobs by state, outcome counts, throughput, ETA,
    /// and the Slurm state of submitted arrays.
    Status(StatusArgs),
    /// Submit a sweep's unfinished work to a Slurm cluster as job arrays.
    Submit(SubmitArgs),
    /// Ingest the result files of Slurm array tasks into the store (idempotent).
    Collect(CollectArgs),
    /// Phase-diagram tables: outcome counts, fractions with 95% Wilson intervals, and labels.
    Table(TableArgs),
    /// Fit the beta_crit line beta* = a alpha~/L~ + b to the walk-past/training crossings.
    Fit(FitArgs),
    /// Compare two result sets point by point and replicate by replicate (two sweeps that
    /// differ only in how they are solved, such as the collision's precision, or one sweep under
    /// two solver versions): counts, pairs that end alike, shifts in decision time, labels, and
    /// a test of whether the outcome statistics differ.
    Compare(CompareArgs),
    /// Write one CSV row per finished replicate of a sweep (seeds, parameters, outcome, times,
    /// attachments, free speed, prep hash, solver version): how results move and are shared.
    Export(ExportArgs),
    /// Bring exported rows back into a store: registers the file's sweep, computes the preps
    /// the rows start from, checks every row against the job it claims (seeds, parameters,
    /// prep hash) and commits them all, or none if any is refused. Idempotent.
    Import(ImportArgs),
    /// Put chosen points of a sweep back to pending, deleting their results, so that the next
    /// `run` computes them again with the same seeds (after a fix that changes how some of
    /// their collisions end). One transaction; the rest of the sweep keeps its results.
    Reset(ResetArgs),
    /// Pictures of every (L, sigma) diagram (SVG and PNG): outcomes with the paper's symbols,
    /// frequency heat maps with the beta_crit lines, and the prep cells' free speed.
    Plot(PlotArgs),
    /// One self-contained HTML page to check the paper against: the six diagrams with n per
    /// point, the beta_crit fit over every spacing and the sigma shift, beta* per column, each
    /// of the paper's claims with the numbers and a verdict, and provenance.
    Report(ReportArgs),
    /// Measure the solver on this machine, one core: step rates, one whole trajectory, and the
    /// NumPy yardstick (scripts/numpy_yardstick.py) where Python and NumPy are available.
    Bench(BenchArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell) to stdout.
    Completions(CompletionsArgs),
    /// Print the manual page (roff) to stdout: `cellsweep man > cellsweep.1`.
    Man,
    /// Serve jobs on stdin/stdout (JSON lines), started by `run`; or, with --slurm, run one
    /// Slurm array task's slice of jobs.
    #[command(hide = true)]
    Worker(WorkerArgs),
}

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// The store to use.
#[derive(Debug, Args)]
pub struct DbArgs {
    /// SQLite database of results.
    #[arg(long, default_value = "cellsweep.sqlite", value_name = "PATH")]
    pub db: std::path::PathBuf,
}

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
}

#[derive(Debug, Args)]
pub struct StatusArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// List every failed job and prep with its error.
    #[arg(long)]
    pub failed: bool,
}

/// Parameters shared by the commands that run the model.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Line-tension parameter alpha.
    #[arg(long, default_value_t = 0.1)]
    pub alpha: f64,
    /// Fiber spacing L (even, lattice sites).
    #[arg(long = "L", default_value_t = 90)]
    pub spacing: u32,
    /// Fiber geometry: two parallel fibers or one.
    #[arg(long, default_value = "two")]
    pub geometry: Geometry,
    /// Any other SPEC parameter, as NAME=VALUE (repeatable), e.g. --set tau=50 --set R0=20.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Single-cell lattice, NXxNY (default 200x200).
    #[arg(long, value_name = "NXxNY")]
    pub lattice: Option<String>,
}

#[derive(Debug, Args)]
pub struct RelaxArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Relaxation steps (default: 40 tau0 = 20,000 steps at dt = 0.002).
    #[arg(long)]
    pub steps: Option<u64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Polarity feedback beta.
    #[arg(long, default_value_t = 10.0)]
    pub beta: f64,
    /// Cell-cell adhesion sigma.
    #[arg(long, default_value_t = 5.0)]
    pub sigma: f64,
    /// Seed of the run; the prep and collision seeds derive from it.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Pair lattice, NXxNY (default: twice the single-cell width, same height).
    #[arg(long, value_name = "NXxNY")]
    pub pair_lattice: Option<String>,
    /// Relaxation time, tau0.
    #[arg(long, default_value_t = 40.0)]
    pub relax_time: f64,
    /// Free-motion time, tau0.
    #[arg(long, default_value_t = 400.0)]
    pub free_time: f64,
    /// Longest collision time, tau0.
    #[arg(long, default_value_t = 400.0)]
    pub collide_time: f64,
    /// Run the collision to the end instead of stopping at the decided outcome.
    #[arg(long)]
    pub full: bool,
    #[command(flatten)]
    pub numerics: CollisionNumerics,
    /// A classifier setting, as NAME=VALUE (repeatable): contact_overlap, speed_fraction,
    /// min_speed, velocity_window, sustain_window, walk_past_margin.
    #[arg(long = "classifier", value_name = "NAME=VALUE")]
    pub classifier: Vec<String>,
    /// Split every step over two threads by rows (the same result, bit for bit): about 1.6x
    /// faster for one interactive run on 2 cores. Sweeps run one process per core instead.
    #[arg(long)]
    pub parallel: bool,
    /// Write PNG snapshots of the collision (phi with its 0.5 contour, fibers, polarity) into
    /// this folder, and an animated GIF of them.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<std::path::PathBuf>,
    /// Time between snapshots, tau0.
    #[arg(long, default_value_t = 10.0)]
    pub frame_every: f64,
    /// Write the collision's observables (one JSON object per sample) to this file.
    #[arg(long, value_name = "FILE")]
    pub track: Option<std::path::PathBuf>,
    /// Print the result as one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Where outcome counts come from: a store, or a counts file.
#[derive(Debug, Args)]
pub struct CountsSource {
    /// SQLite database of results.
    #[arg(
        long,
        default_value = "cellsweep.sqlite",
        value_name = "PATH",
        conflicts_with = "counts"
    )]
    pub db: std::path::PathBuf,
    /// The sweep to read (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// Read counts from a CSV file instead of a store: columns alpha, beta, L, sigma, n_train,
    /// n_walk, n_reversal, n_undetermined, and optionally label (unstable / breakup).
    #[arg(long, value_name = "FILE.csv", conflicts_with = "data")]
    pub counts: Option<std::path::PathBuf>,
    /// Read the results of a `cellsweep export` file instead of a store (e.g.
    /// data/paper/adaptive-L90-sigma5.csv): no store, no recomputation.
    #[arg(long, value_name = "EXPORT.csv", conflicts_with_all = ["db", "sweep"])]
    pub data: Option<std::path::PathBuf>,
}

impl CountsSource {
    /// The results these flags name: an export file, a counts file, or a store.
    pub fn load(&self) -> Result<cellsweep_report::Results, cellsweep_report::load::LoadError> {
        use cellsweep_report::load;
        match (&self.data, &self.counts) {
            (Some(path), _) => load::from_export(path),
            (None, Some(path)) => load::from_counts_csv(path),
            (None, None) => load::from_store(&self.db, self.sweep.as_deref()),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    Text,
    Csv,
    Json,
}

/// What `fit` prints: a fit has no table to give as CSV.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FitFormat {
    Text,
    Json,
}

#[derive(Debug, Args)]
pub struct TableArgs {
    #[command(flatten)]
    pub source: CountsSource,
    /// Only this fiber spacing.
    #[arg(long = "L")]
    pub spacing: Option<u32>,
    /// Only this adhesion.
    #[arg(long)]
    pub sigma: Option<f64>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

#[derive(Debug, Args)]
pub struct FitArgs {
    #[command(flatten)]
    pub source: CountsSource,
    /// text or json.
    #[arg(long, value_enum, default_value = "text")]
    pub format: FitFormat,
    /// Bootstrap resamples for the 95% intervals.
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(0..=1_000_000))]
    pub bootstrap: u32,
    /// Seed of the bootstrap.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The first sweep (A), by name.
    pub a: String,
    /// The second sweep (B), by name (the same name as A to compare two solver versions).
    pub b: String,
    /// The store of A (and of B, unless --db-b is given).
    #[command(flatten)]
    pub db: DbArgs,
    /// The store of B, when it is not A's.
    #[arg(long = "db-b", value_name = "PATH")]
    pub db_b: Option<std::path::PathBuf>,
    /// Solver version of A's results (default: this build's).
    #[arg(long = "version-a", value_name = "VERSION")]
    pub version_a: Option<String>,
    /// Solver version of B's results (default: this build's).
    #[arg(long = "version-b", value_name = "VERSION")]
    pub version_b: Option<String>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

#[derive(Debug, Args)]
pub struct PlotArgs {
    #[command(flatten)]
    pub source: CountsSource,
    /// Folder for the pictures (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: std::path::PathBuf,
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("source").required(true).args(["db", "data"])))]
pub struct ReportArgs {
    /// A store: every sweep in it.
    #[arg(long, value_name = "PATH")]
    pub db: Option<std::path::PathBuf>,
    /// A folder of `cellsweep export` files (every *.csv in it, e.g. data/paper): no store,
    /// no recomputation.
    #[arg(long, value_name = "DIR")]
    pub data: Option<std::path::PathBuf>,
    /// The HTML file to write.
    #[arg(long, value_name = "FILE.html")]
    pub out: std::path::PathBuf,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Skip the whole trajectory (takes about a minute); only the step rates.
    #[arg(long)]
    pub quick: bool,
    /// Skip the NumPy yardstick.
    #[arg(long)]
    pub no_yardstick: bool,
    /// Python interpreter for the yardstick.
    #[arg(long, default_value = "python3")]
    pub python: String,
    #[command(flatten)]
    pub numerics: CollisionNumerics,
}

/// How the collision stage is computed (`simulate` and `bench`).
#[derive(Debug, Args)]
pub struct CollisionNumerics {
    /// Per-cell windows in the collision (one run of columns per row): a site leaves a cell's
    /// window only while |phi| and |P| are below this bound there and nearby; 0 computes both
    /// cells on the whole lattice
    #[arg(long, value_name = "BOUND", default_value_t = cellsweep_solver::PatchSettings::default().bound)]
    pub patch_bound: f64,
    /// Float type of the collision stage: f64 (the reference) or f32 (faster; agrees with f64
    /// in outcome statistics, not trajectory by trajectory)
    #[arg(long, value_name = "f64|f32", default_value = "f64")]
    pub precision: cellsweep_solver::Precision,
}

impl CollisionNumerics {
    /// Set these options in `protocol`.
    pub fn apply(&self, protocol: &mut cellsweep_solver::Protocol) {
        protocol.patch.bound = self.patch_bound;
        protocol.precision = self.precision;
    }
}

#[derive(Debug, Args)]
pub struct WorkerArgs {
    /// Run the array task SLURM_ARRAY_TASK_ID of this submission directory.
    #[arg(long, value_name = "SUB_DIR")]
    pub slurm: Option<std::path::PathBuf>,
    /// prep or collide.
    #[arg(long, default_value = "collide")]
    pub kind: String,
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
pub struct ExportArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// The sweep to export (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// The CSV file to write (replaced atomically).
    #[arg(long, value_name = "FILE.csv")]
    pub out: std::path::PathBuf,
}

#[derive(Debug, Args)]
pub struct ImportArgs {
    /// A file written by `cellsweep export`.
    pub file: std::path::PathBuf,
    #[command(flatten)]
    pub db: DbArgs,
}

#[derive(Debug, Args)]
pub struct ResetArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// The sweep (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// Points to put back, as `alpha=0.1,beta=46` (any of alpha, beta, L, sigma; a key left
    /// out matches every value): repeat it for several.
    #[arg(long, value_name = "KEY=VALUE,...")]
    pub point: Vec<String>,
    /// A CSV file of points to put back: a header naming any of alpha, beta, L, sigma (other
    /// columns are ignored), one point per row.
    #[arg(long, value_name = "FILE.csv")]
    pub points: Option<std::path::PathBuf>,
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
