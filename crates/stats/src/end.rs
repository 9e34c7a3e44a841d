//! How one replicate ended ([`End`]), the counts of a point's ends ([`Tally`], and [`PerEnd`]
//! for anything else kept per end), and a finished replicate as the statistics see it.
//!
//! This is the one home of the outcome kinds: every table column, JSON key, CSV column and
//! printed name of an end comes from [`End::ALL`] and the methods below.

use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::axes::Others;
use crate::label::Label;

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
    /// Every end, in the order tables and files list them.
    pub const ALL: [End; 7] = [
        End::Train,
        End::WalkPast,
        End::Reversal,
        End::Undetermined,
        End::Unstable,
        End::Breakup,
        End::CollisionBreakup,
    ];

    /// How many kinds of end there are.
    pub const COUNT: usize = End::ALL.len();

    fn index(self) -> usize {
        // ALL lists the variants in the order they are declared.
        self as usize
    }

    /// Its name in JSON and in stores' summaries (`walk_past`).
    pub fn name(self) -> &'static str {
        match self {
            End::Train => "train",
            End::WalkPast => "walk_past",
            End::Reversal => "reversal",
            End::Undetermined => "undetermined",
            End::Unstable => "unstable",
            End::Breakup => "breakup",
            End::CollisionBreakup => "collision_breakup",
        }
    }

    /// From its [`End::name`]; the error lists every name.
    pub fn parse(name: &str) -> Result<End, UnknownEnd> {
        End::ALL
            .into_iter()
            .find(|e| e.name() == name)
            .ok_or_else(|| UnknownEnd(name.to_string()))
    }

    /// The column of its count in tables, counts files and comparisons (`n_walk`).
    pub fn count_key(self) -> &'static str {
        match self {
            End::Train => "n_train",
            End::WalkPast => "n_walk",
            End::Reversal => "n_reversal",
            End::Undetermined => "n_undetermined",
            End::Unstable => "n_unstable",
            End::Breakup => "n_breakup",
            End::CollisionBreakup => "n_collision_breakup",
        }
    }

    /// Its name in a line of prose (`walk-past`; `broke up` for a collision's breakup).
    pub fn words(self) -> &'static str {
        match self {
            End::Train => "training",
            End::WalkPast => "walk-past",
            End::CollisionBreakup => "broke up",
            e => e.name(),
        }
    }

    /// What it means, for a legend beside its [`End::initials`].
    pub fn meaning(self) -> &'static str {
        match self {
            End::Unstable => "the prep let go of a fiber (decided by its verdict)",
            End::Breakup => "the prep broke up (decided by its verdict)",
            End::CollisionBreakup => "a cell broke up in the collision",
            e => e.words(),
        }
    }

    /// Its name where room is short (a progress line).
    pub fn short(self) -> &'static str {
        match self {
            End::Train => "train",
            End::WalkPast => "walk",
            End::Reversal => "rev",
            End::Undetermined => "undet",
            End::Unstable => "unstable",
            End::Breakup => "breakup",
            End::CollisionBreakup => "broke up",
        }
    }

    /// Two letters, for a compact column of counts (`tr/wp/rv/un/us/pb/cb`).
    pub fn initials(self) -> &'static str {
        match self {
            End::Train => "tr",
            End::WalkPast => "wp",
            End::Reversal => "rv",
            End::Undetermined => "un",
            End::Unstable => "us",
            End::Breakup => "pb",
            End::CollisionBreakup => "cb",
        }
    }

    /// Whether a collision ran (every share is taken over these).
    pub fn is_collision(self) -> bool {
        !matches!(self, End::Unstable | End::Breakup)
    }

    /// Whether summaries show its count even when it is zero (the paper's four outcomes).
    pub fn always_shown(self) -> bool {
        matches!(
            self,
            End::Train | End::WalkPast | End::Reversal | End::Undetermined
        )
    }

    /// The label of a point where this end dominates.
    pub fn label(self) -> Label {
        match self {
            End::Train => Label::Train,
            End::WalkPast => Label::WalkPast,
            End::Reversal => Label::Reversal,
            End::Undetermined => Label::Undetermined,
            End::Unstable => Label::Unstable,
            End::Breakup | End::CollisionBreakup => Label::Breakup,
        }
    }

    /// The outcome a store writes for it (`breakup` for a collision's breakup), `None` for
    /// an end decided by the prep (no collision ran).
    pub fn stored_outcome(self) -> Option<&'static str> {
        match self {
            End::CollisionBreakup => Some("breakup"),
            e if e.is_collision() => Some(e.name()),
            _ => None,
        }
    }

    /// Every outcome a collision can end in, as stored, for messages (`train, walk_past, ...`).
    pub fn stored_outcomes() -> String {
        let names: Vec<&str> = End::ALL.iter().filter_map(|e| e.stored_outcome()).collect();
        names.join(", ")
    }

    /// Whether the end was decided at a time (a collision that did not run out undetermined).
    pub fn decided(self) -> bool {
        self.is_collision() && self != End::Undetermined
    }

    /// From a collision's outcome as the classifier names it (`walk_past`, `breakup`, ...).
    pub fn of_outcome(outcome: &str) -> Option<End> {
        End::ALL
            .into_iter()
            .find(|e| e.stored_outcome() == Some(outcome))
    }

    /// From a stored result's prep verdict and collision outcome, as named in a file.
    pub fn of(verdict: &str, outcome: Option<&str>) -> Option<End> {
        match (verdict, outcome) {
            (_, Some(o)) => End::of_outcome(o),
            (v, None) => PrepVerdict::parse(v).and_then(PrepVerdict::end),
        }
    }
}

/// A name that is no [`End`]'s.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?}: not one of {names}", names = End::ALL.map(End::name).join(", "))]
pub struct UnknownEnd(pub String);

/// The verdict on a prepped cell, as results store it: `ok` (its collisions run), or a verdict
/// that decides every replicate of the prep without a collision (SPEC section 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PrepVerdict {
    Ok,
    Unstable,
    Breakup,
}

impl PrepVerdict {
    pub const ALL: [PrepVerdict; 3] =
        [PrepVerdict::Ok, PrepVerdict::Unstable, PrepVerdict::Breakup];

    /// Its stored name (`ok`, `unstable`, `breakup`).
    pub fn as_str(self) -> &'static str {
        match self {
            PrepVerdict::Ok => "ok",
            PrepVerdict::Unstable => "unstable",
            PrepVerdict::Breakup => "breakup",
        }
    }

    /// From its stored name.
    pub fn parse(name: &str) -> Option<PrepVerdict> {
        PrepVerdict::ALL.into_iter().find(|v| v.as_str() == name)
    }

    /// The end of every replicate of a prep with this verdict, where the verdict decides it
    /// (`None` for `ok`: the collision decides).
    pub fn end(self) -> Option<End> {
        match self {
            PrepVerdict::Ok => None,
            PrepVerdict::Unstable => Some(End::Unstable),
            PrepVerdict::Breakup => Some(End::Breakup),
        }
    }
}

impl std::fmt::Display for PrepVerdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One value per [`End`], indexed by the end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PerEnd<T>([T; End::COUNT]);

impl<T> std::ops::Index<End> for PerEnd<T> {
    type Output = T;
    fn index(&self, e: End) -> &T {
        &self.0[e.index()]
    }
}

impl<T> std::ops::IndexMut<End> for PerEnd<T> {
    fn index_mut(&mut self, e: End) -> &mut T {
        &mut self.0[e.index()]
    }
}

/// From the values in the order of [`End::ALL`].
impl<T> From<[T; End::COUNT]> for PerEnd<T> {
    fn from(values: [T; End::COUNT]) -> PerEnd<T> {
        PerEnd(values)
    }
}

impl<T: Copy> PerEnd<T> {
    /// `f` of every end.
    pub fn from_fn(mut f: impl FnMut(End) -> T) -> PerEnd<T> {
        PerEnd(End::ALL.map(&mut f))
    }

    /// Each end with its value, in the order of [`End::ALL`].
    pub fn iter(&self) -> impl Iterator<Item = (End, T)> + '_ {
        End::ALL.into_iter().map(|e| (e, self[e]))
    }
}

/// How many replicates ended each way.
pub type Tally = PerEnd<u64>;

impl Tally {
    /// Count `n` more replicates that ended in `end`.
    pub fn add(&mut self, end: End, n: u64) {
        self[end] += n;
    }

    /// All replicates with a result.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }

    /// Replicates whose collision ran, whatever it ended in: the base of every share.
    pub fn collisions(&self) -> u64 {
        self.iter()
            .filter(|(e, _)| e.is_collision())
            .map(|(_, n)| n)
            .sum()
    }

    /// Replicates decided by a prep verdict (no collision ran).
    pub fn by_prep(&self) -> u64 {
        self.total() - self.collisions()
    }

    /// One line of prose: the paper's four outcomes always, the others where there are any
    /// (`train 3 · walk_past 5 · reversal 0 · undetermined 0 · broke up 1`).
    pub fn line(&self, name: fn(End) -> &'static str, between: &str) -> String {
        self.iter()
            .filter(|&(e, n)| e.always_shown() || n > 0)
            .map(|(e, n)| format!("{} {n}", name(e)))
            .collect::<Vec<_>>()
            .join(between)
    }
}

/// Counts of the ends named, every other end zero.
impl FromIterator<(End, u64)> for Tally {
    fn from_iter<I: IntoIterator<Item = (End, u64)>>(counts: I) -> Tally {
        let mut t = Tally::default();
        for (e, n) in counts {
            t.add(e, n);
        }
        t
    }
}

/// Serialised as a map from [`End::name`] to the value.
impl<T: Serialize + Copy> Serialize for PerEnd<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_keyed(self, End::name, s)
    }
}

impl<'de, T: Deserialize<'de> + Copy + Default> Deserialize<'de> for PerEnd<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_keyed(d, End::name)
    }
}

fn serialize_keyed<T: Serialize + Copy, S: Serializer>(
    v: &PerEnd<T>,
    key: fn(End) -> &'static str,
    s: S,
) -> Result<S::Ok, S::Error> {
    let mut m = s.serialize_map(Some(End::COUNT))?;
    for (e, x) in v.iter() {
        m.serialize_entry(key(e), &x)?;
    }
    m.end()
}

/// Reads a map keyed by `key`: a missing end is `T::default()`, other keys are passed over
/// (so that a tally flattened into a struct leaves the struct's own fields alone).
fn deserialize_keyed<'de, T, D>(d: D, key: fn(End) -> &'static str) -> Result<PerEnd<T>, D::Error>
where
    T: Deserialize<'de> + Copy + Default,
    D: Deserializer<'de>,
{
    struct Keyed<T>(fn(End) -> &'static str, std::marker::PhantomData<T>);
    impl<'de, T: Deserialize<'de> + Copy + Default> Visitor<'de> for Keyed<T> {
        type Value = PerEnd<T>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a count for each end")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<PerEnd<T>, A::Error> {
            let mut out = PerEnd([T::default(); End::COUNT]);
            while let Some(k) = m.next_key::<String>()? {
                match End::ALL.into_iter().find(|&e| (self.0)(e) == k) {
                    Some(e) => out[e] = m.next_value()?,
                    None => {
                        m.next_value::<serde::de::IgnoredAny>()?;
                    }
                }
            }
            Ok(out)
        }
    }
    d.deserialize_map(Keyed(key, std::marker::PhantomData))
}

/// A [`Tally`] keyed by [`End::count_key`] (`n_walk`), for `#[serde(with)]`.
pub mod count_keys {
    use super::*;

    pub fn serialize<S: Serializer>(t: &Tally, s: S) -> Result<S::Ok, S::Error> {
        serialize_keyed(t, End::count_key, s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Tally, D::Error> {
        deserialize_keyed(d, End::count_key)
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
    use super::*;

    #[test]
    fn an_end_s_index_is_its_place_in_all() {
        for (i, e) in End::ALL.iter().enumerate() {
            assert_eq!(e.index(), i);
        }
    }

    #[test]
    fn every_stored_pair_is_one_end_and_back() {
        for e in End::ALL {
            let (verdict, outcome) = match e.is_collision() {
                true => (
                    "ok",
                    Some(if e == End::CollisionBreakup {
                        "breakup"
                    } else {
                        e.name()
                    }),
                ),
                false => (e.name(), None),
            };
            assert_eq!(End::of(verdict, outcome), Some(e));
        }
        assert_eq!(End::of("ok", None), None);
        assert_eq!(End::of("ok", Some("sideways")), None);
    }

    #[test]
    fn a_tally_reads_back_what_it_wrote_under_either_keys() {
        let mut t = Tally::default();
        t.add(End::WalkPast, 5);
        t.add(End::CollisionBreakup, 1);
        t.add(End::Unstable, 2);
        assert_eq!((t.total(), t.collisions(), t.by_prep()), (8, 6, 2));
        let json = serde_json::to_value(t).unwrap();
        assert_eq!(json["walk_past"], 5);
        assert_eq!(serde_json::from_value::<Tally>(json).unwrap(), t);
        #[derive(Serialize, Deserialize)]
        struct Row {
            beta: f64,
            #[serde(flatten, with = "count_keys")]
            tally: Tally,
        }
        let row = serde_json::to_value(Row {
            beta: 10.0,
            tally: t,
        })
        .unwrap();
        assert_eq!(
            (row["n_walk"].as_u64(), row["beta"].as_f64()),
            (Some(5), Some(10.0))
        );
        let back: Row = serde_json::from_value(row).unwrap();
        assert_eq!((back.tally, back.beta), (t, 10.0));
        assert_eq!(
            t.line(End::words, " · "),
            "training 0 · walk-past 5 · reversal 0 · undetermined 0 · unstable 2 · broke up 1"
        );
    }
}
