//! Trajectory snapshots for `simulate --frames`: a solver monitor that renders the collision's
//! fields every so many tau0 into PNG files, then an animated GIF of them.

use std::path::{Path, PathBuf};

use anyhow::Context;
use cellsweep_plot::frames::{figure, Snapshot};
use cellsweep_plot::Image;
use cellsweep_solver::{Cell, Decision, Fibers, Lattice, Monitor, Stage};

use crate::progress::StageBars;

/// Progress bars plus snapshots every `every` tau0 of the collision.
pub struct FrameRecorder {
    pub bars: StageBars,
    dir: PathBuf,
    every: f64,
    next: f64,
    /// Half-size copies for the GIF.
    pub gif_frames: Vec<Image>,
    pub written: Vec<PathBuf>,
    pub error: Option<anyhow::Error>,
    /// The outcome once decided, shown on every later frame.
    note: String,
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
            note: String::new(),
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
            let bytes = cellsweep_plot::gif(&self.gif_frames, 25)?;
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

    /// The movie goes on after the decision, so that it shows the outcome happen.
    fn run_on(&self) -> f64 {
        (2.0 * self.every).max(20.0)
    }

    fn decided(&mut self, d: &Decision) {
        self.note = format!(
            "outcome: {}, decided at t = {:.0} τ_0 ({:.0} min)",
            d.outcome,
            d.time,
            d.time * cellsweep_plot::frames::TAU0_MIN
        );
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
            time: t,
            note: self.note.clone(),
        };
        let fig = figure(&snap);
        let path = self.dir.join(format!("frame-{:05.0}.png", t));
        let drawn = fig
            .to_png(2.0)
            .map_err(anyhow::Error::from)
            .and_then(|png| {
                std::fs::write(&path, png)
                    .with_context(|| format!("cannot write {}", path.display()))
            });
        if let Err(e) = drawn {
            self.error.get_or_insert(e);
            return;
        }
        self.written.push(path);
        match fig.rasterize(1.0) {
            Ok(image) => self.gif_frames.push(image),
            Err(e) => {
                self.error.get_or_insert(e.into());
            }
        }
    }
}
