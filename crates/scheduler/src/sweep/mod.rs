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
//! E0    = [1000, 3000]                     # optional: any other SPEC parameter as an axis
//! [params]                                 # optional: any other SPEC parameter
//! tau = 100
//! [protocol]                               # optional: lattices, stage durations (tau0)
//! single_lattice = [200, 200]
//! collide_time = 400
//! patch_bound = 1e-8                       # per-cell windows in the collision; 0: whole lattice
//! precision = "f64"                        # collision float type: "f64" (default) or "f32"
//! resolution = 2                           # a lattice k times finer (SPEC 6), values in l0
//! [classifier]                             # optional: classifier settings
//! sustain_window = 25
//! [adaptive]                               # optional: replicates in rounds until settled
//! batch = 8                                # replicates added to an open point per round
//! min_replicates = 8                       # the first round
//! max_replicates = 96                      # the budget (default: replicates)
//! error = 0.05                             # chance of settling on a wrong label
//! [refine]                                 # optional: beta values where columns cross
//! width = 1.0                              # until beta*'s 95% interval is this narrow
//! step = 0.5                               # on multiples of this, at most
//! max_new_per_column = 6                   # values per column, 2 per round (per_round)
//! [report]                                 # optional: diagrams on other axes (not identity)
//! planes = [{ x = "R0", y = "beta", by = ["xt", "sigma"] }]
//! [run]                                    # optional: fault handling
//! job_timeout = 3600                       # seconds per job before the worker is killed
//! max_attempts = 3
//! ```

use std::path::Path;

use cellsweep_solver::{ClassifierSettings, Params, Protocol};
use cellsweep_stats::{AdaptiveRule, RefineRule};
use serde::{Deserialize, Serialize};

use crate::error::{StoredSweepError, SweepError, ValueError};
use crate::sweep_file::{self, AdaptiveFile, ProtocolFile, RunFile, Whole};

mod differences;
mod layout;
mod others;
mod points;
mod report;
pub use cellsweep_stats::Axes;
pub use others::{proportional_side, OtherAxis, RowAxesError};

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

/// The grid: the paper's four axes, and any other parameter the sweep varies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Grid {
    pub alpha: Vec<f64>,
    pub beta: Vec<f64>,
    pub L: Vec<u32>,
    pub sigma: Vec<f64>,
    /// Other axes (SPEC names, in SPEC order): none in the paper's sweeps, whose definitions
    /// are then exactly as before there were any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub others: Vec<OtherAxis>,
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
    /// Each point's lattices keep the paper's proportions at its R0 ([`Sweep::protocol_for`]):
    /// set where R0 is not the paper's 40 or varies, and the file gives no lattice.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub lattices_follow_r0: bool,
    /// Replicates in rounds until each point is settled (`replicates` is then the budget).
    /// It may change under the same name: it decides how many replicates run, never what one
    /// replicate gives.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<AdaptiveRule>,
    /// Beta values added where each column's crossing lies, until beta* is known to a width
    /// ([`crate::refinement`]). Like `adaptive`, it may change under the same name: it decides
    /// which points run, never what a point gives.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<RefineRule>,
    /// Diagrams on other axes the report draws (`[report] planes`): stored with the
    /// definition so that an export carries them, but not part of its identity (like
    /// `adaptive`, they may change under the same name).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub planes: Vec<cellsweep_stats::Plane>,
    /// Not part of the sweep's identity: changing it does not make a different sweep.
    #[serde(skip)]
    pub run: RunSettings,
}

const GRID_KEYS: &[&str] = &["alpha", "beta", "L", "sigma"];

pub use crate::limits::{
    MAX_ATTEMPTS, MAX_JOBS, MAX_JOB_TIMEOUT, MAX_POINTS, MAX_REPLICATES, MAX_SITES,
};

/// A sweep name, checked: 1 to 100 of `A-Z a-z 0-9 . _ -`, not starting with a dot (the name
/// becomes a directory, a Slurm job name and a word in scripts).
pub fn check_name(name: &str) -> Result<(), ValueError> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-');
    if name.is_empty() || name.len() > 100 || name.starts_with('.') || !name.chars().all(allowed) {
        return Err(ValueError::Name(name.to_string()));
    }
    Ok(())
}

/// A job timeout in seconds, checked: finite, > 0, at most [`MAX_JOB_TIMEOUT`].
pub fn job_timeout(x: f64) -> Result<f64, ValueError> {
    if x.is_finite() && x > 0.0 && x <= MAX_JOB_TIMEOUT {
        Ok(x)
    } else {
        Err(ValueError::Timeout {
            value: x,
            max: MAX_JOB_TIMEOUT,
        })
    }
}

/// Errors of one sweep file, each naming the file.
struct Ctx<'a> {
    file: &'a str,
}

impl Ctx<'_> {
    fn err(&self, key: impl Into<String>, problem: impl Into<String>) -> SweepError {
        SweepError::new(self.file, key, problem)
    }

    /// A whole number in `min..=max`.
    fn whole(&self, v: Whole, key: &str, min: i64, max: u64) -> Result<u64, SweepError> {
        match v.0 {
            n if n < min => Err(self.err(key, format!("{n} must be at least {min}"))),
            n if n as u64 > max => Err(self.err(key, format!("{n} is more than {max}"))),
            n => Ok(n as u64),
        }
    }

    /// A required value.
    fn given<T>(&self, v: Option<T>, key: &str) -> Result<T, SweepError> {
        v.ok_or_else(|| self.err(key, "missing"))
    }
}

/// `[adaptive]`, its budget `replicates` unless it sets its own (`given`: the file set
/// `replicates`, so the two must agree).
fn adaptive_rule(
    a: &AdaptiveFile,
    replicates: u64,
    given: bool,
    cx: &Ctx,
) -> Result<AdaptiveRule, SweepError> {
    let get = |v: Option<Whole>, key: &str, default: u64| -> Result<u32, SweepError> {
        let full = format!("adaptive.{key}");
        v.map_or(Ok(default), |v| cx.whole(v, &full, 1, MAX_REPLICATES))
            .map(|n| n as u32)
    };
    let max = get(a.max_replicates, "max_replicates", replicates)?;
    if given && max as u64 != replicates {
        return Err(cx.err(
            "adaptive.max_replicates",
            format!("{max} differs from replicates = {replicates}: give one of them"),
        ));
    }
    let rule = AdaptiveRule {
        batch: get(a.batch, "batch", 8)?,
        min_replicates: get(a.min_replicates, "min_replicates", 8.min(max as u64))?,
        max_replicates: max,
        error: a.error.map_or(0.05, |e| e.0),
    };
    if a.max_replicates.is_none() && rule.min_replicates > max {
        // The budget came from `replicates`: blame the key the file did set.
        return Err(cx.err(
            "adaptive.min_replicates",
            format!(
                "{} is above the budget of replicates = {max}",
                rule.min_replicates
            ),
        ));
    }
    rule.validate()
        .map_err(|(key, problem)| cx.err(format!("adaptive.{key}"), problem))?;
    Ok(rule)
}

/// `[refine]`, if the file has one, checked against the grid.
fn refine(
    r: Option<&sweep_file::RefineFile>,
    grid: &Grid,
    cx: &Ctx,
) -> Result<Option<RefineRule>, SweepError> {
    r.map(|r| crate::refinement::rule(r, &grid.beta).map_err(|(key, problem)| cx.err(key, problem)))
        .transpose()
}

/// `[run]` over the defaults.
fn run_settings(r: &RunFile, cx: &Ctx) -> Result<RunSettings, SweepError> {
    let mut run = RunSettings::default();
    if let Some(x) = r.job_timeout {
        run.job_timeout = job_timeout(x.0).map_err(|p| cx.err("run.job_timeout", p.to_string()))?;
    }
    if let Some(n) = r.max_attempts {
        run.max_attempts = cx.whole(n, "run.max_attempts", 1, MAX_ATTEMPTS)? as u32;
    }
    Ok(run)
}

/// The grid's points and the sweep's jobs within their limits.
fn check_size(sweep: &Sweep, cx: &Ctx) -> Result<(), SweepError> {
    let g = &sweep.grid;
    let points = [g.alpha.len(), g.beta.len(), g.L.len(), g.sigma.len()]
        .into_iter()
        .chain(g.others.iter().map(|a| a.values.len()))
        .fold(1u64, |n, k| n.saturating_mul(k as u64));
    if points > MAX_POINTS {
        return Err(cx.err("grid", format!("{points} points is more than {MAX_POINTS}")));
    }
    // Refinement may add up to its budget in every column: the limits hold for all of them.
    let points = points.saturating_add(sweep.max_added_points());
    if points > MAX_POINTS {
        return Err(cx.err(
            "refine.max_new_per_column",
            format!("the grid and every value refinement may add make {points} points, more than {MAX_POINTS}"),
        ));
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
    Ok(())
}

/// Every point a valid model: the first invalid one names the key to fix.
fn check_points(sweep: &Sweep, cx: &Ctx) -> Result<(), SweepError> {
    // Every point must be a valid model: the first invalid one names the key to fix.
    for point in sweep.points() {
        sweep.protocol_for(&point).validate(&point).map_err(|e| {
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
            let key =
                if GRID_KEYS.contains(&name) || sweep.grid.others.iter().any(|a| a.name == name) {
                    format!("grid.{name}")
                } else if name.contains("lattice")
                    || name.ends_with("_time")
                    || name.ends_with("_interval")
                {
                    format!("protocol.{name}")
                } else {
                    format!("params.{name}")
                };
            cx.err(key, format!("at {}: {e}", sweep.axes_of(&point)))
        })?;
    }
    Ok(())
}

/// `[protocol]` over the defaults; a single lattice given alone sets the pair lattice to twice
/// its width. Durations and intervals are checked with the model (`Protocol::validate`).
fn protocol(p: ProtocolFile, cx: &Ctx) -> Result<Protocol, SweepError> {
    let mut out = Protocol::default();
    let sides = |pair: [Whole; 2], key: &str| -> Result<[usize; 2], SweepError> {
        Ok([
            cx.whole(pair[0], key, 2, MAX_SITES)? as usize,
            cx.whole(pair[1], key, 2, MAX_SITES)? as usize,
        ])
    };
    if let Some(single) = p.single_lattice {
        out.single_lattice = sides(single, "protocol.single_lattice")?;
        out.pair_lattice = [2 * out.single_lattice[0], out.single_lattice[1]];
    }
    if let Some(pair) = p.pair_lattice {
        out.pair_lattice = sides(pair, "protocol.pair_lattice")?;
    }
    let set = |v: Option<sweep_file::Real>, slot: &mut f64| {
        if let Some(x) = v {
            *slot = x.0;
        }
    };
    set(p.relax_time, &mut out.relax_time);
    set(p.free_time, &mut out.free_time);
    set(p.collide_time, &mut out.collide_time);
    set(p.record_interval, &mut out.record_interval);
    set(p.check_interval, &mut out.check_interval);
    set(p.patch_bound, &mut out.patch.bound);
    out.stop_early = p.stop_early.unwrap_or(out.stop_early);
    out.precision = p.precision.unwrap_or(out.precision);
    if let Some(k) = p.resolution {
        out.resolution = cx.whole(k, "protocol.resolution", 1, 8)? as u32;
    }
    Ok(out)
}

/// Classifier settings: every one >= 0, every window > 0 (a zero window would make every
/// velocity 0 and every collision undetermined). The pattern names every field, so a setting
/// added to the solver cannot go unchecked.
fn check_classifier(c: &ClassifierSettings, cx: &Ctx) -> Result<(), SweepError> {
    let ClassifierSettings {
        contact_overlap,
        speed_fraction,
        min_speed,
        velocity_window,
        sustain_window,
        walk_past_margin,
    } = *c;
    for (key, x) in [
        ("contact_overlap", contact_overlap),
        ("speed_fraction", speed_fraction),
        ("min_speed", min_speed),
        ("velocity_window", velocity_window),
        ("sustain_window", sustain_window),
        ("walk_past_margin", walk_past_margin),
    ] {
        let full = format!("classifier.{key}");
        if x < 0.0 {
            return Err(cx.err(full, format!("{x} must be >= 0")));
        }
        if x == 0.0 && key.ends_with("_window") {
            return Err(cx.err(full, "must be > 0 (tau0)"));
        }
    }
    Ok(())
}

impl Sweep {
    /// Read and validate a sweep file.
    pub fn load(path: &Path) -> Result<Sweep, SweepError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| SweepError::new(&file, "file", format!("cannot read: {e}")))?;
        Sweep::parse(&text, &file)
    }

    /// Parse and validate sweep-file text; `file` names it in errors. Serde gives the file's
    /// shape ([`SweepFile`]); every range, limit and the model's validity is checked here.
    pub fn parse(text: &str, file: &str) -> Result<Sweep, SweepError> {
        let cx = Ctx { file };
        let f = sweep_file::read(text, file)?;

        let name = cx.given(f.name, "name")?;
        check_name(&name).map_err(|p| cx.err("name", p.to_string()))?;
        let seed = cx.whole(cx.given(f.seed, "seed")?, "seed", 0, u64::MAX)?;
        let replicates = f
            .replicates
            .map_or(Ok(96), |v| cx.whole(v, "replicates", 1, MAX_REPLICATES))?;
        let preps_per_point = f
            .preps_per_point
            .map_or(Ok(1), |v| cx.whole(v, "preps_per_point", 1, MAX_REPLICATES))?;
        if preps_per_point > replicates {
            return Err(cx.err(
                "preps_per_point",
                format!("{preps_per_point} exceeds replicates = {replicates}"),
            ));
        }

        let in_params: Vec<String> = f.params.iter().flat_map(|t| t.keys().cloned()).collect();
        let mut params = match f.params {
            Some(t) => sweep_file::params(t, file)?,
            None => Params::default(),
        };
        params.geometry = f.geometry.unwrap_or(params.geometry);

        let grid = layout::grid(
            cx.given(f.grid, "grid")?,
            &in_params,
            f.geometry.is_some(),
            &params,
            &cx,
        )?;
        let lattices_follow_r0 = others::lattices_follow_r0(&params, &grid, f.protocol.as_ref());
        let protocol = match f.protocol {
            Some(p) => protocol(p, &cx)?,
            None => Protocol::default(),
        };
        let classifier = f.classifier.unwrap_or_default();
        check_classifier(&classifier, &cx)?;

        let adaptive = match f.adaptive {
            None => None,
            Some(a) => Some(adaptive_rule(&a, replicates, f.replicates.is_some(), &cx)?),
        };
        let replicates = adaptive.map_or(replicates, |a| a.max_replicates as u64);

        let refine = refine(f.refine.as_ref(), &grid, &cx)?;

        let run = f
            .run
            .map_or(Ok(RunSettings::default()), |r| run_settings(&r, &cx))?;
        let planes = report::planes(f.report, &cx)?;

        let sweep = Sweep {
            name,
            seed,
            replicates: replicates as u32,
            preps_per_point: preps_per_point as u32,
            grid,
            params,
            protocol,
            classifier,
            lattices_follow_r0,
            adaptive,
            refine,
            planes,
            run,
        };
        check_size(&sweep, &cx)?;
        check_points(&sweep, &cx)?;
        Ok(sweep)
    }

    /// Replicates registered per point at the start: the first round of an adaptive sweep,
    /// else all of them.
    pub fn initial_replicates(&self) -> u32 {
        self.adaptive
            .map_or(self.replicates, |a| a.min_replicates.min(self.replicates))
    }

    /// The definition of sweep `id` as `store` holds it (its canonical JSON, parsed): the one
    /// reading of a stored definition, for the ledger, `load`, `compare` and `reset`.
    pub fn stored(store: &cellsweep_store::Store, id: i64) -> Result<Sweep, StoredSweepError> {
        let spec = store.sweep_spec(id)?;
        serde_json::from_str(&spec).map_err(|source| StoredSweepError::Malformed {
            name: serde_json::from_str::<serde_json::Value>(&spec)
                .ok()
                .and_then(|v| v.get("name")?.as_str().map(String::from))
                .unwrap_or_else(|| format!("#{id}")),
            source,
        })
    }

    /// Canonical JSON of the sweep's definition (everything but the run settings).
    pub fn canonical_json(&self) -> String {
        // Plain data with string keys and finite numbers (checked when read): serde_json
        // cannot fail on it.
        serde_json::to_string(self).expect("a sweep serializes")
    }
}
