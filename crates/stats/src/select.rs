//! Choosing points by their axes: `NAME=VALUE` conditions (`alpha=0.1,beta=46`, `R0=32`,
//! `geometry=two`), all of which must hold. The one selector of every command that picks
//! points: `table`/`fit`/`plot --where`, `replay --point`, `reset --point` and `--points`.

/// One `NAME=VALUE`: an axis and the value it must have.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    pub name: String,
    pub value: f64,
}

/// Why a selector could not be read, or does not fit the points it is meant for.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SelectError {
    #[error("{0:?} is not NAME=VALUE (e.g. alpha=0.1 or R0=32)")]
    NotPair(String),
    #[error("{0:?} names no axis")]
    NoName(String),
    #[error("{name} = {value:?} is not a finite number")]
    NotFinite { name: String, value: String },
    #[error("names no axis (write e.g. alpha=0.1,beta=46)")]
    Empty,
    #[error("{0} is given twice")]
    Twice(String),
    #[error("{name:?} is not an axis of {owner} (its axes: {axes})")]
    NotAnAxis {
        name: String,
        owner: String,
        axes: String,
    },
}

impl Condition {
    /// The condition `name = value` (`geometry` takes `one` or `two`), the value finite.
    pub fn new(name: &str, value: &str) -> Result<Condition, SelectError> {
        let name = name.trim();
        if name.is_empty() {
            return Err(SelectError::NoName(format!("={value}")));
        }
        let value = match (name, value.trim()) {
            ("geometry", "one") => 1.0,
            ("geometry", "two") => 2.0,
            (_, v) => v
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| SelectError::NotFinite {
                    name: name.to_string(),
                    value: v.to_string(),
                })?,
        };
        Ok(Condition {
            name: name.to_string(),
            value,
        })
    }

    /// Whether `have` is this condition's value: to 1e-9 of its size (0.0833333 typed for
    /// 1/12 does not match, 0.083333333333 does).
    pub fn holds(&self, have: f64) -> bool {
        (have - self.value).abs() <= 1e-9 * self.value.abs().max(1.0)
    }
}

impl std::str::FromStr for Condition {
    type Err = SelectError;

    /// `NAME=VALUE`.
    fn from_str(s: &str) -> Result<Condition, SelectError> {
        let (name, value) = s
            .split_once('=')
            .ok_or_else(|| SelectError::NotPair(s.to_string()))?;
        Condition::new(name, value)
    }
}

/// Points chosen by some of their axes: every condition must hold; an axis left out matches
/// every value of it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Selector {
    pub conditions: Vec<Condition>,
}

impl Selector {
    /// `alpha=0.1,beta=46`: at least one condition, no axis twice.
    pub fn parse(text: &str) -> Result<Selector, SelectError> {
        let conditions = text
            .split(',')
            .filter(|t| !t.trim().is_empty())
            .map(str::parse)
            .collect::<Result<Vec<Condition>, _>>()?;
        Selector::of(conditions)
    }

    /// A selector of `conditions`: at least one, no axis twice.
    pub fn of(conditions: Vec<Condition>) -> Result<Selector, SelectError> {
        if conditions.is_empty() {
            return Err(SelectError::Empty);
        }
        for (i, c) in conditions.iter().enumerate() {
            if conditions[..i].iter().any(|d| d.name == c.name) {
                return Err(SelectError::Twice(c.name.clone()));
            }
        }
        Ok(Selector { conditions })
    }

    /// Refuse a condition on an axis that is not in `axes` (of `owner`, e.g. `the sweep`):
    /// ignoring it would select every value of that axis.
    pub fn check_axes(&self, axes: &[&str], owner: &str) -> Result<(), SelectError> {
        match self
            .conditions
            .iter()
            .find(|c| !axes.contains(&c.name.as_str()))
        {
            Some(c) => Err(SelectError::NotAnAxis {
                name: c.name.clone(),
                owner: owner.to_string(),
                axes: axes.join(", "),
            }),
            None => Ok(()),
        }
    }

    /// Whether a point whose axis values `value_of` gives is selected (an axis it lacks fails
    /// its condition).
    pub fn matches(&self, value_of: impl Fn(&str) -> Option<f64>) -> bool {
        self.conditions
            .iter()
            .all(|c| value_of(&c.name).is_some_and(|v| c.holds(v)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conditions_parse_names_and_values() {
        let c: Condition = "R0=32".parse().unwrap();
        assert_eq!((c.name.as_str(), c.value), ("R0", 32.0));
        assert_eq!("geometry=two".parse::<Condition>().unwrap().value, 2.0);
        for bad in ["R0", "R0=NaN", "=3", "E0=$(touch x)", "alpha=inf"] {
            assert!(bad.parse::<Condition>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_selector_needs_one_axis_once_and_only_known_axes() {
        assert_eq!(Selector::parse(" , "), Err(SelectError::Empty));
        assert_eq!(
            Selector::parse("alpha=0.1,alpha=0.2"),
            Err(SelectError::Twice("alpha".into()))
        );
        let s = Selector::parse("alpha=0.1,R0=32").unwrap();
        assert!(s.check_axes(&["alpha", "beta", "R0"], "the sweep").is_ok());
        let e = s.check_axes(&["alpha", "beta"], "the sweep").unwrap_err();
        assert_eq!(
            e.to_string(),
            "\"R0\" is not an axis of the sweep (its axes: alpha, beta)"
        );
    }

    #[test]
    fn a_point_matches_when_every_condition_holds_to_1e_9() {
        let s = Selector::parse("alpha=0.083333333333,beta=46").unwrap();
        let at = |alpha: f64| {
            move |n: &str| match n {
                "alpha" => Some(alpha),
                "beta" => Some(46.0),
                _ => None,
            }
        };
        assert!(s.matches(at(1.0 / 12.0)));
        assert!(!s.matches(at(0.0833333)));
        // An axis the point lacks fails its condition.
        assert!(!Selector::parse("R0=32").unwrap().matches(at(0.1)));
    }
}
