//! The label of a phase-diagram point (SPEC section 6) and its symbol.

use serde::{Deserialize, Serialize};

/// The label of a grid point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Label {
    Train,
    WalkPast,
    Reversal,
    Undetermined,
    /// Neither walk-past nor training dominant, they differ by less than 10% of replicates, and
    /// together they are at least half of them.
    Coexist,
    /// The prepped cell let go of a fiber on its own.
    Unstable,
    /// The prepped cell's phase field broke up.
    Breakup,
    /// Nothing dominant, no coexistence.
    Mixed,
}

impl Label {
    pub const ALL: [Label; 8] = [
        Label::WalkPast,
        Label::Train,
        Label::Reversal,
        Label::Coexist,
        Label::Unstable,
        Label::Breakup,
        Label::Undetermined,
        Label::Mixed,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Label::Train => "train",
            Label::WalkPast => "walk_past",
            Label::Reversal => "reversal",
            Label::Undetermined => "undetermined",
            Label::Coexist => "coexist",
            Label::Unstable => "unstable",
            Label::Breakup => "breakup",
            Label::Mixed => "mixed",
        }
    }

    pub fn parse(s: &str) -> Option<Label> {
        Label::ALL.into_iter().find(|l| l.as_str() == s)
    }

    /// The paper's symbol, in ASCII: star walk-past, cross training, plus reversal, dot
    /// unstable, diamond breakup, star over cross for coexistence.
    pub fn symbol(self) -> &'static str {
        match self {
            Label::WalkPast => "*",
            Label::Train => "x",
            Label::Reversal => "+",
            Label::Coexist => "*x",
            Label::Unstable => ".",
            Label::Breakup => "<>",
            Label::Undetermined => "?",
            Label::Mixed => "~",
        }
    }
}
