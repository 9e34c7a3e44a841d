//! What a sweep's work costs: seconds per prep and per collision, measured in a store that
//! has run some, else estimated from a single-cell step timed here (`solver::timing`).

use cellsweep_solver::resolution::to_lattice;
use cellsweep_solver::timing::single_step_s;
use cellsweep_solver::Precision;
use cellsweep_store::MeasuredCost;

use crate::sweep::Sweep;

/// Seconds per prep and per collision, and where they come from.
#[derive(Debug, Clone, Copy)]
pub struct UnitCosts {
    pub prep_s: f64,
    pub collision_s: f64,
    pub basis: CostBasis,
}

/// Where [`UnitCosts`] come from.
#[derive(Debug, Clone, Copy)]
pub enum CostBasis {
    /// The means of the store's own preps and collisions.
    Measured { preps: i64, collisions: i64 },
    /// A single-cell step timed here (`step_s`, f64) and, for an f32 collision, its step
    /// (`collision_step_s`): a collision costed at its longest (per-cell windows and early
    /// stopping make most far cheaper).
    Timed {
        step_s: f64,
        collision_step_s: Option<f64>,
    },
}

/// The unit costs of `sweep`'s work: as `measured` where it has both, else timed here on the
/// lattice the solver runs (its first point's, scaled by the mean size of every point's
/// lattice; dt / k^2 and k^2 the sites at resolution k).
pub fn unit_costs(sweep: &Sweep, measured: Option<MeasuredCost>) -> UnitCosts {
    if let Some(m) = measured {
        if let (Some(prep_s), Some(collision_s)) = (m.prep_s, m.collision_s) {
            return UnitCosts {
                prep_s,
                collision_s,
                basis: CostBasis::Measured {
                    preps: m.preps,
                    collisions: m.collisions,
                },
            };
        }
    }
    let points = sweep.points();
    let first = &points[0];
    let sites = |p| {
        let [nx, ny] = sweep.protocol_for(p).single_lattice;
        (nx * ny) as f64
    };
    let scale = points.iter().map(|p| sites(p) / sites(first)).sum::<f64>() / points.len() as f64;
    let (step, collision_step) = single_step_s(first, &sweep.protocol_for(first));
    let (step, collision_step) = (step * scale, collision_step * scale);
    let (params, p) = &to_lattice(first, &sweep.protocol_for(first));
    let steps = |t: f64| (t / params.dt).round();
    let area = |l: [usize; 2]| (l[0] * l[1]) as f64;
    // A pair step updates two cells on the pair lattice.
    let pair_over_single = 2.0 * area(p.pair_lattice) / area(p.single_lattice);
    UnitCosts {
        prep_s: step * (steps(p.relax_time) + steps(p.free_time)),
        collision_s: collision_step * pair_over_single * steps(p.collide_time),
        basis: CostBasis::Timed {
            step_s: step,
            collision_step_s: (p.precision == Precision::F32).then_some(collision_step),
        },
    }
}
