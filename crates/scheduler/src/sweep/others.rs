//! The sweep's other grid axes: any SPEC parameter besides alpha, beta, L and sigma varied in
//! `[grid]` (SPEC section 2: "a sweep may vary any of them as a grid axis"), and the lattices
//! that follow R0 where it changes and the file gives none.
//!
//! A point's other axes are plain parameters of the point: its seeds derive from its
//! parameters as any point's do ([`crate::plan`]), so the points of `E0 = [1000, 3000]` at
//! E0 = 1000 run the very trajectories of a sweep with `E0 = 1000` in `[params]`, and a sweep
//! without other axes keeps its definition, points and seeds exactly.

use cellsweep_solver::{Geometry, Params, Protocol, PARAM_NAMES};
use cellsweep_stats::{Axes, Others};
use cellsweep_store::export::ExportRow;
use serde::{Deserialize, Serialize};

use super::{Ctx, Sweep};
use crate::error::SweepError;
use crate::grid;
use crate::sweep_file::{OtherAxisFile, ProtocolFile};

/// One grid axis beyond the paper's four: a SPEC parameter and its values (geometry as 1 for
/// one fiber, 2 for two).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OtherAxis {
    pub name: String,
    pub values: Vec<f64>,
}

/// The other axes of a `[grid]`, checked, in the order of SPEC section 2's table (so that the
/// order they were written in does not change the sweep). `in_params`: the keys `[params]`
/// set; `geometry_given`: the file set geometry at the top level.
pub(super) fn other_axes(
    written: Vec<(String, OtherAxisFile)>,
    in_params: &[String],
    geometry_given: bool,
    cx: &Ctx,
) -> Result<Vec<OtherAxis>, SweepError> {
    let mut out = Vec::new();
    for (name, axis) in written {
        let key = format!("grid.{name}");
        if in_params.contains(&name) {
            return Err(cx.err(key, "also set in [params]: give it in one place"));
        }
        let values = match axis {
            OtherAxisFile::Geometries(list) => {
                if geometry_given {
                    return Err(cx.err(key, "also set at the top level: give it in one place"));
                }
                if list.is_empty() {
                    return Err(cx.err(key, "an empty list"));
                }
                let mut values: Vec<f64> = Vec::new();
                for g in list {
                    let v = match g {
                        Geometry::One => 1.0,
                        Geometry::Two => 2.0,
                    };
                    if values.contains(&v) {
                        return Err(cx.err(key, format!("{g} is listed twice")));
                    }
                    values.push(v);
                }
                values
            }
            OtherAxisFile::Numbers(spec) => {
                grid::axis(&spec)
                    .map_err(|p| cx.err(&key, p.to_string()))?
                    .values
            }
        };
        out.push(OtherAxis { name, values });
    }
    let rank = |n: &str| PARAM_NAMES.iter().position(|k| *k == n);
    out.sort_by_key(|a| rank(&a.name));
    Ok(out)
}

/// Sites across a lattice that keeps the paper's proportions at radius `r0`: 5 R0 (200 at
/// R0 = 40), rounded up to even (SPEC section 2).
pub fn proportional_side(r0: f64) -> usize {
    let n = (5.0 * r0).ceil().max(2.0) as usize;
    n + n % 2
}

/// Whether the lattices follow R0 ([`Sweep::protocol_for`]): R0 differs from SPEC's 40 or is
/// an axis, and `[protocol]` sets neither lattice.
pub(super) fn lattices_follow_r0(
    params: &Params,
    grid: &super::Grid,
    protocol: Option<&ProtocolFile>,
) -> bool {
    let r0_changes =
        params.R0 != Params::default().R0 || grid.others.iter().any(|a| a.name == "R0");
    let lattice_given =
        protocol.is_some_and(|p| p.single_lattice.is_some() || p.pair_lattice.is_some());
    r0_changes && !lattice_given
}

/// An exported row whose parameters do not read as a point of the sweep.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct RowAxesError(pub String);

impl Sweep {
    /// Every combination of the other axes' values, the first axis outermost; one empty
    /// combination for a sweep without other axes.
    pub fn other_values(&self) -> Vec<Others> {
        let mut all = vec![Others::default()];
        for axis in &self.grid.others {
            all = all
                .into_iter()
                .flat_map(|o| {
                    axis.values.iter().map(move |&v| {
                        let mut o = o.clone();
                        o.0.push((axis.name.clone(), v));
                        o
                    })
                })
                .collect();
        }
        all
    }

    /// The axes of the point with parameters `p`.
    pub fn axes_of(&self, p: &Params) -> Axes {
        Axes {
            alpha: p.alpha,
            beta: p.beta,
            L: p.L,
            sigma: p.sigma,
            others: Others(
                self.grid
                    .others
                    .iter()
                    .map(|a| (a.name.clone(), p.get(&a.name).unwrap_or(f64::NAN)))
                    .collect(),
            ),
        }
    }

    /// The sweep's fixed parameters with the other axes' values `others`.
    pub(super) fn with_others(&self, others: &Others) -> Params {
        let mut p = self.params.clone();
        for (name, v) in &others.0 {
            // Names and values come from this sweep's own checked grid (or a row's point
            // checked against it), which `Params::set` takes: only an unknown name, a
            // fractional L or a geometry other than 1 or 2 could be refused.
            if p.set(name, *v).is_err() {
                debug_assert!(false, "{name} = {v} is not a parameter value");
            }
        }
        p
    }

    /// The protocol of the point with parameters `p`: the sweep's, with lattices of the
    /// paper's proportions at the point's R0 where the sweep asks for that
    /// (`lattices_follow_r0`).
    pub fn protocol_for(&self, p: &Params) -> Protocol {
        let mut protocol = self.protocol.clone();
        if self.lattices_follow_r0 {
            let n = proportional_side(p.R0);
            protocol.single_lattice = [n, n];
            protocol.pair_lattice = [2 * n, n];
        }
        protocol
    }

    /// The other axes of the point whose stored configuration (a [`cellsweep_solver::Config`]
    /// as JSON) is `config`, as the store reads them ([`cellsweep_store::point_others`]);
    /// empty for a sweep without other axes (nothing is parsed then).
    pub fn others_of_config(&self, config: &str) -> Others {
        if self.grid.others.is_empty() {
            return Others::default();
        }
        let names: Vec<&str> = self.grid.others.iter().map(|a| a.name.as_str()).collect();
        cellsweep_store::point_others(config, &names)
    }

    /// The axes of an exported row's point: its paper axes, and the other axes' values out of
    /// its parameters (those it does not list are the defaults', as `export` leaves them out).
    pub fn axes_of_row(&self, row: &ExportRow) -> Result<Axes, RowAxesError> {
        let mut axes = Axes::new(row.alpha, row.beta, row.L, row.sigma);
        if self.grid.others.is_empty() {
            return Ok(axes);
        }
        let bad = |e: String| RowAxesError(format!("{axes}: parameters {}: {e}", row.params));
        let listed: serde_json::Value =
            serde_json::from_str(&row.params).map_err(|e| bad(e.to_string()))?;
        let mut p = serde_json::to_value(Params::default()).map_err(|e| bad(e.to_string()))?;
        if let (Some(p), Some(listed)) = (p.as_object_mut(), listed.as_object()) {
            for (k, v) in listed {
                p.insert(k.clone(), v.clone());
            }
        }
        let p: Params = serde_json::from_value(p).map_err(|e| bad(e.to_string()))?;
        axes.others = self.axes_of(&p).others;
        Ok(axes)
    }
}
