//! `cellsweep simulate`: one whole trajectory, prep and collision.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use cellsweep_report::movie::FrameRecorder;
use cellsweep_solver::{
    run_trajectory, Collision, Config, Monitor, Prep, Protocol, Seeds, TrajectoryResult,
};

use super::model;
use crate::cli::{MovieArgs, SimulateArgs};
use crate::progress::StageBars;

/// Run `f` on a worker of a two-thread pool when `parallel`, so that each step's `rayon::join`
/// keeps one half on the calling worker and hands the other to a worker that is already awake
/// (called from outside a pool, both halves would be sent to the pool and the caller would sleep).
pub(super) fn on_workers<T: Send>(
    parallel: bool,
    f: impl FnOnce() -> T + Send,
) -> anyhow::Result<T> {
    if !parallel {
        return Ok(f());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .context("cannot start the second thread")?;
    Ok(pool.install(f))
}

pub fn run(args: SimulateArgs) -> anyhow::Result<()> {
    let config = config(&args)?;
    let seeds = Seeds::from_run_seed(args.seed);
    let started = Instant::now();
    let (result, prep, collision) = trajectory(&args, &config, seeds)?;
    let wall = started.elapsed().as_secs_f64();
    if let (Some(path), Some(c)) = (&args.movie.track, &collision) {
        write_track(path, c)?;
    }
    if args.json {
        let mut v = serde_json::to_value(&result)?;
        v["wall_s"] = wall.into();
        println!("{}", serde_json::to_string(&v)?);
        return Ok(());
    }
    print_text(&args, &config, &result, &prep, collision.as_ref());
    println!("  wall time         {wall:.1} s");
    Ok(())
}

/// The trajectory's configuration from the flags, checked.
fn config(args: &SimulateArgs) -> anyhow::Result<Config> {
    let mut params = model::params(&args.model)?;
    params.beta = args.beta;
    params.sigma = args.sigma;
    let single = model::single_lattice(&args.model)?;
    let pair = match &args.pair_lattice {
        Some(s) => model::parse_lattice(s)?,
        None => [2 * single[0], single[1]],
    };
    let mut protocol = Protocol {
        single_lattice: single,
        pair_lattice: pair,
        relax_time: args.relax_time,
        free_time: args.free_time,
        collide_time: args.collide_time,
        stop_early: !args.full,
        ..Protocol::default()
    };
    args.numerics.apply(&mut protocol);
    protocol.validate(&params).context("invalid parameters")?;
    Ok(Config {
        params,
        protocol,
        classifier: model::classifier(&args.classifier)?,
    })
}

/// Run it, recording frames or showing a bar per stage.
fn trajectory(
    args: &SimulateArgs,
    config: &Config,
    seeds: Seeds,
) -> anyhow::Result<(TrajectoryResult, Prep, Option<Collision>)> {
    let (out, written) = watched(&args.movie, args.parallel, |m| {
        run_trajectory(config, seeds, m, args.parallel)
    })?;
    if let Some(dir) = &args.movie.frames {
        let pngs = written
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "png"));
        println!(
            "wrote {} snapshots (PNG) and an animated GIF into {}",
            pngs.count(),
            dir.display()
        );
    }
    Ok(out?)
}

/// Run `f` (on the workers when `parallel`) watched by a progress bar per stage, recording
/// the movie where `--frames` asks for one; with the files the movie wrote.
pub(super) fn watched<T: Send>(
    movie: &MovieArgs,
    parallel: bool,
    f: impl FnOnce(&mut dyn Monitor) -> T + Send,
) -> anyhow::Result<(T, Vec<PathBuf>)> {
    match &movie.frames {
        Some(dir) => {
            let mut rec = FrameRecorder::new(dir, movie.frame_every, StageBars::new())?;
            let out = on_workers(parallel, || f(&mut rec))?;
            rec.inner.finish();
            rec.finish()?;
            Ok((out, rec.written))
        }
        None => {
            let mut bars = StageBars::new();
            let out = on_workers(parallel, || f(&mut bars))?;
            bars.finish();
            Ok((out, Vec::new()))
        }
    }
}

/// The collision's observables, one JSON object per sample.
pub(super) fn write_track(path: &Path, c: &Collision) -> anyhow::Result<()> {
    let mut f = std::io::BufWriter::new(
        std::fs::File::create(path).with_context(|| format!("cannot write {}", path.display()))?,
    );
    for s in &c.track {
        writeln!(f, "{}", serde_json::to_string(s)?)?;
    }
    f.flush()?;
    Ok(())
}

/// The result in a few aligned lines.
fn print_text(
    args: &SimulateArgs,
    config: &Config,
    result: &TrajectoryResult,
    prep: &Prep,
    collision: Option<&Collision>,
) {
    let p = &config.params;
    println!(
        "alpha = {}, beta = {}, L = {}, sigma = {}, geometry = {}, seed = {}, collision in {}",
        p.alpha,
        p.beta,
        p.L,
        p.sigma,
        p.geometry,
        args.seed,
        config.protocol.precision.as_str()
    );
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
    println!("  prep verdict      {}", result.verdict.as_str());
    println!("  free speed        {} l0/tau0", opt(prep.free_speed));
    match (collision, result.outcome) {
        (Some(c), Some(outcome)) => {
            println!("  outcome           {outcome}");
            println!("  contact time      {} tau0", opt(c.contact_time));
            println!("  decision time     {} tau0", opt(c.decision_time));
            println!("  threshold speed   {:.3} l0/tau0", c.threshold_speed);
            println!(
                "  attachment        cell 1: {:?}, cell 2: {:?}",
                c.attachment[0], c.attachment[1]
            );
            println!("  collision steps   {}", c.steps);
            if let Some(pt) = &c.patch {
                println!(
                    "  windows           {:.0}% of the lattice on average, widest {} columns, \
                     {} edge hits",
                    100.0 * pt.mean_fraction,
                    pt.widest,
                    pt.edge_hits
                );
            }
        }
        _ => println!("  no collision (the prep is not ok)"),
    }
}
