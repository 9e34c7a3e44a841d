//! Progress reporting without I/O policy: the caller decides what to do with it.

/// The stages of one trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    Relax,
    Free,
    Collide,
}

/// Receives progress from a running trajectory. Every method has a no-op default.
pub trait Monitor {
    /// Whether this monitor will ask for the collision's fields at all. If not, the collision
    /// advances P only on the fiber rows, where it acts (`Cell::polarity_on_fibers_only`: the
    /// same phi and observables, bit for bit, faster); if so, P is kept on every row for the
    /// pictures.
    fn records_fields(&self) -> bool {
        false
    }
    /// Whether [`Monitor::fields`] wants the collision's fields at time `t` (asked at every
    /// record interval).
    fn wants_fields(&self, _t: f64) -> bool {
        false
    }
    /// The collision's two cells at time `t` (only when [`Monitor::wants_fields`] said yes).
    fn fields(
        &mut self,
        _t: f64,
        _lattice: &crate::Lattice,
        _fibers: &crate::Fibers,
        _cells: [&crate::Cell; 2],
    ) {
    }
    /// Tau0 a collision that stops early should go on after its outcome is decided (a movie
    /// that shows the outcome happen). The outcome is the first event, so it cannot change.
    fn run_on(&self) -> f64 {
        0.0
    }
    /// The collision's outcome was decided.
    fn decided(&mut self, _decision: &crate::Decision) {}
    /// A stage of at most `total_steps` steps begins.
    fn stage(&mut self, _stage: Stage, _total_steps: u64) {}
    /// `steps_done` steps of the current stage are done.
    fn advance(&mut self, _steps_done: u64) {}
}

/// A monitor that ignores everything.
pub struct Silent;

impl Monitor for Silent {}
