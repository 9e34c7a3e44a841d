//! The command line's shape (clap). Each subcommand's behaviour lives in `commands/`.

use clap::{Args, Parser, Subcommand};

mod results;
mod run_flags;
mod selection;
mod solver;

pub use results::*;
pub use run_flags::*;
pub use selection::*;
pub use solver::*;

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
    /// Is it converged? Each column's beta* in variants of the numerics (dt halved, a wider or
    /// taller box, f64, a finer lattice) against a baseline: both with their 95% intervals, the
    /// difference with its interval, and a verdict (agrees / moves).
    Converge(ConvergeArgs),
    /// Compute one stored replicate again from its record (parameters, lattices, seeds,
    /// precision, classifier) and check it comes out identical (outcome, times, steps,
    /// attachments, speeds, prep hash); with --frames its movie, with --track its observables.
    Replay(ReplayArgs),
    /// Audit a store or an export: replay a seeded sample of its rows (or all) and report each
    /// as identical or with the fields that differ.
    Verify(VerifyArgs),
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
    /// A live page for a store that a run or a Slurm `submit --watch` is filling: progress and
    /// ETA, the diagrams filling in, standings, failures and Slurm arrays, updated without a
    /// reload. Read-only, GET only; binds 127.0.0.1 unless told otherwise.
    Serve(ServeArgs),
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
pub struct ServeArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// A folder of `cellsweep export` files (or one file) whose diagrams are shown below the
    /// live ones; give it again to add more.
    #[arg(long, value_name = "DIR")]
    pub data: Vec<std::path::PathBuf>,
    /// The port to listen on (0: any free one, printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// The address to listen on. Anything but a loopback address exposes the page, which has
    /// no authentication, to the network: reach it through an ssh tunnel instead
    /// (`ssh -L 8080:127.0.0.1:8080 host`).
    #[arg(long, default_value = "127.0.0.1", value_parser = parse_bind)]
    pub bind: std::net::IpAddr,
    /// Seconds between the page's polls (and the least time between two readings of the
    /// store).
    #[arg(long, default_value_t = 2.0, value_name = "SECONDS")]
    pub poll: f64,
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

/// `--bind`: an IP address, or `localhost` (the IPv4 loopback, 127.0.0.1).
fn parse_bind(text: &str) -> Result<std::net::IpAddr, String> {
    match text {
        "localhost" => Ok(std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST)),
        _ => text
            .parse()
            .map_err(|_| format!("{text:?} is not an IP address (nor localhost)")),
    }
}
