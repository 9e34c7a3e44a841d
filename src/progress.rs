//! Progress bars for long work: indicatif on a terminal, nothing otherwise.

use std::io::IsTerminal;

use cellsweep_solver::{Monitor, Stage};
use cellsweep_stats::End;
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
                "{msg:>8} [{bar:40}] {human_pos}/{human_len} steps, {elapsed} elapsed, ETA {eta}",
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

/// Progress of a sweep: an indicatif bar on a terminal, a plain line every 10 s otherwise.
pub struct SweepBar {
    bar: Option<ProgressBar>,
    last_line: Option<std::time::Instant>,
    last: cellsweep_scheduler::Progress,
}

impl SweepBar {
    pub fn new() -> Self {
        let bar = std::io::stdout().is_terminal().then(|| {
            let bar = ProgressBar::new(0);
            bar.set_style(
                ProgressStyle::with_template(
                    "{spinner} [{elapsed_precise}] [{bar:30}] {pos}/{len} jobs | {msg}",
                )
                .expect("valid template")
                .progress_chars("=> "),
            );
            // The clock and spinner move between events (a collision takes seconds).
            bar.enable_steady_tick(std::time::Duration::from_millis(250));
            bar
        });
        SweepBar {
            bar,
            last_line: None,
            last: Default::default(),
        }
    }

    fn message(p: &cellsweep_scheduler::Progress) -> String {
        let o = &p.outcomes;
        let mut parts = Vec::new();
        // The phase: prepping cells (no collision starts before its prep), or collisions with
        // the speed and time left once some have finished.
        if p.preps_done < p.preps_total && p.jobs_done == 0 {
            parts.push(format!(
                "preparing cells: {}/{} preps",
                p.preps_done, p.preps_total
            ));
        } else {
            let left = p.jobs_total.saturating_sub(p.jobs_done) as f64;
            parts.push(
                cellsweep_stats::throughput::speed_line(p.jobs_per_s, left)
                    .unwrap_or_else(|| "collisions running, speed after the first".into()),
            );
        }
        parts.push(o.line(End::short, " "));
        parts.push(format!("preps {}/{}", p.preps_done, p.preps_total));
        if let Some(n) = p.refined_points {
            parts.push(format!("refined +{n} betas"));
        }
        if p.failed > 0 || p.retries > 0 {
            parts.push(format!("failed {} retried {}", p.failed, p.retries));
        }
        parts.join(" | ")
    }

    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            // Left where it is: an interrupted sweep shows what it did, not a full bar.
            bar.abandon();
        } else if self.last_line.is_some() {
            self.print_line();
        }
    }

    fn print_line(&self) {
        let p = &self.last;
        say(&format!(
            "progress: {}/{} jobs | {}",
            p.jobs_done,
            p.jobs_total,
            Self::message(p)
        ));
    }
}

impl cellsweep_scheduler::Reporter for SweepBar {
    fn progress(&mut self, p: &cellsweep_scheduler::Progress) {
        self.last = p.clone();
        match &self.bar {
            Some(bar) => {
                if bar.length() != Some(p.jobs_total) {
                    bar.set_length(p.jobs_total);
                    bar.set_position(p.jobs_done);
                    bar.reset_eta();
                }
                bar.set_position(p.jobs_done);
                bar.set_message(Self::message(p));
            }
            None => {
                let due = self
                    .last_line
                    .is_none_or(|t| t.elapsed().as_secs_f64() >= 10.0);
                if due {
                    self.print_line();
                    self.last_line = Some(std::time::Instant::now());
                }
            }
        }
    }

    fn note(&mut self, message: &str) {
        match &self.bar {
            Some(bar) => bar.println(message),
            None => say(message),
        }
    }
}

/// A line on stdout that never panics: a run whose output pipe was closed (`| head`) goes on
/// and finishes its jobs, with the store kept consistent.
fn say(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stdout().lock(), "{line}");
}
