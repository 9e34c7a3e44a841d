//! One cell's fields (phi, P) with the integrals the next step needs, and how cells advance.

use crate::fibers::Fibers;
use crate::kernel::{step_cell, step_cell_in, RowSpans, Span, StepCoeffs, Sums};
use crate::lattice::Lattice;
use crate::params::Params;
use crate::real::Real;

/// A cell on a lattice: phase field, polarity, and S / Ad of the current phi, stored as `T`
/// (f64 unless the collision runs in f32).
#[derive(Debug, Clone)]
pub struct Cell<T: Real = f64> {
    pub phi: Vec<T>,
    pub p: Vec<T>,
    pub sums: Sums,
    /// Whether P is advanced on every row (SPEC literally) or only on the fiber rows, where it
    /// acts (see [`Cell::polarity_on_fibers_only`]).
    polarity_everywhere: bool,
    /// Buffer for phi(t + dt).
    next: Vec<T>,
}

impl<T: Real> Cell<T> {
    pub fn new(lat: &Lattice, fibers: &Fibers, phi: Vec<T>, p: Vec<T>) -> Self {
        assert_eq!(phi.len(), lat.len());
        assert_eq!(p.len(), lat.len());
        Cell {
            sums: Sums::of(lat, fibers, &phi),
            next: vec![T::default(); lat.len()],
            polarity_everywhere: true,
            phi,
            p,
        }
    }

    /// From now on, advance P only on the fiber rows, and set it to zero on every other row.
    ///
    /// P acts on phi only through the motility force A P phi^2 (1 - phi)^2 chi, which is zero
    /// off the fiber rows, and P's update has no stencil, so P off the fiber rows never feeds
    /// back: phi and every observable are the same bits either way (tested). The step then
    /// skips two of the five memory streams of a site on every other row. Only pictures of P
    /// differ, so runs that draw frames keep P everywhere.
    pub fn polarity_on_fibers_only(&mut self, lat: &Lattice, fibers: &Fibers) {
        self.polarity_everywhere = false;
        for (j, row) in self.p.chunks_exact_mut(lat.nx).enumerate() {
            if fibers.of_row(j).is_none() {
                row.fill(T::default());
            }
        }
    }

    /// Whether P is advanced on every row (the default).
    pub fn polarity_everywhere(&self) -> bool {
        self.polarity_everywhere
    }

    /// Step coefficients of this cell.
    fn coeffs(&self, params: &Params, noise: [f64; 2], motile: bool) -> StepCoeffs<T> {
        let k = StepCoeffs::<T>::new(params, &self.sums, noise, motile);
        if self.polarity_everywhere {
            k
        } else {
            k.polarity_on_fibers_only()
        }
    }

    /// The same cell in another precision (rounded to nearest when narrowing).
    pub fn convert<U: Real>(&self, lat: &Lattice, fibers: &Fibers) -> Cell<U> {
        let conv = |f: &[T]| f.iter().map(|v| U::of(v.to_f64())).collect::<Vec<U>>();
        let mut cell = Cell::new(lat, fibers, conv(&self.phi), conv(&self.p));
        cell.polarity_everywhere = self.polarity_everywhere;
        cell
    }

    /// Advance this cell alone by one step (single-cell stages); with `parallel` on two threads
    /// (same result).
    pub fn step(
        &mut self,
        lat: &Lattice,
        fibers: &Fibers,
        params: &Params,
        noise: [f64; 2],
        motile: bool,
        parallel: bool,
    ) {
        let k = self.coeffs(params, noise, motile);
        self.sums = step_cell(
            lat,
            fibers,
            &k,
            &self.phi,
            &mut self.p,
            None,
            &mut self.next,
            parallel,
        );
        std::mem::swap(&mut self.phi, &mut self.next);
    }

    /// Set phi and P to exactly zero at the sites `drop` (in both phi buffers, so they stay
    /// zero where the kernel no longer writes), and recompute the integrals.
    pub(crate) fn zero_sites(&mut self, lat: &Lattice, fibers: &Fibers, drop: &[usize]) {
        for &s in drop {
            self.phi[s] = T::default();
            self.p[s] = T::default();
            self.next[s] = T::default();
        }
        self.sums = Sums::of(lat, fibers, &self.phi);
    }
}

/// Advance two interacting cells by one step; both right-hand sides use the fields at time t.
/// With `parallel` each cell's rows are split between two threads, the same halves for both
/// cells, so each thread reads the rows it wrote the step before (same result, bit for bit).
/// Splitting by cell instead made every thread read the other cell's field from the other
/// core's cache each step, and gained almost nothing.
pub fn step_pair<T: Real>(
    a: &mut Cell<T>,
    b: &mut Cell<T>,
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    noise: [[f64; 2]; 2],
    parallel: bool,
) {
    let full = [Span::full(lat.nx, true)];
    step_pair_in(a, b, lat, fibers, params, noise, [&full, &full], parallel);
}

/// [`step_pair`] with each cell computed only in its columns `spans` (its window: see
/// `crate::patch`); phi and P must be zero outside them.
#[allow(clippy::too_many_arguments)]
pub fn step_pair_in<'s, T: Real>(
    a: &mut Cell<T>,
    b: &mut Cell<T>,
    lat: &Lattice,
    fibers: &Fibers,
    params: &Params,
    noise: [[f64; 2]; 2],
    spans: [impl Into<RowSpans<'s>>; 2],
    parallel: bool,
) {
    let ka = a.coeffs(params, noise[0], true);
    let kb = b.coeffs(params, noise[1], true);
    let (phi_a, p_a, next_a) = (&a.phi, &mut a.p, &mut a.next);
    let (phi_b, p_b, next_b) = (&b.phi, &mut b.p, &mut b.next);
    let [sp_a, sp_b] = spans;
    let sa = step_cell_in(
        lat,
        fibers,
        &ka,
        phi_a,
        p_a,
        Some(phi_b),
        sp_a,
        next_a,
        parallel,
    );
    let sb = step_cell_in(
        lat,
        fibers,
        &kb,
        phi_b,
        p_b,
        Some(phi_a),
        sp_b,
        next_b,
        parallel,
    );
    a.sums = sa;
    b.sums = sb;
    std::mem::swap(&mut a.phi, &mut a.next);
    std::mem::swap(&mut b.phi, &mut b.next);
}
