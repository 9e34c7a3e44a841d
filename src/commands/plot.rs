//! `cellsweep plot`: phase diagrams, frequency heat maps with beta_crit lines, free speeds.

use cellsweep_report::plot_files::write_plots;

use crate::cli::PlotArgs;

pub fn run(args: PlotArgs) -> anyhow::Result<()> {
    let results = args.select.apply(args.source.load()?)?;
    for f in write_plots(&results, &args.out)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}
