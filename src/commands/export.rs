//! `cellsweep export`: one CSV row per finished replicate (format in the first line).

use anyhow::{bail, Context};
use cellsweep_scheduler::wire::PrepPayload;
use cellsweep_scheduler::{plan_targets, Ledger, RowCheck, Settlement, StoreLock, Sweep};
use cellsweep_solver::{prepare, Config, Silent};
use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_store::export::{ExportRow, EXPORT_FORMAT, READ_FORMATS};
use cellsweep_store::JobState;
use cellsweep_store::Store;
use rayon::prelude::*;

use crate::cli::{ExportArgs, ImportArgs};

pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    let store = Store::open_read(&args.db.db)?;
    let name = match &args.sweep {
        Some(n) => n.clone(),
        None => match store.sweep_names()?.as_slice() {
            [one] => one.clone(),
            [] => bail!("no sweeps in {}", args.db.db.display()),
            many => bail!(
                "{} holds several sweeps ({}); pass --sweep NAME",
                args.db.db.display(),
                many.join(", ")
            ),
        },
    };
    let id = store.sweep_id(&name)?;
    let defaults = serde_json::to_value(Params::default())?;
    let rows = store.export_rows(id, SOLVER_VERSION, &defaults)?;
    let out = &args.out;
    crate::output::replace_file(out, |file| {
        use std::io::Write as _;
        writeln!(
            file,
            "# cellsweep export format {EXPORT_FORMAT}; sweep {name:?}; {SOLVER_VERSION}"
        )?;
        // The sweep's definition, so that `cellsweep import` can register it anywhere.
        writeln!(file, "# spec {}", store.sweep_spec(id)?)?;
        let mut w = csv::Writer::from_writer(file);
        for r in &rows {
            w.serialize(r)?;
        }
        w.flush()?;
        Ok(())
    })?;
    println!(
        "wrote {} replicates of {name:?} to {}",
        rows.len(),
        out.display()
    );
    Ok(())
}

/// An export file read back: its sweep's definition (line 2, checked: name and every point's
/// model) and its rows. Each problem names the file and the line or row.
pub fn read_export(path: &std::path::Path) -> anyhow::Result<(Sweep, Vec<ExportRow>)> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {file}"))?;
    let mut lines = text.lines();
    let head = lines.next().unwrap_or("");
    let format = head
        .strip_prefix("# cellsweep export format ")
        .and_then(|rest| rest.split(';').next())
        .and_then(|v| v.parse::<u32>().ok());
    match format {
        Some(f) if READ_FORMATS.contains(&f) => {}
        Some(f) => bail!(
            "{file}: line 1: export format {f}, and this build reads formats {READ_FORMATS:?} \
             (a newer cellsweep wrote it?)"
        ),
        None => bail!(
            "{file}: line 1: not a cellsweep export (expected \"# cellsweep export format \
             {EXPORT_FORMAT}; ...\")"
        ),
    }
    let spec = lines
        .next()
        .and_then(|l| l.strip_prefix("# spec "))
        .with_context(|| format!("{file}: line 2: missing the sweep's definition (# spec ...)"))?;
    let sweep: Sweep = serde_json::from_str(spec)
        .map_err(|e| anyhow::anyhow!("{file}: line 2: malformed sweep definition: {e}"))?;
    cellsweep_scheduler::sweep::check_name(&sweep.name)
        .map_err(|e| anyhow::anyhow!("{file}: line 2: name: {e}"))?;
    for p in sweep.points() {
        sweep
            .protocol
            .validate(&p)
            .map_err(|e| anyhow::anyhow!("{file}: line 2: sweep definition: {e}"))?;
    }
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut rows: Vec<ExportRow> = Vec::new();
    for (i, r) in reader.deserialize().enumerate() {
        rows.push(r.map_err(|e| anyhow::anyhow!("{file}: row {}: {e}", i + 1))?);
    }
    Ok((sweep, rows))
}

/// `cellsweep import`: register the file's sweep, compute the preps its rows need, check every
/// row against the job it claims, and commit them all, or none if any is refused.
pub fn import(args: ImportArgs) -> anyhow::Result<()> {
    let file = args.file.display().to_string();
    let (sweep, rows) = read_export(&args.file)?;
    // Register the sweep with every replicate the rows name (and at least its first round).
    let points = sweep.points();
    let mut targets = vec![sweep.initial_replicates(); points.len()];
    for r in &rows {
        let Some(i) = points
            .iter()
            .position(|p| (p.alpha, p.beta, p.L, p.sigma) == (r.alpha, r.beta, r.L, r.sigma))
        else {
            bail!(
                "{file}: a row at alpha = {}, beta = {}, L = {}, sigma = {} is not a point of sweep {:?}",
                r.alpha, r.beta, r.L, r.sigma, sweep.name
            );
        };
        if r.replicate >= sweep.replicates {
            bail!(
                "{file}: replicate {} is beyond the sweep's {} per point",
                r.replicate,
                sweep.replicates
            );
        }
        targets[i] = targets[i].max(r.replicate + 1);
    }
    let _lock = StoreLock::acquire(&args.db.db)?;
    let mut store = Store::open_or_create(&args.db.db)?;
    store.check_integrity()?;
    let reg = store.register(&plan_targets(&sweep, &file, &|i| targets[i]), false)?;
    let ledger = Ledger::load(&store, reg.sweep_id, SOLVER_VERSION)?;
    // The rows' preps, computed here so that each row's prep hash can be checked.
    let missing: Vec<_> = store
        .preps_of(reg.sweep_id, SOLVER_VERSION)?
        .into_iter()
        .filter(|p| p.state != JobState::Done)
        .collect();
    if !missing.is_empty() {
        eprintln!(
            "computing {} preps to check the rows against (each a whole free motion, about a minute or two on one core)",
            missing.len()
        );
    }
    let computed: Vec<(i64, u64, f64, anyhow::Result<PrepPayload>)> = missing
        .par_iter()
        .map(|p| {
            let start = std::time::Instant::now();
            let run = || -> anyhow::Result<PrepPayload> {
                let config: Config = serde_json::from_str(&p.config)?;
                let prep = prepare(&config.params, &config.protocol, p.seed, &mut Silent)?;
                Ok(PrepPayload::from_prep(&prep))
            };
            let payload = run();
            (p.id, p.seed, start.elapsed().as_secs_f64(), payload)
        })
        .collect();
    for (id, seed, took, payload) in computed {
        let payload = payload.with_context(|| format!("prep {id}"))?;
        // The prep's cost where the rows were made, if they say; else this recomputation's.
        let wall_s = rows
            .iter()
            .find(|r| r.prep_seed == seed)
            .and_then(|r| r.prep_wall_s)
            .filter(|w| w.is_finite() && *w > 0.0)
            .unwrap_or(took);
        if let Settlement::Refused(why) = ledger
            .settle_prep(&mut store, id, &payload, wall_s)?
            .settlement
        {
            bail!("{why}");
        }
    }
    let mut refused = Vec::new();
    let mut to_commit = Vec::new();
    let mut already = 0;
    for r in &rows {
        match ledger.check_row(&store, r)? {
            RowCheck::Commit(job) => to_commit.push((job, r)),
            RowCheck::Already => already += 1,
            RowCheck::Refused(why) => refused.push(why),
        }
    }
    if !refused.is_empty() {
        for why in refused.iter().take(10) {
            eprintln!("refused: {why}");
        }
        bail!(
            "{file}: {} of {} rows do not match the jobs they claim; nothing was imported",
            refused.len(),
            rows.len()
        );
    }
    let mut new = 0;
    for (job, r) in to_commit {
        if ledger.commit_row(&mut store, job, r)? == Settlement::New {
            new += 1;
        }
    }
    println!(
        "imported {new} results of {:?} from {file} ({already} already in the store) into {}",
        sweep.name,
        args.db.db.display()
    );
    Ok(())
}
