//! What a store holds at one moment: every sweep's [`cellsweep_report::status::SweepView`]
//! (the very model `cellsweep status` prints) and its diagrams, gathered through one read-only
//! connection.

use std::path::Path;

use cellsweep_report::status::{gather, StatusError};
use cellsweep_report::{figures, Results};
use cellsweep_store::Store;
use serde::Serialize;

/// Diagrams are drawn live only for sweeps of at most this many points: a figure of more
/// would be megabytes of SVG on every change (`cellsweep plot` draws any size).
pub const MAX_LIVE_POINTS: usize = 5_000;

/// One sweep under one solver version, as the page shows it: its status and its diagrams.
#[derive(Debug, Clone, Serialize)]
pub struct SweepView {
    #[serde(flatten)]
    pub view: cellsweep_report::status::SweepView,
    /// The diagrams as inline SVG, or why they are not drawn.
    #[serde(skip)]
    pub diagrams: Result<Vec<String>, cellsweep_report::status::Unavailable>,
}

impl std::ops::Deref for SweepView {
    type Target = cellsweep_report::status::SweepView;
    fn deref(&self) -> &Self::Target {
        &self.view
    }
}

/// Every sweep of a store at one moment, or why there is none.
#[derive(Debug, Clone, Serialize)]
pub struct Snapshot {
    pub store: String,
    pub sweeps: Vec<SweepView>,
    /// Why there is nothing to show: no store at the path, or a store with no sweep.
    pub message: Option<String>,
    /// When it was gathered (Unix seconds).
    pub at: f64,
}

impl Snapshot {
    /// A page with nothing but a message (no store yet, or a file that is not a store).
    pub fn empty(path: &Path, message: String) -> Snapshot {
        Snapshot {
            store: path.display().to_string(),
            sweeps: Vec::new(),
            message: Some(message),
            at: cellsweep_store::now(),
        }
    }

    /// Everything `store` (opened read-only at `path`) holds now.
    pub fn gather(store: &Store, path: &Path) -> Result<Snapshot, StatusError> {
        let names = store.sweep_names()?;
        let sweeps: Vec<SweepView> = gather(store, path, MAX_LIVE_POINTS)?
            .into_iter()
            .map(|view| SweepView {
                diagrams: view.results.as_ref().map(draw).map_err(Clone::clone),
                view,
            })
            .collect();
        let message = match (names.is_empty(), sweeps.is_empty()) {
            (true, _) => Some(format!("{} holds no sweep yet", path.display())),
            (false, true) => Some(format!(
                "{} holds sweeps ({}) but no jobs yet",
                path.display(),
                names.join(", ")
            )),
            _ => None,
        };
        Ok(Snapshot {
            store: path.display().to_string(),
            sweeps,
            message,
            at: cellsweep_store::now(),
        })
    }

    /// Whether every sweep shown is finished (and there is at least one).
    pub fn finished(&self) -> bool {
        !self.sweeps.is_empty() && self.sweeps.iter().all(|s| s.finished)
    }
}

/// Every diagram of `results` as SVG (the report's four-panel figure, paper's line drawn).
fn draw(results: &Results) -> Vec<String> {
    figures::diagrams(&results.counts)
        .iter()
        .map(|k| figures::diagram_of(results, k, None).to_svg())
        .collect()
}
