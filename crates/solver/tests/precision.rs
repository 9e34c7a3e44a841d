//! The f32 collision: deterministic per seed, the same bits on every instruction-set path, and
//! close to f64 over a short run (agreement in outcome statistics is a sweep's job: README).

mod common;

use cellsweep_solver::kernel::{step_cell_in, step_cell_portable_in, StepCoeffs};
use cellsweep_solver::{
    collide, prepare, Collision, Fibers, Geometry, Lattice, Precision, Silent, Sums,
};
use common::{row_in_two, same_bits, small_config};
use std::f64::consts::PI;

#[test]
fn the_f32_kernel_gives_the_same_bits_on_every_path_and_stays_near_f64() {
    let cfg = small_config(Geometry::Two);
    let params = &cfg.params;
    let lat = Lattice::new(96, 96);
    let fibers = Fibers::new(params, lat.ny);
    let prep = prepare(params, &cfg.protocol, 3, &mut Silent).unwrap();
    let (phi64, p64) = (prep.phi.clone(), prep.p.clone());
    let other64: Vec<f64> = (0..lat.len())
        .map(|s| phi64[(s + 48) % lat.len()])
        .collect();
    let to32 = |f: &[f64]| f.iter().map(|&v| v as f32).collect::<Vec<f32>>();
    let (phi32, p32, other32) = (to32(&phi64), to32(&p64), to32(&other64));

    let spans = row_in_two(32, 96);
    let k64 = StepCoeffs::<f64>::new(params, &Sums::of(&lat, &fibers, &phi64), [0.05, 0.02], true);
    let k32 = StepCoeffs::<f32>::new(params, &Sums::of(&lat, &fibers, &phi32), [0.05, 0.02], true);
    let (mut q64, mut out64) = (p64.clone(), lat.zeros());
    step_cell_in(
        &lat,
        &fibers,
        &k64,
        &phi64,
        &mut q64,
        Some(&other64),
        &spans,
        &mut out64,
        false,
    );
    let (mut q32, mut out32) = (p32.clone(), vec![0f32; lat.len()]);
    let s32 = step_cell_in(
        &lat,
        &fibers,
        &k32,
        &phi32,
        &mut q32,
        Some(&other32),
        &spans,
        &mut out32,
        false,
    );
    let (mut r32, mut port32) = (p32.clone(), vec![0f32; lat.len()]);
    let t32 = step_cell_portable_in(
        &lat,
        &fibers,
        &k32,
        &phi32,
        &mut r32,
        Some(&other32),
        &spans,
        &mut port32,
    );
    assert_eq!(s32, t32);
    assert!(same_bits(&out32, &port32));
    assert!(same_bits(&q32, &r32));
    // One step in f32 is f64's to f32 round-off.
    let worst = out32
        .iter()
        .zip(&out64)
        .map(|(&a, &b)| (a as f64 - b).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "phi differs by {worst:e}");
}

fn run(precision: Precision, seed: u64) -> Collision {
    let mut cfg = small_config(Geometry::Two);
    cfg.protocol.precision = precision;
    let prep = prepare(&cfg.params, &cfg.protocol, 11, &mut Silent).unwrap();
    collide(
        &cfg.params,
        &cfg.protocol,
        &cfg.classifier,
        &prep,
        seed,
        &mut Silent,
        false,
    )
    .unwrap()
}

#[test]
fn an_f32_collision_is_deterministic_and_tracks_f64() {
    let (a, b) = (run(Precision::F32, 5), run(Precision::F32, 5));
    assert_eq!(a.track, b.track, "same seed, same f32 trajectory");
    let c = run(Precision::F64, 5);
    assert_eq!(a.track.len(), c.track.len());
    let a0 = PI * 24.0 * 24.0;
    let mut worst: f64 = 0.0;
    for (x, y) in a.track.iter().zip(&c.track) {
        for k in 0..2 {
            worst = worst.max((x.x[k] - y.x[k]).abs() / 192.0);
            worst = worst.max((x.area[k] - y.area[k]).abs() / a0);
        }
        worst = worst.max((x.overlap - y.overlap).abs() / a0);
    }
    // 4 tau0 (2000 steps) in f32 stay within a few f32 round-offs per step of f64.
    assert!(worst < 1e-4, "f32 drifts from f64 by {worst:e}");
    assert!(worst > 0.0, "the f32 path must really run in f32");
    eprintln!(
        "f32 vs f64 over {} samples: worst scaled difference {worst:e}",
        a.track.len()
    );
}
