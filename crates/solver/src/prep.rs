//! Stages 1 to 4 of a trajectory (SPEC section 4): relax, kick, free motion, prep verdict.
//! They depend only on the single-cell parameters and the prep seed, never on sigma or g.

use serde::{Deserialize, Serialize};

use crate::breakup::BreakupWatch;
use crate::cell::Cell;
use crate::error::SolverError;
use crate::fibers::Fibers;
use crate::lattice::Lattice;
use crate::monitor::{Monitor, Stage};
use crate::noise::Noise;
use crate::observables::{FieldSummary, LET_GO_FRACTION};
use crate::params::{Geometry, Params};
use crate::protocol::Protocol;
use crate::resolution::to_lattice;

/// The verdict on a prepped cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Ok,
    /// The cell let go of one of two fibers on its own (the paper's blue dots, Movie 9).
    Unstable,
    /// The phase field broke apart, vanished or diverged (the paper's cyan diamonds).
    Breakup,
}

impl Verdict {
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Ok => "ok",
            Verdict::Unstable => "unstable",
            Verdict::Breakup => "breakup",
        }
    }
}

/// A prepped cell: the state after free motion, from which every replicate of a point starts.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Prep {
    pub seed: u64,
    pub verdict: Verdict,
    /// When a non-`ok` verdict was reached (tau0 into free motion).
    pub verdict_time: Option<f64>,
    /// Why, in words (`None` for `ok`).
    pub verdict_reason: Option<String>,
    /// Net displacement of the unwrapped centroid over the second half of free motion, per tau0.
    pub free_speed: Option<f64>,
    /// The relaxed cell (end of stage 1).
    pub relaxed: FieldSummary,
    /// The cell at the end of free motion (or at the verdict).
    pub prepped: FieldSummary,
    /// Single-cell lattice [Nx_s, Ny].
    pub lattice: [usize; 2],
    pub phi: Vec<f64>,
    pub p: Vec<f64>,
}

/// The initial circle: phi = 1/2 + 1/2 tanh((R0 - r) / (2 d)), r the distance from the lattice
/// centre ((Nx - 1)/2, (Ny - 1)/2).
pub fn initial_circle(lat: &Lattice, params: &Params) -> Vec<f64> {
    let (cx, cy) = ((lat.nx as f64 - 1.0) / 2.0, (lat.ny as f64 - 1.0) / 2.0);
    let mut phi = lat.zeros();
    for j in 0..lat.ny {
        for i in 0..lat.nx {
            let r = ((i as f64 - cx).powi(2) + (j as f64 - cy).powi(2)).sqrt();
            phi[lat.idx(i, j)] = 0.5 + 0.5 * ((params.R0 - r) / (2.0 * params.d)).tanh();
        }
    }
    phi
}

/// Stage 1: relax the initial circle for `steps` steps, P = 0, no motility force, no noise
/// (on two threads with `parallel`: the same result).
pub fn relax(
    params: &Params,
    lat: &Lattice,
    fibers: &Fibers,
    steps: u64,
    monitor: &mut dyn Monitor,
    parallel: bool,
) -> Cell {
    let mut cell = Cell::new(lat, fibers, initial_circle(lat, params), lat.zeros());
    monitor.stage(Stage::Relax, steps);
    for s in 0..steps {
        cell.step(lat, fibers, params, [0.0, 0.0], false, parallel);
        if (s + 1) % 500 == 0 {
            monitor.advance(s + 1);
        }
    }
    monitor.advance(steps);
    cell
}

/// Stage 2: P = 1 where phi > 0.5 and i >= Nx/2, P = 0 elsewhere (the cell will move to +x).
pub fn kick(lat: &Lattice, cell: &mut Cell) {
    for j in 0..lat.ny {
        for i in 0..lat.nx {
            let k = lat.idx(i, j);
            cell.p[k] = if cell.phi[k] > 0.5 && i >= lat.nx / 2 {
                1.0
            } else {
                0.0
            };
        }
    }
}

/// The verdict checks of SPEC section 4 on the current state, with the reason in words;
/// `None` while the cell is fine.
pub fn check_verdict(
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    cell: &Cell,
    watch: &mut BreakupWatch,
) -> Option<(Verdict, String)> {
    if let Some(why) = watch.check(lat, params, cell) {
        return Some((Verdict::Breakup, why));
    }
    if params.geometry == Geometry::Two && fibers.count() == 2 {
        let [b, t] = cell.sums.adhesive;
        if b < LET_GO_FRACTION * t || t < LET_GO_FRACTION * b || b.max(t) <= 0.0 {
            return Some((
                Verdict::Unstable,
                format!(
                    "let go of a fiber: adhesive area {b:.1} on the bottom fiber, {t:.1} on the top \
                     (below {LET_GO_FRACTION} of the other's)"
                ),
            ));
        }
    }
    None
}

/// Stages 1 to 4: relax, kick, free motion with noise from `seed`, and the verdict.
pub fn prepare(
    params: &Params,
    protocol: &Protocol,
    seed: u64,
    monitor: &mut dyn Monitor,
) -> Result<Prep, SolverError> {
    prepare_with(params, protocol, seed, monitor, false)
}

/// [`prepare`], on two threads with `parallel` (the same result, bit for bit).
pub fn prepare_with(
    params: &Params,
    protocol: &Protocol,
    seed: u64,
    monitor: &mut dyn Monitor,
    parallel: bool,
) -> Result<Prep, SolverError> {
    // On a finer lattice, everything in its units (the same values at k = 1).
    let (params, protocol) = &to_lattice(params, protocol);
    let k = protocol.resolution;
    let steps = protocol.validate(params)?;
    let [nx, ny] = protocol.single_lattice;
    let lat = Lattice::new(nx, ny);
    let fibers = Fibers::at_resolution(params, ny, k);

    let mut cell = relax(params, &lat, &fibers, steps.relax, monitor, parallel);
    let relaxed = FieldSummary::of(&lat, &fibers, &cell.phi, steps.relax);
    kick(&lat, &mut cell);

    monitor.stage(Stage::Free, steps.free);
    let mut noise = Noise::new(seed, 1, params.v0, params.sample_every());
    let mut x_prev = lat.centroid_x(&cell.phi);
    let mut track = vec![(0.0, x_prev)];
    let mut verdict = Verdict::Ok;
    let mut watch = BreakupWatch::at_resolution(k);
    let mut verdict_time = None;
    let mut verdict_reason = None;
    let mut done = 0;
    for s in 0..steps.free {
        let nz = noise.at(s)[0];
        cell.step(&lat, &fibers, params, nz, true, parallel);
        let n = s + 1;
        done = n;
        let t = n as f64 * params.dt;
        if n % steps.record_every == 0 || n == steps.free {
            let x = lat.centroid_x(&cell.phi);
            let xu = track.last().map_or(x, |&(_, xu)| xu) + lat.wrap_dx(x_prev, x);
            x_prev = x;
            track.push((t, xu));
            monitor.advance(n);
        }
        let diverged = !cell.sums.area.is_finite();
        if diverged || n % steps.check_every == 0 || n == steps.free {
            if let Some((v, why)) = check_verdict(&lat, &fibers, params, &cell, &mut watch) {
                verdict = v;
                verdict_time = Some(t);
                verdict_reason = Some(why);
                break;
            }
        }
    }
    if steps.free == 0 {
        if let Some((v, why)) = check_verdict(&lat, &fibers, params, &cell, &mut watch) {
            verdict = v;
            verdict_time = Some(0.0);
            verdict_reason = Some(why);
        }
    }
    // Speeds and summaries in the paper's units (l0, l0^2).
    let free_speed =
        speed_over_second_half(&track, steps.free as f64 * params.dt).map(|v| v / f64::from(k));
    Ok(Prep {
        seed,
        verdict,
        verdict_time,
        verdict_reason,
        free_speed: free_speed.filter(|v| v.is_finite()),
        relaxed: relaxed.in_paper_units(k),
        prepped: FieldSummary::of(&lat, &fibers, &cell.phi, done).in_paper_units(k),
        lattice: [nx, ny],
        phi: cell.phi,
        p: cell.p,
    })
}

/// Net displacement over the second half of free motion (of length `total`), per unit time.
fn speed_over_second_half(track: &[(f64, f64)], total: f64) -> Option<f64> {
    let &(t_end, x_end) = track.last()?;
    let half = total / 2.0;
    let &(t_mid, x_mid) = track.iter().find(|&&(t, _)| t >= half - 1e-9)?;
    (t_end > t_mid).then(|| (x_end - x_mid) / (t_end - t_mid))
}
