//! `cellsweep compare`: two result sets side by side (`cellsweep_report::compare`).

use anyhow::bail;
use cellsweep_report::compare::{csv, load_side, text, CompareSide};
use cellsweep_stats::compare;
use serde_json::json;

use crate::cli::{CompareArgs, Format};

pub fn run(args: CompareArgs) -> anyhow::Result<()> {
    let a = load_side(&args.db.db, &args.a, args.version_a.as_deref())?;
    let db_b = args.db_b.as_deref().unwrap_or(&args.db.db);
    let b = load_side(db_b, &args.b, args.version_b.as_deref())?;
    if a.name == b.name && a.version == b.version && a.db == b.db {
        bail!(
            "A and B are the same results ({} under {}); name two sweeps, or two solver versions \
             with --version-a / --version-b",
            a.name,
            a.version
        );
    }
    let c = compare(&a.replicates, &b.replicates);
    if c.points.is_empty() {
        bail!(
            "{} and {} have no grid point in common (points match by alpha, beta, L and sigma)",
            a.name,
            b.name
        );
    }
    match args.format {
        Format::Text => print!("{}", text(&a, &b, &c)),
        Format::Csv => print!("{}", csv(&c)),
        Format::Json => {
            let side = |s: &CompareSide| {
                json!({"sweep": s.name, "solver_version": s.version, "db": s.db,
                       "replicates": s.replicates.len()})
            };
            let mut v = serde_json::to_value(&c)?;
            v["a"] = side(&a);
            v["b"] = side(&b);
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
    }
    Ok(())
}
