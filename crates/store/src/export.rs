//! One row per finished replicate, with everything needed to check it against the job it
//! claims: the exchange format of `cellsweep export` (format version [`EXPORT_FORMAT`]).

use std::collections::HashMap;

use rusqlite::params;
use rusqlite::OptionalExtension;
use serde::{Deserialize, Serialize};

use cellsweep_stats::{Axes, End, Others};

use crate::database::Store;
use crate::digest::fnv1a;
use crate::encoding::{bytes_to_f64s, seed_from_sql};
use crate::error::Result;
use crate::lifecycle::JobState::Done;

/// Version of the exported columns; bumped on any change to them. Format 2 added the wall
/// times (`wall_s`, `prep_wall_s`); format 3 the outcome `breakup` with its `breakup_reason`;
/// format 4 the drops a collision's cells shed (`sheddings`) and the prepped cell's extent
/// along x (`prep_extent`, for box-limited points, SPEC 4.5). Older files read with the new
/// columns empty (no sheddings: under the rule they were made with, every second piece of 10
/// sites was a breakup).
pub const EXPORT_FORMAT: u32 = 4;
/// The formats this build reads.
pub const READ_FORMATS: [u32; 4] = [1, 2, 3, 4];

/// One exported replicate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct ExportRow {
    pub sweep: String,
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    /// JSON of the point's parameters that differ from the paper's defaults (besides the axes).
    pub params: String,
    pub replicate: u32,
    pub prep_seed: u64,
    pub collision_seed: u64,
    pub verdict: String,
    pub outcome: Option<String>,
    pub contact_time: Option<f64>,
    pub decision_time: Option<f64>,
    pub attachment_1: Option<String>,
    pub attachment_2: Option<String>,
    pub free_speed: Option<f64>,
    pub threshold_speed: Option<f64>,
    pub collision_steps: i64,
    pub precision: String,
    pub solver_version: String,
    /// FNV-1a of the prepped cell's phi and P fields (little-endian f64), in hex.
    pub prep_hash: String,
    /// JSON of the classifier settings.
    pub classifier: String,
    /// Seconds the collision took on its worker (empty: not recorded, e.g. a format 1 row).
    #[serde(default)]
    pub wall_s: Option<f64>,
    /// Seconds the row's prep took (shared by the replicates of that prep).
    #[serde(default)]
    pub prep_wall_s: Option<f64>,
    /// Why a cell of the collision broke up (outcome `breakup` only).
    #[serde(default)]
    pub breakup_reason: Option<String>,
    /// Drops the collision's cells shed: second pieces that did not break a cell up (SPEC
    /// section 5).
    #[serde(default)]
    pub sheddings: u32,
    /// The prepped cell's extent along x in l0: the columns of its lattice holding a site with
    /// phi > 0.5 (over k at resolution k). Empty in files written before it was exported.
    #[serde(default)]
    pub prep_extent: Option<f64>,
}

/// Prep verdicts, as stored.
pub const VERDICTS: [&str; 3] = ["ok", "unstable", "breakup"];
/// A cell's fiber attachment after its collision, as stored.
pub const ATTACHMENTS: [&str; 5] = ["both", "bottom", "top", "single", "detached"];

impl ExportRow {
    /// Every field whose value is impossible on its own or beside the row's other fields,
    /// each as "field = value: why". Empty for a sound row. (Whether the row is the job's is
    /// for the ledger to check against the store.)
    pub fn field_problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut bad = |field: &str, value: &dyn std::fmt::Debug, why: &str| {
            out.push(format!("{field} = {value:?}: {why}"));
        };
        let time = |t: Option<f64>| t.is_none_or(|t| t.is_finite() && t >= 0.0);
        if !VERDICTS.contains(&self.verdict.as_str()) {
            bad("verdict", &self.verdict, "not one of ok, unstable, breakup");
        }
        let collided = self.verdict == "ok";
        match self.outcome.as_deref() {
            Some(o) if End::of_outcome(o).is_none() => bad(
                "outcome",
                &o,
                &format!("not one of {}", End::stored_outcomes()),
            ),
            None if collided => bad(
                "outcome",
                &"",
                "a collision ran (verdict ok) but has no outcome",
            ),
            Some(o) if !collided => bad(
                "outcome",
                &o,
                "no collision runs from a prep that is not ok",
            ),
            _ => {}
        }
        if !time(self.contact_time) {
            bad("contact_time", &self.contact_time, "not a finite time >= 0");
        }
        if !time(self.decision_time) {
            bad(
                "decision_time",
                &self.decision_time,
                "not a finite time >= 0",
            );
        }
        let decided = self
            .outcome
            .as_deref()
            .and_then(End::of_outcome)
            .is_some_and(End::decided);
        if decided && self.decision_time.is_none() {
            bad("decision_time", &"", "a decided outcome needs its time");
        }
        if !decided && self.decision_time.is_some() {
            bad(
                "decision_time",
                &self.decision_time,
                "an undecided replicate has no decision time",
            );
        }
        for (field, a) in [
            ("attachment_1", &self.attachment_1),
            ("attachment_2", &self.attachment_2),
        ] {
            match a.as_deref() {
                Some(v) if !ATTACHMENTS.contains(&v) => {
                    bad(field, &v, "not one of both, bottom, top, single, detached")
                }
                None if collided => {
                    bad(field, &"", "a collision ran but its attachment is missing")
                }
                Some(v) if !collided => bad(field, &v, "no collision ran"),
                _ => {}
            }
        }
        if self.free_speed.is_some_and(|v| !v.is_finite()) {
            bad("free_speed", &self.free_speed, "not a finite speed");
        }
        if collided && self.free_speed.is_none() {
            bad(
                "free_speed",
                &"",
                "a collided replicate's prep has a free speed",
            );
        }
        match self.threshold_speed {
            Some(v) if !(v.is_finite() && v >= 0.0) => {
                bad("threshold_speed", &v, "not a finite speed >= 0")
            }
            None if collided => bad("threshold_speed", &"", "a collision has a threshold speed"),
            _ => {}
        }
        if self.collision_steps < 0 || (!collided && self.collision_steps != 0) {
            bad(
                "collision_steps",
                &self.collision_steps,
                "steps are >= 0, and 0 where no collision ran",
            );
        }
        let broke = self.outcome.as_deref() == Some("breakup");
        match self.breakup_reason.as_deref() {
            None | Some("") if broke => bad("breakup_reason", &"", "a breakup keeps its reason"),
            Some(r) if !r.is_empty() && !broke => bad(
                "breakup_reason",
                &r,
                "only a collision that broke up has one",
            ),
            _ => {}
        }
        for (field, w) in [("wall_s", self.wall_s), ("prep_wall_s", self.prep_wall_s)] {
            if !time(w) {
                bad(field, &w, "not a finite time >= 0");
            }
        }
        out
    }

    /// The fields of two rows of one job that differ, each as (field, this, other): every
    /// column but the sweep's name (an archived `NAME@ID` is the same sweep) and the wall times
    /// (where the rows were made), so that a column added to the format is compared too.
    pub fn result_differences(&self, other: &ExportRow) -> Vec<(String, String, String)> {
        // (prep_extent is the prep's, checked through its hash, and empty in files written
        // before it was exported: not a result to compare either.)
        const NOT_RESULTS: [&str; 4] = ["sweep", "wall_s", "prep_wall_s", "prep_extent"];
        let fields = |r: &ExportRow| match serde_json::to_value(r) {
            Ok(serde_json::Value::Object(map)) => map,
            _ => serde_json::Map::new(),
        };
        let text = |v: Option<&serde_json::Value>| match v {
            None | Some(serde_json::Value::Null) => String::new(),
            Some(serde_json::Value::String(s)) => s.clone(),
            Some(v) => v.to_string(),
        };
        // The speeds are sums over the prep's trajectory: machines that vectorise the sums
        // differently (AVX-512, AVX2) agree on them to round-off only, on the fields exactly.
        const SUMS: [&str; 2] = ["free_speed", "threshold_speed"];
        let (a, b) = (fields(self), fields(other));
        let alike = |k: &str, x: Option<&serde_json::Value>, y: Option<&serde_json::Value>| match (
            x.and_then(|v| v.as_f64()),
            y.and_then(|v| v.as_f64()),
        ) {
            (Some(x), Some(y)) if SUMS.contains(&k) => same_to_round_off(Some(x), Some(y)),
            _ => x == y,
        };
        a.keys()
            .filter(|k| !NOT_RESULTS.contains(&k.as_str()))
            .filter(|k| !alike(k, a.get(*k), b.get(*k)))
            .map(|k| (k.clone(), text(a.get(k)), text(b.get(k))))
            .collect()
    }
}

/// Two speeds equal to round-off (1e-12 relative), or both absent: a prep's speeds computed
/// on two machines, or written before JSON carried floats exactly, can be an ulp apart.
pub fn same_to_round_off(a: Option<f64>, b: Option<f64>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) => (x - y).abs() <= 1e-12 * x.abs().max(y.abs()).max(1e-300),
        _ => false,
    }
}

/// JSON of the parameters of a point's configuration (`{"params": {...}, ...}`) that differ
/// from `defaults`, the grid axes left out.
pub fn changed_params(config: &serde_json::Value, defaults: &serde_json::Value) -> String {
    let mut changed = serde_json::Map::new();
    if let Some(p) = config["params"].as_object() {
        for (k, v) in p {
            if !["alpha", "beta", "L", "sigma"].contains(&k.as_str()) && defaults[k] != *v {
                changed.insert(k.clone(), v.clone());
            }
        }
    }
    serde_json::Value::Object(changed).to_string()
}

impl Store {
    /// Every finished replicate of a sweep under `version`, in grid and replicate order.
    /// `defaults` is the JSON object of the default parameters: only differences are kept.
    pub fn export_rows(
        &self,
        sweep_id: i64,
        version: &str,
        defaults: &serde_json::Value,
    ) -> Result<Vec<ExportRow>> {
        let name: String =
            self.conn
                .query_row("SELECT name FROM sweeps WHERE id = ?1", [sweep_id], |r| {
                    r.get(0)
                })?;
        // (A version 1 store, opened as it is by a reader, has no breakup reasons.)
        let reason = if self.schema >= 2 {
            "r.breakup_reason"
        } else {
            "NULL"
        };
        let mut q = self.conn.prepare(&format!(
            "SELECT p.alpha, p.beta, p.L, p.sigma, p.params, j.replicate, pr.id, pr.seed, j.seed,
                    r.verdict, r.outcome, r.contact_time, r.decision_time, r.attachment_1,
                    r.attachment_2, r.free_speed, r.threshold_speed, r.collision_steps,
                    r.solver_version, r.classifier, r.wall_s, pr.wall_s, {reason},
                    COALESCE(json_extract(r.record, '$.sheddings'), 0)
             FROM results r JOIN jobs j ON j.id = r.job_id JOIN points p ON p.id = j.point_id
             JOIN preps pr ON pr.id = j.prep_id
             WHERE p.sweep_id = ?1 AND r.solver_version = ?2
             ORDER BY p.idx, j.replicate"
        ))?;
        let mut hashes: HashMap<i64, String> = HashMap::new();
        let mut extents: HashMap<i64, Option<f64>> = HashMap::new();
        let mut out = Vec::new();
        let mut rows = q.query(params![sweep_id, version])?;
        while let Some(r) = rows.next()? {
            let config: serde_json::Value = serde_json::from_str(&r.get::<_, String>(4)?)?;
            let prep_id: i64 = r.get(6)?;
            if let std::collections::hash_map::Entry::Vacant(e) = hashes.entry(prep_id) {
                e.insert(self.prep_hash(prep_id)?);
            }
            if let std::collections::hash_map::Entry::Vacant(e) = extents.entry(prep_id) {
                let k = config["protocol"]["resolution"]
                    .as_u64()
                    .unwrap_or(1)
                    .max(1);
                e.insert(self.prep_extent(prep_id)?.map(|n| n as f64 / k as f64));
            }
            out.push(ExportRow {
                sweep: name.clone(),
                alpha: r.get(0)?,
                beta: r.get(1)?,
                L: r.get(2)?,
                sigma: r.get(3)?,
                params: changed_params(&config, defaults),
                replicate: r.get(5)?,
                prep_seed: seed_from_sql(r.get(7)?),
                collision_seed: seed_from_sql(r.get(8)?),
                verdict: r.get(9)?,
                outcome: r.get(10)?,
                contact_time: r.get(11)?,
                decision_time: r.get(12)?,
                attachment_1: r.get(13)?,
                attachment_2: r.get(14)?,
                free_speed: r.get(15)?,
                threshold_speed: r.get(16)?,
                collision_steps: r.get::<_, Option<i64>>(17)?.unwrap_or(0),
                precision: config["protocol"]["precision"]
                    .as_str()
                    .unwrap_or("f64")
                    .to_string(),
                solver_version: r.get(18)?,
                prep_hash: hashes[&prep_id].clone(),
                classifier: r.get(19)?,
                // Zero or absent: not measured (a row imported from format 1).
                wall_s: r.get::<_, Option<f64>>(20)?.filter(|&w| w > 0.0),
                prep_wall_s: r.get::<_, Option<f64>>(21)?.filter(|&w| w > 0.0),
                breakup_reason: r.get(22)?,
                sheddings: r.get(23)?,
                prep_extent: extents[&prep_id],
            });
        }
        Ok(out)
    }

    /// A done prep's free speed (None for a prep that is not done, or has none).
    pub fn prep_free_speed(&self, prep_id: i64) -> Result<Option<f64>> {
        Ok(self
            .conn
            .query_row(
                "SELECT free_speed FROM preps WHERE id = ?1 AND state = ?2",
                params![prep_id, Done],
                |r| r.get::<_, Option<f64>>(0),
            )
            .optional()?
            .flatten())
    }

    /// FNV-1a of a done prep's phi and P bytes, in hex ("" for a prep that is not done).
    pub fn prep_hash(&self, prep_id: i64) -> Result<String> {
        let fields: Option<(Vec<u8>, Vec<u8>)> = self
            .conn
            .query_row(
                "SELECT phi, p FROM preps WHERE id = ?1 AND state = ?2",
                params![prep_id, Done],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .ok();
        Ok(fields.map_or(String::new(), |(phi, p)| {
            format!("{:016x}", fnv1a(&[phi, p].concat()))
        }))
    }
}

impl Store {
    /// A done prep's extent along x in its lattice's sites: the columns holding a site with
    /// phi > 0.5 (None for a prep that is not done).
    pub fn prep_extent(&self, prep_id: i64) -> Result<Option<usize>> {
        let fields: Option<(Vec<u8>, Option<i64>)> = self
            .conn
            .query_row(
                "SELECT phi, nx FROM preps WHERE id = ?1 AND state = ?2",
                params![prep_id, Done],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .optional()?;
        Ok(fields.and_then(|(phi, nx)| {
            let nx = usize::try_from(nx?).ok().filter(|&n| n > 0)?;
            let phi = bytes_to_f64s(&phi);
            let mut held = vec![false; nx];
            for (s, v) in phi.iter().enumerate() {
                if *v > 0.5 {
                    held[s % nx] = true;
                }
            }
            Some(held.iter().filter(|&&h| h).count())
        }))
    }

    /// The job of a sweep's point and replicate under `version`, if any: the point at `axes`,
    /// its other axes read by `others_of` out of each candidate point's configuration JSON.
    pub fn job_at(
        &self,
        sweep_id: i64,
        version: &str,
        axes: &Axes,
        replicate: u32,
        others_of: &dyn Fn(&str) -> Others,
    ) -> Result<Option<i64>> {
        let mut q = self.conn.prepare_cached(
            "SELECT j.id, p.params FROM jobs j JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND p.alpha = ?3
               AND p.beta = ?4 AND p.L = ?5 AND p.sigma = ?6 AND j.replicate = ?7",
        )?;
        let mut rows = q.query(params![
            sweep_id, version, axes.alpha, axes.beta, axes.L, axes.sigma, replicate
        ])?;
        while let Some(r) = rows.next()? {
            let config: String = r.get(1)?;
            if axes.others.is_empty() || others_of(&config).bits() == axes.others.bits() {
                return Ok(Some(r.get(0)?));
            }
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row as a collision of the paper's sweep gives it.
    fn a_row() -> ExportRow {
        ExportRow {
            sweep: "adaptive-L70-sigma5".into(),
            alpha: 0.1,
            beta: 10.0,
            L: 70,
            sigma: 5.0,
            params: "{}".into(),
            replicate: 0,
            prep_seed: 8508916949338792062,
            collision_seed: 3765284608252713618,
            verdict: "ok".into(),
            outcome: Some("train".into()),
            contact_time: Some(71.5),
            decision_time: Some(249.5),
            attachment_1: Some("both".into()),
            attachment_2: Some("both".into()),
            free_speed: Some(0.5592358745309631),
            threshold_speed: Some(0.13980896863274078),
            collision_steps: 124750,
            precision: "f32".into(),
            solver_version: "cellsweep-solver 0.4.1".into(),
            prep_hash: "0ff701a5851746ba".into(),
            classifier: "{}".into(),
            wall_s: Some(11.0),
            prep_wall_s: Some(6.5),
            breakup_reason: None,
            sheddings: 0,
            prep_extent: Some(72.0),
        }
    }

    #[test]
    fn every_result_column_is_compared_and_wall_times_and_the_archived_name_are_not() {
        let row = a_row();
        assert!(row.result_differences(&row).is_empty());
        let mut other = row.clone();
        other.free_speed = other.free_speed.map(|v| v + 1.0);
        other.breakup_reason = Some("cell 1: torn".into());
        other.collision_seed ^= 1;
        let named: Vec<String> = row
            .result_differences(&other)
            .into_iter()
            .map(|(f, _, _)| f)
            .collect();
        assert_eq!(named, ["breakup_reason", "collision_seed", "free_speed"]);
        let mut same = row.clone();
        same.wall_s = Some(1e9);
        same.prep_wall_s = None;
        same.sweep = format!("{}@7", row.sweep);
        same.prep_extent = None;
        assert!(row.result_differences(&same).is_empty());
    }

    #[test]
    fn speeds_one_ulp_apart_are_alike_and_further_apart_are_not() {
        let row = a_row();
        let ulp = |v: f64| f64::from_bits(v.to_bits() + 1);
        let mut other = row.clone();
        other.free_speed = other.free_speed.map(ulp);
        other.threshold_speed = other.threshold_speed.map(ulp);
        assert!(row.result_differences(&other).is_empty());
        other.free_speed = Some(0.1);
        other.threshold_speed = None;
        let named: Vec<String> = row
            .result_differences(&other)
            .into_iter()
            .map(|(f, _, _)| f)
            .collect();
        assert_eq!(named, ["free_speed", "threshold_speed"]);
        // Times are results of the collision itself: exact.
        let mut later = row.clone();
        later.decision_time = later.decision_time.map(ulp);
        assert_eq!(row.result_differences(&later).len(), 1);
    }
}
