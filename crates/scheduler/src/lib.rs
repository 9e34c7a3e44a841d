//! # cellsweep-scheduler
//!
//! Turns a sweep file into seeded jobs and runs them: [`sweep`] parses and validates
//! `sweeps/*.toml`, [`plan`] expands a sweep into points, preps and jobs with seeds derived from
//! the sweep seed and the parameters (never from scheduling order), [`ledger`] is the one way
//! work enters the store (every record checked against the job it claims; an adaptive sweep's
//! rounds planned), [`coordinator`] dispatches jobs to worker processes ([`pool`]) speaking JSON
//! lines ([`wire`]), [`slurm`] runs them as Slurm job arrays, and [`worker`] is the worker side.
//! [`export_file`] reads the export format and [`import`] brings an export into a store.

pub mod coordinator;
pub mod cost;
pub mod engine;
pub mod error;
pub mod export_file;
#[cfg(feature = "fault-injection")]
pub mod fault_injection;
pub mod grid;
pub mod import;
pub mod ledger;
pub mod limits;
pub mod lock;
pub mod plan;
pub mod pool;
pub mod refinement;
pub mod replay;
pub mod reserve;
pub mod reset;
pub mod run_dir;
pub mod slurm;
pub mod slurm_syntax;
pub mod sweep;
pub mod sweep_file;
pub mod wire;
pub mod worker;

pub use coordinator::{run_sweep, Ending, Progress, Reporter, RunOptions, RunReport};
pub use error::{
    AddedPointError, AxisError, CallError, PayloadError, RetuneError, RunError, SlurmError,
    StoredSweepError, SweepError, ValueError,
};
pub use ledger::{Failure, Ledger, Opening, RowCheck, Settlement, TaskRef};
pub use lock::{LockError, StoreLock};
pub use plan::{plan, plan_in, plan_targets};
pub use pool::WorkerCommand;
pub use sweep::{RunSettings, Sweep};
