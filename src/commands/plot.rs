//! `cellsweep plot`: phase diagrams, frequency heat maps with beta_crit lines, free speeds.

use cellsweep_report::plot_files::{write_plane_plots, write_plots};

use crate::cli::PlotArgs;

pub fn run(args: PlotArgs) -> anyhow::Result<()> {
    let results = args.select.apply(args.source.load()?)?;
    let plane = args.plane.plane();
    let written = if plane.is_paper() {
        write_plots(&results, &args.out)?
    } else {
        write_plane_plots(&results, &plane, &args.out)?
    };
    for f in written {
        println!("wrote {}", f.display());
    }
    Ok(())
}
