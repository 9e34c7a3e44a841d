//! Registering a sweep: a new one, the same one again (resume), one that grows its replicates
//! or changes its adaptive rule in place, or a different one under a taken name (refused, or
//! archived with `--replace`).

use cellsweep_stats::{Axes, Others, PointKey};
use rusqlite::{params, OptionalExtension};

use crate::database::Store;
use crate::encoding::{now, point_others, seed_to_sql};
use crate::error::{Result, StoreError};
use crate::lifecycle::JobState;
use crate::plans::{plan_point_jobs, NewJob};

/// A sweep to register: its points, their jobs, and the preps they start from.
#[derive(Debug, Clone)]
pub struct NewSweep {
    pub name: String,
    /// Canonical JSON of the expanded definition; a different text is a different sweep.
    pub spec: String,
    pub source: String,
    pub solver_version: String,
    /// Preps per point: replicate r of a point starts from the prep of replicate r mod this.
    pub preps_per_point: u32,
    pub preps: Vec<NewPrep>,
    pub points: Vec<NewPoint>,
}

#[derive(Debug, Clone)]
pub struct NewPrep {
    pub key: String,
    pub seed: u64,
    /// JSON of what a worker needs to compute it (parameters and protocol).
    pub config: String,
}

#[derive(Debug, Clone)]
pub struct NewPoint {
    pub alpha: f64,
    pub beta: f64,
    pub spacing: u32,
    pub sigma: f64,
    /// The sweep's other axes at this point (empty for the paper's four).
    pub others: Others,
    /// JSON of what a worker needs to run a collision (parameters, protocol, classifier).
    pub config: String,
    pub jobs: Vec<NewJob>,
}

/// What registering a sweep found.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    pub sweep_id: i64,
    /// The sweep was new.
    pub created: bool,
    /// The sweep was registered with this many replicates per point and now has more.
    pub grown_from: Option<u32>,
    /// An older sweep of the same name was archived under this name (`--replace`).
    pub archived_as: Option<String>,
    /// Results of this sweep under other solver versions: (version, count). They stay apart.
    pub other_versions: Vec<(String, i64)>,
}

impl Store {
    /// Register `sweep` (or find it registered), and make sure every one of its preps and jobs
    /// exists for its solver version. A different sweep under an existing name is refused unless
    /// `replace`, which renames the old sweep (its results stay) and registers the new one.
    pub fn register(&mut self, sweep: &NewSweep, replace: bool) -> Result<Registration> {
        let tx = self.write()?;
        let row = sweep_row(&tx, sweep, replace)?;
        let point_ids = point_ids(&tx, row.sweep_id, sweep)?;
        let prep_ids = insert_preps(&tx, sweep)?;
        insert_jobs(&tx, sweep, &point_ids, &prep_ids)?;
        let other_versions = other_versions(&tx, row.sweep_id, &sweep.solver_version)?;
        tx.commit()?;
        Ok(Registration {
            sweep_id: row.sweep_id,
            created: row.created,
            grown_from: row.grown_from,
            archived_as: row.archived_as,
            other_versions,
        })
    }
}

/// The sweep's row after registration, and what registration did to it.
struct SweepRow {
    sweep_id: i64,
    created: bool,
    grown_from: Option<u32>,
    archived_as: Option<String>,
}

/// Find, update, archive or insert the sweep's row: a new sweep is inserted, the same one kept,
/// a retuned or grown one updated; a conflicting one is refused, or archived with `replace`.
fn sweep_row(tx: &rusqlite::Connection, sweep: &NewSweep, replace: bool) -> Result<SweepRow> {
    let existing: Option<(i64, String)> = tx
        .query_row(
            "SELECT id, spec FROM sweeps WHERE name = ?1",
            [&sweep.name],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .optional()?;
    let mut archived_as = None;
    let mut grown_from = None;
    let (sweep_id, created) = match existing {
        None => (insert_sweep(tx, sweep)?, true),
        Some((id, spec)) => match spec_change(&spec, &sweep.spec) {
            SpecChange::Same => (id, false),
            SpecChange::Retuned => {
                tx.execute(
                    "UPDATE sweeps SET spec = ?1, source = ?2 WHERE id = ?3",
                    params![sweep.spec, sweep.source, id],
                )?;
                (id, false)
            }
            SpecChange::Grows { from } => {
                // Replicate r's seed and prep do not depend on how many replicates there
                // are: the stored jobs are the first `from` of the grown sweep, and the
                // jobs insert_jobs adds are the others.
                tx.execute(
                    "UPDATE sweeps SET spec = ?1, source = ?2 WHERE id = ?3",
                    params![sweep.spec, sweep.source, id],
                )?;
                grown_from = Some(from);
                (id, false)
            }
            change if !replace => {
                let name = sweep.name.clone();
                return Err(match change {
                    SpecChange::Shrinks { from, to } => StoreError::SweepShrinks {
                        name,
                        stored: from,
                        asked: to,
                    },
                    _ => StoreError::SweepConflict {
                        archived: format!("{name}@{id}"),
                        differs: spec_differences(&spec, &sweep.spec),
                        name,
                    },
                });
            }
            _ => {
                let archived = format!("{}@{}", sweep.name, id);
                tx.execute(
                    "UPDATE sweeps SET name = ?1 WHERE id = ?2",
                    params![archived, id],
                )?;
                archived_as = Some(archived);
                (insert_sweep(tx, sweep)?, true)
            }
        },
    };
    Ok(SweepRow {
        sweep_id,
        created,
        grown_from,
        archived_as,
    })
}

/// The id of every point of `sweep`, inserting those not stored yet: a new sweep's points in
/// order, and after the points it holds, those its refinement adds. A point is found by its
/// axes, bit for bit (the other axes' values read out of its stored configuration), so a
/// resumed sweep listing only its grid finds the grid's rows, and the points refinement added
/// stay (refused if the definition no longer has `refine`).
fn point_ids(tx: &rusqlite::Connection, sweep_id: i64, sweep: &NewSweep) -> Result<Vec<i64>> {
    let names: Vec<&str> = sweep.points.first().map_or(Vec::new(), |p| {
        p.others.0.iter().map(|(n, _)| n.as_str()).collect()
    });
    let key = |a: f64, b: f64, l: u32, s: f64, others: &Others| {
        Axes {
            alpha: a,
            beta: b,
            L: l,
            sigma: s,
            others: others.clone(),
        }
        .key()
    };
    let mut stored: std::collections::HashMap<PointKey, i64> = std::collections::HashMap::new();
    let mut next = 0i64;
    {
        let mut q = tx.prepare(
            "SELECT id, idx, alpha, beta, L, sigma, params FROM points WHERE sweep_id = ?1",
        )?;
        let rows = q.query_map([sweep_id], |r| {
            let others = if names.is_empty() {
                Others::default()
            } else {
                point_others(&r.get::<_, String>(6)?, &names)
            };
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, i64>(1)?,
                key(r.get(2)?, r.get(3)?, r.get(4)?, r.get(5)?, &others),
            ))
        })?;
        for row in rows {
            let (id, idx, k) = row?;
            next = next.max(idx + 1);
            stored.insert(k, id);
        }
    }
    let extra = stored.len().saturating_sub(sweep.points.len());
    if extra > 0 && !spec_has_refine(&sweep.spec) {
        return Err(StoreError::RefinementDropped {
            name: sweep.name.clone(),
            added: extra,
        });
    }
    let mut insert = tx.prepare(
        "INSERT INTO points (sweep_id, idx, alpha, beta, L, sigma, params)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
    )?;
    let mut ids = Vec::with_capacity(sweep.points.len());
    for pt in &sweep.points {
        let k = key(pt.alpha, pt.beta, pt.spacing, pt.sigma, &pt.others);
        let id = match stored.get(&k) {
            Some(&id) => id,
            None => {
                insert.execute(params![
                    sweep_id, next, pt.alpha, pt.beta, pt.spacing, pt.sigma, pt.config
                ])?;
                next += 1;
                let id = tx.last_insert_rowid();
                stored.insert(k, id);
                id
            }
        };
        ids.push(id);
    }
    Ok(ids)
}

/// Whether a canonical definition asks for refinement.
fn spec_has_refine(spec: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(spec)
        .ok()
        .is_some_and(|v| v.get("refine").is_some_and(|r| !r.is_null()))
}

/// The sweep's preps (those already stored, by key, seed and solver, are shared), with the id
/// of each.
fn insert_preps(tx: &rusqlite::Connection, sweep: &NewSweep) -> Result<Vec<i64>> {
    let mut insert = tx.prepare(
        "INSERT OR IGNORE INTO preps (key, seed, solver_version, config, state)
         VALUES (?1, ?2, ?3, ?4, 'pending')",
    )?;
    let mut id =
        tx.prepare("SELECT id FROM preps WHERE key = ?1 AND seed = ?2 AND solver_version = ?3")?;
    let mut prep_ids = Vec::with_capacity(sweep.preps.len());
    for prep in &sweep.preps {
        let seed = seed_to_sql(prep.seed);
        insert.execute(params![prep.key, seed, sweep.solver_version, prep.config])?;
        prep_ids.push(
            id.query_row(params![prep.key, seed, sweep.solver_version], |r| {
                r.get::<_, i64>(0)
            })?,
        );
    }
    Ok(prep_ids)
}

/// The jobs not yet registered (a resumed sweep's are kept as they are; a grown one gains its
/// new replicates), at the points `point_ids` gives: planned, with one row per prep slot of
/// each point (see [`crate::schema::PLANS`]).
fn insert_jobs(
    tx: &rusqlite::Connection,
    sweep: &NewSweep,
    point_ids: &[i64],
    prep_ids: &[i64],
) -> Result<()> {
    // Each point's new jobs are pending: counted into `point_progress` once per point (see
    // schema::PROGRESS; the triggers there follow every later change).
    let mut count = tx.prepare(
        "INSERT INTO point_progress (point_id, solver_version, pending) VALUES (?1, ?2, ?3)
         ON CONFLICT (point_id, solver_version) DO UPDATE SET pending = pending + excluded.pending",
    )?;
    for (pt, &pid) in sweep.points.iter().zip(point_ids) {
        let added = plan_point_jobs(
            tx,
            pid,
            &sweep.solver_version,
            sweep.preps_per_point,
            &pt.jobs,
            prep_ids,
        )?;
        if added > 0 {
            count.execute(params![pid, sweep.solver_version, added as i64])?;
        }
    }
    Ok(())
}

/// Results of this sweep stored under other solver versions, per version.
fn other_versions(
    tx: &rusqlite::Connection,
    sweep_id: i64,
    solver_version: &str,
) -> Result<Vec<(String, i64)>> {
    let mut q = tx.prepare(
        "SELECT j.solver_version, COUNT(*) FROM jobs j JOIN points p ON p.id = j.point_id
         WHERE p.sweep_id = ?1 AND j.solver_version != ?2 AND j.state = ?3
         GROUP BY j.solver_version ORDER BY j.solver_version",
    )?;
    let rows = q.query_map(params![sweep_id, solver_version, JobState::Done], |r| {
        Ok((r.get(0)?, r.get(1)?))
    })?;
    Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
}

/// How a new definition of a registered sweep differs from the stored one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpecChange {
    Same,
    /// Only the adaptive or the refinement rule differs.
    Retuned,
    /// Only `replicates` (and perhaps the adaptive rule) differs, and it is larger.
    Grows {
        from: u32,
    },
    /// Only `replicates` differs, and it is smaller.
    Shrinks {
        from: u32,
        to: u32,
    },
    /// Anything else: a different sweep.
    Other,
}

/// Compare two canonical sweep definitions. `replicates`, `adaptive` and `refine` are the keys
/// that may change under the same name: growing the budget only adds jobs, since a replicate's
/// seed and prep depend on its index, never on the count (SPEC section 6), the adaptive rule
/// only decides how many of them run, and the refinement rule which points beyond the grid
/// are added (each seeded by its own parameters).
pub fn spec_change(stored: &str, new: &str) -> SpecChange {
    if stored == new {
        return SpecChange::Same;
    }
    let split = |text: &str| -> Option<(u32, serde_json::Value)> {
        let mut v: serde_json::Value = serde_json::from_str(text).ok()?;
        let map = v.as_object_mut()?;
        let n = map.remove("replicates")?.as_u64()?;
        map.remove("adaptive");
        // What the report draws is not what a trajectory gives.
        map.remove("planes");
        // An extension beyond the grid is a sweep of its own (SPEC section 6: never in the
        // paper's sweep): extend_to stays part of the identity.
        let extension = map
            .remove("refine")
            .and_then(|r| r.get("extend_to").cloned());
        if let Some(to) = extension {
            map.insert("extend_to".into(), to);
        }
        Some((u32::try_from(n).ok()?, v))
    };
    match (split(stored), split(new)) {
        (Some((from, a)), Some((to, b))) if a == b => match to.cmp(&from) {
            std::cmp::Ordering::Greater => SpecChange::Grows { from },
            std::cmp::Ordering::Less => SpecChange::Shrinks { from, to },
            std::cmp::Ordering::Equal => SpecChange::Retuned,
        },
        _ => SpecChange::Other,
    }
}

fn insert_sweep(tx: &rusqlite::Connection, sweep: &NewSweep) -> Result<i64> {
    tx.execute(
        "INSERT INTO sweeps (name, spec, source, created_at) VALUES (?1, ?2, ?3, ?4)",
        params![sweep.name, sweep.spec, sweep.source, now()],
    )?;
    Ok(tx.last_insert_rowid())
}

/// What differs between two canonical sweep definitions, for the refusal of a different sweep
/// under a registered name: the first few dotted keys with the stored and the new value
/// (`grid.alpha is [0.1,0.12] in the store and [0.12,0.1] in this file`).
fn spec_differences(stored: &str, new: &str) -> String {
    fn walk(path: &str, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
        use serde_json::Value::Object;
        if a == b {
            return;
        }
        if let (Object(x), Object(y)) = (a, b) {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let null = serde_json::Value::Null;
                let key = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                walk(
                    &key,
                    x.get(k).unwrap_or(&null),
                    y.get(k).unwrap_or(&null),
                    out,
                );
            }
            return;
        }
        let show = |v: &serde_json::Value| {
            let t = if v.is_null() {
                "absent".to_string()
            } else {
                v.to_string()
            };
            if t.chars().count() > 60 {
                format!("{}...", t.chars().take(57).collect::<String>())
            } else {
                t
            }
        };
        out.push(format!(
            "{path} is {} in the store and {} in this file",
            show(a),
            show(b)
        ));
    }
    let parse = |t: &str| serde_json::from_str::<serde_json::Value>(t).ok();
    let (Some(a), Some(b)) = (parse(stored), parse(new)) else {
        return "its stored definition is unreadable".to_string();
    };
    let mut out = Vec::new();
    walk("", &a, &b, &mut out);
    match out.len() {
        0 => "the definitions differ only in form".to_string(),
        1..=3 => out.join("; "),
        n => format!("{} (and {} more)", out[..3].join("; "), n - 3),
    }
}
