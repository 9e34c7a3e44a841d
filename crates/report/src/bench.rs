//! What `cellsweep bench` measures and prints: the solver kernel's step rates on one core
//! ([`kernel_rates`]), the NumPy yardstick's step and its agreement ([`add_yardstick`]), one
//! whole trajectory timed stage by stage ([`add_trajectory`]), and the report in a few lines
//! ([`text`]). The report is one JSON object, the same keys `bench --json` prints.

use std::fmt::Write;
use std::path::Path;

use cellsweep_solver::timing;
use cellsweep_solver::{Config, Params, Seeds, SolverError};
use serde_json::{json, Value};

/// Why the yardstick did not run.
#[derive(Debug, thiserror::Error)]
enum YardstickError {
    #[error("{0} not found")]
    Missing(String),
    #[error("cannot run {python}: {source}")]
    Spawn {
        python: String,
        source: std::io::Error,
    },
    #[error("{0}")]
    Failed(String),
    #[error(transparent)]
    Output(#[from] serde_json::Error),
}

/// The yardstick's step time and integrals, or why it could not run.
fn yardstick(python: &str, script: &Path) -> Result<Value, YardstickError> {
    if !script.exists() {
        return Err(YardstickError::Missing(script.display().to_string()));
    }
    let out = std::process::Command::new(python)
        .arg(script)
        .args(["40", "10"])
        .output()
        .map_err(|source| YardstickError::Spawn {
            python: python.to_string(),
            source,
        })?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last = err.lines().last().unwrap_or("failed").to_string();
        return Err(YardstickError::Failed(last));
    }
    Ok(serde_json::from_slice(&out.stdout)?)
}

/// The kernel's step rates as the report's keys, and the integrals the yardstick must
/// reproduce.
pub fn kernel_rates(params: &Params) -> (Value, Value) {
    let r = timing::kernel_rates(params);
    let check = json!({
        "sum_phi_1": r.check.sum_phi_1,
        "area_1": r.check.area_1,
        "area_2": r.check.area_2,
        "sum_p_1": r.check.sum_p_1,
    });
    let report = json!({
        "single_steps_per_s": r.single,
        "single_site_updates_per_s": r.single * 40_000.0,
        "pair_steps_per_s": r.pair,
        "pair_site_updates_per_s": r.pair * 2.0 * 80_000.0,
        "pair_step_s": 1.0 / r.pair,
        "pair_f32_steps_per_s": r.pair_f32,
        "pair_literal_steps_per_s": r.pair_literal,
        "threads": 1,
    });
    (report, check)
}

/// The NumPy yardstick's step time (`script` run by `python`) and its agreement with
/// `check`, or why it was skipped.
pub fn add_yardstick(report: &mut Value, check: &Value, python: &str, script: &Path) {
    match yardstick(python, script) {
        Ok(y) => {
            let np = y["pair_step_s"].as_f64().unwrap_or(f64::NAN);
            let worst = ["sum_phi_1", "area_1", "area_2", "sum_p_1"]
                .iter()
                .map(|k| {
                    let (r, p) = (
                        check[k].as_f64().unwrap_or(f64::NAN),
                        y[k].as_f64().unwrap_or(f64::NAN),
                    );
                    (r - p).abs() / p.abs().max(1e-300)
                })
                .fold(0.0, f64::max);
            report["numpy_pair_step_s"] = np.into();
            report["numpy_pair_step_mean_s"] = y["pair_step_mean_s"].clone();
            let rate = |k: &str| report[k].as_f64().unwrap_or(f64::NAN);
            let (pair, literal) = (rate("pair_steps_per_s"), rate("pair_literal_steps_per_s"));
            report["speedup_pair_vs_numpy"] = (np * pair).into();
            report["speedup_pair_literal_vs_numpy"] = (np * literal).into();
            report["numpy_agreement_rel"] = worst.into();
            report["numpy_version"] = y["numpy"].clone();
        }
        Err(e) => report["numpy_yardstick"] = format!("skipped: {e}").into(),
    }
}

/// One whole trajectory of `config` (seed 1) timed stage by stage; the yardstick timed again
/// after it, where it ran before.
pub fn add_trajectory(
    report: &mut Value,
    config: &Config,
    python: &str,
    script: &Path,
) -> Result<(), SolverError> {
    let p = &config.params;
    let timed = timing::time_trajectory(config, Seeds::from_run_seed(1))?;
    let (result, total) = (&timed.result, timed.total_s);
    let (relax, free, collide) = (timed.relax_s, timed.free_s, timed.collide_s);
    let collision_rate = result.collision_steps as f64 / collide;
    report["trajectory"] = json!({
        "alpha": p.alpha, "beta": p.beta, "L": p.L, "sigma": p.sigma, "seed": 1,
        "outcome": result.outcome, "collision_steps": result.collision_steps,
        "relax_s": relax, "free_s": free, "collide_s": collide, "total_s": total,
        "collision_steps_per_s": collision_rate,
        "patch_bound": config.protocol.patch.bound, "patch": result.patch,
        "precision": config.protocol.precision.as_str(),
    });
    report["trajectory_s"] = (collide + (relax + free) / 96.0).into();
    report["collision_steps_per_s"] = collision_rate.into();
    // The collision stage's rate is a mean over seconds of a shared machine, so it is set
    // against the yardstick's mean step, timed once before the trajectory and once after.
    if let Some(before) = report["numpy_pair_step_mean_s"].as_f64() {
        let after = yardstick(python, script)
            .ok()
            .and_then(|y| y["pair_step_mean_s"].as_f64());
        let np = after.map_or(before, |a| (before + a) / 2.0);
        report["numpy_pair_step_mean_around_trajectory_s"] = np.into();
        report["speedup_collision_vs_numpy"] = (np * collision_rate).into();
    }
    Ok(())
}

/// The report as a few aligned lines.
pub fn text(r: &Value) -> String {
    let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
    let mut out = String::new();
    let _ = writeln!(out, "one core, float64:");
    let _ = writeln!(
        out,
        "  single-cell step 200x200   {:>8.0} steps/s   {:>6.0} M site updates/s",
        f("single_steps_per_s"),
        f("single_site_updates_per_s") / 1e6
    );
    let _ = writeln!(
        out,
        "  two-cell step 400x200      {:>8.0} steps/s   {:>6.0} M site updates/s",
        f("pair_steps_per_s"),
        f("pair_site_updates_per_s") / 1e6
    );
    let _ = writeln!(
        out,
        "  same, P on every row       {:>8.0} steps/s   (SPEC literally, as the yardstick)",
        f("pair_literal_steps_per_s"),
    );
    let _ = writeln!(
        out,
        "  two-cell step, f32         {:>8.0} steps/s   ({:.2}x the f64 step)",
        f("pair_f32_steps_per_s"),
        f("pair_f32_steps_per_s") / f("pair_steps_per_s")
    );
    if r.get("numpy_pair_step_s").is_some() {
        let _ = writeln!(
            out,
            "  NumPy yardstick            {:>8.2} ms/step (best batch; mean {:.2})   -> the kernel is {:.0}x faster ({:.0}x with P on every row; integrals agree to {:.1e})",
            f("numpy_pair_step_s") * 1e3,
            f("numpy_pair_step_mean_s") * 1e3,
            f("speedup_pair_vs_numpy"),
            f("speedup_pair_literal_vs_numpy"),
            f("numpy_agreement_rel")
        );
    } else if let Some(s) = r.get("numpy_yardstick") {
        let _ = writeln!(
            out,
            "  NumPy yardstick            {}",
            s.as_str().unwrap_or("")
        );
    }
    if let Some(t) = r.get("trajectory") {
        let _ = writeln!(
            out,
            "  trajectory (alpha 0.1, beta 14, L 90, sigma 5): relax {:.1} s, free {:.1} s, collision {:.1} s ({} steps, {})",
            t["relax_s"].as_f64().unwrap_or(0.0),
            t["free_s"].as_f64().unwrap_or(0.0),
            t["collide_s"].as_f64().unwrap_or(0.0),
            t["collision_steps"],
            t["outcome"].as_str().unwrap_or("-")
        );
        let windows = match t["patch"].get("mean_fraction").and_then(|v| v.as_f64()) {
            Some(m) => format!("per-cell windows over {:.0}% of the lattice", 100.0 * m),
            None => "whole lattice".to_string(),
        };
        let _ = writeln!(
            out,
            "  collision stage, {}       {:>8.0} steps/s   ({windows}){}",
            t["precision"].as_str().unwrap_or("f64"),
            f("collision_steps_per_s"),
            match r["speedup_collision_vs_numpy"].as_f64() {
                Some(x) => format!(" -> {x:.0}x the NumPy yardstick's mean step"),
                None => String::new(),
            }
        );
        let _ = writeln!(
            out,
            "  per trajectory, prep shared by 96 replicates: {:.1} s",
            f("trajectory_s")
        );
    }
    out
}
