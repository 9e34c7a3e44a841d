//! The preps an import's rows need, computed (in parallel) so that each row's prep hash can be
//! checked, and committed through the ledger.

use cellsweep_solver::{prepare, Config, Silent, SOLVER_VERSION};
use cellsweep_store::export::ExportRow;
use cellsweep_store::{JobState, Store};
use rayon::prelude::*;

use super::{ImportError, ImportEvent};
use crate::wire::PrepPayload;
use crate::{Ledger, Settlement};

/// Compute and settle every prep of sweep `sweep_id` not yet done.
pub(super) fn compute(
    store: &mut Store,
    ledger: &Ledger,
    sweep_id: i64,
    rows: &[ExportRow],
    on: &mut dyn FnMut(ImportEvent),
) -> Result<(), ImportError> {
    let missing: Vec<_> = store
        .preps_of(sweep_id, SOLVER_VERSION)?
        .into_iter()
        .filter(|p| p.state != JobState::Done)
        .collect();
    // What a prep took where the rows were made (if they say).
    let recorded = |seed: u64| {
        rows.iter()
            .find(|r| r.prep_seed == seed)
            .and_then(|r| r.prep_wall_s)
            .filter(|w| w.is_finite() && *w > 0.0)
    };
    if !missing.is_empty() {
        let known: Vec<f64> = missing.iter().filter_map(|p| recorded(p.seed)).collect();
        let cores = rayon::current_num_threads().max(1);
        let estimate = match known.len() {
            0 => "each a whole free motion".to_string(),
            n => {
                let each = known.iter().sum::<f64>() / n as f64;
                let batches = missing.len().div_ceil(cores);
                format!(
                    "each a whole free motion, {each:.0} s where the rows were made: about {} on {cores} cores",
                    cellsweep_stats::throughput::fmt_duration(batches as f64 * each)
                )
            }
        };
        on(ImportEvent::ComputingPreps {
            count: missing.len(),
            estimate,
        });
    }
    let computed: Vec<(f64, Result<PrepPayload, ImportError>)> = missing
        .par_iter()
        .map(|p| {
            let start = std::time::Instant::now();
            let failed =
                |why: &dyn std::fmt::Display| ImportError::Prep(format!("prep {}: {why}", p.id));
            let payload = serde_json::from_str::<Config>(&p.config)
                .map_err(|e| failed(&e))
                .and_then(|c| {
                    prepare(&c.params, &c.protocol, p.seed, &mut Silent).map_err(|e| failed(&e))
                })
                .map(|prep| PrepPayload::from_prep(&prep));
            (start.elapsed().as_secs_f64(), payload)
        })
        .collect();
    for (p, (took, payload)) in missing.iter().zip(computed) {
        let payload = payload?;
        // The prep's cost where the rows were made, if they say; else this recomputation's.
        let wall_s = recorded(p.seed).unwrap_or(took);
        let settled = ledger.settle_prep(store, p.id, &payload, wall_s)?;
        if let Settlement::Refused(why) = settled.settlement {
            return Err(ImportError::Prep(why));
        }
    }
    Ok(())
}
