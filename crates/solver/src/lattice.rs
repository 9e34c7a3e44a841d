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

    /// Both centroid coordinates, [xbar, ybar], in one pass over the field (SPEC section 5,
    /// weights `phi`):
    /// xbar = Nx/(2 pi) (atan2(-sum phi sin theta, -sum phi cos theta) + pi) (the circular mean of
    /// Bai & Breen 2008), reported in [0, Nx) (the formula's Nx is column 0), ybar = sum phi y /
    /// sum phi (not periodic: cells sit mid-height).
    ///
    /// The field is first summed column by column, sum_j phi and sum_j phi y, element-wise over
    /// the rows (so the compiler vectorises the pass, where one running sum per site would be a
    /// chain of dependent additions), then the columns are combined.
    pub fn centroid<T: Real>(&self, phi: &[T]) -> [f64; 2] {
        let nx = self.nx;
        let mut col = vec![0.0f64; nx];
        let mut col_y = vec![0.0f64; nx];
        for (j, row) in phi.chunks_exact(nx).enumerate() {
            let y = j as f64;
            for ((w, wy), &v) in col.iter_mut().zip(col_y.iter_mut()).zip(row) {
                let v = v.to_f64();
                *w += v;
                *wy += v * y;
            }
        }
        let (mut s, mut c, mut w, mut wy) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..nx {
            s += col[i] * self.sin_x[i];
            c += col[i] * self.cos_x[i];
            w += col[i];
            wy += col_y[i];
        }
        let xbar = nx as f64 / (2.0 * PI) * ((-s).atan2(-c) + PI);
        // The formula gives (0, Nx]; Nx is column 0, reported as 0 so that xbar lies in [0, Nx).
        let xbar = if xbar >= nx as f64 { 0.0 } else { xbar };
        [xbar, wy / w]
    }

    /// Centroid along x by the circular mean (see [`Lattice::centroid`]).
    pub fn centroid_x<T: Real>(&self, phi: &[T]) -> f64 {
        self.centroid(phi)[0]
    }

    /// Centroid along y: sum phi y / sum phi (see [`Lattice::centroid`]).
    pub fn centroid_y<T: Real>(&self, phi: &[T]) -> f64 {
        self.centroid(phi)[1]
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
