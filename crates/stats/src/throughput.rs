//! One estimator of a sweep's speed and time left, shared by `status` (from the store) and the
//! progress bar of a running sweep (from the jobs it has finished), so both say the same.

/// The window of activity the speed is measured over, seconds.
pub const WINDOW_S: f64 = 600.0;

/// Jobs per second from `(started, finished)` times (Unix seconds) of finished jobs: those
/// finished within [`WINDOW_S`] of the latest finish, over the time from the earliest start
/// among them to that finish. None before any job has finished.
pub fn jobs_per_s(spans: &[(f64, f64)]) -> Option<f64> {
    let last = spans.iter().map(|s| s.1).fold(f64::NAN, f64::max);
    if !last.is_finite() {
        return None;
    }
    let recent = spans.iter().filter(|s| s.1 >= last - WINDOW_S);
    let (n, first) = recent.fold((0u64, f64::INFINITY), |(n, f), s| (n + 1, f.min(s.0)));
    (n > 0 && last > first).then(|| n as f64 / (last - first))
}

/// Seconds left for `remaining` jobs at `rate` jobs per second.
pub fn eta_s(remaining: f64, rate: Option<f64>) -> Option<f64> {
    rate.filter(|r| *r > 0.0).map(|r| remaining / r)
}

/// A duration as `45s`, `12m05s` or `3h07m`.
pub fn fmt_duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    match s {
        0..=59 => format!("{s}s"),
        60..=3599 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, (s % 3600) / 60),
    }
}

/// Speed and time left, as `status` and the running sweep's bar both print them (one
/// estimator: this module's). None before any job has finished.
pub fn speed_line(jobs_per_s: Option<f64>, remaining: f64) -> Option<String> {
    let rate = jobs_per_s?;
    Some(match eta_s(remaining, Some(rate)) {
        Some(eta) if remaining > 0.0 => {
            format!("{:.2} jobs/min · ETA {}", rate * 60.0, fmt_duration(eta))
        }
        _ => format!("{:.2} jobs/min", rate * 60.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_counts_the_latest_window_of_activity() {
        assert_eq!(jobs_per_s(&[]), None);
        // Four jobs, 10 s each back to back on one worker: 4 jobs in 40 s.
        let spans = [(0.0, 10.0), (10.0, 20.0), (20.0, 30.0), (30.0, 40.0)];
        assert_eq!(jobs_per_s(&spans), Some(0.1));
        // A job long before the window does not count.
        let mut old = spans.to_vec();
        old.iter_mut()
            .for_each(|s| *s = (s.0 + 5000.0, s.1 + 5000.0));
        old.push((0.0, 100.0));
        assert_eq!(jobs_per_s(&old), Some(0.1));
        assert_eq!(eta_s(30.0, Some(0.1)), Some(300.0));
        assert_eq!(eta_s(30.0, None), None);
    }
}
