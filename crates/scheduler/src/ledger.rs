//! The ledger: the one way work enters the store, shared by the local engine
//! ([`crate::coordinator`]) and the Slurm engine ([`crate::slurm`]).
//!
//! Every prep and collision record is checked against what the store says of the prep or job it
//! claims (its sweep, solver version, seed, parameters, and the prep a collision started from)
//! before it is committed in one transaction; a record that does not match is refused with the
//! reason and nothing is written. A prep whose verdict is not `ok` settles its jobs with that
//! verdict. An adaptive sweep's rounds are planned here too: [`Ledger::plan_rounds`] adds the
//! next replicates of every open point whose round is complete.

use std::collections::HashMap;

use cellsweep_solver::{Config, Params, TrajectoryResult, Verdict};
use cellsweep_store::adaptive::kinds;
use cellsweep_store::export::{changed_params, ExportRow};
use cellsweep_store::{assess, Assessment, JobState, PointEnds, ResultRecord, Store};
use serde_json::json;

use crate::error::RunError;
use crate::plan::plan_targets;
use crate::sweep::Sweep;
use crate::wire::PrepPayload;

/// What became of a record.
#[derive(Debug, Clone, PartialEq)]
pub enum Settlement {
    /// Committed.
    New,
    /// The store already had it; nothing changed.
    Already,
    /// Not committed: the record does not belong to the job or prep it claims.
    Refused(String),
}

/// What [`Ledger::check_row`] found of an exported row.
#[derive(Debug, Clone, PartialEq)]
pub enum RowCheck {
    /// The row matches this job, which has no result yet.
    Commit(i64),
    /// The row matches a job that already has its result.
    Already,
    /// The row does not match the job it claims, with the reason.
    Refused(String),
}

/// A committed prep: its verdict and how many jobs that verdict settled.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepSettled {
    pub settlement: Settlement,
    pub verdict: Option<Verdict>,
    pub jobs_settled: usize,
}

/// The ledger of one sweep under one solver version.
#[derive(Debug, Clone)]
pub struct Ledger {
    pub sweep_id: i64,
    pub version: String,
    pub sweep: Sweep,
    /// JSON of the sweep's classifier settings, stored with every result.
    classifier: String,
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
        verdict: verdict.as_str().to_string(),
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

/// The stored form of a collision's result.
fn result_record(r: &TrajectoryResult, wall_s: f64) -> ResultRecord {
    let name = |a| {
        serde_json::to_value(a)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
            .unwrap_or_default()
    };
    ResultRecord {
        verdict: r.verdict.as_str().to_string(),
        outcome: r.outcome.map(|o| o.as_str().to_string()),
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
    /// The ledger of a registered sweep, its definition read back from the store.
    pub fn load(store: &Store, sweep_id: i64, version: &str) -> Result<Ledger, RunError> {
        let spec = store.sweep_spec(sweep_id)?;
        let sweep: Sweep = serde_json::from_str(&spec)?;
        Ok(Ledger {
            sweep_id,
            version: version.to_string(),
            classifier: serde_json::to_string(&sweep.classifier)?,
            sweep,
        })
    }

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
        let config: Config = serde_json::from_str(&job.config)?;
        if result.config != config {
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
            && job.prep_verdict.as_deref() == Some(result.verdict.as_str());
        if decided_by_prep {
            if job.state == JobState::Done {
                return Ok(Settlement::Already);
            }
            // Settled as every job of that prep is, from the stored prep (one write path).
            self.settle_by_stored_prep(store, job.prep_id)?;
            return Ok(Settlement::New);
        }
        if !decided_by_prep
            && (job.prep_verdict.as_deref() != Some("ok")
                || result.verdict != Verdict::Ok
                || result.outcome.is_none())
        {
            return refuse(format!(
                "a collision with verdict {:?}, but the job's prep is {}",
                result.verdict.as_str(),
                job.prep_verdict.as_deref().unwrap_or("not done")
            ));
        }
        if job.state == JobState::Done {
            return Ok(Settlement::Already);
        }
        store.collect_result(job_id, &self.version, &result_record(result, wall_s))?;
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
        if payload.lattice != config.protocol.single_lattice {
            return refuse(format!(
                "lattice {:?} is not the prep's {:?}",
                payload.lattice, config.protocol.single_lattice
            ));
        }
        let settlement = if prep.state == JobState::Done {
            Settlement::Already
        } else {
            let rec = match payload.to_record(wall_s) {
                Ok(r) => r,
                Err(why) => return refuse(why.to_string()),
            };
            store.collect_prep(prep_id, &rec)?;
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
    fn settle_by_stored_prep(&self, store: &mut Store, prep_id: i64) -> Result<usize, RunError> {
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

    /// A failed attempt of a job: pending again, or failed for good after `max_attempts`.
    pub fn fail_job(
        &self,
        store: &mut Store,
        id: i64,
        error: &str,
        max_attempts: u32,
    ) -> Result<JobState, RunError> {
        Ok(store.fail_job(id, error, max_attempts)?)
    }

    /// A failed attempt of a prep; failed for good, it fails the sweep's jobs that need it.
    /// Returns the new state and how many jobs failed with it.
    pub fn fail_prep(
        &self,
        store: &mut Store,
        id: i64,
        error: &str,
        max_attempts: u32,
    ) -> Result<(JobState, usize), RunError> {
        let state = store.fail_prep(id, error, max_attempts)?;
        let n = if state == JobState::Failed {
            self.fail_jobs_of_prep(store, id, error)?
        } else {
            0
        };
        Ok((state, n))
    }

    /// The sweep's pending jobs of a prep that failed for good cannot run: they fail with it.
    pub fn fail_jobs_of_prep(
        &self,
        store: &mut Store,
        id: i64,
        error: &str,
    ) -> Result<usize, RunError> {
        Ok(store.fail_jobs_of_prep(self.sweep_id, id, &self.version, error)?)
    }

    /// Every point's finished replicates by index, in grid order.
    pub fn point_ends(&self, store: &Store) -> Result<Vec<PointEnds>, RunError> {
        let points = self.sweep.points();
        let key = |a: f64, b: f64, l: u32, s: f64| (a.to_bits(), b.to_bits(), l, s.to_bits());
        let index: HashMap<_, usize> = points
            .iter()
            .enumerate()
            .map(|(i, p)| (key(p.alpha, p.beta, p.L, p.sigma), i))
            .collect();
        let mut out: Vec<PointEnds> = points
            .iter()
            .map(|p| PointEnds::new(p.alpha, p.beta, p.L, p.sigma))
            .collect();
        for r in store.replicates(self.sweep_id, &self.version)? {
            if let Some(&i) = index.get(&key(r.alpha, r.beta, r.L, r.sigma)) {
                let ends = &mut out[i].ends;
                let k = r.replicate as usize;
                if ends.len() <= k {
                    ends.resize(k + 1, None);
                }
                ends[k] = Some(r.end);
            }
        }
        Ok(out)
    }

    /// Where every point stands under the sweep's adaptive rule (None for a fixed sweep).
    pub fn assess(&self, store: &Store) -> Result<Option<Vec<Assessment>>, RunError> {
        let Some(rule) = self.sweep.adaptive else {
            return Ok(None);
        };
        let ends = self.point_ends(store)?;
        Ok(Some(assess(
            &ends,
            &rule,
            kinds(self.sweep.preps_per_point),
        )))
    }

    /// Add the next round of every open point whose round is complete (adaptive sweeps), and
    /// settle new jobs whose prep is already decided. Returns how many jobs were added.
    pub fn plan_rounds(&self, store: &mut Store) -> Result<usize, RunError> {
        let Some(assessed) = self.assess(store)? else {
            return Ok(0);
        };
        let have = store.jobs_per_point(self.sweep_id, &self.version)?;
        let targets: Vec<u32> = assessed
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let h = have.get(i).copied().unwrap_or(0);
                a.next_round.map_or(h, |n| n.max(h))
            })
            .collect();
        let added: u32 = targets
            .iter()
            .enumerate()
            .map(|(i, &t)| t - have.get(i).copied().unwrap_or(0))
            .sum();
        if added == 0 {
            return Ok(0);
        }
        // The sweep is registered already: the source it was read from stays as stored.
        let new = plan_targets(&self.sweep, "", &|i| targets[i]);
        store.register(&new, false)?;
        self.settle_decided(store)?;
        Ok(added as usize)
    }

    /// Check an exported row (`cellsweep export`) against the job it claims: its sweep, point,
    /// replicate, both seeds, the parameters that differ from the defaults, precision,
    /// classifier, solver version, and the prep's verdict and field hash (so the prep must be
    /// computed).
    pub fn check_row(&self, store: &Store, row: &ExportRow) -> Result<RowCheck, RunError> {
        let at = format!(
            "alpha = {}, beta = {}, L = {}, sigma = {}, replicate {}",
            row.alpha, row.beta, row.L, row.sigma, row.replicate
        );
        let refuse = |why: String| Ok(RowCheck::Refused(format!("{at}: {why}")));
        if row.sweep != self.sweep.name {
            return refuse(format!(
                "a row of sweep {:?}, not {:?}",
                row.sweep, self.sweep.name
            ));
        }
        if row.solver_version != self.version {
            return refuse(format!(
                "solver version {:?}, this build is {:?}",
                row.solver_version, self.version
            ));
        }
        let axes = (row.alpha, row.beta, row.L, row.sigma);
        let Some(job_id) = store.job_at(self.sweep_id, &self.version, axes, row.replicate)? else {
            return refuse("no such job in the sweep".into());
        };
        let job = store
            .job_identity(job_id)?
            .expect("a job just found exists");
        if job.seed != row.collision_seed {
            return refuse(format!(
                "collision seed {} is not the job's {}",
                row.collision_seed, job.seed
            ));
        }
        let prep = store.prep_identity(job.prep_id, self.sweep_id)?;
        if prep.as_ref().map(|p| p.seed) != Some(row.prep_seed) {
            return refuse(format!(
                "prep seed {} is not the job's prep's",
                row.prep_seed
            ));
        }
        let config_json: serde_json::Value = serde_json::from_str(&job.config)?;
        let defaults = serde_json::to_value(Params::default())?;
        if changed_params(&config_json, &defaults) != row.params {
            return refuse(format!("parameters {} are not the job's", row.params));
        }
        let config: Config = serde_json::from_str(&job.config)?;
        let steps = match config.protocol.validate(&config.params) {
            Ok(steps) => steps,
            Err(e) => return refuse(format!("the job's protocol: {e}")),
        };
        let end = steps.collide as f64 * config.params.dt;
        for (field, t) in [
            ("contact_time", row.contact_time),
            ("decision_time", row.decision_time),
        ] {
            if t.is_some_and(|t| t > end * (1.0 + 1e-9)) {
                return refuse(format!(
                    "{field} = {} is after the collision's end at {end} tau0",
                    t.unwrap_or_default()
                ));
            }
        }
        if row.collision_steps as u64 > steps.collide {
            return refuse(format!(
                "collision_steps = {} is more than the collision's {}",
                row.collision_steps, steps.collide
            ));
        }
        if config.protocol.precision.as_str() != row.precision {
            return refuse(format!("precision {} is not the job's", row.precision));
        }
        let classifier: Result<serde_json::Value, _> = serde_json::from_str(&row.classifier);
        if classifier.ok() != Some(serde_json::to_value(&config.classifier)?) {
            return refuse("classifier settings are not the job's".into());
        }
        let Some(verdict) = job.prep_verdict.as_deref() else {
            return refuse("its prep is not computed yet".into());
        };
        let hash = store.prep_hash(job.prep_id)?;
        if hash != row.prep_hash {
            return refuse(format!(
                "prep hash {} is not that of the prep computed here ({hash})",
                row.prep_hash
            ));
        }
        let outcome_ok = match row.outcome.as_deref() {
            None => verdict != "ok",
            Some(o) => {
                verdict == "ok"
                    && ["train", "walk_past", "reversal", "undetermined", "breakup"].contains(&o)
            }
        };
        if row.verdict != verdict || !outcome_ok {
            return refuse(format!(
                "verdict {:?} with outcome {:?}, but the job's prep is {verdict}",
                row.verdict,
                row.outcome.as_deref().unwrap_or("")
            ));
        }
        Ok(match job.state {
            JobState::Done => RowCheck::Already,
            _ => RowCheck::Commit(job_id),
        })
    }

    /// Commit a row that [`Ledger::check_row`] passed, as the result of `job_id`.
    pub fn commit_row(
        &self,
        store: &mut Store,
        job_id: i64,
        row: &ExportRow,
    ) -> Result<Settlement, RunError> {
        let mut record = serde_json::to_value(row)?;
        record["imported"] = json!(true);
        let rec = ResultRecord {
            verdict: row.verdict.clone(),
            outcome: row.outcome.clone(),
            contact_time: row.contact_time,
            decision_time: row.decision_time,
            free_speed: row.free_speed,
            threshold_speed: row.threshold_speed,
            attachment: row
                .attachment_1
                .clone()
                .zip(row.attachment_2.clone())
                .map(|(a, b)| [a, b]),
            // (check_row refused a negative count.)
            collision_steps: row.collision_steps.max(0) as u64,
            breakup_reason: row.breakup_reason.clone(),
            // The time the collision took where it ran (0: not recorded).
            wall_s: row
                .wall_s
                .filter(|w| w.is_finite() && *w > 0.0)
                .unwrap_or(0.0),
            classifier: row.classifier.clone(),
            record: record.to_string(),
        };
        Ok(if store.collect_result(job_id, &self.version, &rec)? {
            Settlement::New
        } else {
            Settlement::Already
        })
    }
}
