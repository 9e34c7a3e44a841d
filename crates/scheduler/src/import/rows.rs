//! An export file's rows read against its sweep before anything is opened: each row's fields,
//! its point, its replicate, and two rows of one job that disagree.

use std::collections::HashMap;

use cellsweep_solver::Params;
use cellsweep_stats::Axes;
use cellsweep_store::export::ExportRow;

use super::ImportError;
use crate::Sweep;

/// Every row's field check and point, the sweep's points (its grid's, then any its refinement
/// added), and the replicates to register per point (at least its first round). Rows of an
/// archived sweep (`NAME@ID`, a sweep set aside by `run --replace`) are the rows of the sweep
/// its definition names. Two rows of one job must agree.
pub(super) fn targets(
    file: &str,
    sweep: &Sweep,
    rows: &mut [ExportRow],
) -> Result<(Vec<Params>, Vec<u32>), ImportError> {
    for r in rows.iter_mut() {
        if let Some((name, id)) = r.sweep.rsplit_once('@') {
            if name == sweep.name && !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()) {
                r.sweep = sweep.name.clone();
            }
        }
    }
    // The grid's points, then those a refinement added (refused if this sweep could not have).
    let axes: Vec<Axes> = rows
        .iter()
        .map(|r| sweep.axes_of_row(r))
        .collect::<Result<_, _>>()
        .map_err(|why| ImportError::invalid(file, why))?;
    let points = sweep
        .points_with(axes.iter().cloned())
        .map_err(|why| ImportError::invalid(file, why))?;
    let index: HashMap<_, usize> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (sweep.axes_of(p).key(), i))
        .collect();
    let mut targets = vec![sweep.initial_replicates(); points.len()];
    let mut problems = Vec::new();
    let mut first_of: HashMap<(usize, u32), usize> = HashMap::new();
    for (n, r) in rows.iter().enumerate() {
        let at = format!("row {}", n + 1);
        for p in r.field_problems() {
            problems.push(format!("{at}: {p}"));
        }
        // (points_with holds every row's point.)
        let Some(&i) = index.get(&axes[n].key()) else {
            return Err(ImportError::invalid(
                file,
                format!("{at}: {} is not a point of sweep {:?}", axes[n], sweep.name),
            ));
        };
        if r.replicate >= sweep.replicates {
            return Err(ImportError::invalid(
                file,
                format!(
                    "{at}: replicate {} is beyond the sweep's {} per point",
                    r.replicate, sweep.replicates
                ),
            ));
        }
        targets[i] = targets[i].max(r.replicate + 1);
        match first_of.get(&(i, r.replicate)) {
            Some(&first) => problems.extend(conflicts(
                &format!("{at} and row {} (the same job)", first + 1),
                r,
                &rows[first],
            )),
            None => {
                first_of.insert((i, r.replicate), n);
            }
        }
    }
    refuse(file, rows.len(), problems)?;
    Ok((points, targets))
}

/// Each result field in which `row` and `other` (of one job) differ, as a line naming the
/// replicate, the field and both values.
pub(super) fn conflicts(what: &str, row: &ExportRow, other: &ExportRow) -> Vec<String> {
    let at = format!(
        "alpha = {}, beta = {}, L = {}, sigma = {}, replicate {}",
        row.alpha, row.beta, row.L, row.sigma, row.replicate
    );
    row.result_differences(other)
        .into_iter()
        .map(|(field, a, b)| format!("{what}, {at}: {field} is {a:?} here and {b:?} there"))
        .collect()
}

/// Refuse the file if anything is wrong with it, with every problem.
pub(super) fn refuse(file: &str, rows: usize, problems: Vec<String>) -> Result<(), ImportError> {
    if problems.is_empty() {
        return Ok(());
    }
    Err(ImportError::Refused {
        file: file.to_string(),
        rows,
        problems,
    })
}
