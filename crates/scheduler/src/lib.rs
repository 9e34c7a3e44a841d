//! # cellsweep-scheduler
//!
//! Turns a sweep file into seeded jobs and runs them: [`sweep`] parses and validates
//! `sweeps/*.toml`, [`plan`] expands a sweep into points, preps and jobs with seeds derived from
//! the sweep seed and the parameters (never from scheduling order), [`coordinator`] dispatches
//! them to worker processes ([`pool`]) speaking JSON lines ([`wire`]), and [`worker`] is the
//! worker side.

pub mod coordinator;
pub mod error;
pub mod grid;
pub mod plan;
pub mod pool;
pub mod slurm;
pub mod sweep;
pub mod wire;
pub mod worker;

pub use coordinator::{run_sweep, Ending, Progress, Reporter, RunOptions, RunReport};
pub use error::{RunError, SweepError};
pub use plan::plan;
pub use pool::WorkerCommand;
pub use sweep::{RunSettings, Sweep};
