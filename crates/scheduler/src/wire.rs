//! The worker protocol: one JSON object per line, coordinator -> worker on stdin, worker ->
//! coordinator on stdout. Fields travel as base64 of little-endian f64.

use base64::engine::general_purpose::STANDARD as B64;
use base64::Engine;
use cellsweep_solver::{Config, FieldSummary, Prep, TrajectoryResult, Verdict};
use cellsweep_store::{bytes_to_f64s, f64s_to_bytes, JobTask, PrepRecord, PrepTask};
use serde::{Deserialize, Serialize};

use crate::error::PayloadError;

/// A prepped cell in transit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PrepPayload {
    pub seed: u64,
    pub verdict: Verdict,
    #[serde(with = "cellsweep_solver::nonfinite::option")]
    pub verdict_time: Option<f64>,
    /// Why the verdict is not `ok`, in words.
    #[serde(default)]
    pub verdict_reason: Option<String>,
    #[serde(with = "cellsweep_solver::nonfinite::option")]
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
            verdict_reason: prep.verdict_reason.clone(),
            free_speed: prep.free_speed,
            relaxed: prep.relaxed.clone(),
            prepped: prep.prepped.clone(),
            lattice: prep.lattice,
            phi: B64.encode(f64s_to_bytes(&prep.phi)),
            p: B64.encode(f64s_to_bytes(&prep.p)),
        }
    }

    /// The stored form of this prep (computed in `wall_s` seconds).
    pub fn to_record(&self, wall_s: f64) -> Result<PrepRecord, PayloadError> {
        let prep = self.to_prep()?;
        Ok(PrepRecord {
            verdict: crate::ledger::stored_verdict(self.verdict),
            verdict_time: self.verdict_time,
            free_speed: self.free_speed,
            nx: self.lattice[0],
            ny: self.lattice[1],
            phi: prep.phi,
            p: prep.p,
            summary: serde_json::json!({
                "relaxed": self.relaxed,
                "prepped": self.prepped,
                "verdict_reason": self.verdict_reason,
            })
            .to_string(),
            wall_s,
        })
    }

    /// A prep as the store keeps it, back in transit form.
    pub fn from_record(rec: PrepRecord, seed: u64) -> Result<Self, PayloadError> {
        let summary: serde_json::Value = serde_json::from_str(&rec.summary)?;
        let field = |key: &'static str| {
            serde_json::from_value::<FieldSummary>(summary[key].clone())
                .map_err(|source| PayloadError::SummaryField { key, source })
        };
        let prep = Prep {
            seed,
            verdict: serde_json::from_value(serde_json::json!(rec.verdict)).map_err(|source| {
                PayloadError::SummaryField {
                    key: "verdict",
                    source,
                }
            })?,
            verdict_time: rec.verdict_time,
            verdict_reason: summary["verdict_reason"].as_str().map(String::from),
            free_speed: rec.free_speed,
            relaxed: field("relaxed")?,
            prepped: field("prepped")?,
            lattice: [rec.nx, rec.ny],
            phi: rec.phi,
            p: rec.p,
        };
        Ok(PrepPayload::from_prep(&prep))
    }

    pub fn to_prep(&self) -> Result<Prep, PayloadError> {
        let decode = |s: &str| B64.decode(s).map(|b| bytes_to_f64s(&b));
        let (phi, p) = (decode(&self.phi)?, decode(&self.p)?);
        let n = self.lattice[0] * self.lattice[1];
        if phi.len() != n || p.len() != n {
            return Err(PayloadError::Size {
                phi: phi.len(),
                p: p.len(),
                n,
            });
        }
        Ok(Prep {
            seed: self.seed,
            verdict: self.verdict,
            verdict_time: self.verdict_time,
            verdict_reason: self.verdict_reason.clone(),
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
    /// The request that computes a prep the store holds, as its next attempt.
    pub fn prep(p: &PrepTask) -> Result<Request, serde_json::Error> {
        Ok(Request::Prep {
            task: p.id,
            attempt: p.attempts + 1,
            config: serde_json::from_str(&p.config)?,
            seed: p.seed,
        })
    }

    /// The request that runs a job's collision, as its next attempt; `prep` is its prep's
    /// fields where the worker does not hold them yet (a Slurm task reads them from its file).
    pub fn collide(
        j: &JobTask,
        prep: Option<Box<PrepPayload>>,
    ) -> Result<Request, serde_json::Error> {
        Ok(Request::Collide {
            task: j.id,
            attempt: j.attempts + 1,
            config: serde_json::from_str(&j.config)?,
            seed: j.seed,
            prep_id: j.prep_id,
            prep,
        })
    }

    pub fn task(&self) -> i64 {
        match self {
            Request::Prep { task, .. } | Request::Collide { task, .. } => *task,
        }
    }

    pub fn attempt(&self) -> u32 {
        match self {
            Request::Prep { attempt, .. } | Request::Collide { attempt, .. } => *attempt,
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
    /// The attempt failed, with the error in words.
    Failed {
        task: i64,
        /// The request's attempt number (records written before it was sent say none: 1).
        #[serde(default = "first_attempt")]
        attempt: u32,
        error: String,
    },
}

fn first_attempt() -> u32 {
    1
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
