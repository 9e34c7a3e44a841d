//! The lifecycle of a job (and of a prep): an explicit state machine.
//!
//! ```text
//!  pending --claim--> running --commit--> done
//!     ^                  |
//!     |   failure, attempts < max      failure, attempts = max
//!     +------------------+-----------------------------> failed
//!     ^                  |
//!     +----recover-------+   (coordinator killed or interrupted: the run did not finish)
//! ```
//! Every transition is one guarded UPDATE: it applies only from the expected state, so a job can
//! never be finished twice.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JobState {
    Pending,
    Running,
    Done,
    Failed,
}

impl JobState {
    pub const ALL: [JobState; 4] = [
        JobState::Pending,
        JobState::Running,
        JobState::Done,
        JobState::Failed,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Pending => "pending",
            JobState::Running => "running",
            JobState::Done => "done",
            JobState::Failed => "failed",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        JobState::ALL.into_iter().find(|st| st.as_str() == s)
    }
}

/// A state is bound into SQL by its name, so that a transition names its states as values of
/// this type, never as literals a typo could turn into a state that matches no row.
impl rusqlite::ToSql for JobState {
    fn to_sql(&self) -> rusqlite::Result<rusqlite::types::ToSqlOutput<'_>> {
        Ok(self.as_str().into())
    }
}

/// A stored state read back; a name that is no state is an error, never a default.
impl rusqlite::types::FromSql for JobState {
    fn column_result(value: rusqlite::types::ValueRef<'_>) -> rusqlite::types::FromSqlResult<Self> {
        let name = value.as_str()?;
        JobState::parse(name).ok_or_else(|| {
            rusqlite::types::FromSqlError::Other(format!("{name:?} is not a job state").into())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::JobState;

    /// States cross SQL by name both ways, and a stored name that is no state is an error
    /// (it used to be read as `failed`).
    #[test]
    fn states_bind_by_name_and_an_unknown_stored_state_is_an_error() {
        let conn = rusqlite::Connection::open_in_memory().unwrap();
        conn.execute("CREATE TABLE t (state TEXT)", []).unwrap();
        for s in JobState::ALL {
            conn.execute("INSERT INTO t VALUES (?1)", [s]).unwrap();
            let name: String = conn
                .query_row(
                    "SELECT state FROM t WHERE rowid = last_insert_rowid()",
                    [],
                    |r| r.get(0),
                )
                .unwrap();
            assert_eq!(name, s.as_str());
            let back: JobState = conn
                .query_row("SELECT state FROM t WHERE state = ?1", [s], |r| r.get(0))
                .unwrap();
            assert_eq!(back, s);
        }
        let read = conn.query_row("SELECT 'runing'", [], |r| r.get::<_, JobState>(0));
        let err = read.unwrap_err().to_string();
        assert!(err.contains("\"runing\" is not a job state"), "{err}");
    }

    /// The store's SQL writes states as literals; every one of them, in every source file of
    /// the crate and in the schema's CHECKs, must be a `JobState` (a typo such as 'runing'
    /// would match no row and fail silently).
    #[test]
    fn every_state_literal_in_the_store_s_sql_is_a_job_state() {
        let sources = [
            include_str!("schema.rs"),
            include_str!("transitions.rs"),
            include_str!("record.rs"),
            include_str!("reset.rs"),
            include_str!("status.rs"),
            include_str!("progress.rs"),
            include_str!("export.rs"),
            include_str!("register.rs"),
            include_str!("plans.rs"),
            include_str!("identity.rs"),
            include_str!("tasks.rs"),
        ];
        let names: Vec<&str> = JobState::ALL.iter().map(|s| s.as_str()).collect();
        let mut seen = 0;
        for text in sources {
            // `state = 'x'`, `state != 'x'`, `state IN ('x', 'y')` (also `j.state`, `p.state`).
            for (at, _) in text.match_indices("state ") {
                let rest = &text[at + "state ".len()..];
                let rest = rest
                    .strip_prefix("= ")
                    .or_else(|| rest.strip_prefix("!= "))
                    .or_else(|| rest.strip_prefix("<> "))
                    .or_else(|| rest.strip_prefix("IN "));
                let Some(rest) = rest.filter(|r| r.starts_with('\'') || r.starts_with("('")) else {
                    continue;
                };
                let items: Vec<&str> = match rest.strip_prefix('(') {
                    // ('x', 'y', ...)
                    Some(list) => list[..list.find(')').unwrap_or(list.len())]
                        .split(',')
                        .collect(),
                    // 'x'
                    None => vec![rest[1..].split('\'').next().unwrap_or("")],
                };
                for item in items {
                    let name = item.trim().trim_matches('\'');
                    assert!(
                        names.contains(&name),
                        "state literal {name:?} is not a JobState"
                    );
                    seen += 1;
                }
            }
        }
        // The schema's CHECK lists every state, once per table that has one.
        let check = "state IN ('pending', 'running', 'done', 'failed')";
        assert_eq!(
            check,
            format!(
                "state IN ({})",
                names
                    .iter()
                    .map(|n| format!("'{n}'"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        );
        assert!(include_str!("schema.rs").contains(check));
        assert!(
            seen >= 30,
            "only {seen} state literals found: the scan lost its way"
        );
    }
}
