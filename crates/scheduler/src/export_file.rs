//! The export file (`cellsweep export`): written from a store by [`write_export`], read back
//! by [`read_export`] for `import` and for every reader of results
//! (`cellsweep_report::Results::from_export`). Its first line names the format, the sweep and
//! the solver, its second holds the sweep's definition, then one CSV row per finished
//! replicate ([`ExportRow`]).

use std::path::Path;

use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_store::export::{ExportRow, EXPORT_FORMAT, READ_FORMATS};
use cellsweep_store::{Store, StoreError};

use crate::sweep::Sweep;

/// What is wrong with an export file, naming the file and the line or row.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ExportFileError(pub String);

/// Why an export could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ExportWriteError {
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error(transparent)]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Csv(#[from] csv::Error),
    #[error(transparent)]
    Json(#[from] serde_json::Error),
}

/// Write sweep `name`'s export from `store` to `out`: the format line, the sweep's definition
/// (so that `import` can register it anywhere), one row per finished replicate. Returns the
/// rows written.
pub fn write_export(
    store: &Store,
    name: &str,
    out: &mut dyn std::io::Write,
) -> Result<usize, ExportWriteError> {
    let id = store.sweep_id(name)?;
    let defaults = serde_json::to_value(Params::default())?;
    let rows = store.export_rows(id, SOLVER_VERSION, &defaults)?;
    writeln!(
        out,
        "# cellsweep export format {EXPORT_FORMAT}; sweep {name:?}; {SOLVER_VERSION}"
    )?;
    writeln!(out, "# spec {}", store.sweep_spec(id)?)?;
    let mut w = csv::Writer::from_writer(out);
    for r in &rows {
        w.serialize(r)?;
    }
    w.flush()?;
    Ok(rows.len())
}

/// An export file read back: its sweep's definition (line 2, checked: name and every point's
/// model) and its rows. Each problem names the file and the line or row.
pub fn read_export(path: &Path) -> Result<(Sweep, Vec<ExportRow>), ExportFileError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| ExportFileError(format!("cannot read {file}: {e}")))?;
    let mut lines = text.lines();
    let head = lines.next().unwrap_or("");
    let format = head
        .strip_prefix("# cellsweep export format ")
        .and_then(|rest| rest.split(';').next())
        .and_then(|v| v.parse::<u32>().ok());
    match format {
        Some(f) if READ_FORMATS.contains(&f) => {}
        Some(f) => {
            return Err(ExportFileError(format!(
                "{file}: line 1: export format {f}, and this build reads formats {READ_FORMATS:?} \
             (a newer cellsweep wrote it?)"
            )))
        }
        None => {
            return Err(ExportFileError(format!(
                "{file}: line 1: not a cellsweep export (expected \"# cellsweep export format \
             {EXPORT_FORMAT}; ...\")"
            )))
        }
    }
    let spec = lines
        .next()
        .and_then(|l| l.strip_prefix("# spec "))
        .ok_or_else(|| {
            ExportFileError(format!(
                "{file}: line 2: missing the sweep's definition (# spec ...)"
            ))
        })?;
    let sweep: Sweep = serde_json::from_str(spec)
        .map_err(|e| ExportFileError(format!("{file}: line 2: malformed sweep definition: {e}")))?;
    crate::sweep::check_name(&sweep.name)
        .map_err(|e| ExportFileError(format!("{file}: line 2: name: {e}")))?;
    for p in sweep.points() {
        sweep
            .protocol
            .validate(&p)
            .map_err(|e| ExportFileError(format!("{file}: line 2: sweep definition: {e}")))?;
    }
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut rows: Vec<ExportRow> = Vec::new();
    for (i, r) in reader.deserialize().enumerate() {
        rows.push(r.map_err(|e| ExportFileError(format!("{file}: row {}: {e}", i + 1)))?);
    }
    Ok((sweep, rows))
}
