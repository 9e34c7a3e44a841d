//! `cellsweep replay` (one stored replicate computed again, with its movie) and
//! `cellsweep verify` (a seeded sample of a store's or an export's rows replayed).

use anyhow::{bail, Context};
use cellsweep_scheduler::replay::{
    find_row, replay, replay_with, row_name, PrepCache, ReplayError, Replayed,
};
use cellsweep_scheduler::Sweep;
use cellsweep_solver::Silent;
use cellsweep_stats::{End, Selector};
use cellsweep_store::export::ExportRow;
use rand::seq::SliceRandom;
use rand::SeedableRng;

use super::simulate::{on_workers, write_track};
use crate::cli::{ReplayArgs, VerifyArgs};
use crate::frames::FrameRecorder;
use crate::progress::StageBars;

/// The selector of `--point NAME=VALUE,...`, each naming an axis of the sweep.
fn point_selector(sweep: &Sweep, text: &str) -> anyhow::Result<Selector> {
    let mut axes = vec!["alpha", "beta", "L", "sigma"];
    axes.extend(sweep.grid.others.iter().map(|a| a.name.as_str()));
    let selector = Selector::parse(text).and_then(|s| {
        s.check_axes(&axes, &format!("sweep {:?}", sweep.name))
            .map(|_| s)
    });
    selector.map_err(|e| anyhow::anyhow!("--point {text}: {e}"))
}

/// The row of replicate `replicate` at the one point `--point` names.
fn find_point_row<'a>(
    sweep: &Sweep,
    rows: &'a [ExportRow],
    point: &str,
    replicate: u32,
) -> anyhow::Result<&'a ExportRow> {
    let selector = point_selector(sweep, point)?;
    find_row(sweep, rows, &selector, replicate).map_err(|e| anyhow::anyhow!("--point {point}: {e}"))
}

/// What a replay says, in lines: `identical`, `identical to round-off` with the speeds a few
/// ulps off, or each field that differs with both values.
fn verdict_lines(r: &Replayed) -> Vec<String> {
    if r.differences.is_empty() {
        return vec!["identical".to_string()];
    }
    let mut lines: Vec<String> = r
        .differences
        .iter()
        .map(|d| {
            let kind = if d.round_off { "round-off" } else { "differs" };
            format!(
                "{kind}: {}: stored {}, replayed {}",
                d.field, d.stored, d.replayed
            )
        })
        .collect();
    if r.agrees() {
        lines.push(
            "identical to round-off (a speed an ulp off: stored before floats crossed JSON exactly)"
                .to_string(),
        );
    }
    lines
}

pub fn run(args: ReplayArgs) -> anyhow::Result<i32> {
    let (sweep, rows) = args.source.rows()?;
    let row = find_point_row(&sweep, &rows, &args.point, args.replicate)?;
    println!(
        "replaying {} of {:?} ({}): prep seed {}, collision seed {}, {} collision",
        row_name(&sweep, row),
        sweep.name,
        args.source.name(),
        row.prep_seed,
        row.collision_seed,
        row.precision
    );
    let replayed = match &args.movie.frames {
        Some(dir) => {
            let mut rec = FrameRecorder::new(dir, args.movie.frame_every)?;
            let out = on_workers(args.parallel, || {
                replay(&sweep, row, &mut rec, args.parallel)
            })?;
            rec.finish()?;
            println!(
                "wrote the movie (PNG snapshots and an animated GIF) into {}",
                dir.display()
            );
            out
        }
        None => {
            let mut bars = StageBars::new();
            let out = on_workers(args.parallel, || {
                replay(&sweep, row, &mut bars, args.parallel)
            })?;
            bars.finish();
            out
        }
    };
    let replayed = match replayed {
        Ok(r) => r,
        Err(e @ ReplayError::OtherVersion { .. }) => {
            println!("not compared: {e}");
            return Ok(2);
        }
        Err(e) => return Err(e.into()),
    };
    if let (Some(path), Some(c)) = (&args.movie.track, &replayed.collision) {
        write_track(path, c)?;
        println!("wrote the observables into {}", path.display());
    }
    let opt = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{x}"));
    println!(
        "  stored   {} / {}, contact {}, decision {}, {} steps",
        row.verdict,
        row.outcome.as_deref().unwrap_or("-"),
        opt(row.contact_time),
        opt(row.decision_time),
        row.collision_steps
    );
    let r = &replayed.result;
    println!(
        "  replayed {} / {}, contact {}, decision {}, {} steps",
        r.verdict.as_str(),
        r.outcome
            .map_or("-".to_string(), |o| o.as_str().to_string()),
        opt(r.contact_time),
        opt(r.decision_time),
        r.collision_steps
    );
    for line in verdict_lines(&replayed) {
        println!("{line}");
    }
    Ok(if replayed.agrees() { 0 } else { 1 })
}

pub fn verify(args: VerifyArgs) -> anyhow::Result<i32> {
    let ended: Vec<End> = args
        .ended
        .iter()
        .map(|name| {
            End::ALL
                .into_iter()
                .find(|e| e.name() == name)
                .with_context(|| {
                    let names: Vec<&str> = End::ALL.iter().map(|e| e.name()).collect();
                    format!("--ended {name:?}: not one of {}", names.join(", "))
                })
        })
        .collect::<anyhow::Result<_>>()?;
    let sets = args.source.all_rows()?;
    let mut chosen: Vec<(&Sweep, &ExportRow)> = sets
        .iter()
        .flat_map(|(sweep, rows)| rows.iter().map(move |r| (sweep, r)))
        .filter(|(_, r)| {
            ended.is_empty()
                || End::of(&r.verdict, r.outcome.as_deref()).is_some_and(|e| ended.contains(&e))
        })
        .collect();
    let total = chosen.len();
    if total == 0 {
        let which = match ended.is_empty() {
            true => String::new(),
            false => format!(" that ended as {}", args.ended.join(" or ")),
        };
        bail!("{}: no finished rows{which} to verify", args.source.name());
    }
    if !args.all {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(args.seed);
        chosen.shuffle(&mut rng);
        chosen.truncate(args.sample.max(1));
    }
    println!(
        "verifying {} of {} rows of {} sweep(s) in {}{}",
        chosen.len(),
        total,
        sets.len(),
        args.source.name(),
        if args.all {
            String::new()
        } else {
            format!(", chosen with seed {}", args.seed)
        }
    );
    let (mut same, mut close, mut differ, mut other) = (0, 0, 0, 0);
    let mut preps = PrepCache::new();
    for (k, (sweep, row)) in chosen.iter().enumerate() {
        let started = std::time::Instant::now();
        let what = match replay_with(sweep, row, &mut Silent, false, &mut preps) {
            Ok(r) if r.differences.is_empty() => {
                same += 1;
                "identical".to_string()
            }
            Ok(r) if r.agrees() => {
                close += 1;
                verdict_lines(&r).join("; ")
            }
            Ok(r) => {
                differ += 1;
                verdict_lines(&r).join("; ")
            }
            Err(e @ ReplayError::OtherVersion { .. }) => {
                other += 1;
                format!("not compared: {e}")
            }
            Err(e) => {
                return Err(e).context(format!(
                    "replaying {} of {:?}",
                    row_name(sweep, row),
                    sweep.name
                ))
            }
        };
        println!(
            "  [{}/{}] {:?} {} ({} {}, {:.0} s): {what}",
            k + 1,
            chosen.len(),
            sweep.name,
            row_name(sweep, row),
            row.precision,
            row.outcome.as_deref().unwrap_or(&row.verdict),
            started.elapsed().as_secs_f64()
        );
    }
    println!("{same} identical, {close} identical to round-off in a speed, {differ} differ, {other} of another solver version (not compared)");
    Ok(if differ > 0 { 1 } else { 0 })
}
