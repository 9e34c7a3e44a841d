//! Expanding a sweep into points, preps and seeded jobs (SPEC section 6).
//!
//! - A prep's seed derives from the sweep seed, the single-cell parameters (every parameter but
//!   sigma and g), the prep protocol and the prep index: points that differ only in sigma or g
//!   start from the very same prepped cell.
//! - A job's seed derives from the sweep seed, every parameter of its point and the replicate
//!   index, never from scheduling order.
//! - Replicate r starts from the point's prep r mod `preps_per_point`.

use std::collections::HashMap;

use cellsweep_solver::seed::{derive, COLLISION_TAG, PREP_TAG};
use cellsweep_solver::{Config, Params, Protocol, SOLVER_VERSION};
use cellsweep_store::{NewJob, NewPoint, NewPrep, NewSweep, Store};
use serde_json::{json, Value};

use crate::error::RetuneError;
use crate::sweep::Sweep;

/// FNV-1a, 64 bits: a stable hash of canonical text (not for security).
pub fn fnv1a(text: &str) -> u64 {
    cellsweep_store::digest::fnv1a(text.as_bytes())
}

/// The identity of a prep: single-cell parameters (no sigma, no g) and the stages it runs.
pub fn prep_key(params: &Params, protocol: &Protocol) -> String {
    // Parameters are plain data (finite numbers, checked by `validate`): serde_json cannot
    // fail on them, here or below.
    let mut p = serde_json::to_value(params).expect("params serialize");
    if let Value::Object(map) = &mut p {
        map.remove("sigma");
        map.remove("g");
    }
    json!({
        "params": p,
        "single_lattice": protocol.single_lattice,
        "relax_time": protocol.relax_time,
        "free_time": protocol.free_time,
        "record_interval": protocol.record_interval,
        "check_interval": protocol.check_interval,
    })
    .to_string()
}

/// Seed of prep `index` with identity `key` in a sweep seeded `sweep_seed`.
pub fn prep_seed(sweep_seed: u64, key: &str, index: u32) -> u64 {
    derive(&[sweep_seed, PREP_TAG, fnv1a(key), index as u64])
}

/// Seed of replicate `replicate` of the point with parameters `params`.
pub fn job_seed(sweep_seed: u64, params: &Params, replicate: u32) -> u64 {
    // (As in `prep_key`: plain data.)
    let key = serde_json::to_string(params).expect("params serialize");
    derive(&[sweep_seed, COLLISION_TAG, fnv1a(&key), replicate as u64])
}

/// The rows to register for `sweep`, read from `source`: every replicate, or an adaptive
/// sweep's first round.
pub fn plan(sweep: &Sweep, source: &str) -> NewSweep {
    plan_targets(sweep, source, &sweep.points(), &|_| {
        sweep.initial_replicates()
    })
}

/// The rows to register for `sweep` in `store` (from `source`): its grid's points and, where
/// the store holds the sweep under other rules, the points its refinement added there
/// ([`Sweep::stored_points`]: a grown sweep grows them too; a retuned rule that could not have
/// added them is refused before anything is written).
pub fn plan_in(sweep: &Sweep, source: &str, store: &Store) -> Result<NewSweep, RetuneError> {
    Ok(match sweep.stored_points(store)? {
        Some(points) => plan_targets(sweep, source, &points, &|_| sweep.initial_replicates()),
        None => plan(sweep, source),
    })
}

/// The rows to register for `sweep` at `points` (its grid's, then any its refinement added;
/// see [`Sweep::points_with`]) with `target(point index)` replicates at each point (the first
/// ones, in index order; more than the budget are never planned).
pub fn plan_targets(
    sweep: &Sweep,
    source: &str,
    points: &[Params],
    target: &dyn Fn(usize) -> u32,
) -> NewSweep {
    let mut preps: Vec<NewPrep> = Vec::new();
    let mut prep_index: HashMap<(String, u32), usize> = HashMap::new();
    let mut rows = Vec::new();
    for (idx, params) in points.iter().enumerate() {
        let protocol = sweep.protocol_for(params);
        let key = prep_key(params, &protocol);
        let config = Config {
            params: params.clone(),
            protocol,
            classifier: sweep.classifier.clone(),
        };
        // (Plain data, as in `prep_key`.)
        let config_json = serde_json::to_string(&config).expect("config serializes");
        let mut own_preps = Vec::new();
        for i in 0..sweep.preps_per_point {
            let idx = *prep_index.entry((key.clone(), i)).or_insert_with(|| {
                preps.push(NewPrep {
                    key: key.clone(),
                    seed: prep_seed(sweep.seed, &key, i),
                    config: config_json.clone(),
                });
                preps.len() - 1
            });
            own_preps.push(idx);
        }
        let jobs = (0..target(idx).min(sweep.replicates))
            .map(|r| NewJob {
                replicate: r,
                seed: job_seed(sweep.seed, params, r),
                prep: own_preps[(r % sweep.preps_per_point) as usize],
            })
            .collect();
        rows.push(NewPoint {
            alpha: params.alpha,
            beta: params.beta,
            spacing: params.L,
            sigma: params.sigma,
            others: sweep.axes_of(params).others,
            config: config_json,
            jobs,
        });
    }
    NewSweep {
        name: sweep.name.clone(),
        spec: sweep.canonical_json(),
        source: source.to_string(),
        solver_version: SOLVER_VERSION.to_string(),
        preps_per_point: sweep.preps_per_point,
        preps,
        points: rows,
    }
}
