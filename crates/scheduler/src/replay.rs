//! A stored result computed again from what its record holds, and the two compared field by
//! field: how a user looks at one replicate (its movie, its observables) and how a store or an
//! export is audited (`cellsweep replay`, `cellsweep verify`).
//!
//! A row's trajectory is fixed by its sweep's definition (the point's parameters, the protocol
//! and lattices for that point, the precision), the row's classifier settings and its two
//! seeds. Replaying runs the prep and the collision again from those and turns the result into
//! the stored form by the very function the ledger stores results with, so that equal means
//! what the store would hold. A row of another solver version is not compared: the answer says
//! so instead.

use std::collections::HashMap;

use cellsweep_solver::trajectory::run_from_prep;
use cellsweep_solver::{
    prepare_with, ClassifierSettings, Collision, Config, Monitor, Prep, Seeds, TrajectoryResult,
    SOLVER_VERSION,
};
use cellsweep_store::export::ExportRow;
use cellsweep_store::ResultRecord;
use thiserror::Error;

use crate::ledger::result_record;
use crate::Sweep;

/// Why a row cannot be replayed.
#[derive(Debug, Error)]
pub enum ReplayError {
    /// The row was recorded by another solver: this build would compute something else.
    #[error(
        "recorded by solver {recorded}, this is {this}: not compared (replay it with that version)"
    )]
    OtherVersion { recorded: String, this: String },
    /// The row does not fit its sweep's definition.
    #[error("{0}")]
    Row(String),
    #[error(transparent)]
    Solver(#[from] cellsweep_solver::SolverError),
}

/// One field whose replayed value differs from the stored one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    pub field: &'static str,
    pub stored: String,
    pub replayed: String,
    /// A speed a few ulps off and nothing more: rows stored before floats crossed the worker
    /// pipes' JSON exactly (serde_json's float_roundtrip) can be one ulp off what the worker
    /// computed. Not a different result.
    pub round_off: bool,
}

impl Replayed {
    /// Whether the replay gave the stored result (to round-off in the speeds, see
    /// [`Difference::round_off`]).
    pub fn agrees(&self) -> bool {
        self.differences.iter().all(|d| d.round_off)
    }

    /// What the replay says, in lines: `identical`, `identical to round-off` with the speeds
    /// a few ulps off, or each field that differs with both values.
    pub fn verdict_lines(&self) -> Vec<String> {
        if self.differences.is_empty() {
            return vec!["identical".to_string()];
        }
        let mut lines: Vec<String> = self
            .differences
            .iter()
            .map(|d| {
                let kind = if d.round_off { "round-off" } else { "differs" };
                format!(
                    "{kind}: {}: stored {}, replayed {}",
                    d.field, d.stored, d.replayed
                )
            })
            .collect();
        if self.agrees() {
            lines.push(
                "identical to round-off (a speed an ulp off: stored before floats crossed JSON \
                 exactly)"
                    .to_string(),
            );
        }
        lines
    }

    /// The stored row and the replay side by side: verdict / outcome, contact and decision
    /// times, collision steps.
    pub fn side_by_side(&self, row: &ExportRow) -> [String; 2] {
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x}"));
        let r = &self.result;
        [
            format!(
                "  stored   {} / {}, contact {}, decision {}, {} steps",
                row.verdict,
                row.outcome.as_deref().unwrap_or("-"),
                opt(row.contact_time),
                opt(row.decision_time),
                row.collision_steps
            ),
            format!(
                "  replayed {} / {}, contact {}, decision {}, {} steps",
                r.verdict.as_str(),
                r.outcome.map_or("-", |o| o.as_str()),
                opt(r.contact_time),
                opt(r.decision_time),
                r.collision_steps
            ),
        ]
    }
}

/// A row replayed.
#[derive(Debug)]
pub struct Replayed {
    pub config: Config,
    pub result: TrajectoryResult,
    pub prep: Prep,
    pub collision: Option<Collision>,
    /// Every field that differs; empty when the replay is identical.
    pub differences: Vec<Difference>,
}

/// The configuration row `row` of `sweep` was computed with.
pub fn config_of_row(sweep: &Sweep, row: &ExportRow) -> Result<Config, ReplayError> {
    let axes = sweep
        .axes_of_row(row)
        .map_err(|e| ReplayError::Row(e.to_string()))?;
    let params = sweep.point(&axes);
    let protocol = sweep.protocol_for(&params);
    if protocol.precision.as_str() != row.precision {
        return Err(ReplayError::Row(format!(
            "the row says precision {}, its sweep {}",
            row.precision,
            protocol.precision.as_str()
        )));
    }
    let classifier: ClassifierSettings = serde_json::from_str(&row.classifier)
        .map_err(|e| ReplayError::Row(format!("its classifier settings: {e}")))?;
    Ok(Config {
        params,
        protocol,
        classifier,
    })
}

/// Preps computed by earlier replays, by seed and configuration: the replicates of one point
/// (and the points that differ only in sigma) start from one prep, computed once.
#[derive(Default)]
pub struct PrepCache(HashMap<(u64, String), Prep>);

impl PrepCache {
    pub fn new() -> PrepCache {
        PrepCache::default()
    }

    /// The prep of `config` from `seed`: from the cache, or computed (and kept).
    fn get(
        &mut self,
        config: &Config,
        seed: u64,
        monitor: &mut dyn Monitor,
        parallel: bool,
    ) -> Result<&Prep, ReplayError> {
        // Every parameter and the protocol but the two-cell ones (sigma, g: SPEC 4, stages 1
        // to 3 do not depend on them): more than the prep needs, never less.
        let mut single = config.params.clone();
        (single.sigma, single.g) = (0.0, 0.0);
        let key = (
            seed,
            serde_json::to_string(&(&single, &config.protocol)).unwrap_or_default(),
        );
        if !self.0.contains_key(&key) {
            let prep = prepare_with(&config.params, &config.protocol, seed, monitor, parallel)?;
            self.0.insert(key.clone(), prep);
        }
        Ok(&self.0[&key])
    }
}

/// Replay `row` of `sweep` (progress and frames to `monitor`) and compare it with the row.
pub fn replay(
    sweep: &Sweep,
    row: &ExportRow,
    monitor: &mut dyn Monitor,
    parallel: bool,
) -> Result<Replayed, ReplayError> {
    replay_with(sweep, row, monitor, parallel, &mut PrepCache::new())
}

/// [`replay`], its prep taken from `cache` where an earlier replay computed it.
pub fn replay_with(
    sweep: &Sweep,
    row: &ExportRow,
    monitor: &mut dyn Monitor,
    parallel: bool,
    cache: &mut PrepCache,
) -> Result<Replayed, ReplayError> {
    if row.solver_version != SOLVER_VERSION {
        return Err(ReplayError::OtherVersion {
            recorded: row.solver_version.clone(),
            this: SOLVER_VERSION.to_string(),
        });
    }
    let config = config_of_row(sweep, row)?;
    let seeds = Seeds {
        prep: row.prep_seed,
        collision: row.collision_seed,
    };
    let prep = cache.get(&config, seeds.prep, monitor, parallel)?.clone();
    let (result, collision) = run_from_prep(&config, &prep, seeds.collision, monitor, parallel)?;
    let differences = differences(row, &result_record(&result, 0.0), &prep_hash(&prep));
    Ok(Replayed {
        config,
        result,
        prep,
        collision,
        differences,
    })
}

/// The prep's hash as the store and exports give it (FNV-1a of phi then P, little-endian f64).
pub fn prep_hash(prep: &Prep) -> String {
    use cellsweep_store::f64s_to_bytes;
    let bytes = [f64s_to_bytes(&prep.phi), f64s_to_bytes(&prep.p)].concat();
    format!("{:016x}", cellsweep_store::digest::fnv1a(&bytes))
}

/// The fields of `row` that `replayed` (the stored form of the replayed result) does not give
/// exactly. A prep that is not `ok` gives no collision: its row's outcome and times are empty.
pub fn differences(row: &ExportRow, replayed: &ResultRecord, hash: &str) -> Vec<Difference> {
    let opt = |v: Option<f64>| v.map_or("none".to_string(), |x| format!("{x:?}"));
    let text = |v: Option<&str>| v.unwrap_or("none").to_string();
    let [a1, a2] = replayed
        .attachment
        .clone()
        .map_or([None, None], |[a, b]| [Some(a), Some(b)]);
    // (The drops shed are in the whole record only: the results table has no column for them.)
    let sheddings = serde_json::from_str::<serde_json::Value>(&replayed.record)
        .ok()
        .and_then(|r| r["sheddings"].as_u64())
        .unwrap_or(0);
    let fields: [(&'static str, String, String); 13] = [
        ("verdict", row.verdict.clone(), replayed.verdict.to_string()),
        (
            "outcome",
            text(row.outcome.as_deref()),
            text(
                replayed
                    .outcome
                    .and_then(cellsweep_stats::End::stored_outcome),
            ),
        ),
        (
            "contact_time",
            opt(row.contact_time),
            opt(replayed.contact_time),
        ),
        (
            "decision_time",
            opt(row.decision_time),
            opt(replayed.decision_time),
        ),
        (
            "collision_steps",
            row.collision_steps.to_string(),
            replayed.collision_steps.to_string(),
        ),
        (
            "attachment_1",
            text(row.attachment_1.as_deref()),
            text(a1.as_deref()),
        ),
        (
            "attachment_2",
            text(row.attachment_2.as_deref()),
            text(a2.as_deref()),
        ),
        ("free_speed", opt(row.free_speed), opt(replayed.free_speed)),
        (
            "threshold_speed",
            opt(row.threshold_speed),
            opt(replayed.threshold_speed),
        ),
        (
            "breakup_reason",
            text(row.breakup_reason.as_deref()),
            text(replayed.breakup_reason.as_deref()),
        ),
        (
            "sheddings",
            row.sheddings.to_string(),
            sheddings.to_string(),
        ),
        ("prep_hash", row.prep_hash.clone(), hash.to_string()),
        (
            "classifier",
            canonical(&row.classifier),
            canonical(&replayed.classifier),
        ),
    ];
    fields
        .into_iter()
        .filter(|(_, a, b)| a != b)
        .map(|(field, stored, replayed)| Difference {
            round_off: matches!(field, "free_speed" | "threshold_speed")
                && within_ulps(&stored, &replayed, 4),
            field,
            stored,
            replayed,
        })
        .collect()
}

/// Why no single stored row answers a replay's point and replicate.
#[derive(Debug, Error)]
pub enum FindRowError {
    #[error(transparent)]
    Selector(#[from] cellsweep_stats::SelectError),
    #[error(transparent)]
    Axes(#[from] crate::sweep::RowAxesError),
    #[error("no finished replicate of sweep {sweep:?} is at that point")]
    NoPoint { sweep: String },
    #[error("matches {count} points ({some}): name more axes")]
    Ambiguous { count: usize, some: String },
    #[error("replicate {replicate} has no result ({finished} replicates finished there)")]
    NoReplicate { replicate: u32, finished: usize },
}

/// The row of `replicate` at the one point of `sweep` that `point` (`alpha=0.1,beta=46`, any
/// axis of the sweep) picks among `rows`.
pub fn find_row<'a>(
    sweep: &Sweep,
    rows: &'a [ExportRow],
    point: &str,
    replicate: u32,
) -> Result<&'a ExportRow, FindRowError> {
    let mut axes = vec!["alpha", "beta", "L", "sigma"];
    axes.extend(sweep.grid.others.iter().map(|a| a.name.as_str()));
    let selector = cellsweep_stats::Selector::parse(point)?;
    selector.check_axes(&axes, &format!("sweep {:?}", sweep.name))?;
    let mut at = Vec::new();
    for r in rows {
        let axes = sweep.axes_of_row(r)?;
        if selector.matches(|name| axes.value(name)) {
            at.push((axes.to_string(), r));
        }
    }
    let mut points: Vec<&str> = at.iter().map(|(p, _)| p.as_str()).collect();
    points.sort_unstable();
    points.dedup();
    match points.len() {
        0 => Err(FindRowError::NoPoint {
            sweep: sweep.name.clone(),
        }),
        1 => at
            .iter()
            .find(|(_, r)| r.replicate == replicate)
            .map(|(_, r)| *r)
            .ok_or(FindRowError::NoReplicate {
                replicate,
                finished: at.len(),
            }),
        count => Err(FindRowError::Ambiguous {
            count,
            some: points[..count.min(4)].join("; "),
        }),
    }
}

/// The rows `cellsweep verify` replays from `sets` (each sweep with its rows): those that
/// ended as one of `ended` (every row where it is empty), then all of them (`sample` None) or
/// `n` of them shuffled with `seed` (`sample` Some((n, seed))); and how many there were to
/// choose from.
pub fn choose_rows<'a>(
    sets: &'a [(Sweep, Vec<ExportRow>)],
    ended: &[cellsweep_stats::End],
    sample: Option<(usize, u64)>,
) -> (Vec<(&'a Sweep, &'a ExportRow)>, usize) {
    use rand::seq::SliceRandom;
    use rand::SeedableRng;
    let mut chosen: Vec<(&Sweep, &ExportRow)> = sets
        .iter()
        .flat_map(|(sweep, rows)| rows.iter().map(move |r| (sweep, r)))
        .filter(|(_, r)| {
            ended.is_empty()
                || cellsweep_stats::End::of(&r.verdict, r.outcome.as_deref())
                    .is_some_and(|e| ended.contains(&e))
        })
        .collect();
    let total = chosen.len();
    if let Some((n, seed)) = sample {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        chosen.shuffle(&mut rng);
        chosen.truncate(n.max(1));
    }
    (chosen, total)
}

/// One line naming a row: its point and replicate.
pub fn row_name(sweep: &Sweep, r: &ExportRow) -> String {
    let at = sweep
        .axes_of_row(r)
        .map(|a| a.to_string())
        .unwrap_or_else(|_| format!("alpha = {}, beta = {}", r.alpha, r.beta));
    format!("{at}, replicate {}", r.replicate)
}

/// Two numbers (as printed) at most `n` ulps apart.
fn within_ulps(a: &str, b: &str, n: u64) -> bool {
    match (a.parse::<f64>(), b.parse::<f64>()) {
        (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() && x.signum() == y.signum() => {
            x.to_bits().abs_diff(y.to_bits()) <= n
        }
        _ => false,
    }
}

/// JSON text in one form (keys in order), so that spacing or key order is no difference.
fn canonical(json: &str) -> String {
    serde_json::from_str::<serde_json::Value>(json).map_or(json.to_string(), |v| v.to_string())
}

#[cfg(test)]
mod tests {
    use super::within_ulps;

    #[test]
    fn a_speed_an_ulp_off_is_round_off_and_anything_more_is_not() {
        let x = 0.24887274057726194f64;
        let one_off = f64::from_bits(x.to_bits() - 1);
        assert!(within_ulps(&format!("{x:?}"), &format!("{one_off:?}"), 4));
        assert!(!within_ulps("0.2488727405772", &format!("{x:?}"), 4));
        assert!(!within_ulps("0.1", "-0.1", 4));
        assert!(!within_ulps("none", "0.1", 4));
    }
}
