//! `cellsweep status`: progress of every sweep in the store (works while a sweep runs), as
//! `cellsweep_report::status` gathers it for the live page too.

use cellsweep_report::status::{gather, text};
use cellsweep_store::Store;

use crate::cli::StatusArgs;

pub fn run(args: StatusArgs) -> anyhow::Result<()> {
    let db = &args.db.db;
    let store = Store::open_read(db)?;
    let views = gather(&store, db, 0)?;
    if args.json {
        let rows = views
            .iter()
            .map(|v| text::json(v, args.failed))
            .collect::<Result<Vec<_>, _>>()?;
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    if views.is_empty() {
        println!("no sweeps in {}", db.display());
    }
    for v in &views {
        print!("{}", text::lines(v, args.failed));
    }
    Ok(())
}
