//! Stage 5: the collision of a prepped cell with its mirror image (SPEC sections 4 and 5).

use serde::{Deserialize, Serialize};

use crate::breakup::BreakupWatch;
use crate::cell::{step_pair, step_pair_in, Cell};
use crate::classifier::{Classifier, ClassifierSettings, Decision, Outcome};
use crate::error::SolverError;
use crate::fibers::Fibers;
use crate::kernel::Sums;
use crate::lattice::Lattice;
use crate::monitor::{Monitor, Stage};
use crate::noise::Noise;
use crate::observables::{overlap, Attachment};
use crate::params::Params;
use crate::patch::{PatchStats, Patches};
use crate::prep::Prep;
use crate::protocol::{Precision, Protocol, StageSteps};
use crate::real::Real;
use crate::resolution::{classifier_to_lattice, to_lattice};

/// Observables of both cells at one time (SPEC section 5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time since the collision started (tau0).
    pub t: f64,
    /// Periodic centroids along x.
    pub xbar: [f64; 2],
    /// Centroids along x unwrapped in time (continuous).
    pub x: [f64; 2],
    pub ybar: [f64; 2],
    /// S = sum phi^2 of each cell.
    pub area: [f64; 2],
    /// O = sum phi_1 phi_2.
    pub overlap: f64,
    /// Adhesive area of each cell on [bottom, top] fiber.
    pub adhesive: [[f64; 2]; 2],
}

impl Sample {
    /// The sample of a lattice of resolution `k` in the paper's units (l0, l0^2); the same at
    /// k = 1.
    pub fn in_paper_units(self, k: u32) -> Sample {
        if k <= 1 {
            return self;
        }
        let (l, a) = (f64::from(k), f64::from(k * k));
        Sample {
            t: self.t,
            xbar: self.xbar.map(|x| x / l),
            x: self.x.map(|x| x / l),
            ybar: self.ybar.map(|y| y / l),
            area: self.area.map(|s| s / a),
            overlap: self.overlap / a,
            adhesive: self.adhesive.map(|f| f.map(|s| s / a)),
        }
    }
}

/// What happened in one collision.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Collision {
    pub outcome: Outcome,
    /// When the outcome was decided (tau0), `None` if undetermined.
    pub decision_time: Option<f64>,
    /// First contact (tau0), `None` if the cells never touched.
    pub contact_time: Option<f64>,
    /// Each cell's fiber attachment at the decision (or at the end of the run).
    pub attachment: [Attachment; 2],
    pub threshold_speed: f64,
    /// Why a cell broke up, when the outcome is `breakup` (which cell, and the rule it failed).
    pub breakup_reason: Option<String>,
    /// Drops the two cells shed: second pieces of the region phi > 0.5 that did not break a
    /// cell up (SPEC section 5), counted, not labelled.
    #[serde(default)]
    pub sheddings: u32,
    /// Steps run (fewer than the protocol's when stopped early).
    pub steps: u64,
    /// What the per-cell windows did (`None` when they were off).
    pub patch: Option<PatchStats>,
    pub track: Vec<Sample>,
}

/// The two cells of the collision on the pair lattice: the prepped fields shifted along x by
/// floor((Nx_s - 1)/2 - xbar + 1/2) sites in their Nx_s-wide box so the cell sits mid-box, cell 1
/// in columns 0..Nx_s (zero beyond), cell 2 its mirror image phi_2(i, j) = phi_1(Nx_p - 1 - i, j).
pub fn place_pair(prep: &Prep, pair_nx: usize) -> [(Vec<f64>, Vec<f64>); 2] {
    let [snx, ny] = prep.lattice;
    let single = Lattice::new(snx, ny);
    let xbar = single.centroid_x(&prep.phi);
    let centre = (snx as f64 - 1.0) / 2.0;
    let shift = (centre - xbar + 0.5).floor() as i64;
    let n = pair_nx * ny;
    let (mut phi1, mut p1) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..ny {
        for i in 0..snx {
            let src = (i as i64 - shift).rem_euclid(snx as i64) as usize;
            phi1[j * pair_nx + i] = prep.phi[j * snx + src];
            p1[j * pair_nx + i] = prep.p[j * snx + src];
        }
    }
    let mirror = |f: &[f64]| {
        let mut m = vec![0.0; n];
        for j in 0..ny {
            for i in 0..pair_nx {
                m[j * pair_nx + i] = f[j * pair_nx + (pair_nx - 1 - i)];
            }
        }
        m
    };
    let (phi2, p2) = (mirror(&phi1), mirror(&p1));
    [(phi1, p1), (phi2, p2)]
}

/// The observables of both cells at time `t`; `x` (the unwrapped centroids) is left to the
/// caller, which unwraps it from the `xbar` returned here.
fn sample<T: Real>(lat: &Lattice, t: f64, a: &Cell<T>, b: &Cell<T>) -> Sample {
    let ([xa, ya], [xb, yb]) = (lat.centroid(&a.phi), lat.centroid(&b.phi));
    Sample {
        t,
        xbar: [xa, xb],
        x: [xa, xb],
        ybar: [ya, yb],
        area: [a.sums.area, b.sums.area],
        overlap: overlap(lat.nx, &a.phi, &b.phi),
        adhesive: [a.sums.adhesive, b.sums.adhesive],
    }
}

/// Run the collision of `prep` (whose verdict should be `ok`) with noise from `seed`.
pub fn collide(
    params: &Params,
    protocol: &Protocol,
    settings: &ClassifierSettings,
    prep: &Prep,
    seed: u64,
    monitor: &mut dyn Monitor,
    parallel: bool,
) -> Result<Collision, SolverError> {
    // On a finer lattice, everything in its units (the same values at k = 1).
    let (params, protocol) = &to_lattice(params, protocol);
    let k = protocol.resolution;
    let settings = &classifier_to_lattice(settings, k);
    let steps = protocol.validate(params)?;
    if prep.lattice != protocol.single_lattice
        || prep.phi.len() != prep.lattice[0] * prep.lattice[1]
    {
        return Err(SolverError::PrepMismatch {
            nx: protocol.single_lattice[0],
            ny: protocol.single_lattice[1],
        });
    }
    let [nx, ny] = protocol.pair_lattice;
    let lat = Lattice::new(nx, ny);
    let fibers = Fibers::at_resolution(params, ny, k);
    let [(phi1, p1), (phi2, p2)] = place_pair(prep, nx);
    let mut a = Cell::new(&lat, &fibers, phi1, p1);
    let mut b = Cell::new(&lat, &fibers, phi2, p2);
    if !monitor.records_fields() {
        // P off the fiber rows never acts on phi: same results, fewer memory streams.
        a.polarity_on_fibers_only(&lat, &fibers);
        b.polarity_on_fibers_only(&lat, &fibers);
    }
    let run = Run {
        params,
        protocol,
        steps,
        lat: &lat,
        fibers: &fibers,
        parallel,
    };
    // The prep's free speed is in l0 / tau0; the classifier works in this lattice's sites.
    let free_speed = prep.free_speed.unwrap_or(0.0) * f64::from(k);
    let mut classifier = Classifier::new(settings, free_speed, params.R0);
    let ended = match protocol.precision {
        Precision::F64 => run.steps(a, b, &mut classifier, seed, monitor)?,
        Precision::F32 => {
            let (a, b) = (
                a.convert::<f32>(&lat, &fibers),
                b.convert::<f32>(&lat, &fibers),
            );
            run.steps(a, b, &mut classifier, seed, monitor)?
        }
    };
    let Ended {
        decision,
        breakup_reason,
        sheddings,
        at_decision,
        done,
        patch,
        track,
    } = ended;
    Ok(Collision {
        outcome: decision.map_or(Outcome::Undetermined, |d| d.outcome),
        decision_time: decision.map(|d| d.time),
        contact_time: classifier.contact_time(),
        attachment: [
            Attachment::of(&fibers, &at_decision[0]),
            Attachment::of(&fibers, &at_decision[1]),
        ],
        threshold_speed: classifier.threshold_speed() / f64::from(k),
        breakup_reason,
        sheddings,
        steps: done,
        patch,
        track: track.into_iter().map(|s| s.in_paper_units(k)).collect(),
    })
}

/// What a collision's stepping loop leaves behind.
struct Ended {
    decision: Option<Decision>,
    breakup_reason: Option<String>,
    /// Drops both cells shed (second pieces that did not break a cell up).
    sheddings: u32,
    /// Integrals of both cells at the decision (or at the end).
    at_decision: [Sums; 2],
    done: u64,
    patch: Option<crate::patch::PatchStats>,
    track: Vec<Sample>,
}

/// The fixed inputs of a collision's stepping loop.
struct Run<'a> {
    params: &'a Params,
    protocol: &'a Protocol,
    steps: StageSteps,
    lat: &'a Lattice,
    fibers: &'a Fibers,
    parallel: bool,
}

impl Run<'_> {
    /// Step both cells (stored as `T`) to the decided outcome or the end of the stage.
    fn steps<T: Real>(
        &self,
        mut a: Cell<T>,
        mut b: Cell<T>,
        classifier: &mut Classifier,
        seed: u64,
        monitor: &mut dyn Monitor,
    ) -> Result<Ended, SolverError> {
        let Run {
            params,
            protocol,
            steps,
            lat,
            fibers,
            parallel,
        } = *self;
        // The monitor sees f64 cells (converted only when it asks, in f32 runs).
        let show = |monitor: &mut dyn Monitor, t: f64, a: &Cell<T>, b: &Cell<T>| {
            let (a64, b64) = (a.convert::<f64>(lat, fibers), b.convert::<f64>(lat, fibers));
            monitor.fields(t, lat, fibers, [&a64, &b64]);
        };
        let mut patches = Patches::new(&protocol.patch, lat, fibers, [&mut a, &mut b]);
        let mut noise = Noise::new(seed, 2, params.v0, params.sample_every());
        let first = sample(lat, 0.0, &a, &b);
        let mut decision: Option<Decision> =
            classifier.observe(0.0, first.x[0], first.x[1], first.overlap);
        let mut at_decision: [Sums; 2] = [a.sums, b.sums];
        let mut broke: Option<String> = None;
        let k = self.protocol.resolution;
        let mut watch = [
            BreakupWatch::at_resolution(k),
            BreakupWatch::at_resolution(k),
        ];
        let mut track = vec![first];

        monitor.stage(Stage::Collide, steps.collide);
        let mut shown = None;
        if monitor.wants_fields(0.0) {
            show(monitor, 0.0, &a, &b);
            shown = Some(0);
        }
        let run_on = monitor.run_on().max(0.0);
        let mut done = 0;
        // Where a run that films nothing stops (the step its record counts): a movie runs on
        // past the decision only to show it, and a replay with a movie compares this.
        let mut stop = None;
        for s in 0..steps.collide {
            if let Some(d) = decision {
                stop.get_or_insert(done);
                // (run_on = 0, every sweep: stop at once, as before.)
                if protocol.stop_early && (run_on == 0.0 || s as f64 * params.dt >= d.time + run_on)
                {
                    break;
                }
            }
            let nz = noise.at(s);
            let nz = [nz[0], nz[1]];
            let n = s + 1;
            match &mut patches {
                Some(pt) => {
                    step_pair_in(
                        &mut a,
                        &mut b,
                        lat,
                        fibers,
                        params,
                        nz,
                        pt.spans(),
                        parallel,
                    );
                    pt.after_step(n, lat, fibers, [&mut a, &mut b]);
                }
                None => step_pair(&mut a, &mut b, lat, fibers, params, nz, parallel),
            }
            done = n;
            let t = n as f64 * params.dt;
            // Breakup first (SPEC section 5): every check interval, and at once when an area
            // is no longer finite. It ends the collision like any other outcome.
            let diverged = !(a.sums.area.is_finite() && b.sums.area.is_finite());
            if decision.is_none() && (diverged || n % steps.check_every == 0) {
                // Both cells are checked, so that each watch sees every check.
                let why = [
                    watch[0].check(lat, params, &a),
                    watch[1].check(lat, params, &b),
                ];
                let broken = why
                    .into_iter()
                    .enumerate()
                    .find_map(|(k, why)| Some((k, why?)));
                if let Some((k, why)) = broken {
                    let d = Decision {
                        outcome: Outcome::Breakup,
                        time: t,
                    };
                    decision = Some(d);
                    broke = Some(format!("cell {}: {why}", k + 1));
                    at_decision = [a.sums, b.sums];
                    monitor.decided(&d);
                }
            }
            if diverged {
                // Nothing further can be computed from non-finite fields.
                break;
            }
            if n % steps.record_every == 0 || n == steps.collide {
                // Unwrap the centroids from the previous sample's.
                let mut smp = sample(lat, t, &a, &b);
                // The sample at t = 0 is recorded before the loop.
                let prev = track.last().expect("the first sample is recorded");
                for c in 0..2 {
                    smp.x[c] = prev.x[c] + lat.wrap_dx(prev.xbar[c], smp.xbar[c]);
                }
                if decision.is_none() {
                    decision = classifier.observe(t, smp.x[0], smp.x[1], smp.overlap);
                    if let Some(d) = &decision {
                        at_decision = [a.sums, b.sums];
                        monitor.decided(d);
                    }
                }
                track.push(smp);
                monitor.advance(n);
                if monitor.wants_fields(t) {
                    show(monitor, t, &a, &b);
                    shown = Some(n);
                }
            }
        }
        // The last instant too, so that a movie ends where the run did.
        if monitor.records_fields() && shown != Some(done) {
            show(monitor, done as f64 * params.dt, &a, &b);
        }
        if decision.is_none() {
            at_decision = [a.sums, b.sums];
        }
        Ok(Ended {
            decision,
            breakup_reason: broke,
            sheddings: watch[0].sheddings + watch[1].sheddings,
            at_decision,
            done: match protocol.stop_early {
                true => stop.unwrap_or(done),
                false => done,
            },
            patch: patches.map(|pt| pt.stats()),
            track,
        })
    }
}
