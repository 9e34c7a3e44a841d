//! Which points of a result set `table`, `fit` and `plot` read: `--L`, `--sigma`, and
//! `--where NAME=VALUE` for any axis (alpha, beta, L, sigma, or one of the sweep's others such
//! as R0 or E0).

use anyhow::bail;
use clap::Args;

use cellsweep_report::Results;
use cellsweep_stats::Counts;

/// Only the points at these axis values.
#[derive(Debug, Args, Clone, Default)]
pub struct Selection {
    /// Only this fiber spacing.
    #[arg(long = "L")]
    pub spacing: Option<u32>,
    /// Only this adhesion.
    #[arg(long)]
    pub sigma: Option<f64>,
    /// Only the points where axis NAME has VALUE (`--where R0=32`, `--where geometry=two`);
    /// give it again to narrow further.
    #[arg(long = "where", value_name = "NAME=VALUE", value_parser = parse_condition)]
    pub conditions: Vec<Condition>,
}

/// One `--where NAME=VALUE`.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    pub name: String,
    pub value: f64,
}

pub(crate) fn parse_condition(s: &str) -> Result<Condition, String> {
    let Some((name, value)) = s.split_once('=') else {
        return Err(format!("{s:?} is not NAME=VALUE (e.g. R0=32)"));
    };
    let name = name.trim().to_string();
    let value = match (name.as_str(), value.trim()) {
        ("geometry", "one") => 1.0,
        ("geometry", "two") => 2.0,
        (_, v) => v
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{name} = {v:?} is not a finite number"))?,
    };
    if name.is_empty() {
        return Err(format!("{s:?} names no axis"));
    }
    Ok(Condition { name, value })
}

/// The value of axis `name` at point `c`, if the point has that axis.
fn axis_value(c: &Counts, name: &str) -> Option<f64> {
    match name {
        "alpha" => Some(c.alpha),
        "beta" => Some(c.beta),
        "L" => Some(c.L as f64),
        "sigma" => Some(c.sigma),
        other => c.others.get(other),
    }
}

/// Equal to a value typed on the command line: to 1e-9 of its size (0.0833333 typed for
/// 1/12 does not match, 0.083333333333 does).
fn matches(have: f64, want: f64) -> bool {
    (have - want).abs() <= 1e-9 * want.abs().max(1.0)
}

impl Selection {
    pub fn is_empty(&self) -> bool {
        self.spacing.is_none() && self.sigma.is_none() && self.conditions.is_empty()
    }

    /// `results` with only the selected points; an error naming the problem if an axis is not
    /// in the results or nothing matches.
    pub fn apply(&self, results: Results) -> anyhow::Result<Results> {
        if self.is_empty() {
            return Ok(results);
        }
        let mut conditions = self.conditions.clone();
        conditions.extend(self.spacing.map(|l| Condition {
            name: "L".into(),
            value: l as f64,
        }));
        conditions.extend(self.sigma.map(|v| Condition {
            name: "sigma".into(),
            value: v,
        }));
        for c in &conditions {
            if !results
                .counts
                .iter()
                .any(|p| axis_value(p, &c.name).is_some())
            {
                let mut axes = vec!["alpha", "beta", "L", "sigma"];
                if let Some(p) = results.counts.first() {
                    axes.extend(p.others.0.iter().map(|(n, _)| n.as_str()));
                }
                bail!(
                    "--where {}: {} has no such axis (its axes: {})",
                    c.name,
                    results.name,
                    axes.join(", ")
                );
            }
        }
        let name = results.name.clone();
        let kept = results.only(|p| {
            conditions
                .iter()
                .all(|c| axis_value(p, &c.name).is_some_and(|v| matches(v, c.value)))
        });
        if kept.counts.is_empty() {
            let asked: Vec<String> = conditions
                .iter()
                .map(|c| format!("{} = {}", c.name, c.value))
                .collect();
            bail!("no points match {} in {name}", asked.join(", "));
        }
        Ok(kept)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conditions_parse_names_and_values() {
        assert_eq!(
            parse_condition("R0=32"),
            Ok(Condition {
                name: "R0".into(),
                value: 32.0
            })
        );
        assert_eq!(parse_condition("geometry=two").unwrap().value, 2.0);
        assert!(parse_condition("R0").is_err());
        assert!(parse_condition("R0=NaN").is_err());
        assert!(parse_condition("=3").is_err());
        assert!(parse_condition("E0=$(touch x)").is_err());
    }
}
