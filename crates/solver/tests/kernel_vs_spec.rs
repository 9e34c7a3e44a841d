//! The fused kernel against a literal, unfused transcription of SPEC section 3 (one array per
//! term, as the spec writes it), on random fields, single-cell and pair, with noise and P.

mod common;

use common::{same_bits, tiny_params};

use cellsweep_solver::kernel::{step_cell, step_cell_portable, StepCoeffs, Sums};
use cellsweep_solver::{Fibers, Geometry, Lattice, Params};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

struct Reference<'a> {
    lat: &'a Lattice,
    chi: Vec<f64>,
}

impl<'a> Reference<'a> {
    fn new(lat: &'a Lattice, fibers: &Fibers) -> Self {
        let mut chi = lat.zeros();
        for j in 0..lat.ny {
            if fibers.of_row(j).is_some() {
                for i in 0..lat.nx {
                    chi[lat.idx(i, j)] = 1.0;
                }
            }
        }
        Reference { lat, chi }
    }
    fn at(&self, f: &[f64], i: isize, j: isize) -> f64 {
        let (nx, ny) = (self.lat.nx as isize, self.lat.ny as isize);
        f[self
            .lat
            .idx(i.rem_euclid(nx) as usize, j.rem_euclid(ny) as usize)]
    }
    /// Returns (phi(t+dt), P(t+dt)) per SPEC section 3, term by term.
    fn step(
        &self,
        p: &Params,
        phi: &[f64],
        pol: &[f64],
        other: Option<&[f64]>,
        noise: [f64; 2],
        motile: bool,
    ) -> (Vec<f64>, Vec<f64>) {
        let lat = self.lat;
        let n = lat.len();
        let s_area: f64 = phi.iter().map(|v| v * v).sum();
        let ad: f64 = (0..n)
            .map(|k| phi[k] * phi[k] * (3.0 - 2.0 * phi[k]) * self.chi[k])
            .sum();
        let a0 = PI * p.R0 * p.R0;
        let (mut lap, mut gx, mut gy) = (lat.zeros(), lat.zeros(), lat.zeros());
        for j in 0..lat.ny as isize {
            for i in 0..lat.nx as isize {
                let k = lat.idx(i as usize, j as usize);
                lap[k] = self.at(phi, i + 1, j)
                    + self.at(phi, i - 1, j)
                    + self.at(phi, i, j + 1)
                    + self.at(phi, i, j - 1)
                    - 4.0 * phi[k];
                gx[k] = (self.at(phi, i + 1, j) - self.at(phi, i - 1, j)) / 2.0;
                gy[k] = (self.at(phi, i, j + 1) - self.at(phi, i, j - 1)) / 2.0;
            }
        }
        let (mut out_phi, mut out_p) = (lat.zeros(), lat.zeros());
        for k in 0..n {
            let f = phi[k];
            let chi = self.chi[k];
            let mut mu = p.alpha
                * (f.powi(3) - 1.5 * f.powi(2) + 0.5 * f - p.d * p.d / 2.0 * lap[k])
                - (4.0 * p.lambda * f / a0) * (1.0 - s_area / a0)
                - 6.0 * p.E0 * p.A_ref * f * (1.0 - f) * chi / (p.A_ref + ad).powi(2);
            if let Some(q) = other {
                let fj = q[k];
                mu += 2.0 * p.g * f * fj * fj
                    - 2.0
                        * p.sigma
                        * (f.powi(3) - 1.5 * f.powi(2) + 0.5 * f)
                        * fj
                        * fj
                        * (1.0 - fj).powi(2);
            }
            let gn = (gx[k] * gx[k] + gy[k] * gy[k]).sqrt();
            let a = if motile { p.A } else { 0.0 };
            let (fx, fy) = if gn > 0.0 {
                let m = a * pol[k] * f * f * (1.0 - f).powi(2) * chi;
                (m * -gx[k] / gn, m * -gy[k] / gn)
            } else {
                (0.0, 0.0)
            };
            let vx = (mu * gx[k] + fx) / p.eta + noise[0];
            let vy = (mu * gy[k] + fy) / p.eta + noise[1];
            let dphi = -(vx * gx[k] + vy * gy[k] + mu * p.inv_gamma);
            out_phi[k] = f + p.dt * dphi;
            let theta = if f > p.phi_min { 1.0 } else { 0.0 };
            out_p[k] = (pol[k] + p.dt * (p.beta * f * dphi - pol[k] / p.tau)) * theta;
        }
        (out_phi, out_p)
    }
}

fn random_cell(lat: &Lattice, rng: &mut ChaCha8Rng) -> (Vec<f64>, Vec<f64>) {
    // A smooth blob plus noise, so every term (tails below phi_min included) is exercised.
    let mut phi = lat.zeros();
    let mut pol = lat.zeros();
    let (cx, cy) = (rng.random_range(5.0..25.0), rng.random_range(8.0..16.0));
    for j in 0..lat.ny {
        for i in 0..lat.nx {
            let r = ((i as f64 - cx).powi(2) + (j as f64 - cy).powi(2)).sqrt();
            let k = lat.idx(i, j);
            phi[k] = (0.5 + 0.5 * ((7.0 - r) / 3.0).tanh()) * rng.random_range(0.9..1.1);
            pol[k] = rng.random_range(-1.0..1.0);
        }
    }
    (phi, pol)
}

fn close(a: &[f64], b: &[f64], tol: f64) -> f64 {
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(worst <= tol, "max difference {worst:e} > {tol:e}");
    worst
}

#[test]
fn fused_step_matches_the_spec_term_by_term() {
    let lat = Lattice::new(30, 24);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    // sigma = 0 runs the pair sites without the adhesion factor (a specialisation).
    for (geometry, sigma) in [
        (Geometry::One, 5.0),
        (Geometry::Two, 5.0),
        (Geometry::Two, 0.0),
    ] {
        let params = Params {
            geometry,
            sigma,
            beta: 20.0,
            ..tiny_params()
        };
        let fibers = Fibers::new(&params, lat.ny);
        let reference = Reference::new(&lat, &fibers);
        for (pair, motile) in [(false, false), (false, true), (true, true)] {
            let (phi, pol) = random_cell(&lat, &mut rng);
            let (other, _) = random_cell(&lat, &mut rng);
            let other = pair.then_some(other.as_slice());
            let noise = [rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3)];
            let (want_phi, want_p) = reference.step(&params, &phi, &pol, other, noise, motile);

            let sums = Sums::of(&lat, &fibers, &phi);
            let k = StepCoeffs::new(&params, &sums, noise, motile);
            let (mut p, mut out) = (pol.clone(), lat.zeros());
            let got = step_cell(&lat, &fibers, &k, &phi, &mut p, other, &mut out, false);
            close(&out, &want_phi, 1e-12);
            close(&p, &want_p, 1e-12);
            // The returned sums are those of the new phi.
            let fresh = Sums::of(&lat, &fibers, &out);
            assert_eq!(got, fresh);
            let s_ref: f64 = want_phi.iter().map(|v| v * v).sum();
            assert!((got.area - s_ref).abs() < 1e-9 * s_ref);

            // Two threads give the same bits.
            let (mut p3, mut out3) = (pol.clone(), lat.zeros());
            let got3 = step_cell(&lat, &fibers, &k, &phi, &mut p3, other, &mut out3, true);
            assert_eq!(got, got3);
            assert!(same_bits(&out, &out3));
            assert!(same_bits(&p, &p3));

            // The dispatched (SIMD) path is bit-identical to the portable one.
            let (mut p2, mut out2) = (pol.clone(), lat.zeros());
            let got2 = step_cell_portable(&lat, &fibers, &k, &phi, &mut p2, other, &mut out2);
            assert_eq!(got, got2);
            assert!(same_bits(&out, &out2));
            assert!(same_bits(&p, &p2));

            // At sigma = 0, skipping the adhesion factor gives the same bits as computing it.
            if sigma == 0.0 {
                let ka = k.with_adhesion_term();
                let (mut p4, mut out4) = (pol.clone(), lat.zeros());
                let got4 = step_cell(&lat, &fibers, &ka, &phi, &mut p4, other, &mut out4, false);
                assert_eq!(got, got4);
                assert!(same_bits(&out, &out4));
                assert!(same_bits(&p, &p4));
            }
        }
    }
}
