//! Trajectory snapshots for `simulate --frames`: a solver monitor that renders the collision's
//! fields every so many tau0 into PNG files, then an animated GIF of them.

use std::path::{Path, PathBuf};

use anyhow::Context;
use cellsweep_plot::frames::{render, Snapshot};
use cellsweep_plot::Raster;
use cellsweep_solver::{Cell, Fibers, Lattice, Monitor, Stage};

use crate::progress::StageBars;

/// Progress bars plus snapshots every `every` tau0 of the collision.
pub struct FrameRecorder {
    pub bars: StageBars,
    dir: PathBuf,
    every: f64,
    next: f64,
    /// Half-size copies for the GIF.
    pub gif_frames: Vec<Raster>,
    pub written: Vec<PathBuf>,
    pub error: Option<anyhow::Error>,
}

impl FrameRecorder {
    pub fn new(dir: &Path, every: f64) -> anyhow::Result<Self> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        Ok(FrameRecorder {
            bars: StageBars::new(),
            dir: dir.to_path_buf(),
            every: every.max(0.5),
            next: 0.0,
            gif_frames: Vec::new(),
            written: Vec::new(),
            error: None,
        })
    }

    /// Write the animated GIF of the snapshots taken.
    pub fn finish(&mut self) -> anyhow::Result<()> {
        self.bars.finish();
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        if !self.gif_frames.is_empty() {
            let path = self.dir.join("collision.gif");
            let bytes = cellsweep_plot::gif(&self.gif_frames, 25).map_err(anyhow::Error::msg)?;
            std::fs::write(&path, bytes)
                .with_context(|| format!("cannot write {}", path.display()))?;
            self.written.push(path);
        }
        Ok(())
    }
}

impl Monitor for FrameRecorder {
    fn stage(&mut self, stage: Stage, total_steps: u64) {
        self.bars.stage(stage, total_steps);
    }

    fn advance(&mut self, steps_done: u64) {
        self.bars.advance(steps_done);
    }

    fn records_fields(&self) -> bool {
        true
    }

    fn wants_fields(&self, t: f64) -> bool {
        t + 1e-9 >= self.next
    }

    fn fields(&mut self, t: f64, lattice: &Lattice, fibers: &Fibers, cells: [&Cell; 2]) {
        self.next = t + self.every;
        let rows = fibers.rows();
        let snap = Snapshot {
            nx: lattice.nx,
            ny: lattice.ny,
            phi: [&cells[0].phi, &cells[1].phi],
            p: [&cells[0].p, &cells[1].p],
            fiber_rows: &rows,
            caption: format!("t = {t:.0} tau0 after the start of the collision"),
        };
        let path = self.dir.join(format!("frame-{:05.0}.png", t));
        if let Err(e) = std::fs::write(&path, render(&snap, 2).to_png()) {
            self.error
                .get_or_insert(anyhow::anyhow!("cannot write {}: {e}", path.display()));
            return;
        }
        self.written.push(path);
        self.gif_frames.push(render(&snap, 1));
    }
}
