//! # cellsweep-serve
//!
//! `cellsweep serve`: one live page for a store that a local `run` or a Slurm `submit --watch`
//! is filling. The page shows each sweep's progress and ETA (the estimator `status` uses), its
//! phase diagrams filling in point by point (the report's figures, with counts and Wilson
//! intervals in the tooltips), the points' adaptive standings and what refinement added,
//! failures with their errors and the command that retries them, and the Slurm arrays; it
//! updates without a reload and says "finished" when a sweep is done.
//!
//! Main types: [`Snapshot`] (what a store holds at one moment, gathered read-only by
//! [`Snapshot::gather`]), [`Watcher`] (one read connection that gathers a new snapshot only
//! when SQLite's `data_version` says another connection wrote), and [`serve`] with its
//! [`ServeOptions`] (an axum router that answers GET only). The page itself is rendered on the
//! server ([`page`]), every name escaped as in the report; its script only swaps in fragments.

pub mod page;
mod server;
mod snapshot;
mod watcher;

pub use server::{serve, ServeError, ServeOptions};
pub use snapshot::{Snapshot, SweepView};
pub use watcher::{Live, Watcher};
