//! `cellsweep export`: one CSV row per finished replicate (format in the first line).

use anyhow::{bail, Context};
use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_store::export::EXPORT_FORMAT;
use cellsweep_store::Store;

use crate::cli::ExportArgs;

pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    let store = Store::open(&args.db.db)?;
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
    let tmp = out.with_extension("csv.tmp");
    let write = || -> anyhow::Result<()> {
        let mut file = std::fs::File::create(&tmp)?;
        use std::io::Write as _;
        writeln!(
            file,
            "# cellsweep export format {EXPORT_FORMAT}; sweep {name:?}; {SOLVER_VERSION}"
        )?;
        let mut w = csv::Writer::from_writer(file);
        for r in &rows {
            w.serialize(r)?;
        }
        w.flush()?;
        Ok(())
    };
    write().with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, out).with_context(|| format!("cannot write {}", out.display()))?;
    println!(
        "wrote {} replicates of {name:?} to {}",
        rows.len(),
        out.display()
    );
    Ok(())
}
