//! A Slurm run directory belongs to one sweep: `sweep.uid` in it names the sweep's uid (kept in
//! the store), so that a stale directory of another sweep (an earlier store, a renamed sweep)
//! is never submitted into or collected from.

use std::path::Path;

use crate::error::SlurmError;

/// An I/O error on a file of the run directory, naming it.
pub(crate) fn io(e: std::io::Error, what: &Path) -> SlurmError {
    SlurmError::Io {
        path: what.display().to_string(),
        source: e,
    }
}

/// Write a file of the run directory whole or not at all (a temporary file, then a rename).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SlurmError> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, bytes).map_err(|e| io(e, &tmp))?;
    std::fs::rename(&tmp, path).map_err(|e| io(e, path))
}

/// The file in a run directory that names the sweep whose files it holds.
const STAMP: &str = "sweep.uid";

/// Check that `run_dir` belongs to the sweep with `uid`: its stamp names it, or the directory
/// is new or empty (then it is stamped, unless `dry_run`). A directory of another sweep (a
/// stale one from an earlier store, say) is refused before anything is read or written.
pub fn claim_run_dir(run_dir: &Path, uid: &str, dry_run: bool) -> Result<(), SlurmError> {
    let stamp = run_dir.join(STAMP);
    match std::fs::read_to_string(&stamp) {
        Ok(found) if found.trim() == uid => Ok(()),
        Ok(found) => Err(SlurmError::Refused(format!(
            "{} holds the files of another sweep (uid {}, this one is {uid}); choose another \
             --run-dir or remove that directory",
            run_dir.display(),
            found.trim()
        ))),
        Err(_) => {
            let empty = std::fs::read_dir(run_dir).map_or(true, |mut d| d.next().is_none());
            if !empty {
                return Err(SlurmError::Refused(format!(
                    "{} is not empty and has no {STAMP}: it is not this sweep's run directory; \
                     choose another --run-dir",
                    run_dir.display()
                )));
            }
            if !dry_run {
                std::fs::create_dir_all(run_dir).map_err(|e| io(e, run_dir))?;
                write_atomic(&stamp, format!("{uid}\n").as_bytes())?;
            }
            Ok(())
        }
    }
}

/// Whether `run_dir` is stamped with `uid` (what `collect` reads only then).
pub fn run_dir_is(run_dir: &Path, uid: &str) -> Result<(), SlurmError> {
    match std::fs::read_to_string(run_dir.join(STAMP)) {
        Ok(found) if found.trim() == uid => Ok(()),
        Ok(found) => Err(SlurmError::Refused(format!(
            "{} holds the files of another sweep (uid {}, this one is {uid}); not read",
            run_dir.display(),
            found.trim()
        ))),
        Err(_) => Err(SlurmError::Refused(format!(
            "{} has no {STAMP} naming this sweep; not read",
            run_dir.display()
        ))),
    }
}
