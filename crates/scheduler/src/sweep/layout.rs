//! The sweep's `[grid]` built into a [`Grid`]: the paper's four axes, the fiber spacings
//! checked as lattice distances, and any other SPEC parameter as an axis ([`super::others`]).

use cellsweep_solver::{Geometry, Params};
use toml::Table;

use super::{others, Ctx, Grid, MAX_SITES};
use crate::error::SweepError;
use crate::grid as axis_spec;
use crate::sweep_file::{self, AxisFile};

/// `[grid]`: alpha, beta, L and sigma, each required, and the other axes. `in_params`: the
/// keys `[params]` set; `geometry_given`: the file set geometry at the top level; `params`:
/// the fixed parameters (L must be even where any point has two fibers).
pub(super) fn grid(
    table: Table,
    in_params: &[String],
    geometry_given: bool,
    params: &Params,
    cx: &Ctx,
) -> Result<Grid, SweepError> {
    let (g, written) = sweep_file::grid(table, cx.file)?;
    let others = others::other_axes(written, in_params, geometry_given, cx)?;
    let axis = |spec: Option<AxisFile>, key: &str| -> Result<Vec<f64>, SweepError> {
        let full = format!("grid.{key}");
        let spec = cx.given(spec, &full)?;
        axis_spec::axis(&spec)
            .map(|a| a.values)
            .map_err(|p| cx.err(&full, p.to_string()))
    };
    let two_fibers = params.geometry == Geometry::Two
        || others
            .iter()
            .any(|a| a.name == "geometry" && a.values.contains(&2.0));
    Ok(Grid {
        alpha: axis(g.alpha, "alpha")?,
        beta: axis(g.beta, "beta")?,
        L: spacings(&axis(g.L, "L")?, two_fibers, cx)?,
        sigma: axis(g.sigma, "sigma")?,
        others,
    })
}

/// The fiber spacings of `grid.L`: whole, non-negative, within the lattice limit, and even on
/// two fibers.
fn spacings(values: &[f64], two_fibers: bool, cx: &Ctx) -> Result<Vec<u32>, SweepError> {
    let mut spacing = Vec::new();
    for &l in values {
        if l > MAX_SITES as f64 {
            return Err(cx.err("grid.L", format!("{l} is more than {MAX_SITES} sites")));
        }
        if l < 0.0 {
            return Err(cx.err(
                "grid.L",
                format!("{l} is negative: a fiber spacing is a distance, in lattice sites"),
            ));
        }
        if l.fract() != 0.0 {
            return Err(cx.err(
                "grid.L",
                format!("{l} is not a whole number of lattice sites"),
            ));
        }
        if two_fibers && !(l as u64).is_multiple_of(2) {
            return Err(cx.err(
                "grid.L",
                format!("{l} is odd (fibers sit at Ny/2 -+ L/2: L must be even)"),
            ));
        }
        spacing.push(l as u32);
    }
    Ok(spacing)
}
