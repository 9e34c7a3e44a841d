//! `cellsweep relax`: the deterministic relaxation of SPEC stage 1.

use anyhow::Context;
use cellsweep_solver::{relax, Fibers, FieldSummary, Lattice, Protocol};

use super::model;
use crate::cli::RelaxArgs;
use crate::progress::StageBars;

pub fn run(args: RelaxArgs) -> anyhow::Result<()> {
    let params = model::params(&args.model)?;
    let single = model::single_lattice(&args.model)?;
    let protocol = Protocol {
        single_lattice: single,
        pair_lattice: [2 * single[0], single[1]],
        ..Protocol::default()
    };
    let stage = protocol.validate(&params).context("invalid parameters")?;
    let steps = args.steps.unwrap_or(stage.relax);
    let lat = Lattice::new(single[0], single[1]);
    let fibers = Fibers::new(&params, single[1]);
    let mut bars = StageBars::new();
    let cell = relax(&params, &lat, &fibers, steps, &mut bars, true);
    bars.finish();
    let summary = FieldSummary::of(&lat, &fibers, &cell.phi, steps);
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        println!("relaxed {} steps on {}x{}:", steps, lat.nx, lat.ny);
        println!("  sum phi            {:.10}", summary.sum_phi);
        println!(
            "  area S             {:.10}   (pi R0^2 = {:.4})",
            summary.area,
            params.target_area()
        );
        println!("  adhesive area Ad   {:.10}", summary.adhesive_area);
        println!(
            "    bottom / top     {:.10} / {:.10}",
            summary.adhesive_area_bottom, summary.adhesive_area_top
        );
        println!(
            "  centroid           ({:.6}, {:.6})",
            summary.xbar, summary.ybar
        );
        println!("  max phi            {:.10}", summary.max_phi);
    }
    Ok(())
}
