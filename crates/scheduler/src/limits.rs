//! Bounds on what a sweep file may ask for, shared by its reader, its grid and their errors.

/// Most points one axis may have.
pub const MAX_AXIS_POINTS: usize = 1_000;
