//! `cellsweep bench`: speed of the solver on this machine, on one core.

use std::path::PathBuf;

use cellsweep_solver::timing;
use cellsweep_solver::{Config, Params, Seeds};
use serde_json::{json, Value};

use crate::cli::BenchArgs;

fn yardstick(python: &str) -> Result<Value, String> {
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/numpy_yardstick.py");
    if !script.exists() {
        return Err(format!("{} not found", script.display()));
    }
    let out = std::process::Command::new(python)
        .arg(&script)
        .args(["40", "10"])
        .output()
        .map_err(|e| format!("cannot run {python}: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(err.lines().last().unwrap_or("failed").to_string());
    }
    serde_json::from_slice(&out.stdout).map_err(|e| e.to_string())
}

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let params = Params {
        alpha: 0.1,
        beta: 14.0,
        L: 90,
        sigma: 5.0,
        ..Params::default()
    };
    let (mut report, check) = kernel_rates(&params);
    if !args.no_yardstick {
        add_yardstick(&mut report, &check, &args.python);
    }
    if !args.quick {
        add_trajectory(&mut report, &args, &params)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_text(&report);
    }
    Ok(())
}

/// The kernel's step rates as the report's keys, and the integrals the yardstick must
/// reproduce.
fn kernel_rates(params: &Params) -> (Value, Value) {
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

/// The NumPy yardstick's step time and its agreement with `check`, or why it was skipped.
fn add_yardstick(report: &mut Value, check: &Value, python: &str) {
    match yardstick(python) {
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

/// One whole trajectory at the benchmark's point, timed stage by stage.
fn add_trajectory(report: &mut Value, args: &BenchArgs, params: &Params) -> anyhow::Result<()> {
    let mut config = Config {
        params: params.clone(),
        ..Config::default()
    };
    args.numerics.apply(&mut config.protocol);
    let timed = timing::time_trajectory(&config, Seeds::from_run_seed(1))?;
    let (result, total) = (&timed.result, timed.total_s);
    let (relax, free, collide) = (timed.relax_s, timed.free_s, timed.collide_s);
    let collision_rate = result.collision_steps as f64 / collide;
    report["trajectory"] = json!({
        "alpha": 0.1, "beta": 14.0, "L": 90, "sigma": 5.0, "seed": 1,
        "outcome": result.outcome, "collision_steps": result.collision_steps,
        "relax_s": relax, "free_s": free, "collide_s": collide, "total_s": total,
        "collision_steps_per_s": collision_rate,
        "patch_bound": args.numerics.patch_bound, "patch": result.patch,
        "precision": args.numerics.precision.as_str(),
    });
    report["trajectory_s"] = (collide + (relax + free) / 96.0).into();
    report["collision_steps_per_s"] = collision_rate.into();
    // The collision stage's rate is a mean over seconds of a shared machine, so it is set
    // against the yardstick's mean step, timed once before the trajectory and once after.
    if let Some(before) = report["numpy_pair_step_mean_s"].as_f64() {
        let after = yardstick(&args.python)
            .ok()
            .and_then(|y| y["pair_step_mean_s"].as_f64());
        let np = after.map_or(before, |a| (before + a) / 2.0);
        report["numpy_pair_step_mean_around_trajectory_s"] = np.into();
        report["speedup_collision_vs_numpy"] = (np * collision_rate).into();
    }
    Ok(())
}

/// The report as a few aligned lines.
fn print_text(r: &Value) {
    let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
    println!("one core, float64:");
    println!(
        "  single-cell step 200x200   {:>8.0} steps/s   {:>6.0} M site updates/s",
        f("single_steps_per_s"),
        f("single_site_updates_per_s") / 1e6
    );
    println!(
        "  two-cell step 400x200      {:>8.0} steps/s   {:>6.0} M site updates/s",
        f("pair_steps_per_s"),
        f("pair_site_updates_per_s") / 1e6
    );
    println!(
        "  same, P on every row       {:>8.0} steps/s   (SPEC literally, as the yardstick)",
        f("pair_literal_steps_per_s"),
    );
    println!(
        "  two-cell step, f32         {:>8.0} steps/s   ({:.2}x the f64 step)",
        f("pair_f32_steps_per_s"),
        f("pair_f32_steps_per_s") / f("pair_steps_per_s")
    );
    if r.get("numpy_pair_step_s").is_some() {
        println!(
            "  NumPy yardstick            {:>8.2} ms/step (best batch; mean {:.2})   -> the kernel is {:.0}x faster ({:.0}x with P on every row; integrals agree to {:.1e})",
            f("numpy_pair_step_s") * 1e3,
            f("numpy_pair_step_mean_s") * 1e3,
            f("speedup_pair_vs_numpy"),
            f("speedup_pair_literal_vs_numpy"),
            f("numpy_agreement_rel")
        );
    } else if let Some(s) = r.get("numpy_yardstick") {
        println!("  NumPy yardstick            {}", s.as_str().unwrap_or(""));
    }
    if let Some(t) = r.get("trajectory") {
        println!(
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
        println!(
            "  collision stage, {}       {:>8.0} steps/s   ({windows}){}",
            t["precision"].as_str().unwrap_or("f64"),
            f("collision_steps_per_s"),
            match r["speedup_collision_vs_numpy"].as_f64() {
                Some(x) => format!(" -> {x:.0}x the NumPy yardstick's mean step"),
                None => String::new(),
            }
        );
        println!(
            "  per trajectory, prep shared by 96 replicates: {:.1} s",
            f("trajectory_s")
        );
    }
}
