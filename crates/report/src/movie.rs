//! The movie of a trajectory (`simulate --frames`, `replay --frames`): a solver [`Monitor`]
//! that renders the collision's fields every so many tau0 into PNG files, then an animated GIF
//! of them, passing stages and steps on to another monitor (the command's progress bars).
//! Main type: [`FrameRecorder`]; every file is written whole or not at all.

use std::path::{Path, PathBuf};

use cellsweep_plot::frames::{figure, Snapshot};
use cellsweep_plot::Image;
use cellsweep_solver::{Cell, Decision, Fibers, Lattice, Monitor, Stage};

use crate::plot_files::WriteError;
use crate::whole_file::write_whole;

/// A file of the movie, written whole or not at all.
fn write(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    write_whole(path, bytes).map_err(|e| WriteError::io(path, e))
}

/// Snapshots every `every` tau0 of the collision, with `inner` told of every stage and step.
pub struct FrameRecorder<M: Monitor> {
    pub inner: M,
    dir: PathBuf,
    every: f64,
    next: f64,
    /// Half-size copies for the GIF.
    gif_frames: Vec<Image>,
    /// Every file written, in order (the PNG snapshots, then the GIF).
    pub written: Vec<PathBuf>,
    /// The first failure to draw or write a snapshot (the trajectory goes on; [`finish`]
    /// reports it).
    ///
    /// [`finish`]: FrameRecorder::finish
    error: Option<WriteError>,
    /// The outcome once decided, shown on every later frame.
    note: String,
}

impl<M: Monitor> FrameRecorder<M> {
    /// A recorder writing into `dir` (created), a snapshot every `every` tau0 (at least 0.5).
    pub fn new(dir: &Path, every: f64, inner: M) -> Result<Self, WriteError> {
        std::fs::create_dir_all(dir).map_err(|e| WriteError::create(dir, e))?;
        Ok(FrameRecorder {
            inner,
            dir: dir.to_path_buf(),
            every: every.max(0.5),
            next: 0.0,
            gif_frames: Vec::new(),
            written: Vec::new(),
            error: None,
            note: String::new(),
        })
    }

    /// Write the animated GIF of the snapshots taken; the first failure, if any.
    pub fn finish(&mut self) -> Result<(), WriteError> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        if !self.gif_frames.is_empty() {
            let path = self.dir.join("collision.gif");
            write(&path, &cellsweep_plot::gif(&self.gif_frames, 25)?)?;
            self.written.push(path);
        }
        Ok(())
    }
}

impl<M: Monitor> Monitor for FrameRecorder<M> {
    fn stage(&mut self, stage: Stage, total_steps: u64) {
        self.inner.stage(stage, total_steps);
    }

    fn advance(&mut self, steps_done: u64) {
        self.inner.advance(steps_done);
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
            .map_err(WriteError::from)
            .and_then(|png| write(&path, &png))
            .and_then(|()| Ok(fig.rasterize(1.0)?));
        match drawn {
            Ok(image) => {
                self.written.push(path);
                self.gif_frames.push(image);
            }
            Err(e) => {
                self.error.get_or_insert(e);
            }
        }
    }
}
