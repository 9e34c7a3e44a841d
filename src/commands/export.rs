//! `cellsweep export` and `cellsweep import`: the export file written from a store and read
//! into one (`cellsweep_scheduler::export_file`, `cellsweep_scheduler::import`).

use cellsweep_scheduler::import::{import as import_file, ImportError, ImportEvent};
use cellsweep_store::Store;

use crate::cli::{ExportArgs, ImportArgs};

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

/// `cellsweep import`: all of the file or nothing; a refused file's first problems one a line,
/// then one line that says nothing was imported.
pub fn import(args: ImportArgs) -> anyhow::Result<()> {
    let db = &args.db.db;
    let done = import_file(&args.file, db, &mut |event| match event {
        ImportEvent::Retuned { sweep } => println!(
            "note: sweep {sweep:?} in the store takes the file's replicates, [adaptive], \
             [refine] and [report] rules (its points and results are kept)"
        ),
        ImportEvent::ComputingPreps { count, estimate } => {
            let preps = if count == 1 { "prep" } else { "preps" };
            eprintln!("computing {count} {preps} to check the rows against ({estimate})");
        }
    });
    let imported = match done {
        Ok(i) => i,
        Err(e) => {
            if let ImportError::Refused { file, problems, .. } = &e {
                for why in problems.iter().take(10) {
                    eprintln!("refused: {file}: {why}");
                }
                if problems.len() > 10 {
                    eprintln!("refused: ... and {} more", problems.len() - 10);
                }
            }
            return Err(e.into());
        }
    };
    println!(
        "imported {} results of {:?} from {} ({} already in the store) into {}",
        imported.new,
        imported.sweep,
        args.file.display(),
        imported.already,
        db.display()
    );
    Ok(())
}
