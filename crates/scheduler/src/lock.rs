//! One writer per store at a time: an advisory lock on `<store>.lock`, beside the database.
//!
//! `run`, `submit`, `collect` and `import` hold it while they write; read commands never take
//! it, so `status`, `table` and `plot` work while a sweep runs. The operating system drops the
//! lock when its holder dies (even by SIGKILL), so the next writer can take it at once, and
//! work left `running` in the store then belongs to a dead holder: recovering it is safe. The
//! file names the holder (pid, host, start time) for the message a second writer gets.
//!
//! The lock belongs to the database file, not to the name it was reached by: it sits beside the
//! file's canonical path (symlinks, `./` and relative paths resolved), so two names of one file
//! take one lock. A file with several hard links has several canonical paths, and SQLite itself
//! would keep a different journal beside each name (its "how to corrupt" notes, multiple
//! links): a writer refuses such a store.
//!
//! The lock file lives only while it is held: its holder removes it as it lets go (still holding
//! it), so a finished run leaves no `.lock` behind. A writer that opened the file just before it
//! went would then lock a name no longer in the directory: having taken the lock, a writer checks
//! that the name still leads to the file it locked, and starts again where it does not.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

use thiserror::Error;

#[derive(Debug, Error)]
pub enum LockError {
    #[error(
        "{path} is held by another cellsweep writer ({holder}); wait for it to finish or stop it"
    )]
    Held { path: PathBuf, holder: String },
    #[error(
        "{path} has {links} hard links: two writers could reach it by different names (and \
         SQLite would keep a journal beside each); keep one name (a symlink is fine) and remove \
         the others"
    )]
    HardLinked { path: PathBuf, links: u64 },
    #[error("cannot lock {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// The held lock; dropping it removes the lock file and releases it.
#[derive(Debug)]
pub struct StoreLock {
    file: File,
    path: PathBuf,
}

impl Drop for StoreLock {
    fn drop(&mut self) {
        // Removed while still held (a writer waiting on this file finds, once it has the lock,
        // that the name no longer leads to it); the lock goes with the file's last descriptor.
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Whether `path` names the very file `file` has open.
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

impl StoreLock {
    /// The lock file of the store at `db`.
    pub fn path_of(db: &Path) -> PathBuf {
        let mut name = db.as_os_str().to_owned();
        name.push(".lock");
        PathBuf::from(name)
    }

    /// The one name of the database file at `db`: its canonical path (or, for a file still to
    /// be created, its canonical directory's). Refuses a file with several hard links.
    pub fn identity(db: &Path) -> Result<PathBuf, LockError> {
        use std::os::unix::fs::MetadataExt as _;
        if let Ok(meta) = std::fs::metadata(db) {
            if meta.is_file() && meta.nlink() > 1 {
                return Err(LockError::HardLinked {
                    path: db.to_path_buf(),
                    links: meta.nlink(),
                });
            }
            if let Ok(real) = db.canonicalize() {
                return Ok(real);
            }
        }
        let dir = match db.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        match (dir.canonicalize(), db.file_name()) {
            (Ok(dir), Some(name)) => Ok(dir.join(name)),
            // (No such directory: the store's own open says so.)
            _ => Ok(db.to_path_buf()),
        }
    }

    /// Take the lock of the store at `db` (by whatever name), or say who holds it.
    pub fn acquire(db: &Path) -> Result<StoreLock, LockError> {
        let path = Self::path_of(&Self::identity(db)?);
        let io = |source| LockError::Io {
            path: path.clone(),
            source,
        };
        // A holder removes the file as it lets go: a file locked after that is no longer the
        // one the name leads to, and the lock is taken again on the name's new file.
        let mut file = loop {
            let file = Self::lock_file(&path)?;
            if same_file(&file, &path) {
                break file;
            }
        };
        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .map(|h| h.trim().to_string())
            .unwrap_or_else(|_| "this host".into());
        let since = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        file.set_len(0).map_err(io)?;
        file.rewind().map_err(io)?;
        write!(
            file,
            "pid {} on {host}, since {since} (Unix seconds)",
            std::process::id()
        )
        .map_err(io)?;
        file.flush().map_err(io)?;
        Ok(StoreLock { file, path })
    }

    /// Open (or create) the lock file at `path` and lock it, or say who holds it.
    fn lock_file(path: &Path) -> Result<File, LockError> {
        let io = |source| LockError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(io)?;
        // A reader's probe ([`StoreLock::is_held`]) holds a shared lock for a moment: a few
        // short waits ride it out; a writer holds it for good.
        let mut tries = 0;
        let taken = loop {
            match file.try_lock() {
                Err(TryLockError::WouldBlock) if tries < 5 => {
                    tries += 1;
                    std::thread::sleep(std::time::Duration::from_millis(20));
                }
                other => break other,
            }
        };
        match taken {
            Ok(()) => Ok(file),
            Err(TryLockError::WouldBlock) => {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                let holder = holder.trim();
                Err(LockError::Held {
                    path: path.to_path_buf(),
                    holder: if holder.is_empty() {
                        "unknown holder".into()
                    } else {
                        holder.to_string()
                    },
                })
            }
            Err(TryLockError::Error(e)) => Err(io(e)),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether a writer holds the store at `db` now (a run, a submit watching, a collect, an
    /// import). Jobs marked `running` in a store no writer holds were left by a run that died;
    /// the next run recovers them. Probes with a shared lock for a moment, never creating the
    /// lock file; false where there is none.
    pub fn is_held(db: &Path) -> bool {
        let Ok(id) = Self::identity(db) else {
            return false;
        };
        let Ok(file) = File::open(Self::path_of(&id)) else {
            return false;
        };
        match file.try_lock_shared() {
            Ok(()) => {
                let _ = file.unlock();
                false
            }
            Err(TryLockError::WouldBlock) => true,
            Err(TryLockError::Error(_)) => false,
        }
    }
}
