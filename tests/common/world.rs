//! A world whose crossing is known, for tests of refinement: the ledger driven as the local
//! engine drives it.
//!
//! Preps and collisions are the real solver's (on small lattices, 2 tau0 collisions), and every
//! record goes through the ledger's own checks. Only the outcome of each collision is drawn
//! from a known logistic law, P(walk past | walk past or training) = 1 / (1 + exp(-k (beta -
//! beta*))), with the draw a function of the job's seed: the real model cannot decide a
//! collision in 2 tau0, and this is what lets a test know where the crossing is. What is
//! tested is the bookkeeping: which points rounds add, where, how many, their seeds, resume,
//! and that the order in which results arrive changes nothing.

#![allow(dead_code)]

use std::collections::{BTreeSet, HashMap};
use std::path::PathBuf;

use cellsweep_scheduler::wire::{PrepPayload, Request, Response};
use cellsweep_scheduler::worker::{answer, PrepCache};
use cellsweep_scheduler::{plan, Ledger, Settlement, Sweep};
use cellsweep_solver::{Outcome, Params, SOLVER_VERSION};
use cellsweep_store::{JobState, Store};

pub const STEP: f64 = 0.5;

pub fn sweep_text(name: &str, beta: &str, refine: bool) -> String {
    let refine = if refine {
        format!("[refine]\nwidth = 1.2\nstep = {STEP}\nmax_new_per_column = 6\nper_round = 2\n")
    } else {
        String::new()
    };
    format!(
        "name = \"{name}\"\nseed = 5\nreplicates = 40\n[grid]\nalpha = [0.1, 0.12]\nbeta = {beta}\n\
         L = [48]\nsigma = [5]\n[params]\nR0 = 24\n[protocol]\nsingle_lattice = [96, 96]\n\
         relax_time = 5\nfree_time = 10\ncollide_time = 2\n{refine}"
    )
}

/// The known crossing of each column, and the law's slope.
pub fn beta_star(alpha: f64) -> f64 {
    if alpha < 0.11 {
        17.3
    } else {
        23.8
    }
}
pub const K: f64 = 0.8;

/// The law's outcome for a job: walk past with probability sigma(K (beta - beta*)), drawn from
/// the job's seed (itself a hash of the sweep seed, the parameters and the replicate).
pub fn law(params: &Params, seed: u64) -> Outcome {
    let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
    let p = 1.0 / (1.0 + (-K * (params.beta - beta_star(params.alpha))).exp());
    if u < p {
        Outcome::WalkPast
    } else {
        Outcome::Train
    }
}

pub fn store_at(name: &str) -> (super::Scratch, Store) {
    let db = super::Scratch::file("refinement", name, "r.sqlite");
    let store = Store::open_or_create(&db).unwrap();
    (db, store)
}

/// Register `sweep` and open its ledger as a run does.
pub fn open(store: &mut Store, sweep: &Sweep) -> Ledger {
    let reg = store.register(&plan(sweep, "test"), false).unwrap();
    Ledger::open(store, reg.sweep_id, SOLVER_VERSION, 3)
        .unwrap()
        .0
}

/// Run every prep and job the store holds, rounds included, as the local engine does (plan
/// after each result), in point order or reversed; stop after `limit` jobs. Returns the jobs
/// run.
pub fn drive(store: &mut Store, ledger: &Ledger, reverse: bool, limit: usize) -> usize {
    let (id, v) = (ledger.sweep_id, ledger.version.clone());
    let mut cache = PrepCache::new();
    let mut payloads: HashMap<i64, PrepPayload> = HashMap::new();
    let mut ran = 0;
    loop {
        for p in store.preps_of(id, &v).unwrap() {
            if p.state == JobState::Pending {
                store.claim_prep(p.id).unwrap();
                let Response::Prep { task, prep, wall_s } =
                    answer(Request::prep(&p).unwrap(), &mut cache)
                else {
                    panic!("prep {} failed", p.id)
                };
                let s = ledger.settle_prep(store, task, &prep, wall_s).unwrap();
                assert_eq!(s.settlement, Settlement::New);
            }
            if let std::collections::hash_map::Entry::Vacant(e) = payloads.entry(p.id) {
                if let Ok(rec) = store.load_prep(p.id) {
                    e.insert(PrepPayload::from_record(rec, p.seed).unwrap());
                }
            }
        }
        // As an engine does: the planned jobs become rows before they are listed.
        store.materialize_next(id, &v, usize::MAX).unwrap();
        let mut jobs = store.pending_jobs(id, &v).unwrap();
        if jobs.is_empty() {
            if ledger.plan_rounds(store).unwrap() == 0 {
                return ran;
            }
            continue;
        }
        if reverse {
            jobs.reverse();
        }
        for j in jobs {
            if ran == limit {
                return ran;
            }
            store.claim_job(j.id).unwrap();
            let prep = payloads.get(&j.prep_id).cloned().map(Box::new);
            let Response::Collide {
                task,
                mut result,
                wall_s,
            } = answer(Request::collide(&j, prep).unwrap(), &mut cache)
            else {
                panic!("job {} failed", j.id)
            };
            // The law decides; a decided outcome has its time, inside the collision.
            result.outcome = Some(law(&result.config.params, j.seed));
            result.decision_time = Some(1.0);
            let s = ledger.settle_job(store, task, &result, wall_s).unwrap();
            assert_eq!(s, Settlement::New);
            ran += 1;
            ledger.plan_rounds(store).unwrap();
        }
    }
}

/// Every stored result as the rows an export gives, without wall times, by point and replicate.
pub fn rows(store: &Store, ledger: &Ledger) -> Vec<String> {
    let defaults = serde_json::to_value(Params::default()).unwrap();
    let mut out: Vec<String> = store
        .export_rows(ledger.sweep_id, SOLVER_VERSION, &defaults)
        .unwrap()
        .into_iter()
        .map(|mut r| {
            (r.wall_s, r.prep_wall_s) = (None, None);
            format!("{r:?}")
        })
        .collect();
    out.sort();
    out
}

/// The betas each column holds beyond the grid.
pub fn added(ledger: &Ledger, store: &Store) -> BTreeSet<(u64, u64)> {
    ledger
        .points(store)
        .unwrap()
        .iter()
        .filter(|p| !ledger.sweep.grid.beta.contains(&p.beta))
        .map(|p| (p.alpha.to_bits(), p.beta.to_bits()))
        .collect()
}

/// The grid's betas of the world's sweeps.
pub const GRID_BETA: &str = "{ from = 10, to = 30, step = 4 }";

/// A refined sweep `name` (its file written into `dir`) whose grid has run in the known world,
/// exported as `cellsweep export` writes it: what `import` brings into a store where a run
/// goes on with the refinement rounds. Returns the sweep file and the export.
pub fn refined_export(dir: &std::path::Path, name: &str) -> (PathBuf, PathBuf) {
    let fixed = Sweep::parse(&sweep_text(name, GRID_BETA, false), "grid.toml").unwrap();
    let (db, mut store) = store_at(&format!("{name}-grid"));
    let ledger = open(&mut store, &fixed);
    drive(&mut store, &ledger, false, usize::MAX);
    drop(store);
    let grid_csv = dir.join("grid.csv");
    super::export(&db, &grid_csv);
    // The same rows under the refined sweep's definition (refinement changes no seed).
    let toml = dir.join(format!("{name}.toml"));
    std::fs::write(&toml, sweep_text(name, GRID_BETA, true)).unwrap();
    let refined = Sweep::load(&toml).unwrap();
    let text = std::fs::read_to_string(&grid_csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[1] = format!("# spec {}", refined.canonical_json());
    let csv = dir.join(format!("{name}.csv"));
    std::fs::write(&csv, lines.join("\n") + "\n").unwrap();
    (toml, csv)
}
