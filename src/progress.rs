//! Progress bars for long work: indicatif on a terminal, nothing otherwise.

use std::io::IsTerminal;

use cellsweep_solver::{Monitor, Stage};
use indicatif::{ProgressBar, ProgressStyle};

/// A solver [`Monitor`] that draws one bar per stage on stderr when stderr is a terminal.
pub struct StageBars {
    enabled: bool,
    bar: Option<ProgressBar>,
}

impl StageBars {
    pub fn new() -> Self {
        StageBars {
            enabled: std::io::stderr().is_terminal(),
            bar: None,
        }
    }

    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Monitor for StageBars {
    fn stage(&mut self, stage: Stage, total_steps: u64) {
        self.finish();
        if !self.enabled {
            return;
        }
        let bar = ProgressBar::new(total_steps);
        bar.set_style(
            ProgressStyle::with_template(
                "{msg:>8} [{bar:40}] {pos}/{len} steps ({per_sec}, ETA {eta})",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_message(match stage {
            Stage::Relax => "relax",
            Stage::Free => "free",
            Stage::Collide => "collide",
        });
        self.bar = Some(bar);
    }

    fn advance(&mut self, steps_done: u64) {
        if let Some(bar) = &self.bar {
            bar.set_position(steps_done);
        }
    }
}
