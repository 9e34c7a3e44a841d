//! The store's schema. Documented for users in the README ("The store").

/// Version of the layout below; bumped on incompatible changes. Version 2 lets a collision end
/// in `breakup` (SPEC section 5) and keeps its reason; version 3 keeps, per prep and job, the
/// failed attempts counted before its latest retry (`attempts_at_retry`), so that `attempts`
/// only ever grows and a failure record read twice (a Slurm results file) counts once. An older
/// store is migrated by the first writer that opens it ([`MIGRATE_1_TO_2`], [`MIGRATE_2_TO_3`])
/// and read as it is by the readers. Version 4 keeps each point's jobs counted by state
/// (`point_progress`, kept by triggers in the same transaction as every change to `jobs`) and
/// indexes finished jobs by time, so that `status` reads ten million jobs in milliseconds
/// ([`MIGRATE_3_TO_4`]). Version 5 stores a point's jobs as a plan until they are needed
/// ([`PLANS`]): registering ten million jobs writes one row per point, not one per job
/// ([`MIGRATE_4_TO_5`]). Version 6 records a Slurm array before `sbatch` is run (its job id
/// empty until sbatch answers), with its submission directory, and the time it was seen to have
/// left the queue and its tasks were examined ([`MIGRATE_5_TO_6`]).
pub const SCHEMA_VERSION: u32 = 6;

/// Versions a reader opens as they are.
pub const READ_SCHEMAS: [u32; 6] = [1, 2, 3, 4, 5, 6];

/// The first layout whose `slurm_arrays` has `sub_dir` and `ended_at` (and a job id that may
/// be empty while the array is being submitted).
pub const ARRAYS_SCHEMA: u32 = 6;

/// The first layout with `point_plans`: every version before it holds a row for every job.
pub const PLANS_SCHEMA: u32 = 5;

/// The first layout with `point_progress`: readers of older files count `jobs` instead.
pub const PROGRESS_SCHEMA: u32 = 4;

/// Identifies a cellsweep database in its `meta` table.
pub const APPLICATION: &str = "cellsweep";

pub const DDL: &str = r#"
CREATE TABLE meta (
    key   TEXT PRIMARY KEY,
    value TEXT NOT NULL
);

-- One row per registered sweep; `spec` is the canonical JSON of the expanded definition.
CREATE TABLE sweeps (
    id         INTEGER PRIMARY KEY,
    name       TEXT NOT NULL UNIQUE,
    spec       TEXT NOT NULL,
    source     TEXT,
    created_at REAL NOT NULL
);

-- Grid points: the four swept parameters, and every parameter as JSON.
CREATE TABLE points (
    id       INTEGER PRIMARY KEY,
    sweep_id INTEGER NOT NULL REFERENCES sweeps(id),
    idx      INTEGER NOT NULL,
    alpha    REAL NOT NULL,
    beta     REAL NOT NULL,
    L        INTEGER NOT NULL,
    sigma    REAL NOT NULL,
    params   TEXT NOT NULL,
    UNIQUE (sweep_id, idx)
);

-- Prepped cells (stages 1-4), shared by every point and sweep with the same single-cell
-- parameters, prep protocol, seed and solver version.
CREATE TABLE preps (
    id             INTEGER PRIMARY KEY,
    key            TEXT NOT NULL,
    seed           INTEGER NOT NULL,
    solver_version TEXT NOT NULL,
    config         TEXT NOT NULL,
    state          TEXT NOT NULL CHECK (state IN ('pending', 'running', 'done', 'failed')),
    attempts       INTEGER NOT NULL DEFAULT 0,
    error          TEXT,
    verdict        TEXT CHECK (verdict IN ('ok', 'unstable', 'breakup')),
    verdict_time   REAL,
    free_speed     REAL,
    nx             INTEGER,
    ny             INTEGER,
    phi            BLOB,
    p              BLOB,
    summary        TEXT,
    wall_s         REAL,
    finished_at    REAL,
    -- Failed attempts before the latest retry: it gives up after `max_attempts` more.
    attempts_at_retry INTEGER NOT NULL DEFAULT 0,
    UNIQUE (key, seed, solver_version)
);

-- One collision trajectory per (point, replicate, solver version).
CREATE TABLE jobs (
    id             INTEGER PRIMARY KEY,
    point_id       INTEGER NOT NULL REFERENCES points(id),
    replicate      INTEGER NOT NULL,
    solver_version TEXT NOT NULL,
    prep_id        INTEGER NOT NULL REFERENCES preps(id),
    seed           INTEGER NOT NULL,
    state          TEXT NOT NULL CHECK (state IN ('pending', 'running', 'done', 'failed')),
    attempts       INTEGER NOT NULL DEFAULT 0,
    error          TEXT,
    started_at     REAL,
    finished_at    REAL,
    attempts_at_retry INTEGER NOT NULL DEFAULT 0,
    UNIQUE (point_id, replicate, solver_version)
);

-- Exactly one result per finished job.
CREATE TABLE results (
    job_id          INTEGER PRIMARY KEY REFERENCES jobs(id),
    solver_version  TEXT NOT NULL,
    verdict         TEXT NOT NULL CHECK (verdict IN ('ok', 'unstable', 'breakup')),
    outcome         TEXT CHECK (outcome IN ('train', 'walk_past', 'reversal', 'undetermined',
                                        'breakup')),
    contact_time    REAL,
    decision_time   REAL,
    free_speed      REAL,
    threshold_speed REAL,
    attachment_1    TEXT,
    attachment_2    TEXT,
    collision_steps INTEGER,
    wall_s          REAL,
    classifier      TEXT NOT NULL,
    record          TEXT NOT NULL,
    finished_at     REAL NOT NULL,
    -- Why a cell of the collision broke up (outcome 'breakup' only).
    breakup_reason  TEXT
);

-- Slurm job arrays of a sweep (`cellsweep submit`): written before sbatch runs (job id NULL
-- while it is being submitted), completed with the id sbatch gives, and marked ended once the
-- array has left the queue and its tasks were examined for jobs they left without a result.
CREATE TABLE slurm_arrays (
    id             INTEGER PRIMARY KEY,
    sweep_id       INTEGER NOT NULL REFERENCES sweeps(id),
    solver_version TEXT NOT NULL,
    kind           TEXT NOT NULL CHECK (kind IN ('prep', 'collide')),
    slurm_job_id   TEXT,
    run_dir        TEXT NOT NULL,
    sub_dir        TEXT,
    tasks          INTEGER NOT NULL,
    jobs           INTEGER NOT NULL,
    submitted_at   REAL NOT NULL,
    ended_at       REAL
);

CREATE INDEX jobs_by_point ON jobs(point_id, solver_version, state);
CREATE INDEX jobs_by_prep ON jobs(prep_id, state);
CREATE INDEX points_by_sweep ON points(sweep_id);
"#;

/// Each point's jobs by state under each solver version, and the latest finish among them,
/// kept in the very transaction that changes the jobs: by triggers on a change of state and a
/// delete, and by registration, the one place that inserts jobs (always pending), which adds
/// each point's new jobs at once (a trigger per inserted row tripled the time to register
/// ten million jobs) (a done job that leaves `done` has its point's latest
/// finish looked up again among the point's own jobs). With the partial index of finished jobs by time
/// (nothing for a pending job), `status` and the live page read sums over points, not jobs.
/// Part of the layout since version 4: a new store runs it after [`DDL`], a migration from 3
/// runs it and fills the counts ([`MIGRATE_3_TO_4`]).
pub const PROGRESS: &str = r#"
CREATE TABLE point_progress (
    point_id       INTEGER NOT NULL REFERENCES points(id),
    solver_version TEXT NOT NULL,
    pending        INTEGER NOT NULL DEFAULT 0,
    running        INTEGER NOT NULL DEFAULT 0,
    done           INTEGER NOT NULL DEFAULT 0,
    failed         INTEGER NOT NULL DEFAULT 0,
    last_finished  REAL,
    PRIMARY KEY (point_id, solver_version)
) WITHOUT ROWID;

CREATE INDEX jobs_done_by_finish ON jobs(finished_at) WHERE state = 'done';

-- Each point's results by (verdict, outcome) under each solver version ('' for no outcome),
-- kept by triggers on results (inserted once per job, deleted only by a reset).
CREATE TABLE point_outcomes (
    point_id       INTEGER NOT NULL REFERENCES points(id),
    solver_version TEXT NOT NULL,
    verdict        TEXT NOT NULL,
    outcome        TEXT NOT NULL,
    n              INTEGER NOT NULL,
    PRIMARY KEY (point_id, solver_version, verdict, outcome)
) WITHOUT ROWID;

CREATE TRIGGER results_outcomes_insert AFTER INSERT ON results BEGIN
    INSERT INTO point_outcomes (point_id, solver_version, verdict, outcome, n)
    VALUES ((SELECT point_id FROM jobs WHERE id = new.job_id), new.solver_version,
            new.verdict, COALESCE(new.outcome, ''), 1)
    ON CONFLICT (point_id, solver_version, verdict, outcome) DO UPDATE SET n = n + 1;
END;

CREATE TRIGGER results_outcomes_delete AFTER DELETE ON results BEGIN
    UPDATE point_outcomes SET n = n - 1
    WHERE point_id = (SELECT point_id FROM jobs WHERE id = old.job_id)
      AND solver_version = old.solver_version AND verdict = old.verdict
      AND outcome = COALESCE(old.outcome, '');
END;

CREATE TRIGGER jobs_progress_delete AFTER DELETE ON jobs BEGIN
    UPDATE point_progress SET
        pending = pending - (old.state = 'pending'), running = running - (old.state = 'running'),
        done = done - (old.state = 'done'), failed = failed - (old.state = 'failed'),
        last_finished = CASE WHEN old.state = 'done' THEN (
            SELECT MAX(finished_at) FROM jobs WHERE point_id = old.point_id
              AND solver_version = old.solver_version AND state = 'done') ELSE last_finished END
    WHERE point_id = old.point_id AND solver_version = old.solver_version;
END;

CREATE TRIGGER jobs_progress_update AFTER UPDATE OF state, point_id, solver_version, finished_at
ON jobs BEGIN
    UPDATE point_progress SET
        pending = pending - (old.state = 'pending'), running = running - (old.state = 'running'),
        done = done - (old.state = 'done'), failed = failed - (old.state = 'failed'),
        last_finished = CASE WHEN old.state = 'done' THEN (
            SELECT MAX(finished_at) FROM jobs WHERE point_id = old.point_id
              AND solver_version = old.solver_version AND state = 'done') ELSE last_finished END
    WHERE point_id = old.point_id AND solver_version = old.solver_version;
    INSERT INTO point_progress (point_id, solver_version, pending, running, done, failed,
                                last_finished)
    VALUES (new.point_id, new.solver_version, new.state = 'pending', new.state = 'running',
            new.state = 'done', new.state = 'failed',
            CASE WHEN new.state = 'done' THEN new.finished_at END)
    ON CONFLICT (point_id, solver_version) DO UPDATE SET
        pending = pending + excluded.pending, running = running + excluded.running,
        done = done + excluded.done, failed = failed + excluded.failed,
        last_finished = MAX(COALESCE(last_finished, excluded.last_finished),
                            COALESCE(excluded.last_finished, last_finished));
END;
"#;

/// A point's jobs, planned (since version 5). Registration writes a row of `jobs` for the
/// first replicates only, one per prep of the point (so every prep a point uses is reached
/// through `jobs`, as before), and plans the rest here: replicates `materialized..planned`
/// exist only as their seeds (8 bytes each, little-endian, in replicate order; replicate r
/// starts from the prep of replicate r mod `cycle`, SPEC section 4's round-robin). They are
/// counted `pending` in `point_progress` from registration on, and become rows of `jobs`
/// (pending, in one write, the whole tail of a point at once) when a run is about to dispatch
/// them, a Slurm submission lists them, an import or a prep's verdict settles them
/// ([`crate::Store::materialize_next`]). Rows of `jobs` always hold replicates
/// `0..materialized` of a point, so that a plan is a prefix and a tail.
pub const PLANS: &str = r#"
CREATE TABLE point_plans (
    id             INTEGER PRIMARY KEY,
    point_id       INTEGER NOT NULL REFERENCES points(id),
    solver_version TEXT NOT NULL,
    planned        INTEGER NOT NULL,
    materialized   INTEGER NOT NULL,
    cycle          INTEGER NOT NULL,
    seeds          BLOB NOT NULL,
    UNIQUE (point_id, solver_version)
);

-- The plans with jobs still to write, by point (in a sweep's grid order).
CREATE INDEX point_plans_open ON point_plans(point_id, solver_version)
    WHERE planned > materialized;
"#;

/// Version 5 to 6: `slurm_arrays` gains `sub_dir` and `ended_at`, and its job id may be NULL
/// (an array being submitted). Rebuilt with its rows (SQLite cannot drop a NOT NULL in place);
/// written out here, frozen at the layout of version 6. Arrays recorded before have no
/// submission directory: they are marked ended when they leave the queue, not examined.
pub const MIGRATE_5_TO_6: &str = r#"
CREATE TABLE slurm_arrays_v6 (
    id             INTEGER PRIMARY KEY,
    sweep_id       INTEGER NOT NULL REFERENCES sweeps(id),
    solver_version TEXT NOT NULL,
    kind           TEXT NOT NULL CHECK (kind IN ('prep', 'collide')),
    slurm_job_id   TEXT,
    run_dir        TEXT NOT NULL,
    sub_dir        TEXT,
    tasks          INTEGER NOT NULL,
    jobs           INTEGER NOT NULL,
    submitted_at   REAL NOT NULL,
    ended_at       REAL
);
INSERT INTO slurm_arrays_v6 (id, sweep_id, solver_version, kind, slurm_job_id, run_dir, tasks,
    jobs, submitted_at)
  SELECT id, sweep_id, solver_version, kind, slurm_job_id, run_dir, tasks, jobs, submitted_at
  FROM slurm_arrays;
DROP TABLE slurm_arrays;
ALTER TABLE slurm_arrays_v6 RENAME TO slurm_arrays;
UPDATE meta SET value = '6' WHERE key = 'schema_version';
"#;

/// Version 4 to 5: [`PLANS`], every job of a store before it being a row already.
pub const MIGRATE_4_TO_5: &str = r#"
INSERT INTO point_plans (point_id, solver_version, planned, materialized, cycle, seeds)
  SELECT point_id, solver_version, MAX(replicate) + 1, MAX(replicate) + 1, 1, X''
  FROM jobs GROUP BY point_id, solver_version;
UPDATE meta SET value = '5' WHERE key = 'schema_version';
"#;

/// Version 3 to 4: [`PROGRESS`], with every point's counts taken from its jobs.
pub const MIGRATE_3_TO_4: &str = r#"
INSERT INTO point_progress (point_id, solver_version, pending, running, done, failed,
                            last_finished)
  SELECT point_id, solver_version, SUM(state = 'pending'), SUM(state = 'running'),
         SUM(state = 'done'), SUM(state = 'failed'),
         MAX(CASE WHEN state = 'done' THEN finished_at END)
  FROM jobs GROUP BY point_id, solver_version;
INSERT INTO point_outcomes (point_id, solver_version, verdict, outcome, n)
  SELECT j.point_id, r.solver_version, r.verdict, COALESCE(r.outcome, ''), COUNT(*)
  FROM results r JOIN jobs j ON j.id = r.job_id
  GROUP BY j.point_id, r.solver_version, r.verdict, COALESCE(r.outcome, '');
UPDATE meta SET value = '4' WHERE key = 'schema_version';
"#;

/// Version 1 to 2: `results` gains the outcome `breakup` (SQLite cannot change a CHECK in
/// place, so the table is rebuilt with its rows) and the column `breakup_reason`. The table is
/// written out here, not taken from [`DDL`]: a migration is frozen at the layout of version 2,
/// while `DDL` moves on with later versions.
pub const MIGRATE_1_TO_2: &str = r#"
CREATE TABLE results_v2 (
    job_id          INTEGER PRIMARY KEY REFERENCES jobs(id),
    solver_version  TEXT NOT NULL,
    verdict         TEXT NOT NULL CHECK (verdict IN ('ok', 'unstable', 'breakup')),
    outcome         TEXT CHECK (outcome IN ('train', 'walk_past', 'reversal', 'undetermined',
                                        'breakup')),
    contact_time    REAL,
    decision_time   REAL,
    free_speed      REAL,
    threshold_speed REAL,
    attachment_1    TEXT,
    attachment_2    TEXT,
    collision_steps INTEGER,
    wall_s          REAL,
    classifier      TEXT NOT NULL,
    record          TEXT NOT NULL,
    finished_at     REAL NOT NULL,
    breakup_reason  TEXT
);
INSERT INTO results_v2 (job_id, solver_version, verdict, outcome, contact_time, decision_time,
    free_speed, threshold_speed, attachment_1, attachment_2, collision_steps, wall_s, classifier,
    record, finished_at)
  SELECT job_id, solver_version, verdict, outcome, contact_time, decision_time, free_speed,
    threshold_speed, attachment_1, attachment_2, collision_steps, wall_s, classifier, record,
    finished_at FROM results;
DROP TABLE results;
ALTER TABLE results_v2 RENAME TO results;
UPDATE meta SET value = '2' WHERE key = 'schema_version';
"#;

/// Version 2 to 3: preps and jobs gain `attempts_at_retry` (a retry used to reset `attempts`).
pub const MIGRATE_2_TO_3: &str = r#"
ALTER TABLE preps ADD COLUMN attempts_at_retry INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN attempts_at_retry INTEGER NOT NULL DEFAULT 0;
UPDATE meta SET value = '3' WHERE key = 'schema_version';
"#;
