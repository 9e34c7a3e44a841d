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
