//! The two arrays of a submission: preps, then collisions.

/// Which array a task belongs to: the prep array or the collision array (stored as `prep` /
/// `collide` in the store's `slurm_arrays.kind`, in file names and in job names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ArrayKind {
    Prep,
    Collide,
}

impl ArrayKind {
    pub const ALL: [ArrayKind; 2] = [ArrayKind::Prep, ArrayKind::Collide];

    pub fn as_str(self) -> &'static str {
        match self {
            ArrayKind::Prep => "prep",
            ArrayKind::Collide => "collide",
        }
    }
}

impl std::fmt::Display for ArrayKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A name that is neither `prep` nor `collide`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is not an array kind (prep or collide)")]
pub struct UnknownArrayKind(pub String);

impl std::str::FromStr for ArrayKind {
    type Err = UnknownArrayKind;

    /// `prep` or `collide`.
    fn from_str(s: &str) -> Result<ArrayKind, UnknownArrayKind> {
        ArrayKind::ALL
            .into_iter()
            .find(|k| k.as_str() == s)
            .ok_or_else(|| UnknownArrayKind(s.to_string()))
    }
}
