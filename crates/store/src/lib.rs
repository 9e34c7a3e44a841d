//! # cellsweep-store
//!
//! The SQLite store of cellsweep (rusqlite, bundled SQLite, WAL mode so that `status` can read
//! while a sweep runs): registered sweeps, their grid points, cached preps, collision jobs with
//! an explicit lifecycle, and one result per job. Every result is committed in its own
//! transaction together with its job's state change, so nothing is lost or counted twice.
//! The schema is in [`schema::DDL`].

mod atomic;
mod database;
pub mod digest;
mod encoding;
pub mod error;
pub mod export;
pub mod identity;
mod kinds;
pub mod lifecycle;
mod plans;
mod progress;
pub mod record;
mod register;
mod replicates;
pub mod reset;
pub mod schema;
pub mod slurm_arrays;
pub mod status;
mod tasks;
mod transitions;

pub use database::Store;
pub use encoding::{bytes_to_f64s, f64s_to_bytes, now, point_others};
pub use error::{Result, StoreError};
pub use identity::{JobIdentity, PointJobs, PrepIdentity};
pub use lifecycle::JobState;
pub use plans::NewJob;
pub use record::{PrepRecord, ResultRecord};
pub use register::{spec_change, NewPoint, NewPrep, NewSweep, Registration, SpecChange};
pub use reset::{PointRef, Reset};
pub use slurm_arrays::SlurmArray;
pub use status::{Failure, MeasuredCost, PointCounts, StateCounts, SweepStatus};
pub use tasks::{JobTask, PrepTask};
