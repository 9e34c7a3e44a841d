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

/// The values of a sweep's other grid axes `names` in a point's stored configuration JSON
/// (`{"params": {...}, ...}`, as the planner wrote it): numbers as they are, geometry `"one"`
/// as 1 and `"two"` as 2. A value that is missing or of another kind reads NaN, which matches
/// no point.
pub fn point_others(config: &str, names: &[&str]) -> cellsweep_stats::Others {
    let parsed: Option<serde_json::Value> = serde_json::from_str(config).ok();
    let params = parsed.as_ref().map(|c| &c["params"]);
    cellsweep_stats::Others(
        names
            .iter()
            .map(|&name| {
                let v = params.map(|p| &p[name]);
                let x = match v {
                    Some(serde_json::Value::String(s)) if s == "one" => 1.0,
                    Some(serde_json::Value::String(s)) if s == "two" => 2.0,
                    Some(v) => v.as_f64().unwrap_or(f64::NAN),
                    None => f64::NAN,
                };
                (name.to_string(), x)
            })
            .collect(),
    )
}
