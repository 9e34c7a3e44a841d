//! Which points of a result set `table`, `fit` and `plot` read: `--L`, `--sigma`, and
//! `--where NAME=VALUE` for any axis (alpha, beta, L, sigma, or one of the sweep's others such
//! as R0 or E0).

use anyhow::bail;
use clap::Args;

use cellsweep_report::Results;
use cellsweep_stats::{Condition, Selector};

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

/// `--where NAME=VALUE` (`cellsweep_stats::Condition`), as clap reads it.
pub(crate) fn parse_condition(s: &str) -> Result<Condition, String> {
    s.parse()
        .map_err(|e: cellsweep_stats::SelectError| e.to_string())
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
                .any(|p| p.axes().value(&c.name).is_some())
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
        let selector = Selector { conditions };
        let kept = results.only(|p| {
            let axes = p.axes();
            selector.matches(|name| axes.value(name))
        });
        if kept.counts.is_empty() {
            let asked: Vec<String> = selector
                .conditions
                .iter()
                .map(|c| format!("{} = {}", c.name, c.value))
                .collect();
            bail!("no points match {} in {name}", asked.join(", "));
        }
        Ok(kept)
    }
}
