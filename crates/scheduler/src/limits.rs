//! Bounds on what a sweep file may ask for, shared by its reader, its grid and their errors.

/// Most points one axis may have.
pub const MAX_AXIS_POINTS: usize = 1_000;

/// Most replicates per point (and preps per point).
pub const MAX_REPLICATES: u64 = 10_000;
/// Most grid points of one sweep.
pub const MAX_POINTS: u64 = 100_000;
/// Most jobs (points x replicates) of one sweep.
pub const MAX_JOBS: u64 = 10_000_000;
/// Largest fiber spacing and lattice side, in sites.
pub const MAX_SITES: u64 = 4_096;
/// Longest job timeout: 30 days.
pub const MAX_JOB_TIMEOUT: f64 = 30.0 * 86_400.0;
/// Most attempts of one job.
pub const MAX_ATTEMPTS: u64 = 100;
