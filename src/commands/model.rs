//! Turning command-line model arguments into solver parameters and protocol.

use anyhow::{bail, Context};
use cellsweep_solver::{ClassifierSettings, Params, Protocol};

use crate::cli::ModelArgs;

/// Parse `NXxNY`.
pub fn parse_lattice(s: &str) -> anyhow::Result<[usize; 2]> {
    let (a, b) = s
        .split_once(['x', 'X'])
        .with_context(|| format!("lattice {s:?} must look like 200x200"))?;
    let nx = a
        .trim()
        .parse()
        .with_context(|| format!("lattice {s:?}: bad width"))?;
    let ny = b
        .trim()
        .parse()
        .with_context(|| format!("lattice {s:?}: bad height"))?;
    Ok([nx, ny])
}

/// Split `NAME=VALUE` into a name and a number.
fn name_value(s: &str) -> anyhow::Result<(&str, f64)> {
    let (name, value) = s
        .split_once('=')
        .with_context(|| format!("{s:?} must look like NAME=VALUE"))?;
    let v: f64 = value
        .trim()
        .parse()
        .with_context(|| format!("{name} = {value:?} is not a number"))?;
    Ok((name.trim(), v))
}

/// The parameters named on the command line (everything else at the paper's defaults).
pub fn params(args: &ModelArgs) -> anyhow::Result<Params> {
    let mut p = Params {
        alpha: args.alpha,
        L: args.spacing,
        geometry: args.geometry,
        ..Params::default()
    };
    for s in &args.set {
        let (name, v) = name_value(s)?;
        p.set(name, v).map_err(anyhow::Error::msg)?;
    }
    Ok(p)
}

/// The single-cell lattice named on the command line, or the default.
pub fn single_lattice(args: &ModelArgs) -> anyhow::Result<[usize; 2]> {
    match &args.lattice {
        Some(s) => parse_lattice(s),
        None => Ok(Protocol::default().single_lattice),
    }
}

/// Classifier settings with `NAME=VALUE` overrides.
pub fn classifier(overrides: &[String]) -> anyhow::Result<ClassifierSettings> {
    let mut c = ClassifierSettings::default();
    for s in overrides {
        let (name, v) = name_value(s)?;
        let slot = match name {
            "contact_overlap" => &mut c.contact_overlap,
            "speed_fraction" => &mut c.speed_fraction,
            "min_speed" => &mut c.min_speed,
            "velocity_window" => &mut c.velocity_window,
            "sustain_window" => &mut c.sustain_window,
            "walk_past_margin" => &mut c.walk_past_margin,
            _ => bail!("unknown classifier setting {name:?}"),
        };
        *slot = v;
    }
    Ok(c)
}
