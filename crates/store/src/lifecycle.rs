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

#[cfg(test)]
mod tests {
    use super::JobState;

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
            seen >= 70,
            "only {seen} state literals found: the scan lost its way"
        );
    }
}
