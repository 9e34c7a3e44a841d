//! `cellsweep reset`: put chosen points of a sweep back to pending (their results deleted), so
//! that the next run computes them again with the same seeds (`scheduler::reset`).

use cellsweep_scheduler::reset::{reset, ResetKind, ResetRequest};

use crate::cli::ResetArgs;

pub fn run(args: ResetArgs) -> anyhow::Result<()> {
    let done = reset(&ResetRequest {
        db: &args.db.db,
        sweep: args.sweep.as_deref(),
        points: &args.point,
        points_file: args.points.as_deref(),
        kind: match args.breakups {
            true => ResetKind::Breakups,
            false => ResetKind::Jobs,
        },
        dry_run: args.dry_run,
    })?;
    println!("{done}");
    Ok(())
}
