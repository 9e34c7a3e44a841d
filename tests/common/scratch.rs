//! A test's scratch space under the system's temporary directory, removed when the test is done
//! with it, so that the tests leave nothing behind; kept, and named on stderr, when the test
//! fails, for a look. Shared by the store crate's tests too (by path).

use std::path::{Path, PathBuf};

/// A scratch directory (or a file path inside a fresh one); derefs to that path and removes the
/// directory when dropped.
#[derive(Debug)]
pub struct Scratch {
    dir: PathBuf,
    path: PathBuf,
}

impl Scratch {
    /// A fresh, empty `cellsweep-{prefix}-{pid}-{name}` directory.
    pub fn dir(prefix: &str, name: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("cellsweep-{prefix}-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Scratch {
            path: dir.clone(),
            dir,
        }
    }

    /// The path `file` inside a fresh scratch directory (e.g. a store not yet created).
    pub fn file(prefix: &str, name: &str, file: &str) -> Scratch {
        let mut s = Scratch::dir(prefix, name);
        s.path = s.dir.join(file);
        s
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept {} (the test failed)", self.dir.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}
