//! One read connection to the store that gathers a new [`Snapshot`] only when something
//! changed: SQLite's `data_version` moves when another connection commits, so an idle sweep
//! costs one pragma per poll, and a busy one one gathering per `min_interval`.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use cellsweep_store::Store;

use crate::page;
use crate::snapshot::Snapshot;

/// Gather again after this long even when nothing was written: the ETA and Slurm's queue
/// move on their own.
const REFRESH_ANYWAY: Duration = Duration::from_secs(15);

/// What the page shows now, rendered once for every client that asks.
#[derive(Debug)]
pub struct Live {
    /// Grows by one each time the rendered page changes.
    pub generation: u64,
    pub finished: bool,
    /// The live part of the page (HTML).
    pub html: String,
    /// The snapshot as JSON (`/api/status`).
    pub json: String,
}

/// The store at `path`, opened read-only when it exists, and the latest [`Live`] view of it.
pub struct Watcher {
    path: PathBuf,
    store: Option<Store>,
    /// The file the store was opened from (device, inode): a store replaced at the path (its
    /// files removed, another sweep run into it) is a new file, opened anew.
    opened: Option<(u64, u64)>,
    seen_version: Option<i64>,
    gathered: Option<Instant>,
    min_interval: Duration,
    live: Arc<Live>,
}

impl Watcher {
    /// A watcher of `path` that gathers at most once per `min_interval`.
    pub fn new(path: PathBuf, min_interval: Duration) -> Watcher {
        Watcher {
            path,
            store: None,
            opened: None,
            seen_version: None,
            gathered: None,
            min_interval,
            live: Arc::new(Live {
                generation: 0,
                finished: false,
                html: String::new(),
                json: "{}".to_string(),
            }),
        }
    }

    /// The view now: the last one, or a new one when the store changed (or is new).
    pub fn current(&mut self) -> Arc<Live> {
        let due = self
            .gathered
            .is_none_or(|t| t.elapsed() >= self.min_interval);
        if !due {
            return self.live.clone();
        }
        let snapshot = self.look();
        if let Some(s) = snapshot {
            self.gathered = Some(Instant::now());
            let html = page::live_fragment(&s);
            if html != self.live.html || self.live.generation == 0 {
                self.live = Arc::new(Live {
                    generation: self.live.generation + 1,
                    finished: s.finished(),
                    json: serde_json::to_string(&s).unwrap_or_else(|_| "{}".into()),
                    html,
                });
            }
        }
        self.live.clone()
    }

    /// A new snapshot if the store changed since the last, else None.
    fn look(&mut self) -> Option<Snapshot> {
        let now = file_id(&self.path);
        if self.store.is_some() && now != self.opened {
            self.store = None;
            self.seen_version = None;
        }
        if self.store.is_none() {
            if !self.path.is_file() {
                return Some(Snapshot::empty(
                    &self.path,
                    format!("no store at {} (yet)", self.path.display()),
                ));
            }
            match Store::open_read(&self.path) {
                Ok(s) => {
                    self.store = Some(s);
                    self.opened = now;
                }
                Err(e) => return Some(Snapshot::empty(&self.path, e.to_string())),
            }
        }
        let store = self.store.as_ref()?;
        let version = store.data_version().ok();
        let stale = self.gathered.is_none_or(|t| t.elapsed() >= REFRESH_ANYWAY);
        if version.is_some() && version == self.seen_version && !stale {
            return None;
        }
        self.seen_version = version;
        match Snapshot::gather(store, &self.path) {
            Ok(s) => Some(s),
            Err(e) => {
                // A store that cannot be read now (replaced, or mid-migration): open it anew
                // next time, and say why meanwhile.
                self.store = None;
                Some(Snapshot::empty(&self.path, e.to_string()))
            }
        }
    }
}

/// The (device, inode) of the file at `path`, None where there is none.
fn file_id(path: &std::path::Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt as _;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}
