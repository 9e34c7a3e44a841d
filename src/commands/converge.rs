//! `cellsweep converge`: each column's beta* in variants of the numerics against a baseline.

use anyhow::Context;
use cellsweep_report::load;
use cellsweep_stats::{compare_columns, ColumnChange, Side};
use serde_json::json;

use crate::cli::{ConvergeArgs, Format};

/// "18.21 [17.60, 18.83]", or why there is no crossing.
fn side_text(s: &Side) -> String {
    match (s.beta_star, s.ci) {
        (Some(b), Some([lo, hi])) => format!("{b:.2} [{lo:.2}, {hi:.2}]"),
        _ => "none".to_string(),
    }
}

fn difference_text(c: &ColumnChange) -> String {
    match (c.difference, c.difference_ci) {
        (Some(d), Some([lo, hi])) => format!("{d:+.2} [{lo:+.2}, {hi:+.2}]"),
        _ => "-".to_string(),
    }
}

pub fn run(args: ConvergeArgs) -> anyhow::Result<()> {
    let (base_sweep, base) = load::from_export_with_sweep(&args.baseline)
        .with_context(|| format!("cannot read the baseline {}", args.baseline.display()))?;
    let mut json_out = Vec::new();
    if args.format == Format::Csv {
        println!("variant,changes,L,sigma,alpha,beta_star_baseline,baseline_lo,baseline_hi,collisions_baseline,beta_star_variant,variant_lo,variant_hi,collisions_variant,difference,difference_lo,difference_hi,verdict");
    }
    for path in &args.variants {
        let (sweep, var) = load::from_export_with_sweep(path)
            .with_context(|| format!("cannot read the variant {}", path.display()))?;
        let changes: Vec<String> = base_sweep
            .differences(&sweep)
            .into_iter()
            .map(|(k, a, b)| format!("{k} {a} -> {b}"))
            .collect();
        let changes = if changes.is_empty() {
            "nothing in how a trajectory is computed (another seed or grid only)".to_string()
        } else {
            changes.join(", ")
        };
        let cols = compare_columns(&base.counts, &base.scales, &var.counts, &var.scales);
        match args.format {
            Format::Json => json_out.push(json!({
                "variant": path.display().to_string(),
                "sweep": sweep.name,
                "changes": changes,
                "columns": cols,
            })),
            Format::Csv => {
                let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
                for c in &cols {
                    let (bl, bh) = (c.baseline.ci.map(|x| x[0]), c.baseline.ci.map(|x| x[1]));
                    let (vl, vh) = (c.variant.ci.map(|x| x[0]), c.variant.ci.map(|x| x[1]));
                    let (dl, dh) = (c.difference_ci.map(|x| x[0]), c.difference_ci.map(|x| x[1]));
                    println!(
                        "{},\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                        sweep.name,
                        changes.replace('"', "\"\""),
                        c.L,
                        c.sigma,
                        c.alpha,
                        opt(c.baseline.beta_star),
                        opt(bl),
                        opt(bh),
                        c.baseline.collisions,
                        opt(c.variant.beta_star),
                        opt(vl),
                        opt(vh),
                        c.variant.collisions,
                        opt(c.difference),
                        opt(dl),
                        opt(dh),
                        c.verdict.as_str()
                    );
                }
            }
            Format::Text => {
                println!(
                    "{} against {} ({}): {changes}",
                    sweep.name,
                    base_sweep.name,
                    args.baseline.display()
                );
                if cols.is_empty() {
                    println!("  no column in common with the baseline");
                }
                for c in &cols {
                    println!(
                        "  L = {:>3}  sigma = {:>3}  alpha = {:<5}  baseline {:<22} ({:>5} coll.)  variant {:<22} ({:>5} coll.)  difference {:<22} {}",
                        c.L,
                        c.sigma,
                        c.alpha,
                        side_text(&c.baseline),
                        c.baseline.collisions,
                        side_text(&c.variant),
                        c.variant.collisions,
                        difference_text(c),
                        c.verdict.as_str()
                    );
                    if let Some(why) = c.variant.skipped.as_ref().or(c.baseline.skipped.as_ref()) {
                        println!("      open: {why}");
                    }
                }
            }
        }
    }
    if args.format == Format::Json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "baseline": args.baseline.display().to_string(),
                "sweep": base_sweep.name,
                "variants": json_out,
            }))?
        );
    }
    Ok(())
}
