//! Grid axes: ranges that include both ends without floating-point drift, or explicit lists.

use crate::error::AxisError;
use crate::sweep_file::AxisFile;

/// The values along one grid axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    pub values: Vec<f64>,
}

pub use crate::limits::MAX_AXIS_POINTS;

/// A value rounded to 12 significant digits: `0.10 + 5 x 0.02` becomes exactly `0.2`.
pub fn clean(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// `from, from + step, ..., to`, both ends included; `(to - from) / step` must be whole.
pub fn range(from: f64, to: f64, step: f64) -> Result<Vec<f64>, AxisError> {
    if !(from.is_finite() && to.is_finite() && step.is_finite()) {
        return Err(AxisError::RangeNotFinite);
    }
    if step <= 0.0 {
        return Err(AxisError::StepNotPositive(step));
    }
    if to < from {
        return Err(AxisError::Reversed { from, to });
    }
    let n = (to - from) / step;
    // (n is finite here: from, to and step are, and step > 0.)
    if n >= MAX_AXIS_POINTS as f64 {
        return Err(AxisError::RangeTooLong(n));
    }
    let k = n.round();
    if (n - k).abs() > 1e-6 {
        return Err(AxisError::NotWhole { steps: n, to });
    }
    if k as usize + 1 > MAX_AXIS_POINTS {
        return Err(AxisError::RangeTooLong(n));
    }
    Ok((0..=k as usize)
        .map(|i| clean(from + i as f64 * step))
        .collect())
}

/// An axis as written in a sweep file, checked: a number, a non-empty list of distinct
/// finite numbers, or a range.
pub fn axis(spec: &AxisFile) -> Result<Axis, AxisError> {
    let values = match spec {
        AxisFile::One(x) => vec![*x],
        AxisFile::List(items) => {
            if items.is_empty() {
                return Err(AxisError::Empty);
            }
            if items.len() > MAX_AXIS_POINTS {
                return Err(AxisError::TooMany(items.len()));
            }
            items.clone()
        }
        AxisFile::Range { from, to, step } => range(*from, *to, *step)?,
    };
    if let Some(x) = values.iter().find(|x| !x.is_finite()) {
        return Err(AxisError::NotFinite(*x));
    }
    let values: Vec<f64> = values.into_iter().map(clean).collect();
    for (i, a) in values.iter().enumerate() {
        if values[..i].contains(a) {
            return Err(AxisError::Twice(*a));
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
        assert!(range(0.1, 0.2, 0.0)
            .unwrap_err()
            .to_string()
            .contains("step"));
        assert!(range(0.2, 0.1, 0.02)
            .unwrap_err()
            .to_string()
            .contains("below"));
        assert!(range(0.1, 0.2, 0.03)
            .unwrap_err()
            .to_string()
            .contains("whole"));
        assert!(range(0.1, 0.2, 1e-300)
            .unwrap_err()
            .to_string()
            .contains("more than 1000"));
        assert!(range(0.0, 1000.0, 1.0)
            .unwrap_err()
            .to_string()
            .contains("more than 1000"));
        assert!(axis(&AxisFile::List(vec![]))
            .unwrap_err()
            .to_string()
            .contains("empty"));
        let dup = AxisFile::List(vec![1.0, 2.0, 1.0]);
        assert!(axis(&dup).unwrap_err().to_string().contains("twice"));
        assert!(axis(&AxisFile::One(f64::NAN))
            .unwrap_err()
            .to_string()
            .contains("finite"));
    }
}
