//! # cellsweep-stats
//!
//! The statistics of cellsweep's phase diagrams, apart from where the data is kept: this crate
//! knows nothing of SQLite or files. Data comes in as finished replicates ([`Replicate`], each
//! with its [`End`]) or as counts per point ([`Counts`], whose [`Tally`] counts each end) and
//! goes out as:
//! - a point's [`Label`] (SPEC section 6) with Wilson and Clopper-Pearson intervals
//!   ([`wilson`], [`clopper_pearson`]);
//! - where each point stands under an adaptive rule ([`assess`] on [`PointEnds`] gives an
//!   [`Assessment`]: open, settled or at its budget, and the next round);
//! - beta* of one column from a logistic model of the whole column ([`fit_column`] on
//!   [`WalkTrain`]s gives a [`ColumnModel`] with its profile-likelihood interval, or why none);
//! - the transition line beta_crit = a alpha~/L~ + b over the diagrams' columns ([`fit_line`]
//!   gives a [`Fit`], its columns read by [`Method::Model`] or the paper's
//!   [`Method::Interpolate`], the latter in [`interpolation`]); the line through columns
//!   pooled from several sweeps, each at its own alpha~/L~ ([`fit_columns`]: the collapse
//!   test); and the shift between two sigmas ([`measure_shift`]), one for all columns and each column's
//!   own with the test of one for all ([`column_shifts`] gives [`ColumnShifts`]);
//! - where refinement adds beta values next ([`RefineRule::need`] gives a column's
//!   [`ColumnNeed`]; an extension climbs above the grid for a column open at its top);
//! - the diagrams on any two axes ([`Plane::diagrams`] gives each [`PlaneDiagram`]);
//! - two result sets compared point by point ([`compare()`] gives a [`Comparison`]), and
//!   column by column, a variant of the numerics against a baseline ([`compare_columns`] gives
//!   each column's [`ColumnChange`] with its [`Verdict`]: the convergence check);
//! - a run's throughput and ETA ([`throughput`]).
//!
//! The path: `cellsweep_store` reads replicates and counts out of a store, `cellsweep_report`
//! loads them from a store or an export file into its `Results`, and this crate turns them into
//! labels, standings, lines and tests.

pub mod adaptive;
pub mod axes;
pub mod binomial;
pub mod box_limit;
pub mod column_model;
pub mod column_shift;
pub mod compare;
pub mod convergence;
pub mod counts;
pub mod distributions;
pub mod end;
pub mod fit;
pub mod interpolation;
pub mod label;
mod model_line;
pub mod plane;
pub mod refine;
mod sampling;
pub mod select;
pub mod shift;
pub mod throughput;

pub use adaptive::{assess, AdaptiveRule, Assessment, Bounds, PointEnds, Standing};
pub use axes::{Axes, ColumnKey, Others, PointKey};
pub use binomial::clopper_pearson;
pub use box_limit::box_limited;
pub use column_model::{falls_back, fit_column, ColumnModel, NoModelCrossing, WalkTrain};
pub use column_shift::{column_shifts, ColumnShift, ColumnShifts};
pub use compare::{compare, Comparison, PointComparison, Test};
pub use convergence::{compare_columns, ColumnChange, Side, Verdict};
pub use counts::{wilson, Counts, Fraction, Label};
pub use end::{End, PerEnd, PrepVerdict, Replicate, Tally, UnknownEnd};
pub use fit::{fit_columns, fit_line, Column, Fit, Method, NoFit, Scales};
pub use interpolation::NoCrossing;
pub use plane::{Plane, PlaneDiagram, PlaneError};
pub use refine::{ColumnNeed, RefineRule};
pub use select::{Condition, SelectError, Selector};
pub use shift::{measure_shift, Shift};
