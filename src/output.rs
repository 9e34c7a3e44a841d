//! Writing a whole output file or nothing: into a temporary file beside it, then renamed over
//! it, so that a kill or a full disk never leaves half a file under the name asked for.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};

/// Write `out` with `fill`: all of it, or (on any error) nothing, the temporary file removed.
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
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp-{}", std::process::id()));
    let tmp: PathBuf = out.with_file_name(name);
    let result = (|| -> anyhow::Result<()> {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        w.flush()?;
        w.get_ref().sync_all()?;
        std::fs::rename(&tmp, out)?;
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", out.display()))
}
