//! Where a refined sweep's columns stand, as the lines `status` and `run --dry-run` print.

use cellsweep_scheduler::ledger::ColumnStanding;
use cellsweep_stats::{ColumnNeed, RefineRule};

/// The widest columns named, at most.
const WIDEST_SHOWN: usize = 3;

/// What the columns' next round adds: its values and the columns they go to.
pub struct NextRound {
    pub values: usize,
    pub columns: usize,
    /// Per column: `alpha = 0.1, L = 70, sigma = 0: beta 29.5, 29.625`.
    pub list: Vec<String>,
}

/// The columns' standing: values added, columns narrow enough, refining, at their budget or
/// out of lattice, the widest, and the next round. Each line starts with `indent`.
pub fn lines(
    columns: &[ColumnStanding],
    rule: &RefineRule,
    indent: &str,
) -> (Vec<String>, NextRound) {
    let added: u32 = columns.iter().map(|c| c.added).sum();
    // A column whose points still run is counted as such: its need is only what it would be
    // now (a value just added is held but has no collision yet).
    let count = |f: &dyn Fn(&ColumnNeed) -> bool| {
        columns
            .iter()
            .filter(|c| !c.busy && f(&c.round.need))
            .count()
    };
    let narrow = count(&|n| matches!(n, ColumnNeed::Narrow { .. }));
    let adding = count(&|n| matches!(n, ColumnNeed::Add(_)));
    let budget = count(&|n| matches!(n, ColumnNeed::Budget { .. }));
    let lattice = count(&|n| matches!(n, ColumnNeed::Lattice { .. }));
    let none = count(&|n| matches!(n, ColumnNeed::NoCrossing(_)));
    let running = columns.iter().filter(|c| c.busy).count();
    let mut out = vec![format!(
        "{added} beta values added (width {}, step {}, at most {} per column); of {} columns: \
         {running} with points running; {narrow} narrow enough, {adding} to refine, {budget} at \
         their budget, {lattice} out of lattice, {none} without a crossing",
        rule.width,
        rule.step,
        rule.max_new_per_column,
        columns.len()
    )];
    let mut wide: Vec<(f64, &ColumnStanding)> = columns
        .iter()
        .filter_map(|c| c.round.width.map(|w| (w, c)))
        .filter(|(w, _)| *w > rule.width)
        .collect();
    wide.sort_by(|a, b| b.0.total_cmp(&a.0));
    if !wide.is_empty() {
        let named: Vec<String> = wide
            .iter()
            .take(WIDEST_SHOWN)
            .map(|(w, c)| format!("{w:.2} at {}", column_name(c)))
            .collect();
        let more = wide.len().saturating_sub(WIDEST_SHOWN);
        out.push(format!(
            "{indent}wider than {}: {}{}",
            rule.width,
            named.join("; "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        ));
    }
    let ready: Vec<&ColumnStanding> = columns
        .iter()
        .filter(|c| !c.busy && matches!(c.round.need, ColumnNeed::Add(_)))
        .collect();
    let next = NextRound {
        values: ready
            .iter()
            .map(|c| match &c.round.need {
                ColumnNeed::Add(v) => v.len(),
                _ => 0,
            })
            .sum(),
        columns: ready.len(),
        list: ready
            .iter()
            .filter_map(|c| match &c.round.need {
                ColumnNeed::Add(v) => Some(format!(
                    "{}: beta {}",
                    column_name(c),
                    v.iter().map(f64::to_string).collect::<Vec<_>>().join(", ")
                )),
                _ => None,
            })
            .collect(),
    };
    out.push(format!(
        "{indent}next round: {} values in {} columns now{}",
        next.values,
        next.columns,
        if running > 0 {
            format!("; {running} columns wait for their points to finish first")
        } else {
            String::new()
        }
    ));
    (out, next)
}

/// `alpha = 0.18, L = 90, sigma = 5` and any other axis.
fn column_name(c: &ColumnStanding) -> String {
    let r = &c.round;
    let mut s = format!("alpha = {}, L = {}, sigma = {}", r.alpha, r.L, r.sigma);
    if !r.others.is_empty() {
        s += &format!(", {}", r.others);
    }
    s
}
