//! Writing a whole output file or nothing: into a temporary file beside it, then renamed over
//! it, so that a kill or a full disk never leaves half a file (or an empty one) under the name
//! asked for. Every picture and page the project writes goes through [`replace_file`].

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Write `out` with `fill`: all of it, or (on any error) nothing, the temporary file removed.
pub fn replace_file(
    out: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp-{}", std::process::id()));
    let tmp: PathBuf = out.with_file_name(name);
    let result = (|| {
        let mut w = BufWriter::new(File::create(&tmp)?);
        fill(&mut w)?;
        w.flush()?;
        w.get_ref().sync_all()?;
        std::fs::rename(&tmp, out)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// [`replace_file`] with the bytes `data`.
pub fn write_whole(out: &Path, data: &[u8]) -> std::io::Result<()> {
    replace_file(out, |w| w.write_all(data))
}
