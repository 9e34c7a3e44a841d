//! One whole trajectory (prep, then collision) and the record of its result.

use serde::{Deserialize, Serialize};

use crate::classifier::{ClassifierSettings, Outcome};
use crate::collision::{collide, Collision};
use crate::error::SolverError;
use crate::monitor::Monitor;
use crate::observables::Attachment;
use crate::params::Params;
use crate::prep::{prepare_with, Prep, Verdict};
use crate::protocol::Protocol;

/// Version of the numerics; stored with every result so that versions never mix silently.
pub const SOLVER_VERSION: &str = concat!("cellsweep-solver ", env!("CARGO_PKG_VERSION"));

/// Seeds of the two noisy stages.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Seeds {
    pub prep: u64,
    pub collision: u64,
}

impl Seeds {
    /// The seeds of a stand-alone run (`cellsweep simulate --seed N`).
    pub fn from_run_seed(seed: u64) -> Self {
        use crate::seed::{derive, COLLISION_TAG, PREP_TAG};
        Seeds {
            prep: derive(&[seed, PREP_TAG]),
            collision: derive(&[seed, COLLISION_TAG]),
        }
    }
}

/// Everything a trajectory needs besides its seeds.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Config {
    pub params: Params,
    pub protocol: Protocol,
    pub classifier: ClassifierSettings,
}

/// The result of one trajectory, with everything needed to reproduce it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryResult {
    pub solver_version: String,
    pub config: Config,
    pub seeds: Seeds,
    pub verdict: Verdict,
    /// The collision's outcome; `None` when the prep verdict is not `ok` (no collision is run).
    pub outcome: Option<Outcome>,
    pub free_speed: Option<f64>,
    pub threshold_speed: Option<f64>,
    pub contact_time: Option<f64>,
    pub decision_time: Option<f64>,
    /// Why a cell broke up, when the outcome is `breakup` (absent otherwise, and in records
    /// written before the collision had a breakup check).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub breakup_reason: Option<String>,
    /// Drops the cells shed during the collision (SPEC section 5; 0 without a collision, and
    /// in records written before they were counted, when any second piece was a breakup).
    #[serde(default)]
    pub sheddings: u32,
    /// Fiber attachment of cell 1 and cell 2 after the collision.
    pub attachment: Option<[Attachment; 2]>,
    pub collision_steps: u64,
    /// What the collision's per-cell windows did (`None` with windows off or no collision).
    #[serde(default)]
    pub patch: Option<crate::patch::PatchStats>,
}

impl TrajectoryResult {
    /// The record of a prep and, if it was run, its collision.
    pub fn new(config: &Config, prep: &Prep, collision_seed: u64, c: Option<&Collision>) -> Self {
        TrajectoryResult {
            solver_version: SOLVER_VERSION.to_string(),
            config: config.clone(),
            seeds: Seeds {
                prep: prep.seed,
                collision: collision_seed,
            },
            verdict: prep.verdict,
            outcome: c.map(|c| c.outcome),
            free_speed: prep.free_speed,
            threshold_speed: c.map(|c| c.threshold_speed),
            contact_time: c.and_then(|c| c.contact_time),
            decision_time: c.and_then(|c| c.decision_time),
            breakup_reason: c.and_then(|c| c.breakup_reason.clone()),
            sheddings: c.map_or(0, |c| c.sheddings),
            attachment: c.map(|c| c.attachment),
            collision_steps: c.map_or(0, |c| c.steps),
            patch: c.and_then(|c| c.patch),
        }
    }
}

/// Run one whole trajectory: prep with `seeds.prep`, and, if its verdict is `ok`, the collision
/// with `seeds.collision`; with `parallel` on two threads (the same result, bit for bit). Returns the prep and collision too, for callers that want the fields
/// or the track.
pub fn run_trajectory(
    config: &Config,
    seeds: Seeds,
    monitor: &mut dyn Monitor,
    parallel: bool,
) -> Result<(TrajectoryResult, Prep, Option<Collision>), SolverError> {
    let prep = prepare_with(
        &config.params,
        &config.protocol,
        seeds.prep,
        monitor,
        parallel,
    )?;
    let (result, collision) = run_from_prep(config, &prep, seeds.collision, monitor, parallel)?;
    Ok((result, prep, collision))
}

/// The rest of a trajectory from its prep: the collision with `collision_seed` if the prep's
/// verdict is `ok`, and the result record of both ([`run_trajectory`] after the prep, and a
/// replay whose prep was computed before).
pub fn run_from_prep(
    config: &Config,
    prep: &Prep,
    collision_seed: u64,
    monitor: &mut dyn Monitor,
    parallel: bool,
) -> Result<(TrajectoryResult, Option<Collision>), SolverError> {
    let collision = match prep.verdict {
        Verdict::Ok => Some(collide(
            &config.params,
            &config.protocol,
            &config.classifier,
            prep,
            collision_seed,
            monitor,
            parallel,
        )?),
        _ => None,
    };
    let result = TrajectoryResult::new(config, prep, collision_seed, collision.as_ref());
    Ok((result, collision))
}
