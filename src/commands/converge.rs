//! `cellsweep converge`: each column's beta* in variants of the numerics against a baseline
//! (`cellsweep_report::converge`).

use anyhow::Context;
use cellsweep_report::converge::{compare_variant, csv_rows, text_lines, CSV_HEADER};
use cellsweep_report::load;
use serde_json::json;

use crate::cli::{ConvergeArgs, Format};

pub fn run(args: ConvergeArgs) -> anyhow::Result<()> {
    let (base_sweep, base) = load::from_export_with_sweep(&args.baseline)
        .with_context(|| format!("cannot read the baseline {}", args.baseline.display()))?;
    let mut variants = Vec::new();
    if args.format == Format::Csv {
        println!("{CSV_HEADER}");
    }
    for path in &args.variants {
        let (sweep, var) = load::from_export_with_sweep(path)
            .with_context(|| format!("cannot read the variant {}", path.display()))?;
        let v = compare_variant(&base_sweep, &base, path, (&sweep, &var));
        let lines = match args.format {
            Format::Csv => csv_rows(&v),
            Format::Text => text_lines(&v, &base_sweep.name, &args.baseline),
            Format::Json => Vec::new(),
        };
        for line in lines {
            println!("{line}");
        }
        variants.push(v);
    }
    if args.format == Format::Json {
        let out = json!({
            "baseline": args.baseline.display().to_string(),
            "sweep": base_sweep.name,
            "variants": variants,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    }
    Ok(())
}
