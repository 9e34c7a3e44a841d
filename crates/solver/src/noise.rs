//! The velocity noise (SPEC section 3): v0 (X, Y), X and Y standard normals drawn from a seeded
//! ChaCha generator for each cell every t_sample, held constant in between, uniform in space.

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use rand_distr::{Distribution, StandardNormal};

/// Seeded noise for a fixed number of cells. At each sampling instant the draws are, in order,
/// X then Y of cell 1, then X then Y of cell 2.
#[derive(Debug, Clone)]
pub struct Noise {
    rng: ChaCha20Rng,
    v0: f64,
    every: u64,
    current: Vec<[f64; 2]>,
}

impl Noise {
    pub fn new(seed: u64, cells: usize, v0: f64, every: u64) -> Self {
        Noise {
            rng: ChaCha20Rng::seed_from_u64(seed),
            v0,
            every: every.max(1),
            current: vec![[0.0; 2]; cells],
        }
    }

    /// The noise of every cell at step `step` (counted from the start of the stage): fresh draws
    /// when `step` is a multiple of t_sample/dt, the held values otherwise.
    pub fn at(&mut self, step: u64) -> &[[f64; 2]] {
        if step.is_multiple_of(self.every) {
            for v in self.current.iter_mut() {
                let x: f64 = StandardNormal.sample(&mut self.rng);
                let y: f64 = StandardNormal.sample(&mut self.rng);
                *v = [self.v0 * x, self.v0 * y];
            }
        }
        &self.current
    }
}
