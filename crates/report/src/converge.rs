//! `cellsweep converge`: each column's beta* in a variant of the numerics against a baseline
//! ([`cellsweep_stats::compare_columns`]), with what the variant changes, rendered as text, CSV
//! and JSON.

use std::path::Path;

use cellsweep_scheduler::Sweep;
use cellsweep_stats::{compare_columns, ColumnChange, Side};
use serde::Serialize;

use crate::Results;

/// One variant's columns against the baseline's.
#[derive(Debug, Clone, Serialize)]
pub struct VariantComparison {
    /// The variant's export.
    pub variant: String,
    /// The variant's sweep.
    pub sweep: String,
    /// What the variant changes in how a trajectory is computed, in words.
    pub changes: String,
    pub columns: Vec<ColumnChange>,
}

/// The variant `(sweep, results)` read from `path`, against the baseline.
pub fn compare_variant(
    base_sweep: &Sweep,
    base: &Results,
    path: &Path,
    (sweep, variant): (&Sweep, &Results),
) -> VariantComparison {
    let changes: Vec<String> = base_sweep
        .differences(sweep)
        .into_iter()
        .map(|(k, a, b)| format!("{k} {a} -> {b}"))
        .collect();
    let changes = match changes.is_empty() {
        true => "nothing in how a trajectory is computed (another seed or grid only)".to_string(),
        false => changes.join(", "),
    };
    VariantComparison {
        variant: path.display().to_string(),
        sweep: sweep.name.clone(),
        changes,
        columns: compare_columns(&base.counts, &base.scales, &variant.counts, &variant.scales),
    }
}

/// The CSV header of [`csv_rows`].
pub const CSV_HEADER: &str = "variant,changes,L,sigma,alpha,beta_star_baseline,baseline_lo,baseline_hi,collisions_baseline,beta_star_variant,variant_lo,variant_hi,collisions_variant,difference,difference_lo,difference_hi,verdict";

/// One CSV row per column.
pub fn csv_rows(v: &VariantComparison) -> Vec<String> {
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x}"));
    let ends = |ci: Option<[f64; 2]>| (opt(ci.map(|x| x[0])), opt(ci.map(|x| x[1])));
    v.columns
        .iter()
        .map(|c| {
            let (bl, bh) = ends(c.baseline.ci);
            let (vl, vh) = ends(c.variant.ci);
            let (dl, dh) = ends(c.difference_ci);
            format!(
                "{},\"{}\",{},{},{},{},{bl},{bh},{},{},{vl},{vh},{},{},{dl},{dh},{}",
                v.sweep,
                v.changes.replace('"', "\"\""),
                c.L,
                c.sigma,
                c.alpha,
                opt(c.baseline.beta_star),
                c.baseline.collisions,
                opt(c.variant.beta_star),
                c.variant.collisions,
                opt(c.difference),
                c.verdict.as_str()
            )
        })
        .collect()
}

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

/// The variant against the baseline `base` (read from `baseline`), a line per column.
pub fn text_lines(v: &VariantComparison, base: &str, baseline: &Path) -> Vec<String> {
    let mut out = vec![format!(
        "{} against {base} ({}): {}",
        v.sweep,
        baseline.display(),
        v.changes
    )];
    if v.columns.is_empty() {
        out.push("  no column in common with the baseline".to_string());
    }
    for c in &v.columns {
        out.push(format!(
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
        ));
        if let Some(why) = c.variant.skipped.as_ref().or(c.baseline.skipped.as_ref()) {
            out.push(format!("      open: {why}"));
        }
    }
    out
}
