//! A prep's verdict ([`PrepVerdict`]) and a collision's outcome (an [`End`] that is a
//! collision) across SQL: stored by name, read back checked, so that a name that is neither is
//! an error where it is read, never a default.

use cellsweep_stats::{End, PrepVerdict};
use rusqlite::types::Type;
use rusqlite::Row;

#[derive(Debug, thiserror::Error)]
#[error("{0:?} is not a stored {1}")]
struct NotAKind(String, &'static str);

fn refused(i: usize, name: &str, what: &'static str) -> rusqlite::Error {
    rusqlite::Error::FromSqlConversionFailure(i, Type::Text, Box::new(NotAKind(name.into(), what)))
}

/// The prep verdict in column `i`.
pub(crate) fn verdict_at(r: &Row, i: usize) -> rusqlite::Result<PrepVerdict> {
    let name: String = r.get(i)?;
    PrepVerdict::parse(&name).ok_or_else(|| refused(i, &name, "prep verdict"))
}

/// The prep verdict in column `i`, where there is one.
pub(crate) fn maybe_verdict_at(r: &Row, i: usize) -> rusqlite::Result<Option<PrepVerdict>> {
    match r.get::<_, Option<String>>(i)? {
        None => Ok(None),
        Some(name) => PrepVerdict::parse(&name)
            .map(Some)
            .ok_or_else(|| refused(i, &name, "prep verdict")),
    }
}

/// The collision outcome in column `i` (NULL or empty: none).
pub(crate) fn outcome_at(r: &Row, i: usize) -> rusqlite::Result<Option<End>> {
    match r.get::<_, Option<String>>(i)? {
        None => Ok(None),
        Some(name) if name.is_empty() => Ok(None),
        Some(name) => End::of_outcome(&name)
            .map(Some)
            .ok_or_else(|| refused(i, &name, "collision outcome")),
    }
}

/// A collision outcome's stored name (NULL for none).
pub(crate) fn outcome_name(outcome: Option<End>) -> Option<&'static str> {
    outcome.and_then(End::stored_outcome)
}

/// How a stored result ended: its collision's outcome, else its prep's verdict (an `ok`
/// verdict without an outcome is no end).
pub(crate) fn end_of(verdict: PrepVerdict, outcome: Option<End>) -> Option<End> {
    outcome.or(verdict.end())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every verdict and collision outcome reads back as written; a name that is neither is an
    /// error naming it (the counts used to read an unknown outcome as a breakup).
    #[test]
    fn stored_kinds_read_back_and_unknown_names_are_errors() {
        let conn = rusqlite::Connection::open_in_memory().unwrap();
        let read =
            |sql: &str| conn.query_row(sql, [], |r| Ok((verdict_at(r, 0)?, outcome_at(r, 1)?)));
        for v in PrepVerdict::ALL {
            let got = read(&format!("SELECT '{}', NULL", v.as_str())).unwrap();
            assert_eq!(got, (v, None));
        }
        for e in End::ALL.into_iter().filter(|e| e.is_collision()) {
            let name = outcome_name(Some(e)).unwrap();
            let got = read(&format!("SELECT 'ok', '{name}'")).unwrap();
            assert_eq!(got, (PrepVerdict::Ok, Some(e)));
            assert_eq!(end_of(PrepVerdict::Ok, Some(e)), Some(e));
        }
        assert_eq!(end_of(PrepVerdict::Unstable, None), Some(End::Unstable));
        assert_eq!(end_of(PrepVerdict::Ok, None), None);
        let err = read("SELECT 'fine', NULL").unwrap_err().to_string();
        assert!(
            err.contains("\"fine\" is not a stored prep verdict"),
            "{err}"
        );
        let err = read("SELECT 'ok', 'trained'").unwrap_err().to_string();
        assert!(
            err.contains("\"trained\" is not a stored collision outcome"),
            "{err}"
        );
    }
}
