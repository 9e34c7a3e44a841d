//! Grid axes: ranges that include both ends without floating-point drift, or explicit lists.

use toml::Value;

use crate::sweep::number;

/// The values along one grid axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    pub values: Vec<f64>,
}

/// Most points one axis may have.
pub const MAX_AXIS_POINTS: usize = 1_000;

/// A value rounded to 12 significant digits: `0.10 + 5 x 0.02` becomes exactly `0.2`.
pub fn clean(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// `from, from + step, ..., to`, both ends included; `(to - from) / step` must be whole.
pub fn range(from: f64, to: f64, step: f64) -> Result<Vec<f64>, String> {
    if !(from.is_finite() && to.is_finite() && step.is_finite()) {
        return Err("from, to and step must be finite numbers".into());
    }
    if step <= 0.0 {
        return Err(format!("step = {step} must be > 0"));
    }
    if to < from {
        return Err(format!("to = {to} is below from = {from}"));
    }
    let n = (to - from) / step;
    // (n is finite here: from, to and step are, and step > 0.)
    if n >= MAX_AXIS_POINTS as f64 {
        return Err(format!(
            "(to - from) / step = {n:e}: more than {MAX_AXIS_POINTS} points"
        ));
    }
    let k = n.round();
    if (n - k).abs() > 1e-6 {
        return Err(format!(
            "(to - from) / step = {n} is not a whole number, so {to} is not on the range"
        ));
    }
    if k as usize + 1 > MAX_AXIS_POINTS {
        return Err(format!("{} points is too many", k as usize + 1));
    }
    Ok((0..=k as usize)
        .map(|i| clean(from + i as f64 * step))
        .collect())
}

/// An axis from a TOML value: a number, a non-empty list of numbers, or `{ from, to, step }`.
pub fn parse_axis(v: &Value) -> Result<Axis, String> {
    let values = match v {
        Value::Array(items) => {
            if items.is_empty() {
                return Err("is empty".into());
            }
            if items.len() > MAX_AXIS_POINTS {
                return Err(format!(
                    "{} values: more than {MAX_AXIS_POINTS}",
                    items.len()
                ));
            }
            let mut out = Vec::with_capacity(items.len());
            for item in items {
                match number(item) {
                    Some(x) if x.is_finite() => out.push(clean(x)),
                    _ => return Err(format!("{item} is not a number")),
                }
            }
            out
        }
        Value::Table(t) => {
            for key in t.keys() {
                if !["from", "to", "step"].contains(&key.as_str()) {
                    return Err(format!(
                        "unknown range key {key:?} (expected from, to, step)"
                    ));
                }
            }
            let get = |k: &str| {
                t.get(k)
                    .and_then(number)
                    .ok_or_else(|| format!("range needs a number {k:?}"))
            };
            range(get("from")?, get("to")?, get("step")?)?
        }
        other => match number(other) {
            Some(x) if x.is_finite() => vec![clean(x)],
            _ => return Err("must be a number, a list of numbers, or { from, to, step }".into()),
        },
    };
    for (i, a) in values.iter().enumerate() {
        if values[..i].contains(a) {
            return Err(format!("{a} appears twice"));
        }
    }
    Ok(Axis { values })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_include_both_ends_without_drift() {
        let a = range(0.10, 0.20, 0.02).unwrap();
        assert_eq!(a, vec![0.1, 0.12, 0.14, 0.16, 0.18, 0.2]);
        assert_eq!(a[5], 0.2, "0.10 + 5 x 0.02 is exactly 0.2");
        assert_eq!(range(10.0, 50.0, 4.0).unwrap().len(), 11);
        assert_eq!(range(5.0, 5.0, 1.0).unwrap(), vec![5.0]);
        assert_eq!(range(0.1, 0.3, 0.1).unwrap(), vec![0.1, 0.2, 0.3]);
    }

    #[test]
    fn bad_ranges_say_why() {
        assert!(range(0.1, 0.2, 0.0).unwrap_err().contains("step"));
        assert!(range(0.2, 0.1, 0.02).unwrap_err().contains("below"));
        assert!(range(0.1, 0.2, 0.03).unwrap_err().contains("whole"));
        assert!(range(0.1, 0.2, 1e-300)
            .unwrap_err()
            .contains("more than 1000"));
        assert!(range(0.0, 1000.0, 1.0)
            .unwrap_err()
            .contains("more than 1000"));
        assert!(parse_axis(&Value::Array(vec![]))
            .unwrap_err()
            .contains("empty"));
        let dup: Value = toml::from_str::<toml::Table>("a = [1, 2, 1]").unwrap()["a"].clone();
        assert!(parse_axis(&dup).unwrap_err().contains("twice"));
    }
}
