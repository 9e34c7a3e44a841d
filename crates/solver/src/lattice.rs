//! The periodic lattice: sizes, indexing and the trigonometric tables of the periodic centroid.

use std::f64::consts::PI;

use crate::real::Real;

/// A periodic Nx x Ny lattice; site (i, j) sits at x = i, y = j and is stored at `j * nx + i`.
#[derive(Debug, Clone)]
pub struct Lattice {
    pub nx: usize,
    pub ny: usize,
    /// cos(2 pi i / Nx) for every column (SPEC section 5, circular mean).
    cos_x: Vec<f64>,
    /// sin(2 pi i / Nx) for every column.
    sin_x: Vec<f64>,
}

impl Lattice {
    pub fn new(nx: usize, ny: usize) -> Self {
        let theta = |i: usize| 2.0 * PI * i as f64 / nx as f64;
        Lattice {
            nx,
            ny,
            cos_x: (0..nx).map(|i| theta(i).cos()).collect(),
            sin_x: (0..nx).map(|i| theta(i).sin()).collect(),
        }
    }

    /// Number of sites.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of site (i, j).
    #[inline]
    pub fn idx(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// A zero field on this lattice.
    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.len()]
    }

    /// Centroid along x by the circular mean (Bai & Breen 2008), weights `phi`:
    /// xbar = Nx/(2 pi) (atan2(-sum phi sin theta, -sum phi cos theta) + pi).
    pub fn centroid_x<T: Real>(&self, phi: &[T]) -> f64 {
        let (mut s, mut c) = (0.0, 0.0);
        for row in phi.chunks_exact(self.nx) {
            for ((&v, &si), &ci) in row.iter().zip(&self.sin_x).zip(&self.cos_x) {
                let v = v.to_f64();
                s += v * si;
                c += v * ci;
            }
        }
        self.nx as f64 / (2.0 * PI) * ((-s).atan2(-c) + PI)
    }

    /// Centroid along y: sum phi y / sum phi (not periodic: cells sit mid-height).
    pub fn centroid_y<T: Real>(&self, phi: &[T]) -> f64 {
        let (mut w, mut wy) = (0.0, 0.0);
        for (j, row) in phi.chunks_exact(self.nx).enumerate() {
            let r: f64 = row.iter().map(|v| v.to_f64()).sum();
            w += r;
            wy += r * j as f64;
        }
        wy / w
    }

    /// Shortest periodic displacement from `a` to `b` along x.
    pub fn wrap_dx(&self, a: f64, b: f64) -> f64 {
        let n = self.nx as f64;
        let mut d = (b - a) % n;
        if d > n / 2.0 {
            d -= n;
        } else if d < -n / 2.0 {
            d += n;
        }
        d
    }
}
