//! Opening a store: creating, identifying, migrating and checking the file, and naming its
//! sweeps.

use std::path::{Path, PathBuf};

use rusqlite::{params, Connection, ErrorCode, OpenFlags, OptionalExtension};

use crate::error::{Result, StoreError};
use crate::schema::{
    APPLICATION, DDL, MIGRATE_1_TO_2, MIGRATE_2_TO_3, MIGRATE_3_TO_4, MIGRATE_4_TO_5,
    MIGRATE_5_TO_6, PLANS, PROGRESS, READ_SCHEMAS, SCHEMA_VERSION,
};

/// A cellsweep SQLite database.
pub struct Store {
    pub(crate) conn: Connection,
    path: PathBuf,
    /// The layout of the file as opened: [`SCHEMA_VERSION`], or an older one a reader opened
    /// as it is (see `schema::READ_SCHEMAS`).
    pub(crate) schema: u32,
}

fn sql_error_is_notadb(e: &rusqlite::Error) -> bool {
    matches!(e, rusqlite::Error::SqliteFailure(f, _) if f.code == ErrorCode::NotADatabase || f.code == ErrorCode::DatabaseCorrupt)
}

impl Store {
    /// Open the store at `path`, creating it if the file does not exist (or is empty).
    /// An existing file that is not a cellsweep database is refused and left untouched.
    pub fn open_or_create(path: &Path) -> Result<Store> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            if !dir.is_dir() {
                return Err(StoreError::NoDirectory {
                    path: path.to_path_buf(),
                    dir: dir.to_path_buf(),
                });
            }
        }
        let fresh = match std::fs::metadata(path) {
            Ok(m) => m.len() == 0,
            Err(_) => true,
        };
        if !fresh {
            return Store::open(path);
        }
        let conn = Connection::open(path)?;
        conn.execute_batch("PRAGMA journal_mode = WAL;")?;
        let mut store = Store {
            conn,
            path: path.to_path_buf(),
            schema: SCHEMA_VERSION,
        };
        store.configure()?;
        let tx = store.conn.transaction()?;
        tx.execute_batch(DDL)?;
        tx.execute_batch(PROGRESS)?;
        tx.execute_batch(PLANS)?;
        tx.execute(
            "INSERT INTO meta (key, value) VALUES ('application', ?1), ('schema_version', ?2)",
            params![APPLICATION, SCHEMA_VERSION.to_string()],
        )?;
        tx.commit()?;
        Ok(store)
    }

    /// Close the store with everything in the database file itself (the write-ahead log
    /// checkpointed and gone), so that the file alone is the store: it may then be moved.
    pub fn close(self) -> Result<()> {
        self.conn
            .query_row("PRAGMA wal_checkpoint(TRUNCATE)", [], |_| Ok(()))?;
        self.conn.close().map_err(|(_, e)| e)?;
        Ok(())
    }

    /// Open an existing store for reading only (`status`, `table`, `plot`, ...): it works on
    /// read-only media too, where SQLite cannot create the WAL index beside the file (then the
    /// file is opened as immutable: nothing can be writing it there).
    pub fn open_read(path: &Path) -> Result<Store> {
        Self::open_with(path, OpenFlags::SQLITE_OPEN_READ_ONLY).or_else(|first| {
            let uri = format!("file:{}?immutable=1", path.display());
            Self::open_with(
                Path::new(&uri),
                OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_URI,
            )
            .map(|mut s| {
                s.path = path.to_path_buf();
                s
            })
            .map_err(|_| first)
        })
    }

    /// Open an existing store; a missing, corrupt or foreign file is a clear error.
    pub fn open(path: &Path) -> Result<Store> {
        Self::open_with(path, OpenFlags::SQLITE_OPEN_READ_WRITE)
    }

    fn open_with(path: &Path, mode: OpenFlags) -> Result<Store> {
        let is_uri = mode.contains(OpenFlags::SQLITE_OPEN_URI);
        if !is_uri && !path.exists() {
            return Err(StoreError::Missing(path.to_path_buf()));
        }
        if path.is_dir() {
            return Err(StoreError::IsDirectory(path.to_path_buf()));
        }
        let conn = Connection::open_with_flags(path, mode | OpenFlags::SQLITE_OPEN_NO_MUTEX)
            .map_err(|e| StoreError::Corrupt {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })?;
        let mut store = Store {
            conn,
            path: path.to_path_buf(),
            schema: SCHEMA_VERSION,
        };
        // Any SQLite error while reading what the file is means it is not a sound store.
        let named = |e: StoreError| match e {
            StoreError::Sql(e) => StoreError::Corrupt {
                path: path.to_path_buf(),
                reason: e.to_string(),
            },
            other => other,
        };
        store.schema = store.check_identity().map_err(named)?;
        store.configure().map_err(named)?;
        if store.schema != SCHEMA_VERSION && mode.contains(OpenFlags::SQLITE_OPEN_READ_WRITE) {
            store.migrate()?;
        }
        Ok(store)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// SQLite's `PRAGMA quick_check`: a writer runs it before it writes, so that a damaged
    /// file is reported and left as it is instead of written into.
    pub fn check_integrity(&self) -> Result<()> {
        let mut q = self.conn.prepare("PRAGMA quick_check")?;
        let problems: Vec<String> = q
            .query_map([], |r| r.get::<_, String>(0))
            .map_err(|e| StoreError::Corrupt {
                path: self.path.clone(),
                reason: e.to_string(),
            })?
            .collect::<rusqlite::Result<_>>()
            .map_err(|e| StoreError::Corrupt {
                path: self.path.clone(),
                reason: e.to_string(),
            })?;
        if problems.len() == 1 && problems[0] == "ok" {
            return Ok(());
        }
        Err(StoreError::Corrupt {
            path: self.path.clone(),
            reason: format!("integrity check: {}", problems.join("; ")),
        })
    }

    /// Bring a store of an older layout to [`SCHEMA_VERSION`], in one transaction.
    fn migrate(&mut self) -> Result<()> {
        let tx = self
            .conn
            .transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)?;
        if self.schema == 1 {
            tx.execute_batch(MIGRATE_1_TO_2)?;
        }
        if self.schema <= 2 {
            tx.execute_batch(MIGRATE_2_TO_3)?;
        }
        if self.schema <= 3 {
            tx.execute_batch(PROGRESS)?;
            tx.execute_batch(MIGRATE_3_TO_4)?;
        }
        if self.schema <= 4 {
            tx.execute_batch(PLANS)?;
            tx.execute_batch(MIGRATE_4_TO_5)?;
        }
        if self.schema <= 5 {
            tx.execute_batch(MIGRATE_5_TO_6)?;
        }
        tx.commit()?;
        self.schema = SCHEMA_VERSION;
        Ok(())
    }

    /// That the file is a cellsweep store of a layout this build reads; returns the layout.
    fn check_identity(&self) -> Result<u32> {
        let corrupt = |e: rusqlite::Error| StoreError::Corrupt {
            path: self.path.clone(),
            reason: e.to_string(),
        };
        let has_meta: Option<String> = self
            .conn
            .query_row(
                "SELECT name FROM sqlite_master WHERE type = 'table' AND name = 'meta'",
                [],
                |r| r.get(0),
            )
            .optional()
            .map_err(|e| {
                if sql_error_is_notadb(&e) {
                    corrupt(e)
                } else {
                    StoreError::Sql(e)
                }
            })?;
        if has_meta.is_none() {
            return Err(StoreError::NotOurs {
                path: self.path.clone(),
                reason: "no cellsweep meta table".into(),
            });
        }
        let get = |key: &str| -> Result<Option<String>> {
            Ok(self
                .conn
                .query_row("SELECT value FROM meta WHERE key = ?1", [key], |r| r.get(0))
                .optional()?)
        };
        if get("application")?.as_deref() != Some(APPLICATION) {
            return Err(StoreError::NotOurs {
                path: self.path.clone(),
                reason: "its meta table names another application".into(),
            });
        }
        let version = get("schema_version")?.unwrap_or_default();
        match version.parse::<u32>() {
            Ok(v) if READ_SCHEMAS.contains(&v) => Ok(v),
            _ => Err(StoreError::SchemaVersion {
                path: self.path.clone(),
                found: version,
                expected: SCHEMA_VERSION,
            }),
        }
    }

    fn configure(&self) -> Result<()> {
        // Another writer holding the database (a backup, a query tool) is waited on, up to a
        // minute, before an operation fails.
        self.conn.busy_timeout(std::time::Duration::from_secs(60))?;
        // Temporary files (the statement journals of nested savepoints, which `collect` opens
        // for each record it commits inside a file's transaction) in memory, not on disk.
        self.conn.execute_batch(
            "PRAGMA foreign_keys = ON; PRAGMA synchronous = NORMAL; PRAGMA temp_store = MEMORY;",
        )?;
        Ok(())
    }

    /// Id of the sweep called `name`.
    /// The sweep a command reads: the one named, else the store's only one.
    pub fn choose_sweep(&self, name: Option<&str>) -> Result<String> {
        if let Some(n) = name {
            return Ok(n.to_string());
        }
        let names = self.sweep_names()?;
        match names.as_slice() {
            [one] => Ok(one.clone()),
            [] => Err(StoreError::NoSweeps(self.path().to_path_buf())),
            many => Err(StoreError::SeveralSweeps {
                path: self.path().to_path_buf(),
                names: many.join(", "),
            }),
        }
    }

    pub fn sweep_id(&self, name: &str) -> Result<i64> {
        self.conn
            .query_row("SELECT id FROM sweeps WHERE name = ?1", [name], |r| {
                r.get(0)
            })
            .optional()?
            .ok_or_else(|| StoreError::UnknownSweep(name.to_string()))
    }
}
