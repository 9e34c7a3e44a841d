//! Opening a store, the work a run needs, and finishing jobs and preps (the other lifecycle
//! transitions are in `transitions`).

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use rusqlite::{params, Connection, ErrorCode, OpenFlags, OptionalExtension};

use crate::error::{Result, StoreError};
use crate::lifecycle::JobState;
use crate::schema::{APPLICATION, DDL, MIGRATE_1_TO_2, READ_SCHEMAS, SCHEMA_VERSION};

/// Seconds since the Unix epoch.
pub fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// u64 seeds are stored bit for bit in SQLite's signed 64-bit integers.
pub(crate) fn seed_to_sql(seed: u64) -> i64 {
    seed as i64
}

pub(crate) fn seed_from_sql(v: i64) -> u64 {
    v as u64
}

/// Fields as little-endian f64 bytes.
pub fn f64s_to_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub fn bytes_to_f64s(b: &[u8]) -> Vec<f64> {
    b.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// A cellsweep SQLite database.
pub struct Store {
    pub(crate) conn: Connection,
    path: PathBuf,
    /// The layout of the file as opened: [`SCHEMA_VERSION`], or an older one a reader opened
    /// as it is (see `schema::READ_SCHEMAS`).
    pub(crate) schema: u32,
}

/// A sweep to register: its points, their jobs, and the preps they start from.
#[derive(Debug, Clone)]
pub struct NewSweep {
    pub name: String,
    /// Canonical JSON of the expanded definition; a different text is a different sweep.
    pub spec: String,
    pub source: String,
    pub solver_version: String,
    pub preps: Vec<NewPrep>,
    pub points: Vec<NewPoint>,
}

#[derive(Debug, Clone)]
pub struct NewPrep {
    pub key: String,
    pub seed: u64,
    /// JSON of what a worker needs to compute it (parameters and protocol).
    pub config: String,
}

#[derive(Debug, Clone)]
pub struct NewPoint {
    pub alpha: f64,
    pub beta: f64,
    pub spacing: u32,
    pub sigma: f64,
    /// JSON of what a worker needs to run a collision (parameters, protocol, classifier).
    pub config: String,
    pub jobs: Vec<NewJob>,
}

#[derive(Debug, Clone, Copy)]
pub struct NewJob {
    pub replicate: u32,
    pub seed: u64,
    /// Index into [`NewSweep::preps`].
    pub prep: usize,
}

/// What registering a sweep found.
#[derive(Debug, Clone, PartialEq)]
pub struct Registration {
    pub sweep_id: i64,
    /// The sweep was new.
    pub created: bool,
    /// The sweep was registered with this many replicates per point and now has more.
    pub grown_from: Option<u32>,
    /// An older sweep of the same name was archived under this name (`--replace`).
    pub archived_as: Option<String>,
    /// Results of this sweep under other solver versions: (version, count). They stay apart.
    pub other_versions: Vec<(String, i64)>,
}

/// A prep a run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepTask {
    pub id: i64,
    pub seed: u64,
    pub config: String,
    pub state: JobState,
    pub verdict: Option<String>,
    pub attempts: u32,
}

/// A collision job a run needs.
#[derive(Debug, Clone, PartialEq)]
pub struct JobTask {
    pub id: i64,
    pub point_id: i64,
    pub replicate: u32,
    pub seed: u64,
    pub prep_id: i64,
    pub attempts: u32,
    pub config: String,
}

/// A finished prep, as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct PrepRecord {
    pub verdict: String,
    pub verdict_time: Option<f64>,
    pub free_speed: Option<f64>,
    pub nx: usize,
    pub ny: usize,
    pub phi: Vec<f64>,
    pub p: Vec<f64>,
    /// JSON summaries of the relaxed and prepped cell.
    pub summary: String,
    pub wall_s: f64,
}

/// A finished collision, as stored.
#[derive(Debug, Clone, PartialEq)]
pub struct ResultRecord {
    pub verdict: String,
    pub outcome: Option<String>,
    pub contact_time: Option<f64>,
    pub decision_time: Option<f64>,
    pub free_speed: Option<f64>,
    pub threshold_speed: Option<f64>,
    pub attachment: Option<[String; 2]>,
    pub collision_steps: u64,
    /// Why a cell broke up (outcome `breakup` only).
    pub breakup_reason: Option<String>,
    pub wall_s: f64,
    /// JSON of the classifier settings.
    pub classifier: String,
    /// JSON of the whole trajectory result.
    pub record: String,
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
        tx.execute(
            "INSERT INTO meta (key, value) VALUES ('application', ?1), ('schema_version', ?2)",
            params![APPLICATION, SCHEMA_VERSION.to_string()],
        )?;
        tx.commit()?;
        Ok(store)
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
        self.conn
            .execute_batch("PRAGMA foreign_keys = ON; PRAGMA synchronous = NORMAL;")?;
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

    /// The preps the sweep's jobs of `version` start from, in id order.
    pub fn preps_of(&self, sweep_id: i64, version: &str) -> Result<Vec<PrepTask>> {
        let mut q = self.conn.prepare(
            "SELECT id, seed, config, state, verdict, attempts FROM preps WHERE id IN (
                 SELECT j.prep_id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.solver_version = ?2)
             ORDER BY id",
        )?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            let state: String = r.get(3)?;
            Ok(PrepTask {
                id: r.get(0)?,
                seed: seed_from_sql(r.get(1)?),
                config: r.get(2)?,
                state: JobState::parse(&state).unwrap_or(JobState::Failed),
                verdict: r.get(4)?,
                attempts: r.get(5)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// The sweep's pending jobs of `version`, in (point, replicate) order.
    pub fn pending_jobs(&self, sweep_id: i64, version: &str) -> Result<Vec<JobTask>> {
        let mut q = self.conn.prepare(
            "SELECT j.id, j.point_id, j.replicate, j.seed, j.prep_id, j.attempts, p.params
             FROM jobs j JOIN points p ON p.id = j.point_id
             WHERE p.sweep_id = ?1 AND j.solver_version = ?2 AND j.state = 'pending'
             ORDER BY p.idx, j.replicate",
        )?;
        let rows = q.query_map(params![sweep_id, version], |r| {
            Ok(JobTask {
                id: r.get(0)?,
                point_id: r.get(1)?,
                replicate: r.get(2)?,
                seed: seed_from_sql(r.get(3)?),
                prep_id: r.get(4)?,
                attempts: r.get(5)?,
                config: r.get(6)?,
            })
        })?;
        Ok(rows.collect::<rusqlite::Result<Vec<_>>>()?)
    }

    /// running -> done for a job, with its result, in one transaction.
    pub fn commit_result(&mut self, job_id: i64, version: &str, r: &ResultRecord) -> Result<()> {
        let tx = self.write()?;
        let t = now();
        let n = tx.execute(
            "UPDATE jobs SET state = 'done', finished_at = ?2, error = NULL WHERE id = ?1 AND state = 'running'",
            params![job_id, t],
        )?;
        if n != 1 {
            drop(tx);
            return self.expect_one(n, "job", job_id, "running", "jobs");
        }
        insert_result(&tx, job_id, version, r, t)?;
        tx.commit()?;
        Ok(())
    }

    /// running -> done for a prep, with its fields.
    pub fn commit_prep(&mut self, prep_id: i64, r: &PrepRecord) -> Result<()> {
        let n = self.conn.execute(
            "UPDATE preps SET state = 'done', error = NULL, verdict = ?2, verdict_time = ?3,
                 free_speed = ?4, nx = ?5, ny = ?6, phi = ?7, p = ?8, summary = ?9, wall_s = ?10,
                 finished_at = ?11
             WHERE id = ?1 AND state = 'running'",
            params![
                prep_id,
                r.verdict,
                r.verdict_time,
                r.free_speed,
                r.nx as i64,
                r.ny as i64,
                f64s_to_bytes(&r.phi),
                f64s_to_bytes(&r.p),
                r.summary,
                r.wall_s,
                now()
            ],
        )?;
        self.expect_one(n, "prep", prep_id, "running", "preps")
    }

    /// The stored fields of a finished prep.
    pub fn load_prep(&self, prep_id: i64) -> Result<PrepRecord> {
        Ok(self.conn.query_row(
            "SELECT verdict, verdict_time, free_speed, nx, ny, phi, p, summary, wall_s
             FROM preps WHERE id = ?1 AND state = 'done'",
            [prep_id],
            |r| {
                Ok(PrepRecord {
                    verdict: r.get(0)?,
                    verdict_time: r.get(1)?,
                    free_speed: r.get(2)?,
                    nx: r.get::<_, i64>(3)? as usize,
                    ny: r.get::<_, i64>(4)? as usize,
                    phi: bytes_to_f64s(&r.get::<_, Vec<u8>>(5)?),
                    p: bytes_to_f64s(&r.get::<_, Vec<u8>>(6)?),
                    summary: r.get(7)?,
                    wall_s: r.get(8)?,
                })
            },
        )?)
    }

    /// A prep whose verdict is not `ok` decides its pending jobs of `sweep_id` without a
    /// collision: each gets a result carrying the verdict, in one transaction. Returns how many.
    pub fn settle_jobs_of_prep(
        &mut self,
        sweep_id: i64,
        prep_id: i64,
        version: &str,
        r: &ResultRecord,
    ) -> Result<usize> {
        let tx = self.write()?;
        let ids: Vec<i64> = {
            let mut q = tx.prepare(
                "SELECT j.id FROM jobs j JOIN points p ON p.id = j.point_id
                 WHERE p.sweep_id = ?1 AND j.prep_id = ?2 AND j.solver_version = ?3 AND j.state = 'pending'",
            )?;
            let rows = q.query_map(params![sweep_id, prep_id, version], |r| r.get(0))?;
            rows.collect::<rusqlite::Result<Vec<_>>>()?
        };
        let t = now();
        for &id in &ids {
            tx.execute(
                "UPDATE jobs SET state = 'done', finished_at = ?2 WHERE id = ?1",
                params![id, t],
            )?;
            insert_result(&tx, id, version, r, t)?;
        }
        tx.commit()?;
        Ok(ids.len())
    }
}

pub(crate) fn insert_result(
    tx: &Connection,
    job_id: i64,
    version: &str,
    r: &ResultRecord,
    t: f64,
) -> Result<()> {
    let (a1, a2) = match &r.attachment {
        Some([a, b]) => (Some(a.as_str()), Some(b.as_str())),
        None => (None, None),
    };
    tx.execute(
        "INSERT INTO results (job_id, solver_version, verdict, outcome, contact_time, decision_time,
             free_speed, threshold_speed, attachment_1, attachment_2, collision_steps, wall_s,
             classifier, record, finished_at, breakup_reason)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16)",
        params![
            job_id,
            version,
            r.verdict,
            r.outcome,
            r.contact_time,
            r.decision_time,
            r.free_speed,
            r.threshold_speed,
            a1,
            a2,
            r.collision_steps as i64,
            r.wall_s,
            r.classifier,
            r.record,
            t,
            r.breakup_reason
        ],
    )?;
    Ok(())
}
