//! Several exports read as one where they ran the same trajectories: an extension beside the
//! sweep whose seed and parameters it shares (SPEC section 6: a refinement may extend the axis
//! in a separately named sweep), or an adaptive sweep beside the fixed one it is a prefix of.
//! Seeds derive from the sweep seed, the point and the replicate index, never from a sweep's
//! name, so such sets hold the very same runs at the points they share; `Results::merged`
//! refuses them (their replicates would count twice), and pooling reads each run once.
//!
//! The rule, point by point: the set with the most rows at a point is read there; another
//! set's rows at that point are left out when every one of them is among those (the same
//! collision seed, prep seed, prepped cell, precision and classifier: the same trajectory);
//! a point where they are not (independent runs, another seed) is refused, since adding
//! independent replicates to another set's point is not what pooling means.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use cellsweep_scheduler::export_file::read_export;
use cellsweep_store::export::ExportRow;

use crate::load::{from_rows, LoadError};
use crate::Results;

/// What makes two rows the same run.
fn run_identity(r: &ExportRow) -> (u64, u64, u32, &str, &str, &str) {
    (
        r.collision_seed,
        r.prep_seed,
        r.replicate,
        r.prep_hash.as_str(),
        r.precision.as_str(),
        r.classifier.as_str(),
    )
}

/// The exports at `paths` read as one, every run once (see the module's rule).
pub fn pooled_exports(paths: &[&Path]) -> Result<Results, LoadError> {
    let sets = paths
        .iter()
        .map(|p| read_export(p).map(|(sweep, rows)| (p.display().to_string(), sweep, rows)))
        .collect::<Result<Vec<_>, _>>()?;
    // Each point's rows, set by set.
    let mut at: HashMap<_, Vec<(usize, Vec<usize>)>> = HashMap::new();
    for (i, (source, sweep, rows)) in sets.iter().enumerate() {
        for (j, r) in rows.iter().enumerate() {
            let axes = sweep
                .axes_of_row(r)
                .map_err(|e| LoadError::Invalid(format!("{source}: {e}")))?;
            let holders = at.entry(axes.key()).or_default();
            match holders.iter_mut().find(|(set, _)| *set == i) {
                Some((_, js)) => js.push(j),
                None => holders.push((i, vec![j])),
            }
        }
    }
    let mut keep: Vec<Vec<bool>> = sets.iter().map(|s| vec![true; s.2.len()]).collect();
    for holders in at.values().filter(|h| h.len() > 1) {
        let (best, best_rows) = holders
            .iter()
            .max_by_key(|(set, js)| (js.len(), std::cmp::Reverse(*set)))
            .expect("a point held by two sets");
        let runs: HashSet<_> = best_rows
            .iter()
            .map(|&j| run_identity(&sets[*best].2[j]))
            .collect();
        for (set, js) in holders.iter().filter(|(set, _)| set != best) {
            if let Some(&j) = js
                .iter()
                .find(|&&j| !runs.contains(&run_identity(&sets[*set].2[j])))
            {
                let r = &sets[*set].2[j];
                return Err(LoadError::Invalid(format!(
                    "{}: replicate {} at alpha = {}, beta = {}, L = {}, sigma = {} is not a run \
                     of {} (another seed, prepped cell, precision or classifier): pooling reads \
                     the same runs once and does not add independent ones",
                    sets[*set].0, r.replicate, r.alpha, r.beta, r.L, r.sigma, sets[*best].0
                )));
            }
            for &j in js {
                keep[*set][j] = false;
            }
        }
    }
    let mut parts = Vec::new();
    for ((source, sweep, rows), kept) in sets.iter().zip(&keep) {
        if !kept.iter().any(|k| *k) {
            continue;
        }
        let rows: Vec<ExportRow> = rows
            .iter()
            .zip(kept)
            .filter(|(_, k)| **k)
            .map(|(r, _)| r.clone())
            .collect();
        // A point every row of which another set holds is left out of this one.
        parts.push(from_rows(source, sweep, &rows)?.only(|c| c.total() > 0));
    }
    Results::merged(parts)
}
