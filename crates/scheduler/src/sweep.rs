//! Sweep files (`sweeps/*.toml`): what to run, parsed with one-line errors.
//!
//! ```toml
//! name = "paper-L90"
//! seed = 1
//! replicates = 96
//! preps_per_point = 1                      # optional
//! geometry = "two"                         # or "one"
//! [grid]
//! alpha = { from = 0.10, to = 0.20, step = 0.02 }   # or a list, or one number
//! beta  = { from = 10, to = 50, step = 4 }
//! L     = [90]
//! sigma = [5]
//! [params]                                 # optional: any other SPEC parameter
//! tau = 100
//! [protocol]                               # optional: lattices, stage durations (tau0)
//! single_lattice = [200, 200]
//! collide_time = 400
//! patch_bound = 1e-8                       # per-cell windows in the collision; 0: whole lattice
//! precision = "f64"                        # collision float type: "f64" (default) or "f32"
//! [classifier]                             # optional: classifier settings
//! sustain_window = 25
//! [adaptive]                               # optional: replicates in rounds until settled
//! batch = 8                                # replicates added to an open point per round
//! min_replicates = 8                       # the first round
//! max_replicates = 96                      # the budget (default: replicates)
//! error = 0.05                             # chance of settling on a wrong label
//! [run]                                    # optional: fault handling
//! job_timeout = 3600                       # seconds per job before the worker is killed
//! max_attempts = 3
//! ```

use std::path::Path;

use cellsweep_solver::{ClassifierSettings, Geometry, Params, Protocol};
use cellsweep_store::AdaptiveRule;
use serde::{Deserialize, Serialize};
use toml::{Table, Value};

use crate::error::SweepError;
use crate::grid::{parse_axis, Axis};

/// Fault handling of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSettings {
    /// Seconds a worker may spend on one job before it is killed and the job retried.
    pub job_timeout: f64,
    /// Attempts of a job (crash, timeout or error) before it is marked failed.
    pub max_attempts: u32,
}

impl Default for RunSettings {
    fn default() -> Self {
        RunSettings {
            job_timeout: 3600.0,
            max_attempts: 3,
        }
    }
}

/// The four grid axes of the paper.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Grid {
    pub alpha: Vec<f64>,
    pub beta: Vec<f64>,
    pub L: Vec<u32>,
    pub sigma: Vec<f64>,
}

/// A parsed, validated sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    pub name: String,
    pub seed: u64,
    pub replicates: u32,
    pub preps_per_point: u32,
    pub grid: Grid,
    /// Every parameter that is not a grid axis (geometry included).
    pub params: Params,
    pub protocol: Protocol,
    pub classifier: ClassifierSettings,
    /// Replicates in rounds until each point is settled (`replicates` is then the budget).
    /// It may change under the same name: it decides how many replicates run, never what one
    /// replicate gives.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<AdaptiveRule>,
    /// Not part of the sweep's identity: changing it does not make a different sweep.
    #[serde(skip)]
    pub run: RunSettings,
}

const TOP_KEYS: &[&str] = &[
    "name",
    "description",
    "seed",
    "replicates",
    "preps_per_point",
    "geometry",
    "grid",
    "params",
    "protocol",
    "classifier",
    "adaptive",
    "run",
];
const GRID_KEYS: &[&str] = &["alpha", "beta", "L", "sigma"];

/// Most replicates per point (and preps per point).
pub const MAX_REPLICATES: u64 = 10_000;
/// Most grid points of one sweep.
pub const MAX_POINTS: u64 = 100_000;
/// Most jobs (points x replicates) of one sweep.
pub const MAX_JOBS: u64 = 10_000_000;
/// Largest fiber spacing and lattice side, in sites.
pub const MAX_SITES: u64 = 4_096;
/// Longest job timeout: 30 days.
pub const MAX_JOB_TIMEOUT: f64 = 30.0 * 86_400.0;
/// Most attempts of one job.
pub const MAX_ATTEMPTS: u64 = 100;

/// A sweep name, checked: 1 to 100 of `A-Z a-z 0-9 . _ -`, not starting with a dot (the name
/// becomes a directory, a Slurm job name and a word in scripts).
pub fn check_name(name: &str) -> Result<(), String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-');
    if name.is_empty() || name.len() > 100 || name.starts_with('.') || !name.chars().all(allowed) {
        return Err(format!(
            "{name:?} is not a sweep name: 1 to 100 of the characters A-Z a-z 0-9 . _ -, not \
             starting with a dot"
        ));
    }
    Ok(())
}

/// A job timeout in seconds, checked: finite, > 0, at most [`MAX_JOB_TIMEOUT`].
pub fn job_timeout(x: f64) -> Result<f64, String> {
    if x.is_finite() && x > 0.0 && x <= MAX_JOB_TIMEOUT {
        Ok(x)
    } else {
        Err(format!(
            "{x} is not a number of seconds in (0, {MAX_JOB_TIMEOUT}] (30 days)"
        ))
    }
}

/// A number (integer or float) from a TOML value.
pub(crate) fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    }
}

struct Ctx<'a> {
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, key: impl Into<String>, problem: impl Into<String>) -> SweepError {
        SweepError::new(self.file, key, problem)
    }

    fn unknown_keys(&self, table: &Table, prefix: &str, known: &[&str]) -> Result<(), SweepError> {
        for key in table.keys() {
            if !known.contains(&key.as_str()) {
                return Err(self.err(
                    format!("{prefix}{key}"),
                    format!("unknown key (expected one of: {})", known.join(", ")),
                ));
            }
        }
        Ok(())
    }

    fn table<'t>(&self, top: &'t Table, key: &str) -> Result<Option<&'t Table>, SweepError> {
        match top.get(key) {
            None => Ok(None),
            Some(Value::Table(t)) => Ok(Some(t)),
            Some(_) => Err(self.err(key, "must be a table")),
        }
    }

    fn uint(&self, v: &Value, key: &str, min: i64) -> Result<u64, SweepError> {
        match v {
            Value::Integer(i) if *i >= min => Ok(*i as u64),
            Value::Integer(i) => Err(self.err(key, format!("{i} must be at least {min}"))),
            _ => Err(self.err(key, "must be a whole number")),
        }
    }

    fn num(&self, v: &Value, key: &str) -> Result<f64, SweepError> {
        number(v)
            .filter(|x| x.is_finite())
            .ok_or_else(|| self.err(key, "must be a number"))
    }
}

impl Sweep {
    /// Read and validate a sweep file.
    pub fn load(path: &Path) -> Result<Sweep, SweepError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| SweepError::new(&file, "file", format!("cannot read: {e}")))?;
        Sweep::parse(&text, &file)
    }

    /// Parse and validate sweep-file text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Sweep, SweepError> {
        let cx = Ctx { file };
        let top: Table = text.parse().map_err(|e: toml::de::Error| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].lines().count().max(1))
                .map_or("syntax".to_string(), |l| format!("line {l}"));
            cx.err(
                line,
                e.message()
                    .lines()
                    .next()
                    .unwrap_or("malformed TOML")
                    .to_string(),
            )
        })?;
        cx.unknown_keys(&top, "", TOP_KEYS)?;

        let name = match top.get("name") {
            Some(Value::String(s)) => s.clone(),
            Some(_) => return Err(cx.err("name", "must be a string")),
            None => return Err(cx.err("name", "missing")),
        };
        check_name(&name).map_err(|p| cx.err("name", p))?;
        let seed = match top.get("seed") {
            Some(v) => cx.uint(v, "seed", 0)?,
            None => return Err(cx.err("seed", "missing")),
        };
        let bounded = |key: &str, default: u64| -> Result<u64, SweepError> {
            let n = top.get(key).map_or(Ok(default), |v| cx.uint(v, key, 1))?;
            if n > MAX_REPLICATES {
                return Err(cx.err(key, format!("{n} is more than {MAX_REPLICATES}")));
            }
            Ok(n)
        };
        let replicates = bounded("replicates", 96)?;
        let preps_per_point = bounded("preps_per_point", 1)?;
        if preps_per_point > replicates {
            return Err(cx.err(
                "preps_per_point",
                format!("{preps_per_point} exceeds replicates = {replicates}"),
            ));
        }
        let mut params = Params::default();
        if let Some(g) = top.get("geometry") {
            params.geometry = match g.as_str().map(str::parse::<Geometry>) {
                Some(Ok(geo)) => geo,
                _ => return Err(cx.err("geometry", "must be \"one\" or \"two\"")),
            };
        }

        let grid_table = cx
            .table(&top, "grid")?
            .ok_or_else(|| cx.err("grid", "missing"))?;
        cx.unknown_keys(grid_table, "grid.", GRID_KEYS)?;
        let axis = |key: &str| -> Result<Axis, SweepError> {
            let full = format!("grid.{key}");
            let v = grid_table
                .get(key)
                .ok_or_else(|| cx.err(&full, "missing"))?;
            parse_axis(v).map_err(|p| cx.err(&full, p))
        };
        let spacing: Vec<u32> = {
            let values = axis("L")?.values;
            let mut out = Vec::new();
            for l in values {
                if l > MAX_SITES as f64 {
                    return Err(cx.err("grid.L", format!("{l} is more than {MAX_SITES} sites")));
                }
                if l.fract() != 0.0 || l < 0.0 {
                    return Err(cx.err(
                        "grid.L",
                        format!("{l} is not a whole number of lattice sites"),
                    ));
                }
                if params.geometry == Geometry::Two && (l as u64) % 2 != 0 {
                    return Err(cx.err(
                        "grid.L",
                        format!("{l} is odd (fibers sit at Ny/2 -+ L/2: L must be even)"),
                    ));
                }
                out.push(l as u32);
            }
            out
        };
        let grid = Grid {
            alpha: axis("alpha")?.values,
            beta: axis("beta")?.values,
            L: spacing,
            sigma: axis("sigma")?.values,
        };

        if let Some(t) = cx.table(&top, "params")? {
            for (key, v) in t {
                let full = format!("params.{key}");
                if GRID_KEYS.contains(&key.as_str()) {
                    return Err(cx.err(full, "is a grid axis: set it in [grid]"));
                }
                if key == "geometry" {
                    return Err(cx.err(full, "set geometry at the top level"));
                }
                let x = cx.num(v, &full)?;
                params.set(key, x).map_err(|p| cx.err(&full, p))?;
            }
        }

        let mut protocol = Protocol::default();
        if let Some(t) = cx.table(&top, "protocol")? {
            cx.unknown_keys(
                t,
                "protocol.",
                &[
                    "single_lattice",
                    "pair_lattice",
                    "relax_time",
                    "free_time",
                    "collide_time",
                    "record_interval",
                    "check_interval",
                    "stop_early",
                    "patch_bound",
                    "precision",
                ],
            )?;
            for (key, v) in t {
                let full = format!("protocol.{key}");
                match key.as_str() {
                    "single_lattice" | "pair_lattice" => {
                        let side = |x: &Value| -> Result<usize, SweepError> {
                            let n = cx.uint(x, &full, 2)?;
                            if n > MAX_SITES {
                                return Err(
                                    cx.err(&full, format!("{n} is more than {MAX_SITES} sites"))
                                );
                            }
                            Ok(n as usize)
                        };
                        let pair = match v.as_array().map(|a| a.as_slice()) {
                            Some([a, b]) => [side(a)?, side(b)?],
                            _ => return Err(cx.err(full, "must be [NX, NY]")),
                        };
                        if key == "single_lattice" {
                            protocol.single_lattice = pair;
                            if t.get("pair_lattice").is_none() {
                                protocol.pair_lattice = [2 * pair[0], pair[1]];
                            }
                        } else {
                            protocol.pair_lattice = pair;
                        }
                    }
                    "stop_early" => {
                        protocol.stop_early = v
                            .as_bool()
                            .ok_or_else(|| cx.err(&full, "must be true or false"))?
                    }
                    "precision" => {
                        protocol.precision = v
                            .as_str()
                            .ok_or_else(|| cx.err(&full, "must be \"f64\" or \"f32\""))?
                            .parse()
                            .map_err(|e: String| cx.err(&full, &e))?
                    }
                    _ => {
                        let x = cx.num(v, &full)?;
                        // Every key named: one added to the list above but not here is an
                        // error, never a write to some other field.
                        *match key.as_str() {
                            "relax_time" => &mut protocol.relax_time,
                            "free_time" => &mut protocol.free_time,
                            "collide_time" => &mut protocol.collide_time,
                            "record_interval" => &mut protocol.record_interval,
                            "patch_bound" => &mut protocol.patch.bound,
                            "check_interval" => &mut protocol.check_interval,
                            other => return Err(cx.err(full, format!("{other} has no field"))),
                        } = x;
                    }
                }
            }
        }

        let mut classifier = ClassifierSettings::default();
        if let Some(t) = cx.table(&top, "classifier")? {
            let known = [
                "contact_overlap",
                "speed_fraction",
                "min_speed",
                "velocity_window",
                "sustain_window",
                "walk_past_margin",
            ];
            cx.unknown_keys(t, "classifier.", &known)?;
            for (key, v) in t {
                let full = format!("classifier.{key}");
                let x = cx.num(v, &full)?;
                if x < 0.0 {
                    return Err(cx.err(full, format!("{x} must be >= 0")));
                }
                // A zero window would make every velocity 0 and every collision undetermined.
                if x == 0.0 && key.ends_with("_window") {
                    return Err(cx.err(full, "must be > 0 (tau0)"));
                }
                *match key.as_str() {
                    "contact_overlap" => &mut classifier.contact_overlap,
                    "speed_fraction" => &mut classifier.speed_fraction,
                    "min_speed" => &mut classifier.min_speed,
                    "velocity_window" => &mut classifier.velocity_window,
                    "sustain_window" => &mut classifier.sustain_window,
                    "walk_past_margin" => &mut classifier.walk_past_margin,
                    other => return Err(cx.err(full, format!("{other} has no field"))),
                } = x;
            }
        }

        let adaptive = match cx.table(&top, "adaptive")? {
            None => None,
            Some(t) => {
                cx.unknown_keys(
                    t,
                    "adaptive.",
                    &["batch", "min_replicates", "max_replicates", "error"],
                )?;
                let get = |key: &str, default: u64| -> Result<u32, SweepError> {
                    let full = format!("adaptive.{key}");
                    let v = t.get(key).map_or(Ok(default), |v| cx.uint(v, &full, 1))?;
                    u32::try_from(v).map_err(|_| cx.err(full, format!("{v} is too large")))
                };
                let max = get("max_replicates", replicates)?;
                if top.get("replicates").is_some() && max as u64 != replicates {
                    return Err(cx.err(
                        "adaptive.max_replicates",
                        format!("{max} differs from replicates = {replicates}: give one of them"),
                    ));
                }
                let rule = AdaptiveRule {
                    batch: get("batch", 8)?,
                    min_replicates: get("min_replicates", 8.min(max as u64))?,
                    max_replicates: max,
                    error: t
                        .get("error")
                        .map_or(Ok(0.05), |v| cx.num(v, "adaptive.error"))?,
                };
                rule.validate()
                    .map_err(|(key, problem)| cx.err(format!("adaptive.{key}"), problem))?;
                Some(rule)
            }
        };
        let replicates = adaptive.map_or(replicates, |a| a.max_replicates as u64);

        let mut run = RunSettings::default();
        if let Some(t) = cx.table(&top, "run")? {
            cx.unknown_keys(t, "run.", &["job_timeout", "max_attempts"])?;
            if let Some(v) = t.get("job_timeout") {
                run.job_timeout = number(v)
                    .ok_or_else(|| cx.err("run.job_timeout", "must be a number"))
                    .and_then(|x| job_timeout(x).map_err(|p| cx.err("run.job_timeout", p)))?;
            }
            if let Some(v) = t.get("max_attempts") {
                let n = cx.uint(v, "run.max_attempts", 1)?;
                if n > MAX_ATTEMPTS {
                    return Err(cx.err(
                        "run.max_attempts",
                        format!("{n} is more than {MAX_ATTEMPTS}"),
                    ));
                }
                run.max_attempts = n as u32;
            }
        }

        let sweep = Sweep {
            name,
            seed,
            replicates: replicates as u32,
            preps_per_point: preps_per_point as u32,
            grid,
            params,
            protocol,
            classifier,
            adaptive,
            run,
        };
        let g = &sweep.grid;
        let points = [g.alpha.len(), g.beta.len(), g.L.len(), g.sigma.len()]
            .iter()
            .fold(1u64, |n, &k| n.saturating_mul(k as u64));
        if points > MAX_POINTS {
            return Err(cx.err("grid", format!("{points} points is more than {MAX_POINTS}")));
        }
        let jobs = points.saturating_mul(sweep.replicates as u64);
        if jobs > MAX_JOBS {
            return Err(cx.err(
                "replicates",
                format!(
                    "{points} points x {} replicates = {jobs} jobs is more than {MAX_JOBS}",
                    sweep.replicates
                ),
            ));
        }
        // Every point must be a valid model: the first invalid one names the key to fix.
        for point in sweep.points() {
            sweep.protocol.validate(&point).map_err(|e| {
                let mut name = e.parameter();
                if matches!(e, cellsweep_solver::ParamError::Unstable { .. }) {
                    // Blame the grid's alpha if its smallest value would be stable, else dt.
                    let min_alpha = sweep
                        .grid
                        .alpha
                        .iter()
                        .copied()
                        .fold(f64::INFINITY, f64::min);
                    let calmer = Params {
                        alpha: min_alpha,
                        ..point.clone()
                    };
                    if calmer.diffusive_number() <= 0.25 {
                        name = "alpha";
                    }
                }
                let key = if GRID_KEYS.contains(&name) {
                    format!("grid.{name}")
                } else if name.contains("lattice")
                    || name.ends_with("_time")
                    || name.ends_with("_interval")
                {
                    format!("protocol.{name}")
                } else {
                    format!("params.{name}")
                };
                cx.err(
                    key,
                    format!(
                        "at alpha = {}, beta = {}, L = {}, sigma = {}: {e}",
                        point.alpha, point.beta, point.L, point.sigma
                    ),
                )
            })?;
        }
        Ok(sweep)
    }

    /// Parameters of every grid point, ordered by L, sigma, alpha, beta.
    pub fn points(&self) -> Vec<Params> {
        let mut out = Vec::new();
        for &l in &self.grid.L {
            for &sigma in &self.grid.sigma {
                for &alpha in &self.grid.alpha {
                    for &beta in &self.grid.beta {
                        out.push(Params {
                            alpha,
                            beta,
                            L: l,
                            sigma,
                            ..self.params.clone()
                        });
                    }
                }
            }
        }
        out
    }

    /// Replicates registered per point at the start: the first round of an adaptive sweep,
    /// else all of them.
    pub fn initial_replicates(&self) -> u32 {
        self.adaptive
            .map_or(self.replicates, |a| a.min_replicates.min(self.replicates))
    }

    /// Canonical JSON of the sweep's definition (everything but the run settings).
    pub fn canonical_json(&self) -> String {
        serde_json::to_string(self).expect("a sweep serializes")
    }
}
