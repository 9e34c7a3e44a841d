//! The worker protocol: one JSON object per line, coordinator -> worker on stdin, worker ->
//! coordinator on stdout. Fields travel as base64 of little-endian f64.

use base64::engine::general_purpose::STANDARD as B64;
use base64::Engine;
use cellsweep_solver::{Config, FieldSummary, Prep, TrajectoryResult, Verdict};
use cellsweep_store::{bytes_to_f64s, f64s_to_bytes};
use serde::{Deserialize, Serialize};

/// A prepped cell in transit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PrepPayload {
    pub seed: u64,
    pub verdict: Verdict,
    pub verdict_time: Option<f64>,
    pub free_speed: Option<f64>,
    pub relaxed: FieldSummary,
    pub prepped: FieldSummary,
    pub lattice: [usize; 2],
    pub phi: String,
    pub p: String,
}

impl PrepPayload {
    pub fn from_prep(prep: &Prep) -> Self {
        PrepPayload {
            seed: prep.seed,
            verdict: prep.verdict,
            verdict_time: prep.verdict_time,
            free_speed: prep.free_speed,
            relaxed: prep.relaxed.clone(),
            prepped: prep.prepped.clone(),
            lattice: prep.lattice,
            phi: B64.encode(f64s_to_bytes(&prep.phi)),
            p: B64.encode(f64s_to_bytes(&prep.p)),
        }
    }

    pub fn to_prep(&self) -> Result<Prep, String> {
        let decode = |s: &str| {
            B64.decode(s)
                .map(|b| bytes_to_f64s(&b))
                .map_err(|e| format!("bad field encoding: {e}"))
        };
        let (phi, p) = (decode(&self.phi)?, decode(&self.p)?);
        let n = self.lattice[0] * self.lattice[1];
        if phi.len() != n || p.len() != n {
            return Err(format!(
                "prep fields have {} and {} values, lattice needs {n}",
                phi.len(),
                p.len()
            ));
        }
        Ok(Prep {
            seed: self.seed,
            verdict: self.verdict,
            verdict_time: self.verdict_time,
            free_speed: self.free_speed,
            relaxed: self.relaxed.clone(),
            prepped: self.prepped.clone(),
            lattice: self.lattice,
            phi,
            p,
        })
    }
}

/// Coordinator -> worker.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Request {
    /// Compute a prep (stages 1-4).
    Prep {
        task: i64,
        attempt: u32,
        config: Config,
        seed: u64,
    },
    /// Run a collision from prep `prep_id`; `prep` is sent once per worker and cached there.
    Collide {
        task: i64,
        attempt: u32,
        config: Config,
        seed: u64,
        prep_id: i64,
        prep: Option<Box<PrepPayload>>,
    },
}

impl Request {
    pub fn task(&self) -> i64 {
        match self {
            Request::Prep { task, .. } | Request::Collide { task, .. } => *task,
        }
    }
}

/// Worker -> coordinator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Response {
    Prep {
        task: i64,
        prep: Box<PrepPayload>,
        wall_s: f64,
    },
    Collide {
        task: i64,
        result: Box<TrajectoryResult>,
        wall_s: f64,
    },
    Failed {
        task: i64,
        error: String,
    },
}

impl Response {
    pub fn task(&self) -> i64 {
        match self {
            Response::Prep { task, .. }
            | Response::Collide { task, .. }
            | Response::Failed { task, .. } => *task,
        }
    }
}
