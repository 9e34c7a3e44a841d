//! `cellsweep bench`: speed of the solver on this machine, on one core.

use std::path::PathBuf;
use std::time::Instant;

use cellsweep_solver::cell::step_pair;
use cellsweep_solver::prep::{initial_circle, kick};
use cellsweep_solver::{
    run_trajectory, Cell, Config, Fibers, Lattice, Monitor, Params, Real, Seeds, Stage,
};
use serde_json::{json, Value};

use crate::cli::BenchArgs;

/// Wall time of each stage of a trajectory.
#[derive(Default)]
struct StageClock {
    current: Option<(Stage, Instant)>,
    seconds: Vec<(Stage, f64)>,
}

impl StageClock {
    fn close(&mut self) {
        if let Some((stage, t)) = self.current.take() {
            self.seconds.push((stage, t.elapsed().as_secs_f64()));
        }
    }
    fn get(&self, s: Stage) -> f64 {
        self.seconds.iter().filter(|x| x.0 == s).map(|x| x.1).sum()
    }
}

impl Monitor for StageClock {
    fn stage(&mut self, stage: Stage, _total: u64) {
        self.close();
        self.current = Some((stage, Instant::now()));
    }
}

/// The yardstick's start on the pair lattice: two circles, fronts kicked, cell 2 mirrored.
fn pair_start(params: &Params) -> (Lattice, Fibers, Cell, Cell) {
    let lat = Lattice::new(400, 200);
    let fibers = Fibers::new(params, 200);
    let circle = |cx: f64| -> Vec<f64> {
        let mut phi = lat.zeros();
        for j in 0..200 {
            for i in 0..400 {
                let r = ((i as f64 - cx).powi(2) + (j as f64 - 99.5).powi(2)).sqrt();
                phi[lat.idx(i, j)] = 0.5 + 0.5 * ((params.R0 - r) / (2.0 * params.d)).tanh();
            }
        }
        phi
    };
    let (phi1, phi2) = (circle(99.5), circle(299.5));
    let kicked = |phi: &[f64], front: &dyn Fn(usize) -> bool| -> Vec<f64> {
        (0..phi.len())
            .map(|k| {
                if phi[k] > 0.5 && front(k % 400) {
                    1.0
                } else {
                    0.0
                }
            })
            .collect()
    };
    let (p1, p2) = (kicked(&phi1, &|i| i >= 100), kicked(&phi2, &|i| i <= 299));
    let a = Cell::new(&lat, &fibers, phi1, p1);
    let b = Cell::new(&lat, &fibers, phi2, p2);
    (lat, fibers, a, b)
}

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

/// Steps per second of `step`, from the fastest of five batches of `batch` steps: on a shared
/// VM the other batches mostly measure the neighbours.
fn best_rate(batch: u32, mut step: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                step();
            }
            batch as f64 / t.elapsed().as_secs_f64()
        })
        .fold(0.0, f64::max)
}

/// Noise-free pair steps per second on the whole lattice, one thread, in `T`; with
/// `fibers_only`, P advanced only on the fiber rows, as the collision runs it.
fn pair_rate<T: Real>(
    mut a: Cell<T>,
    mut b: Cell<T>,
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    fibers_only: bool,
) -> f64 {
    if fibers_only {
        a.polarity_on_fibers_only(lat, fibers);
        b.polarity_on_fibers_only(lat, fibers);
    }
    best_rate(200, || {
        step_pair(&mut a, &mut b, lat, fibers, params, [[0.0; 2]; 2], false)
    })
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

/// The step rates of the kernel (single cell, pair in f64 as SPEC and as run, pair in f32),
/// and the integrals of the pair after ten steps that the yardstick must reproduce.
fn kernel_rates(params: &Params) -> (Value, Value) {
    // Single-cell step, 200 x 200, motile with noise.
    let lat = Lattice::new(200, 200);
    let fibers = Fibers::new(params, 200);
    let mut cell = Cell::new(&lat, &fibers, initial_circle(&lat, params), lat.zeros());
    kick(&lat, &mut cell);
    for _ in 0..200 {
        cell.step(&lat, &fibers, params, [0.05, -0.03], true, false);
    }
    let single = best_rate(600, || {
        cell.step(&lat, &fibers, params, [0.05, -0.03], true, false)
    });

    // Two-cell step, 400 x 200, one thread.
    let (plat, pfib, mut a, mut b) = pair_start(params);
    let mut noise_free = params.clone();
    noise_free.v0 = 0.0;
    for _ in 0..10 {
        step_pair(
            &mut a,
            &mut b,
            &plat,
            &pfib,
            &noise_free,
            [[0.0; 2]; 2],
            false,
        );
    }
    let check = json!({
        "sum_phi_1": a.phi.iter().sum::<f64>(),
        "area_1": a.sums.area,
        "area_2": b.sums.area,
        "sum_p_1": a.p.iter().sum::<f64>(),
    });
    // The same start in f32 (the opt-in precision of the collision stage).
    let (a32, b32) = (
        a.convert::<f32>(&plat, &pfib),
        b.convert::<f32>(&plat, &pfib),
    );
    // SPEC literally (P on every row, as the yardstick does), then as the collision runs it
    // (P only on the fiber rows, where it acts: the same phi).
    let pair_literal = pair_rate(a.clone(), b.clone(), &plat, &pfib, &noise_free, false);
    let pair = pair_rate(a, b, &plat, &pfib, &noise_free, true);
    let pair_f32 = pair_rate(a32, b32, &plat, &pfib, &noise_free, true);

    let report = json!({
        "single_steps_per_s": single,
        "single_site_updates_per_s": single * 40_000.0,
        "pair_steps_per_s": pair,
        "pair_site_updates_per_s": pair * 2.0 * 80_000.0,
        "pair_step_s": 1.0 / pair,
        "pair_f32_steps_per_s": pair_f32,
        "pair_literal_steps_per_s": pair_literal,
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
    let mut clock = StageClock::default();
    let t = Instant::now();
    let (result, _, _) = run_trajectory(&config, Seeds::from_run_seed(1), &mut clock, false)?;
    let total = t.elapsed().as_secs_f64();
    clock.close();
    let (relax, free, collide) = (
        clock.get(Stage::Relax),
        clock.get(Stage::Free),
        clock.get(Stage::Collide),
    );
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
