//! # cellsweep-solver
//!
//! One trajectory of Luo, Nain & Camley's phase-field model of two crawling cells colliding on
//! one or two fibers, exactly as the project's numerical contract (`SPEC.md`) says: relax a
//! circular cell on the fibers, kick it, let it move freely with seeded noise, judge the prepped
//! cell (`ok`, `unstable`, `breakup`), then collide it with its mirror image and classify the
//! outcome (`train`, `walk_past`, `reversal`, `undetermined`).
//!
//! Pure computation: no files, no threads beyond an optional `rayon::join` of each step's rows, no
//! async. Progress goes to a [`Monitor`] the caller provides.
//!
//! ```no_run
//! use cellsweep_solver::{run_trajectory, Config, Seeds, Silent};
//! let config = Config::default(); // the paper's defaults, alpha = 0.1, beta = 10, L = 90
//! let (result, _prep, _collision) =
//!     run_trajectory(&config, Seeds::from_run_seed(1), &mut Silent, false).unwrap();
//! println!("{:?}", result.outcome);
//! ```

pub mod breakup;
pub mod cell;
pub mod classifier;
pub mod collision;
pub mod error;
pub mod fibers;
pub mod kernel;
pub mod lattice;
pub mod monitor;
pub mod noise;
pub mod nonfinite;
pub mod observables;
pub mod params;
pub mod patch;
pub mod prep;
pub mod protocol;
pub mod real;
pub mod resolution;
pub mod seed;
pub mod timing;
pub mod trajectory;

pub use breakup::BreakupWatch;
pub use cell::Cell;
pub use classifier::{Classifier, ClassifierSettings, Decision, Outcome};
pub use collision::{collide, place_pair, Collision, Sample};
pub use error::{NameError, ParamError, SolverError};
pub use fibers::{Fiber, Fibers};
pub use kernel::Sums;
pub use lattice::Lattice;
pub use monitor::{Monitor, Silent, Stage};
pub use observables::{Attachment, FieldSummary};
pub use params::{Geometry, Params, PARAM_NAMES};
pub use patch::{PatchSettings, PatchStats};
pub use prep::{prepare, prepare_with, relax, Prep, Verdict};
pub use protocol::{Precision, Protocol, StageSteps};
pub use real::Real;
pub use trajectory::{run_trajectory, Config, Seeds, TrajectoryResult, SOLVER_VERSION};
