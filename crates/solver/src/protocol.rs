//! The protocol of one trajectory (SPEC section 4): lattices and stage durations.

use serde::{Deserialize, Serialize};

use crate::error::{NameError, ParamError};
use crate::params::Params;
use crate::patch::PatchSettings;

/// Lattice sizes and stage durations (in tau0). Defaults are the paper's protocol.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Protocol {
    /// Single-cell lattice [Nx_s, Ny] for relaxation and free motion.
    pub single_lattice: [usize; 2],
    /// Two-cell lattice [Nx_p, Ny] for the collision.
    pub pair_lattice: [usize; 2],
    /// Relaxation (stage 1), tau0.
    pub relax_time: f64,
    /// Free motion (stage 3), tau0.
    pub free_time: f64,
    /// Longest collision (stage 5), tau0.
    pub collide_time: f64,
    /// Observables are recorded every this many tau0.
    pub record_interval: f64,
    /// Prep verdict checks (breakup, one fiber let go) every this many tau0.
    pub check_interval: f64,
    /// Stop the collision as soon as the outcome is decided (the label is the same either way).
    pub stop_early: bool,
    /// Per-cell windows in the collision (`crate::patch`); `bound = 0` computes every cell on the
    /// whole lattice.
    pub patch: PatchSettings,
    /// Floating-point type of the collision stage (the prep always runs in f64).
    pub precision: Precision,
    /// Resolution k of the lattice (SPEC section 6): l0' = l0 / k, every parameter and the
    /// lattices given in the paper's units and converted (`crate::resolution`). 1: the paper's.
    #[serde(skip_serializing_if = "is_one")]
    pub resolution: u32,
}

/// Whether `k` is 1 (the paper's resolution is left out of stored definitions, so that they
/// read as they did before resolutions existed).
fn is_one(k: &u32) -> bool {
    *k == 1
}

/// The float the collision stage runs in. f64 is the default and the reference; f32 halves
/// the memory traffic and doubles the vector width, at the price of trajectories that agree
/// with f64 only statistically (see the README for the sweep that compares them).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Precision {
    #[default]
    F64,
    F32,
}

impl Precision {
    pub fn as_str(self) -> &'static str {
        match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        }
    }
}

impl std::str::FromStr for Precision {
    type Err = NameError;
    fn from_str(s: &str) -> Result<Self, NameError> {
        match s {
            "f64" => Ok(Precision::F64),
            "f32" => Ok(Precision::F32),
            _ => Err(NameError::Precision(s.to_string())),
        }
    }
}

impl Default for Protocol {
    fn default() -> Self {
        Protocol {
            single_lattice: [200, 200],
            pair_lattice: [400, 200],
            relax_time: 40.0,
            free_time: 400.0,
            collide_time: 400.0,
            record_interval: 0.5,
            check_interval: 1.0,
            stop_early: true,
            patch: PatchSettings::default(),
            precision: Precision::F64,
            resolution: 1,
        }
    }
}

/// Whole number of steps in `time` at step `dt`, or an error naming the duration.
pub fn steps_in(name: &'static str, time: f64, dt: f64) -> Result<u64, ParamError> {
    if !time.is_finite() || time < 0.0 {
        return Err(ParamError::Negative { name, value: time });
    }
    let n = time / dt;
    if (n - n.round()).abs() > 1e-6 {
        return Err(ParamError::DurationNotMultiple {
            name,
            value: time,
            dt,
        });
    }
    Ok(n.round() as u64)
}

/// Step counts of every stage, derived from a validated protocol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageSteps {
    pub relax: u64,
    pub free: u64,
    pub collide: u64,
    pub record_every: u64,
    pub check_every: u64,
}

impl Protocol {
    /// A lattice given in l0 in the solver's sites: its sides times the resolution k.
    pub fn sites(&self, [nx, ny]: [usize; 2]) -> [usize; 2] {
        let k = self.resolution.max(1) as usize;
        [nx * k, ny * k]
    }

    /// The single-cell lattice in the solver's sites: a prep's field has this size.
    pub fn single_sites(&self) -> [usize; 2] {
        self.sites(self.single_lattice)
    }

    /// Validate the lattices and durations against the parameters; return the step counts.
    pub fn validate(&self, params: &Params) -> Result<StageSteps, ParamError> {
        if !(1..=8).contains(&self.resolution) {
            return Err(ParamError::OutOfRange {
                name: "resolution",
                value: f64::from(self.resolution),
                range: "1..=8 (a whole number: l0' = l0 / k)",
            });
        }
        let [snx, sny] = self.single_lattice;
        let [pnx, pny] = self.pair_lattice;
        for (name, nx, ny) in [("single_lattice", snx, sny), ("pair_lattice", pnx, pny)] {
            if nx == 0 || ny == 0 || nx % 2 != 0 || ny % 2 != 0 {
                return Err(ParamError::OddLattice { name, nx, ny });
            }
        }
        if (snx.min(sny) as f64) <= 2.0 * params.R0 {
            return Err(ParamError::LatticeTooSmall {
                name: "single_lattice",
                nx: snx,
                ny: sny,
                r0: params.R0,
            });
        }
        if pny != sny || pnx < 2 * snx {
            return Err(ParamError::PairLattice { pnx, pny, snx, sny });
        }
        params.validate(sny)?;
        let dt = params.dt;
        let steps = StageSteps {
            relax: steps_in("relax_time", self.relax_time, dt)?,
            free: steps_in("free_time", self.free_time, dt)?,
            collide: steps_in("collide_time", self.collide_time, dt)?,
            record_every: steps_in("record_interval", self.record_interval, dt)?,
            check_every: steps_in("check_interval", self.check_interval, dt)?,
        };
        if steps.record_every == 0 {
            return Err(ParamError::NotPositive {
                name: "record_interval",
                value: self.record_interval,
            });
        }
        if steps.check_every == 0 {
            return Err(ParamError::NotPositive {
                name: "check_interval",
                value: self.check_interval,
            });
        }
        let patch = &self.patch;
        if !patch.bound.is_finite() || patch.bound < 0.0 {
            return Err(ParamError::Negative {
                name: "patch_bound",
                value: patch.bound,
            });
        }
        if patch.bound >= params.phi_min {
            // P is cut to zero only below phi_min: a looser bound could drop a column of live P.
            return Err(ParamError::OutOfRange {
                name: "patch_bound",
                value: patch.bound,
                range: "[0, phi_min)",
            });
        }
        for (name, v) in [
            ("patch_check_every", patch.check_every),
            ("patch_refit_every", patch.refit_every),
        ] {
            if v == 0 {
                return Err(ParamError::NotPositive { name, value: 0.0 });
            }
        }
        Ok(steps)
    }
}
