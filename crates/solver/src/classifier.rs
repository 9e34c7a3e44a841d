//! The outcome of a collision (SPEC section 5), decided causally from the centroid track.
//!
//! The classifier sees one sample at a time and never looks ahead, so the label of a run stopped
//! as soon as it is decided is exactly the label of the full-length run. Events, the first of
//! which decides:
//! - `walk_past`: Delta = xbar_2 - xbar_1 (unwrapped) falls below -margin (R0/2);
//! - `train`: after contact, both cells move the same way faster than the threshold speed for a
//!   sustained window;
//! - `reversal`: after contact, cell 1 moves towards -x and cell 2 towards +x, both faster than the
//!   threshold, for a sustained window, and the cells are no longer in contact;
//! - `undetermined`: none of these by the end of the run.
//!
//! One more end comes from the fields, not the track: `breakup`, when a cell of the collision
//! breaks up (the prep's rule, SPEC section 5), checked by the collision loop before each sample
//! is classified ([`crate::collide`]); it is neither training, walk-past nor reversal.
//!
//! Velocities are centroid displacements over `velocity_window`. The threshold speed is
//! `speed_fraction` times the prep cell's free speed, but never below `min_speed` (the noise alone
//! moves a centroid by about v0 sqrt(dt W), far below it).

use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The label of one collision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    Train,
    WalkPast,
    Reversal,
    Undetermined,
    /// A cell broke up during the collision (an artefact of the lattice, not a result).
    Breakup,
}

impl Outcome {
    pub const ALL: [Outcome; 5] = [
        Outcome::Train,
        Outcome::WalkPast,
        Outcome::Reversal,
        Outcome::Undetermined,
        Outcome::Breakup,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Train => "train",
            Outcome::WalkPast => "walk_past",
            Outcome::Reversal => "reversal",
            Outcome::Undetermined => "undetermined",
            Outcome::Breakup => "breakup",
        }
    }
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The classifier's parameters; stored with every result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClassifierSettings {
    /// Cells are in contact while the overlap O = sum phi_1 phi_2 is at least this (l0^2).
    pub contact_overlap: f64,
    /// Threshold speed as a fraction of the prep cell's free speed.
    pub speed_fraction: f64,
    /// Lower bound of the threshold speed (l0 / tau0).
    pub min_speed: f64,
    /// Velocities are displacements over this window (tau0).
    pub velocity_window: f64,
    /// A train or reversal must hold for this long (tau0).
    pub sustain_window: f64,
    /// Walk-past when Delta < -walk_past_margin * R0.
    pub walk_past_margin: f64,
}

impl Default for ClassifierSettings {
    fn default() -> Self {
        ClassifierSettings {
            contact_overlap: 1.0,
            speed_fraction: 0.25,
            min_speed: 0.05,
            velocity_window: 10.0,
            sustain_window: 25.0,
            walk_past_margin: 0.5,
        }
    }
}

impl ClassifierSettings {
    /// The threshold speed for a prep cell of free speed `free_speed`.
    pub fn threshold_speed(&self, free_speed: f64) -> f64 {
        let v = self.speed_fraction * free_speed.abs();
        if v.is_finite() {
            v.max(self.min_speed)
        } else {
            self.min_speed
        }
    }
}

/// A decided outcome and when it was decided.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Decision {
    pub outcome: Outcome,
    pub time: f64,
}

/// The causal classifier: feed it samples in time order with [`Classifier::observe`].
#[derive(Debug, Clone)]
pub struct Classifier {
    settings: ClassifierSettings,
    threshold: f64,
    margin: f64,
    /// Recent (t, x1, x2), covering at least the velocity window.
    history: VecDeque<(f64, f64, f64)>,
    contact_time: Option<f64>,
    train_since: Option<f64>,
    reversal_since: Option<f64>,
    decision: Option<Decision>,
}

impl Classifier {
    /// A classifier for cells of radius `r0` whose prep cell moved at `free_speed`.
    pub fn new(settings: &ClassifierSettings, free_speed: f64, r0: f64) -> Self {
        Classifier {
            threshold: settings.threshold_speed(free_speed),
            margin: settings.walk_past_margin * r0,
            settings: settings.clone(),
            history: VecDeque::new(),
            contact_time: None,
            train_since: None,
            reversal_since: None,
            decision: None,
        }
    }

    pub fn threshold_speed(&self) -> f64 {
        self.threshold
    }

    pub fn contact_time(&self) -> Option<f64> {
        self.contact_time
    }

    pub fn decision(&self) -> Option<Decision> {
        self.decision
    }

    /// Take the sample at time `t`: unwrapped centroids `x1`, `x2` and overlap `overlap`.
    /// Returns the decision once made (and the same decision for every later sample).
    pub fn observe(&mut self, t: f64, x1: f64, x2: f64, overlap: f64) -> Option<Decision> {
        if self.decision.is_some() {
            return self.decision;
        }
        let eps = 1e-9;
        let w = self.settings.velocity_window;
        self.history.push_back((t, x1, x2));
        while self.history.len() > 1 && self.history[1].0 <= t - w + eps {
            self.history.pop_front();
        }
        let in_contact = overlap >= self.settings.contact_overlap;
        if in_contact && self.contact_time.is_none() {
            self.contact_time = Some(t);
        }
        let decide = |outcome| Some(Decision { outcome, time: t });

        if x2 - x1 < -self.margin {
            self.decision = decide(Outcome::WalkPast);
            return self.decision;
        }
        let (t0, x10, x20) = self.history[0];
        let velocities = (self.contact_time.is_some() && t - t0 >= w - eps)
            .then(|| ((x1 - x10) / (t - t0), (x2 - x20) / (t - t0)));
        let th = self.threshold;
        let sustain = self.settings.sustain_window - eps;

        let train =
            velocities.is_some_and(|(v1, v2)| (v1 > th && v2 > th) || (v1 < -th && v2 < -th));
        self.train_since = if train {
            self.train_since.or(Some(t))
        } else {
            None
        };
        if self.train_since.is_some_and(|s| t - s >= sustain) {
            self.decision = decide(Outcome::Train);
            return self.decision;
        }

        let apart = velocities.is_some_and(|(v1, v2)| v1 < -th && v2 > th);
        self.reversal_since = if apart {
            self.reversal_since.or(Some(t))
        } else {
            None
        };
        if !in_contact && self.reversal_since.is_some_and(|s| t - s >= sustain) {
            self.decision = decide(Outcome::Reversal);
        }
        self.decision
    }
}
