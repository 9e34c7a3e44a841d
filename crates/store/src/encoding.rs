//! How values are written in SQLite: seeds bit for bit in signed integers, fields as
//! little-endian f64 bytes, times as seconds since the Unix epoch.

use std::time::{SystemTime, UNIX_EPOCH};

/// Seconds since the Unix epoch.
pub fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// u64 seeds are stored bit for bit in SQLite's signed 64-bit integers.
pub(crate) fn seed_to_sql(seed: u64) -> i64 {
    seed as i64
}

pub(crate) fn seed_from_sql(v: i64) -> u64 {
    v as u64
}

/// Fields as little-endian f64 bytes.
pub fn f64s_to_bytes(v: &[f64]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

pub fn bytes_to_f64s(b: &[u8]) -> Vec<f64> {
    b.chunks_exact(8)
        // chunks_exact(8) gives slices of 8 bytes only.
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}
