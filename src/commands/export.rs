//! `cellsweep export`: a sweep's results written from a store as an export file
//! (`cellsweep_scheduler::export_file`; `cellsweep import` reads one back).

use cellsweep_store::Store;

use crate::cli::ExportArgs;

pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    let store = Store::open_read(&args.db.db)?;
    let name = store.choose_sweep(args.sweep.as_deref())?;
    let out = &args.out;
    let mut rows = 0;
    crate::output::replace_file(out, |file| {
        rows = cellsweep_scheduler::export_file::write_export(&store, &name, file)?;
        Ok(())
    })?;
    println!("wrote {rows} replicates of {name:?} to {}", out.display());
    Ok(())
}
