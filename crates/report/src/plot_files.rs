//! The pictures of `cellsweep plot` (and `run --plot`) written as files: each diagram, the
//! free-speed figure and the collapse figure (beta* against alpha~/L~), as SVG and PNG.

use std::path::{Path, PathBuf};

use cellsweep_plot::{Figure, RenderError};
use cellsweep_stats::{fit_line, Method};

use crate::collapse::{collapse_of, Placed};
use crate::whole_file::write_whole;
use crate::{figures, Results};

/// A picture that could not be drawn or written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("cannot create {path}: {source}")]
    Create {
        path: String,
        source: std::io::Error,
    },
    #[error("cannot write {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(transparent)]
    Plane(#[from] cellsweep_stats::PlaneError),
}

impl WriteError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        WriteError::Io {
            path: path.display().to_string(),
            source,
        }
    }

    /// `dir` could not be made.
    pub(crate) fn create(dir: &Path, source: std::io::Error) -> Self {
        WriteError::Create {
            path: dir.display().to_string(),
            source,
        }
    }
}

fn write(
    fig: &Figure,
    dir: &Path,
    stem: &str,
    written: &mut Vec<PathBuf>,
) -> Result<(), WriteError> {
    let svg = dir.join(format!("{stem}.svg"));
    write_whole(&svg, fig.to_svg().as_bytes()).map_err(|e| WriteError::io(&svg, e))?;
    let png = dir.join(format!("{stem}.png"));
    write_whole(&png, &fig.to_png(2.0)?).map_err(|e| WriteError::io(&png, e))?;
    written.extend([svg, png]);
    Ok(())
}

/// Write each diagram of `results` in `plane` into `dir` (`plot --x R0 --y beta`); returns
/// the files written. Nothing is written where the plane cannot be drawn.
pub fn write_plane_plots(
    results: &Results,
    plane: &cellsweep_stats::Plane,
    dir: &Path,
) -> Result<Vec<PathBuf>, WriteError> {
    let diagrams = figures::plane_diagrams(results, plane)?;
    std::fs::create_dir_all(dir).map_err(|e| WriteError::create(dir, e))?;
    let mut written = Vec::new();
    for (stem, d) in diagrams {
        write(
            &cellsweep_plot::phase::diagram_figure(&d),
            dir,
            &stem,
            &mut written,
        )?;
    }
    Ok(written)
}

/// Write every picture of `results` into `dir`; returns the files written.
pub fn write_plots(results: &Results, dir: &Path) -> Result<Vec<PathBuf>, WriteError> {
    std::fs::create_dir_all(dir).map_err(|e| WriteError::create(dir, e))?;
    let read = fit_line(&results.counts, &results.scales, 0, 1, Method::Model);
    let fitted = read.as_ref().ok();
    let columns = match &read {
        Ok(f) => &f.columns,
        Err(no) => &no.columns,
    };
    let placed: Vec<Placed> = columns
        .iter()
        .map(|c| (results.scales, c.clone()))
        .collect();
    let mut written = Vec::new();
    for key in figures::diagrams(&results.counts) {
        let fig = figures::diagram_of(results, &key, fitted);
        write(&fig, dir, &key.file_stem(), &mut written)?;
    }
    write(&figures::speed_of(results), dir, "free-speed", &mut written)?;
    write(&collapse_of(&placed, fitted), dir, "collapse", &mut written)?;
    Ok(written)
}
