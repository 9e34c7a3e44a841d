//! Room to put work back: a small file of reserved space beside the store, held while a run
//! writes and given up only when a write has failed (a full disk), so that the jobs in flight
//! can still go back to pending before the run exits. A run that starts on a disk too full to
//! reserve anything goes on without it.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Bytes held back: room for the few WAL frames that putting jobs back to pending writes.
const RESERVED: usize = 1 << 20;

/// The reserved space of one run; removed when dropped.
pub struct Reserve {
    path: Option<PathBuf>,
}

impl Reserve {
    /// Reserve room beside the store at `db` (`<db>.reserve`), if the disk has it.
    pub fn beside(db: &Path) -> Reserve {
        let mut name = db.as_os_str().to_owned();
        name.push(".reserve");
        let path = PathBuf::from(name);
        // Real bytes, synced: space a filesystem has handed out (a sparse file would not be).
        let made = std::fs::File::create(&path).and_then(|mut f| {
            f.write_all(&vec![0x5a; RESERVED])?;
            f.sync_all()
        });
        match made {
            Ok(()) => Reserve { path: Some(path) },
            Err(_) => {
                let _ = std::fs::remove_file(&path);
                Reserve { path: None }
            }
        }
    }

    /// Give the room back to the disk (after a write failed); true if there was any.
    pub fn release(&mut self) -> bool {
        match self.path.take() {
            Some(p) => std::fs::remove_file(p).is_ok(),
            None => false,
        }
    }
}

impl Drop for Reserve {
    fn drop(&mut self) {
        self.release();
    }
}
