//! `cellsweep replay` (one stored replicate computed again, with its movie) and
//! `cellsweep verify` (a seeded sample of a store's or an export's rows replayed), both by
//! `scheduler::replay`.

use anyhow::Context;
use cellsweep_scheduler::replay::{
    choose_rows, find_row, replay, replay_with, row_name, PrepCache, ReplayError,
};
use cellsweep_solver::Silent;
use cellsweep_stats::End;

use super::simulate::{watched, write_track};
use crate::cli::{ReplayArgs, VerifyArgs};

pub fn run(args: ReplayArgs) -> anyhow::Result<i32> {
    let (sweep, rows) = args.source.rows()?;
    let point = &args.point;
    let row = find_row(&sweep, &rows, point, args.replicate)
        .map_err(|e| anyhow::anyhow!("--point {point}: {e}"))?;
    println!(
        "replaying {} of {:?} ({}): prep seed {}, collision seed {}, {} collision",
        row_name(&sweep, row),
        sweep.name,
        args.source.name(),
        row.prep_seed,
        row.collision_seed,
        row.precision
    );
    let (replayed, _) = watched(&args.movie, args.parallel, |m| {
        replay(&sweep, row, m, args.parallel)
    })?;
    if let Some(dir) = &args.movie.frames {
        println!(
            "wrote the movie (PNG snapshots and an animated GIF) into {}",
            dir.display()
        );
    }
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
    for line in replayed
        .side_by_side(row)
        .iter()
        .chain(&replayed.verdict_lines())
    {
        println!("{line}");
    }
    Ok(if replayed.agrees() { 0 } else { 1 })
}

pub fn verify(args: VerifyArgs) -> anyhow::Result<i32> {
    let ended: Vec<End> = args
        .ended
        .iter()
        .map(|name| End::parse(name).map_err(|e| anyhow::anyhow!("--ended {e}")))
        .collect::<anyhow::Result<_>>()?;
    let sets = args.source.all_rows()?;
    let sample = (!args.all).then_some((args.sample, args.seed));
    let (chosen, total) = choose_rows(&sets, &ended, sample);
    if total == 0 {
        let which = match ended.is_empty() {
            true => String::new(),
            false => format!(" that ended as {}", args.ended.join(" or ")),
        };
        anyhow::bail!("{}: no finished rows{which} to verify", args.source.name());
    }
    println!(
        "verifying {} of {total} rows of {} sweep(s) in {}{}",
        chosen.len(),
        sets.len(),
        args.source.name(),
        match sample {
            None => String::new(),
            Some((_, seed)) => format!(", chosen with seed {seed}"),
        }
    );
    let (mut same, mut close, mut differ, mut other) = (0, 0, 0, 0);
    let mut preps = PrepCache::new();
    for (k, (sweep, row)) in chosen.iter().enumerate() {
        let started = std::time::Instant::now();
        let what = match replay_with(sweep, row, &mut Silent, false, &mut preps) {
            Ok(r) => {
                match (r.differences.is_empty(), r.agrees()) {
                    (true, _) => same += 1,
                    (false, true) => close += 1,
                    (false, false) => differ += 1,
                }
                r.verdict_lines().join("; ")
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
