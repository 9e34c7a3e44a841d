//! Exported rows (`cellsweep import`) checked against the jobs they claim, and committed.

use cellsweep_solver::resolution::to_lattice;
use cellsweep_solver::{Config, Params};
use cellsweep_stats::{End, PrepVerdict};
use cellsweep_store::export::{changed_params, same_to_round_off, ExportRow};
use cellsweep_store::{JobIdentity, JobState, ResultRecord, Store};
use serde_json::json;

use super::{Ledger, Settlement};
use crate::error::RunError;

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

impl Ledger {
    /// Check an exported row (`cellsweep export`) against the job it claims: its sweep, point,
    /// replicate, both seeds, the parameters that differ from the defaults, precision,
    /// classifier, solver version, and the prep's verdict and field hash (so the prep must be
    /// computed).
    pub fn check_row(&self, store: &Store, row: &ExportRow) -> Result<RowCheck, RunError> {
        let axes = match self.sweep.axes_of_row(row) {
            Ok(axes) => axes,
            Err(why) => return Ok(RowCheck::Refused(why.to_string())),
        };
        let at = format!("{axes}, replicate {}", row.replicate);
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
        let others_of = |c: &str| self.sweep.others_of_config(c);
        let job = store.job_at(
            self.sweep_id,
            &self.version,
            &axes,
            row.replicate,
            &others_of,
        )?;
        let Some(job_id) = job else {
            return refuse("no such job in the sweep".into());
        };
        let Some(job) = store.job_identity(job_id)? else {
            return refuse("no such job in the sweep".into());
        };
        let problem = match identity_problem(store, self.sweep_id, &job, row)? {
            Some(why) => Some(why),
            None => match fit_problem(&job, row)? {
                Some(why) => Some(why),
                None => prep_problem(store, &job, row)?,
            },
        };
        if let Some(why) = problem {
            return refuse(why);
        }
        Ok(match job.state {
            JobState::Done => RowCheck::Already,
            _ => RowCheck::Commit(job_id),
        })
    }
}

/// Why a row is not the job it names (seeds, parameters), if it is not.
fn identity_problem(
    store: &Store,
    sweep_id: i64,
    job: &JobIdentity,
    row: &ExportRow,
) -> Result<Option<String>, RunError> {
    if job.seed != row.collision_seed {
        return Ok(Some(format!(
            "collision seed {} is not the job's {}",
            row.collision_seed, job.seed
        )));
    }
    let prep = store.prep_identity(job.prep_id, sweep_id)?;
    if prep.as_ref().map(|p| p.seed) != Some(row.prep_seed) {
        return Ok(Some(format!(
            "prep seed {} is not the job's prep's",
            row.prep_seed
        )));
    }
    let config_json: serde_json::Value = serde_json::from_str(&job.config)?;
    let defaults = serde_json::to_value(Params::default())?;
    if changed_params(&config_json, &defaults) != row.params {
        return Ok(Some(format!("parameters {} are not the job's", row.params)));
    }
    Ok(None)
}

/// Why a row does not fit its job's protocol (times and steps past the collision's end,
/// precision, classifier), if it does not.
fn fit_problem(job: &JobIdentity, row: &ExportRow) -> Result<Option<String>, RunError> {
    let config: Config = serde_json::from_str(&job.config)?;
    // Steps as the solver took them: on a finer lattice (resolution k) dt is dt / k^2.
    let (params, protocol) = to_lattice(&config.params, &config.protocol);
    let steps = match protocol.validate(&params) {
        Ok(steps) => steps,
        Err(e) => return Ok(Some(format!("the job's protocol: {e}"))),
    };
    let end = steps.collide as f64 * params.dt;
    for (field, t) in [
        ("contact_time", row.contact_time),
        ("decision_time", row.decision_time),
    ] {
        if t.is_some_and(|t| t > end * (1.0 + 1e-9)) {
            return Ok(Some(format!(
                "{field} = {} is after the collision's end at {end} tau0",
                t.unwrap_or_default()
            )));
        }
    }
    if row.collision_steps as u64 > steps.collide {
        return Ok(Some(format!(
            "collision_steps = {} is more than the collision's {}",
            row.collision_steps, steps.collide
        )));
    }
    if config.protocol.precision.as_str() != row.precision {
        return Ok(Some(format!(
            "precision {} is not the job's",
            row.precision
        )));
    }
    let classifier: Result<serde_json::Value, _> = serde_json::from_str(&row.classifier);
    if classifier.ok() != Some(serde_json::to_value(&config.classifier)?) {
        return Ok(Some("classifier settings are not the job's".into()));
    }
    Ok(None)
}

/// Why a row's prep is not the prep computed here (not yet computed, another hash, another
/// verdict or an outcome that verdict cannot have), if it is not.
fn prep_problem(
    store: &Store,
    job: &JobIdentity,
    row: &ExportRow,
) -> Result<Option<String>, RunError> {
    let Some(verdict) = job.prep_verdict else {
        return Ok(Some("its prep is not computed yet".into()));
    };
    let hash = store.prep_hash(job.prep_id)?;
    if hash != row.prep_hash {
        return Ok(Some(format!(
            "prep hash {} is not that of the prep computed here ({hash})",
            row.prep_hash
        )));
    }
    let outcome_ok = match row.outcome.as_deref() {
        None => verdict != PrepVerdict::Ok,
        Some(o) => verdict == PrepVerdict::Ok && End::of_outcome(o).is_some(),
    };
    if row.verdict != verdict.as_str() || !outcome_ok {
        return Ok(Some(format!(
            "verdict {:?} with outcome {:?}, but the job's prep is {verdict}",
            row.verdict,
            row.outcome.as_deref().unwrap_or("")
        )));
    }
    // The speeds follow from the prep: its free speed, and the classifier's threshold from it.
    // (To round-off: rows written before JSON carried floats exactly can be an ulp off.)
    let free = store.prep_free_speed(job.prep_id)?;
    if !same_to_round_off(row.free_speed, free) {
        return Ok(Some(format!(
            "free_speed {} contradicts its prep's {}",
            shown(row.free_speed),
            shown(free)
        )));
    }
    if row.outcome.is_some() {
        let config: Config = serde_json::from_str(&job.config)?;
        let threshold = Some(config.classifier.threshold_speed(free.unwrap_or(0.0)));
        if !same_to_round_off(row.threshold_speed, threshold) {
            return Ok(Some(format!(
                "threshold_speed {} contradicts the classifier's {} for its prep",
                shown(row.threshold_speed),
                shown(threshold)
            )));
        }
    }
    Ok(None)
}

fn shown(v: Option<f64>) -> String {
    v.map_or("none".to_string(), |x| x.to_string())
}

impl Ledger {
    /// Commit a row that [`Ledger::check_row`] passed, as the result of `job_id`.
    pub fn commit_row(
        &self,
        store: &mut Store,
        job_id: i64,
        row: &ExportRow,
    ) -> Result<Settlement, RunError> {
        let mut record = serde_json::to_value(row)?;
        record["imported"] = json!(true);
        let unchecked = || RunError::UncheckedRow {
            verdict: row.verdict.clone(),
            outcome: row.outcome.clone().unwrap_or_default(),
        };
        let outcome = match row.outcome.as_deref() {
            None => None,
            Some(o) => Some(End::of_outcome(o).ok_or_else(unchecked)?),
        };
        let rec = ResultRecord {
            verdict: PrepVerdict::parse(&row.verdict).ok_or_else(unchecked)?,
            outcome,
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
        Ok(if store.record_result(job_id, &self.version, &rec)? {
            Settlement::New
        } else {
            Settlement::Already
        })
    }
}
