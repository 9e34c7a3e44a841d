//! `cellsweep import`: an export file brought into a store through the ledger
//! (`cellsweep_scheduler::import`), all of it or nothing.

use cellsweep_scheduler::import::{import as import_file, ImportError, ImportEvent};

use crate::cli::ImportArgs;

/// `cellsweep import`: all of the file or nothing; a refused file's first problems one a line,
/// then one line that says nothing was imported.
pub fn run(args: ImportArgs) -> anyhow::Result<()> {
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
