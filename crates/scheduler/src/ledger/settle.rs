//! Records checked and committed: a prep, a collision, and the jobs a prep's verdict decides.

use cellsweep_solver::{Config, Outcome, TrajectoryResult, Verdict};
use cellsweep_stats::{End, PrepVerdict};
use cellsweep_store::{JobState, ResultRecord, Store};
use serde_json::json;

use super::{Ledger, Settlement};
use crate::error::RunError;
use crate::wire::PrepPayload;

/// A committed prep: its verdict and how many jobs that verdict settled.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepSettled {
    pub settlement: Settlement,
    pub verdict: Option<Verdict>,
    pub jobs_settled: usize,
}

/// The verdict a prep's solver verdict is stored as.
pub(crate) fn stored_verdict(v: Verdict) -> PrepVerdict {
    match v {
        Verdict::Ok => PrepVerdict::Ok,
        Verdict::Unstable => PrepVerdict::Unstable,
        Verdict::Breakup => PrepVerdict::Breakup,
    }
}

/// The end a collision's outcome (the classifier's) is stored and counted as: the one
/// conversion from the classifier's kinds to [`End`] (a new outcome fails to compile here).
pub(crate) fn collision_end(o: Outcome) -> End {
    match o {
        Outcome::Train => End::Train,
        Outcome::WalkPast => End::WalkPast,
        Outcome::Reversal => End::Reversal,
        Outcome::Undetermined => End::Undetermined,
        Outcome::Breakup => End::CollisionBreakup,
    }
}

/// The record of a job decided by its prep's verdict (no collision run).
fn verdict_record(
    verdict: Verdict,
    reason: Option<&str>,
    free_speed: Option<f64>,
    prep_id: i64,
    classifier: &str,
) -> ResultRecord {
    ResultRecord {
        verdict: stored_verdict(verdict),
        outcome: None,
        contact_time: None,
        decision_time: None,
        free_speed,
        threshold_speed: None,
        attachment: None,
        collision_steps: 0,
        breakup_reason: None,
        wall_s: 0.0,
        classifier: classifier.to_string(),
        record: json!({
            "verdict": verdict,
            "reason": reason,
            "prep_id": prep_id,
            "free_speed": free_speed,
        })
        .to_string(),
    }
}

/// The stored form of a collision's result (what `replay` compares a stored row with).
pub(crate) fn result_record(r: &TrajectoryResult, wall_s: f64) -> ResultRecord {
    let name = |a| {
        serde_json::to_value(a)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
            .unwrap_or_default()
    };
    ResultRecord {
        verdict: stored_verdict(r.verdict),
        outcome: r.outcome.map(collision_end),
        contact_time: r.contact_time,
        decision_time: r.decision_time,
        free_speed: r.free_speed,
        threshold_speed: r.threshold_speed,
        attachment: r.attachment.map(|[a, b]| [name(a), name(b)]),
        collision_steps: r.collision_steps,
        breakup_reason: r.breakup_reason.clone(),
        wall_s,
        classifier: serde_json::to_string(&r.config.classifier).unwrap_or_default(),
        record: serde_json::to_string(r).unwrap_or_default(),
    }
}

impl Ledger {
    /// Check a collision result against job `job_id` and commit it.
    pub fn settle_job(
        &self,
        store: &mut Store,
        job_id: i64,
        result: &TrajectoryResult,
        wall_s: f64,
    ) -> Result<Settlement, RunError> {
        let refuse = |why: String| Ok(Settlement::Refused(format!("job {job_id}: {why}")));
        let Some(job) = store.job_identity(job_id)? else {
            return refuse("no such job in this store".into());
        };
        if job.sweep_id != self.sweep_id {
            return refuse("belongs to another sweep".into());
        }
        if job.solver_version != self.version || result.solver_version != self.version {
            return refuse(format!(
                "solver version {:?} (job {:?}), this run is {:?}",
                result.solver_version, job.solver_version, self.version
            ));
        }
        if result.seeds.collision != job.seed {
            return refuse(format!(
                "collision seed {} is not the job's {}",
                result.seeds.collision, job.seed
            ));
        }
        if !self.is_stored_config(&job.config, &result.config)? {
            return refuse("its parameters are not the job's".into());
        }
        let prep = store.prep_identity(job.prep_id, self.sweep_id)?;
        if prep.as_ref().map(|p| p.seed) != Some(result.seeds.prep) {
            return refuse(format!(
                "prep seed {} is not that of the job's prep {}",
                result.seeds.prep, job.prep_id
            ));
        }
        // A Slurm collide task whose prep turned out unstable or broke up reports the prep's
        // verdict without a collision: the job is decided by its prep, which the ledger has
        // settled (or will) from the prep itself, so such a record agrees and adds nothing.
        let decided_by_prep = result.verdict != Verdict::Ok
            && result.outcome.is_none()
            && job.prep_verdict == Some(stored_verdict(result.verdict));
        if decided_by_prep {
            if job.state == JobState::Done {
                return Ok(Settlement::Already);
            }
            // Settled as every job of that prep is, from the stored prep (one write path).
            self.settle_by_stored_prep(store, job.prep_id)?;
            return Ok(Settlement::New);
        }
        if !decided_by_prep
            && (job.prep_verdict != Some(PrepVerdict::Ok)
                || result.verdict != Verdict::Ok
                || result.outcome.is_none())
        {
            return refuse(format!(
                "a collision with verdict {:?}, but the job's prep is {}",
                result.verdict.as_str(),
                job.prep_verdict.map_or("not done", PrepVerdict::as_str)
            ));
        }
        if job.state == JobState::Done {
            return Ok(Settlement::Already);
        }
        store.record_result(job_id, &self.version, &result_record(result, wall_s))?;
        Ok(Settlement::New)
    }

    /// Check a prep against prep `prep_id` and commit it; a verdict that is not `ok` settles
    /// the sweep's pending jobs of that prep.
    pub fn settle_prep(
        &self,
        store: &mut Store,
        prep_id: i64,
        payload: &PrepPayload,
        wall_s: f64,
    ) -> Result<PrepSettled, RunError> {
        let refuse = |why: String| {
            Ok(PrepSettled {
                settlement: Settlement::Refused(format!("prep {prep_id}: {why}")),
                verdict: None,
                jobs_settled: 0,
            })
        };
        let Some(prep) = store.prep_identity(prep_id, self.sweep_id)? else {
            return refuse("no such prep in this store".into());
        };
        if !prep.used_by_sweep || prep.solver_version != self.version {
            return refuse("no job of this sweep and solver version starts from it".into());
        }
        if payload.seed != prep.seed {
            return refuse(format!(
                "seed {} is not the prep's {}",
                payload.seed, prep.seed
            ));
        }
        let config: Config = serde_json::from_str(&prep.config)?;
        // In sites: a finer lattice (resolution k) has k times the paper's sides.
        let sites = config.protocol.single_sites();
        if payload.lattice != sites {
            return refuse(format!(
                "lattice {:?} is not the prep's {:?}",
                payload.lattice, sites
            ));
        }
        let settlement = if prep.state == JobState::Done {
            Settlement::Already
        } else {
            let rec = match payload.to_record(wall_s) {
                Ok(r) => r,
                Err(why) => return refuse(why.to_string()),
            };
            store.record_prep(prep_id, &rec)?;
            Settlement::New
        };
        let jobs_settled = self.settle_verdict(
            store,
            prep_id,
            payload.verdict,
            payload.verdict_reason.as_deref(),
            payload.free_speed,
        )?;
        Ok(PrepSettled {
            settlement,
            verdict: Some(payload.verdict),
            jobs_settled,
        })
    }

    /// A prep's verdict that is not `ok` decides its pending jobs of this sweep.
    fn settle_verdict(
        &self,
        store: &mut Store,
        prep_id: i64,
        verdict: Verdict,
        reason: Option<&str>,
        free_speed: Option<f64>,
    ) -> Result<usize, RunError> {
        if verdict == Verdict::Ok {
            return Ok(0);
        }
        let rec = verdict_record(verdict, reason, free_speed, prep_id, &self.classifier);
        Ok(store.settle_jobs_of_prep(self.sweep_id, prep_id, &self.version, &rec)?)
    }

    /// Settle the pending jobs of every prep already decided with a verdict that is not `ok`
    /// (jobs added after their prep was done: a grown sweep, a new round). Returns how many.
    pub fn settle_decided(&self, store: &mut Store) -> Result<usize, RunError> {
        let mut n = 0;
        for p in store.preps_of(self.sweep_id, &self.version)? {
            if p.state == JobState::Done {
                n += self.settle_by_stored_prep(store, p.id)?;
            }
        }
        Ok(n)
    }

    /// Settle the pending jobs of one done prep from its stored verdict, if that is not `ok`.
    pub(super) fn settle_by_stored_prep(
        &self,
        store: &mut Store,
        prep_id: i64,
    ) -> Result<usize, RunError> {
        let stored = store.load_prep(prep_id)?;
        let verdict = match stored.verdict.as_str() {
            "unstable" => Verdict::Unstable,
            "breakup" => Verdict::Breakup,
            _ => return Ok(0),
        };
        let reason = serde_json::from_str::<serde_json::Value>(&stored.summary)
            .ok()
            .and_then(|v| v["verdict_reason"].as_str().map(String::from));
        self.settle_verdict(
            store,
            prep_id,
            verdict,
            reason.as_deref(),
            stored.free_speed,
        )
    }
}
