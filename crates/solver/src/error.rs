//! Typed errors of the solver: every message names the parameter and the problem.

use thiserror::Error;

/// A parameter set or protocol that the solver refuses to run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParamError {
    #[error("parameter {name} = {value} is not a finite number")]
    NotFinite { name: &'static str, value: f64 },
    #[error("parameter {name} = {value} must be > 0")]
    NotPositive { name: &'static str, value: f64 },
    #[error("parameter {name} = {value} must be >= 0")]
    Negative { name: &'static str, value: f64 },
    #[error("parameter {name} = {value} must lie in {range}")]
    OutOfRange {
        name: &'static str,
        value: f64,
        range: &'static str,
    },
    #[error("fiber spacing L = {0} must be an even integer (fibers sit at Ny/2 -+ L/2)")]
    OddSpacing(u32),
    #[error("fiber spacing L = {spacing} must be at least 4 (below that the two fibers touch)")]
    SpacingTooSmall { spacing: u32 },
    #[error(
        "fiber spacing L = {spacing} does not fit in a lattice of height Ny = {ny} (L <= Ny - 2)"
    )]
    SpacingTooLarge { spacing: u32, ny: usize },
    #[error(
        "explicit scheme unstable: (1/gamma) alpha d^2/2 dt = {number:.4} > 0.25 \
         (inv_gamma = {inv_gamma}, alpha = {alpha}, d = {d}, dt = {dt}); lower dt or alpha"
    )]
    Unstable {
        number: f64,
        inv_gamma: f64,
        alpha: f64,
        d: f64,
        dt: f64,
    },
    #[error("t_sample = {t_sample} must be a whole multiple of dt = {dt}")]
    SampleNotMultiple { t_sample: f64, dt: f64 },
    #[error("{name} = {value} tau0 must be a whole multiple of dt = {dt}")]
    DurationNotMultiple {
        name: &'static str,
        value: f64,
        dt: f64,
    },
    #[error("lattice {name} = {nx} x {ny} must have even, non-zero sizes")]
    OddLattice {
        name: &'static str,
        nx: usize,
        ny: usize,
    },
    #[error("lattice {name} = {nx} x {ny} is too small for a cell of radius R0 = {r0} (need sizes > 2 R0)")]
    LatticeTooSmall {
        name: &'static str,
        nx: usize,
        ny: usize,
        r0: f64,
    },
    #[error(
        "pair lattice {pnx} x {pny} must have the single-cell height {sny} and a width >= 2 x {snx}"
    )]
    PairLattice {
        pnx: usize,
        pny: usize,
        snx: usize,
        sny: usize,
    },
}

/// A name or value given for a parameter that is not one (`Params::set`, `FromStr`).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NameError {
    #[error("unknown parameter {given:?} (known: {known})")]
    Parameter { given: String, known: String },
    #[error("unknown geometry {0:?} (expected \"one\" or \"two\")")]
    Geometry(String),
    #[error("geometry = {0} must be 1 or 2")]
    GeometryNumber(f64),
    #[error("precision {0:?} must be \"f64\" or \"f32\"")]
    Precision(String),
    #[error("L = {0} must be a non-negative integer")]
    Spacing(f64),
}

/// Failures while running a trajectory.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolverError {
    #[error(transparent)]
    Param(#[from] ParamError),
    #[error("prep fields do not match the single-cell lattice {nx} x {ny}")]
    PrepMismatch { nx: usize, ny: usize },
}

impl ParamError {
    /// The parameter (or protocol setting) the error is about.
    pub fn parameter(&self) -> &'static str {
        match self {
            ParamError::NotFinite { name, .. }
            | ParamError::NotPositive { name, .. }
            | ParamError::Negative { name, .. }
            | ParamError::OutOfRange { name, .. }
            | ParamError::DurationNotMultiple { name, .. }
            | ParamError::OddLattice { name, .. }
            | ParamError::LatticeTooSmall { name, .. } => name,
            ParamError::OddSpacing(_)
            | ParamError::SpacingTooSmall { .. }
            | ParamError::SpacingTooLarge { .. } => "L",
            ParamError::Unstable { .. } => "dt",
            ParamError::SampleNotMultiple { .. } => "t_sample",
            ParamError::PairLattice { .. } => "pair_lattice",
        }
    }
}
