//! `cellsweep plot`: phase diagrams, frequency heat maps with beta_crit lines, free speeds.

use std::path::{Path, PathBuf};

use anyhow::Context;
use cellsweep_plot::Figure;
use cellsweep_report::{figures, Results};
use cellsweep_stats::fit_line;

use super::counts;
use crate::cli::PlotArgs;

fn write(fig: &Figure, dir: &Path, stem: &str, written: &mut Vec<PathBuf>) -> anyhow::Result<()> {
    let svg = dir.join(format!("{stem}.svg"));
    std::fs::write(&svg, fig.to_svg())
        .with_context(|| format!("cannot write {}", svg.display()))?;
    let png = dir.join(format!("{stem}.png"));
    std::fs::write(&png, fig.to_png(2.0)?)
        .with_context(|| format!("cannot write {}", png.display()))?;
    written.extend([svg, png]);
    Ok(())
}

/// Write every picture of `results` into `dir`; returns the files written.
pub fn write_plots(results: &Results, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let fitted = fit_line(&results.counts, &results.scales, 0, 1).ok();
    let mut written = Vec::new();
    for (l, sigma) in figures::diagrams(&results.counts) {
        let fig = figures::diagram_of(results, (l, sigma), fitted.as_ref());
        write(&fig, dir, &format!("phase-L{l}-sigma{sigma}"), &mut written)?;
    }
    write(&figures::speed_of(results), dir, "free-speed", &mut written)?;
    Ok(written)
}

pub fn run(args: PlotArgs) -> anyhow::Result<()> {
    let results = counts::load(&args.source)?;
    for f in write_plots(&results, &args.out)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}
