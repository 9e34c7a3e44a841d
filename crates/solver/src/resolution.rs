//! A finer lattice (SPEC section 6): resolution k, lattice spacing l0' = l0 / k. A sweep gives
//! every parameter in the paper's units; [`to_lattice`] turns them into the finer lattice's
//! units, where the solver runs unchanged, and results come back in the paper's units
//! (speeds and positions in l0, areas in l0^2, times in tau0 as they are).
//!
//! Each factor follows from the units of the paper's Table I: lengths in sites scale by k (R0,
//! d, L, the fibers' 2k rows, the lattices), areas by k^2 (A_ref, the classifier's contact
//! overlap, the breakup rule's 10 sites), energies per area by 1/k^2 (alpha, sigma, g: eps0 /
//! l0^2), 1/gamma by k^2 (l0^2 / (eps0 tau0)), eta by 1/k^4 (eps0 tau0 / l0^4), A by 1/k^3 (a
//! force density, eps0 / l0^3), velocities by k (v0, the classifier's min_speed); lambda, E0,
//! beta, tau, the protocol's times, t_sample and phi_min stay; dt scales by 1/k^2 so that the
//! diffusive number stays (k = 2 costs 16 times: 4 times the sites, 4 times the steps).

use crate::classifier::ClassifierSettings;
use crate::params::Params;
use crate::protocol::Protocol;

/// The parameters and protocol in the units of a lattice of resolution `protocol.resolution`
/// (the very same values at k = 1).
pub fn to_lattice(params: &Params, protocol: &Protocol) -> (Params, Protocol) {
    let k = protocol.resolution.max(1);
    if k == 1 {
        return (params.clone(), protocol.clone());
    }
    let kf = f64::from(k);
    let k2 = kf * kf;
    let mut p = params.clone();
    // Lengths.
    p.R0 *= kf;
    p.d *= kf;
    p.L *= k;
    // Areas.
    p.A_ref *= k2;
    // Energies per area.
    p.alpha /= k2;
    p.sigma /= k2;
    p.g /= k2;
    // Transport and friction.
    p.inv_gamma *= k2;
    p.eta /= k2 * k2;
    // A force density, a velocity.
    p.A /= k2 * kf;
    p.v0 *= kf;
    // The diffusive number stays.
    p.dt /= k2;
    let mut q = protocol.clone();
    q.single_lattice = protocol.sites(protocol.single_lattice);
    q.pair_lattice = protocol.sites(protocol.pair_lattice);
    q.patch.pad *= k as usize;
    (p, q)
}

/// The classifier's settings in the units of a lattice of resolution `k`.
pub fn classifier_to_lattice(settings: &ClassifierSettings, k: u32) -> ClassifierSettings {
    let kf = f64::from(k.max(1));
    ClassifierSettings {
        contact_overlap: settings.contact_overlap * kf * kf,
        min_speed: settings.min_speed * kf,
        ..settings.clone()
    }
}
