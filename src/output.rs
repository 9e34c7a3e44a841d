//! Writing a whole output file or nothing: into a temporary file beside it, then renamed over
//! it, so that a kill or a full disk never leaves half a file under the name asked for.

use std::path::Path;

use anyhow::{bail, Context};

/// Write `out` with `fill`: all of it, or (on any error) nothing, the temporary file removed
/// ([`cellsweep_report::whole_file::replace_file`]).
pub fn replace_file(
    out: &Path,
    fill: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    if out.is_dir() {
        bail!(
            "{} is a folder; --out names the file to write",
            out.display()
        );
    }
    // The filler's own error (a CSV writer's, say) is carried through the io::Error and back.
    let mut failed = None;
    let result = cellsweep_report::whole_file::replace_file(out, |w| {
        fill(w).map_err(|e| {
            let io = std::io::Error::other(e.to_string());
            failed = Some(e);
            io
        })
    });
    match (result, failed) {
        (Ok(()), _) => Ok(()),
        (Err(_), Some(e)) => Err(e),
        (Err(e), None) => Err(e.into()),
    }
    .with_context(|| format!("cannot write {}", out.display()))
}
