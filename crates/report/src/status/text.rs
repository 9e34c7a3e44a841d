//! A [`SweepView`] as `cellsweep status` prints it: a few lines per sweep, or one JSON object.

use std::fmt::Write as _;

use cellsweep_stats::throughput::speed_line;
use cellsweep_stats::End;
use serde_json::{json, Value};

use super::refinement;
use super::SweepView;

/// The sweep's lines; `failed`: each failed job and prep with its attempts and error too.
pub fn lines(v: &SweepView, failed: bool) -> String {
    let mut out = String::new();
    let s = &v.status;
    let j = &s.jobs;
    let other = if v.current {
        ""
    } else {
        " (another solver version)"
    };
    let _ = writeln!(out, "{} [{}{other}]", s.sweep, s.solver_version);
    let running = if v.live || j.running == 0 {
        format!("{} running", j.running)
    } else {
        format!(
            "{} interrupted (no run holds the store: the next run takes them up again)",
            j.running
        )
    };
    let _ = writeln!(
        out,
        "  jobs     {} done / {} total · {} pending · {running} · {} failed",
        j.done,
        j.total(),
        j.pending,
        j.failed
    );
    let _ = writeln!(out, "  preps    {} / {} done", s.preps_done, s.preps_total);
    let _ = writeln!(out, "  outcomes {}", s.outcomes.line(End::words, " · "));
    if let Some(by) = &v.standings {
        // Jobs of open points' later rounds are not registered yet: the total grows.
        let _ = writeln!(
            out,
            "  adaptive points {} (open points get more rounds: the job total grows)",
            by.iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(" · ")
        );
    }
    if let Some((rule, columns)) = &v.refinement {
        let (lines, _) = refinement::lines(columns, rule, "           ");
        let _ = writeln!(out, "  refine   {}", lines.join("\n"));
    }
    if !v.box_limited.is_empty() {
        let _ = writeln!(
            out,
            "  box      {} (SPEC 4.5: the prepped cell leaves its fronts under 0.35 Nx_s \
             apart, so the outcome depends on the pair lattice): {}",
            crate::text::counted(v.box_limited.len(), "box-limited point"),
            v.box_limited.join("; ")
        );
    }
    if !v.arrays.is_empty() {
        let queue = match &v.queue {
            Err(e) => format!("the queue could not be asked ({e})"),
            Ok(st) if st.is_empty() => "none queued or running".to_string(),
            Ok(st) => st
                .iter()
                .map(|(k, n)| format!("{n} {k}"))
                .collect::<Vec<_>>()
                .join(", "),
        };
        let labels: Vec<String> = v.arrays.iter().map(|a| a.label()).collect();
        let _ = writeln!(
            out,
            "  slurm    arrays {} · tasks: {queue}",
            labels.join(", ")
        );
    }
    if failed {
        for f in &v.failures {
            let _ = writeln!(
                out,
                "  failed   {} {} at alpha = {}, beta = {}, L = {}, sigma = {}{} after {} attempts: {}",
                f.kind,
                f.id,
                f.alpha,
                f.beta,
                f.L,
                f.sigma,
                f.replicate
                    .map_or(String::new(), |r| format!(", replicate {r}")),
                f.attempts,
                f.error
            );
        }
    }
    if let Some(line) = speed_line(s.jobs_per_s, (j.pending + j.running) as f64) {
        if v.live || j.pending + j.running == 0 {
            let _ = writeln!(out, "  speed    {line}");
        } else {
            let _ = writeln!(
                out,
                "  speed    stopped: no run holds the store (the last run's speed: {})",
                line.split(" · ETA").next().unwrap_or(&line)
            );
        }
    }
    out
}

/// `status --json`: the sweep's progress with `live`, its box-limited points (the current
/// solver's), adaptive standings, failures (with `failed`) and Slurm arrays where it has them.
pub fn json(v: &SweepView, failed: bool) -> Result<Value, serde_json::Error> {
    let mut o = serde_json::to_value(&v.status)?;
    o["live"] = json!(v.live);
    if v.current {
        o["box_limited"] = json!(v.box_limited);
    }
    if let Some(by) = &v.standings {
        o["adaptive"] = json!(by);
    }
    if failed {
        o["failures"] = serde_json::to_value(&v.failures)?;
    }
    if !v.arrays.is_empty() {
        let queue = match &v.queue {
            Ok(states) => json!(states),
            Err(e) => json!({ "unknown": e.0 }),
        };
        o["slurm"] = json!({ "arrays": v.arrays, "queue": queue });
    }
    Ok(o)
}
