//! Timing the kernel on this machine: step rates for `cellsweep bench` and the single-cell step
//! behind a dry run's cost estimate, a trajectory timed stage by stage, and the pair start
//! the NumPy yardstick (`scripts/numpy_yardstick.py`) reproduces. Wall time only: nothing here
//! decides a result, and no test asserts a time.

use std::time::Instant;

use crate::cell::step_pair;
use crate::prep::{initial_circle, kick};
use crate::resolution::to_lattice;
use crate::{
    run_trajectory, Cell, Config, Fibers, Lattice, Monitor, Params, Precision, Protocol, Real,
    Seeds, SolverError, Stage, TrajectoryResult,
};

/// Calls per second of `step`, from the fastest of `batches` batches of `batch` calls: on a
/// shared machine the other batches mostly measure the neighbours.
pub fn best_rate(batches: u32, batch: u32, mut step: impl FnMut()) -> f64 {
    (0..batches)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                step();
            }
            batch as f64 / t.elapsed().as_secs_f64()
        })
        .fold(0.0, f64::max)
}

/// A kicked, motile single cell on `protocol`'s single-cell lattice (at its resolution), with
/// the lattice and fibers it steps on.
fn kicked_cell(params: &Params, protocol: &Protocol) -> (Lattice, Fibers, Cell, Params) {
    let (params, protocol) = to_lattice(params, protocol);
    let [nx, ny] = protocol.single_lattice;
    let lat = Lattice::new(nx, ny);
    let fibers = Fibers::at_resolution(&params, ny, protocol.resolution);
    let mut cell = Cell::new(&lat, &fibers, initial_circle(&lat, &params), lat.zeros());
    kick(&lat, &mut cell);
    (lat, fibers, cell, params)
}

/// Single-cell steps per second of `cell` with a fixed noise velocity (the free motion's step).
fn single_rate<T: Real>(
    cell: &mut Cell<T>,
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    batches: u32,
    batch: u32,
) -> f64 {
    best_rate(batches, batch, || {
        cell.step(lat, fibers, params, [0.05, -0.03], true, false)
    })
}

/// Seconds per single-cell step at `params` on `protocol`'s lattice (a finer resolution has
/// k^2 the sites), quickly (the best of 4 batches of 20): in f64, the prep's precision, and in
/// the collision's precision.
pub fn single_step_s(params: &Params, protocol: &Protocol) -> (f64, f64) {
    let (lat, fibers, mut cell, params) = kicked_cell(params, protocol);
    let f64_step = 1.0 / single_rate(&mut cell, &lat, &fibers, &params, 4, 20);
    let collision_step = match protocol.precision {
        Precision::F64 => f64_step,
        Precision::F32 => {
            let mut cell = cell.convert::<f32>(&lat, &fibers);
            1.0 / single_rate(&mut cell, &lat, &fibers, &params, 4, 20)
        }
    };
    (f64_step, collision_step)
}

/// The yardstick's start on the 400 x 200 pair lattice: two circles at x = 99.5 and 299.5,
/// fronts kicked (cell 1 towards +x, cell 2 towards -x).
pub fn pair_start(params: &Params) -> (Lattice, Fibers, Cell, Cell) {
    let lat = Lattice::new(400, 200);
    let fibers = Fibers::new(params, 200);
    // phi = 1/2 + 1/2 tanh((R0 - r) / (2 d)) around (cx, 99.5), SPEC section 4.1.
    let circle = |cx: f64| -> Vec<f64> {
        let mut phi = lat.zeros();
        for j in 0..200 {
            for i in 0..400 {
                let r = ((i as f64 - cx).powi(2) + (j as f64 - 99.5).powi(2)).sqrt();
                phi[lat.idx(i, j)] = 0.5 + 0.5 * ((params.R0 - r) / (2.0 * params.d)).tanh();
            }
        }
        phi
    };
    let (phi1, phi2) = (circle(99.5), circle(299.5));
    let kicked = |phi: &[f64], front: &dyn Fn(usize) -> bool| -> Vec<f64> {
        (0..phi.len())
            .map(|k| f64::from(u8::from(phi[k] > 0.5 && front(k % 400))))
            .collect()
    };
    let (p1, p2) = (kicked(&phi1, &|i| i >= 100), kicked(&phi2, &|i| i <= 299));
    let a = Cell::new(&lat, &fibers, phi1, p1);
    let b = Cell::new(&lat, &fibers, phi2, p2);
    (lat, fibers, a, b)
}

/// What [`kernel_rates`] measured, one thread.
#[derive(Debug, Clone, Copy)]
pub struct KernelRates {
    /// Single-cell steps per second, 200 x 200, motile with noise, f64.
    pub single: f64,
    /// Noise-free pair steps per second, 400 x 200, f64, P only on the fiber rows (as run).
    pub pair: f64,
    /// The same with P on every row (SPEC literally, as the yardstick does).
    pub pair_literal: f64,
    /// The pair step in f32 (the collision's opt-in precision).
    pub pair_f32: f64,
    /// Integrals of the pair after ten noise-free steps, which the yardstick must reproduce.
    pub check: PairCheck,
}

/// Integrals of the yardstick's pair after ten noise-free f64 steps.
#[derive(Debug, Clone, Copy)]
pub struct PairCheck {
    pub sum_phi_1: f64,
    pub area_1: f64,
    pub area_2: f64,
    pub sum_p_1: f64,
}

/// Noise-free pair steps per second, in `T`; with `fibers_only`, P advanced only on the fiber
/// rows, as the collision runs it.
fn pair_rate<T: Real>(
    mut a: Cell<T>,
    mut b: Cell<T>,
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    fibers_only: bool,
) -> f64 {
    if fibers_only {
        a.polarity_on_fibers_only(lat, fibers);
        b.polarity_on_fibers_only(lat, fibers);
    }
    best_rate(5, 200, || {
        step_pair(&mut a, &mut b, lat, fibers, params, [[0.0; 2]; 2], false)
    })
}

/// The kernel's step rates at `params` (on the paper's lattices, one thread).
pub fn kernel_rates(params: &Params) -> KernelRates {
    let (lat, fibers, mut cell, params) = kicked_cell(params, &Protocol::default());
    for _ in 0..200 {
        cell.step(&lat, &fibers, &params, [0.05, -0.03], true, false);
    }
    let single = single_rate(&mut cell, &lat, &fibers, &params, 5, 600);

    let (plat, pfib, mut a, mut b) = pair_start(&params);
    let noise_free = Params { v0: 0.0, ..params };
    for _ in 0..10 {
        step_pair(
            &mut a,
            &mut b,
            &plat,
            &pfib,
            &noise_free,
            [[0.0; 2]; 2],
            false,
        );
    }
    let check = PairCheck {
        sum_phi_1: a.phi.iter().sum(),
        area_1: a.sums.area,
        area_2: b.sums.area,
        sum_p_1: a.p.iter().sum(),
    };
    let (a32, b32) = (
        a.convert::<f32>(&plat, &pfib),
        b.convert::<f32>(&plat, &pfib),
    );
    KernelRates {
        single,
        pair_literal: pair_rate(a.clone(), b.clone(), &plat, &pfib, &noise_free, false),
        pair: pair_rate(a, b, &plat, &pfib, &noise_free, true),
        pair_f32: pair_rate(a32, b32, &plat, &pfib, &noise_free, true),
        check,
    }
}

/// Wall time of each stage of a trajectory, as a [`Monitor`].
#[derive(Debug, Default)]
pub struct StageClock {
    current: Option<(Stage, Instant)>,
    seconds: Vec<(Stage, f64)>,
}

impl StageClock {
    fn close(&mut self) {
        if let Some((stage, t)) = self.current.take() {
            self.seconds.push((stage, t.elapsed().as_secs_f64()));
        }
    }

    /// Seconds spent in `stage`.
    pub fn get(&self, stage: Stage) -> f64 {
        self.seconds
            .iter()
            .filter(|x| x.0 == stage)
            .map(|x| x.1)
            .sum()
    }
}

impl Monitor for StageClock {
    fn stage(&mut self, stage: Stage, _total: u64) {
        self.close();
        self.current = Some((stage, Instant::now()));
    }
}

/// One trajectory, timed stage by stage.
#[derive(Debug, Clone)]
pub struct TimedTrajectory {
    pub result: TrajectoryResult,
    pub relax_s: f64,
    pub free_s: f64,
    pub collide_s: f64,
    pub total_s: f64,
}

/// Run one trajectory of `config` (one thread) and time its stages.
pub fn time_trajectory(config: &Config, seeds: Seeds) -> Result<TimedTrajectory, SolverError> {
    let mut clock = StageClock::default();
    let t = Instant::now();
    let (result, _, _) = run_trajectory(config, seeds, &mut clock, false)?;
    let total_s = t.elapsed().as_secs_f64();
    clock.close();
    Ok(TimedTrajectory {
        result,
        relax_s: clock.get(Stage::Relax),
        free_s: clock.get(Stage::Free),
        collide_s: clock.get(Stage::Collide),
        total_s,
    })
}
