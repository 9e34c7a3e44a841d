//! How one replicate ended, and a finished replicate as the statistics see it.

use serde::{Deserialize, Serialize};

use crate::axes::Others;

/// How one replicate ended: its collision's outcome, or its prep's verdict where the prep was
/// not `ok` (no collision ran). `Breakup` is the prep's verdict; a collision in which a cell
/// broke up is `CollisionBreakup`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum End {
    Train,
    WalkPast,
    Reversal,
    Undetermined,
    Unstable,
    Breakup,
    CollisionBreakup,
}

impl End {
    pub const ALL: [End; 7] = [
        End::Train,
        End::WalkPast,
        End::Reversal,
        End::Undetermined,
        End::Unstable,
        End::Breakup,
        End::CollisionBreakup,
    ];

    pub(crate) fn index(self) -> usize {
        // ALL lists the variants in the order they are declared.
        self as usize
    }

    /// From a stored result's verdict and outcome.
    pub fn of(verdict: &str, outcome: Option<&str>) -> Option<End> {
        match (verdict, outcome) {
            (_, Some("train")) => Some(End::Train),
            (_, Some("walk_past")) => Some(End::WalkPast),
            (_, Some("reversal")) => Some(End::Reversal),
            (_, Some("undetermined")) => Some(End::Undetermined),
            (_, Some("breakup")) => Some(End::CollisionBreakup),
            ("unstable", None) => Some(End::Unstable),
            ("breakup", None) => Some(End::Breakup),
            _ => None,
        }
    }
}

/// One finished replicate of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Replicate {
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    /// The sweep's other axes at its point (empty for the paper's four).
    #[serde(default, skip_serializing_if = "Others::is_empty")]
    pub others: Others,
    /// Its point's index in the sweep.
    #[serde(default)]
    pub point: u32,
    pub replicate: u32,
    /// The collision's seed.
    pub seed: u64,
    /// The seed of the prep it started from.
    pub prep_seed: u64,
    pub end: End,
    /// When the outcome was decided (tau0), if it was.
    pub decision_time: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::End;

    #[test]
    fn an_end_s_index_is_its_place_in_all() {
        for (i, e) in End::ALL.iter().enumerate() {
            assert_eq!(e.index(), i);
        }
    }
}
