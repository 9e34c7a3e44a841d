//! `[report] planes`: diagrams on other axes that the report draws for a sweep (beta against
//! R0 at fixed alpha~/L~, E0 against beta, ...), checked here so that a report never meets a
//! plane it cannot read. They decide what is drawn, never what a trajectory gives: not part of
//! the sweep's identity.

use cellsweep_solver::PARAM_NAMES;
use cellsweep_stats::plane::{DERIVED, LT, XT};
use cellsweep_stats::Plane;

use super::Ctx;
use crate::error::SweepError;
use crate::sweep_file::ReportFile;

/// Planes a sweep may ask for (the report draws each once, however many sweeps ask).
const MAX_PLANES: usize = 16;

/// The planes of `[report]`, each axis a SPEC parameter or `xt`, x and y different, `by`
/// without x, y or a repeat.
pub(super) fn planes(r: Option<ReportFile>, cx: &Ctx) -> Result<Vec<Plane>, SweepError> {
    let Some(files) = r.and_then(|r| r.planes) else {
        return Ok(Vec::new());
    };
    if files.len() > MAX_PLANES {
        return Err(cx.err(
            "report.planes",
            format!("{} planes is more than {MAX_PLANES}", files.len()),
        ));
    }
    let known = |a: &str| DERIVED.contains(&a) || PARAM_NAMES.contains(&a);
    let mut out: Vec<Plane> = Vec::new();
    for (i, p) in files.into_iter().enumerate() {
        let key = format!("report.planes[{i}]");
        let axes = [&p.x, &p.y].into_iter().chain(p.by.iter().flatten());
        for a in axes {
            if !known(a) {
                return Err(cx.err(
                    &key,
                    format!(
                        "{a:?} is not an axis (one of {}, {XT}: alpha~/L~ with the shift, or {LT}: L/R0)",
                        PARAM_NAMES.join(", ")
                    ),
                ));
            }
        }
        if p.x == p.y {
            return Err(cx.err(&key, format!("x and y are both {}", p.x)));
        }
        if let Some(by) = &p.by {
            for (j, a) in by.iter().enumerate() {
                if *a == p.x || *a == p.y {
                    return Err(cx.err(&key, format!("by names {a}, which is x or y")));
                }
                if by[..j].contains(a) {
                    return Err(cx.err(&key, format!("by names {a} twice")));
                }
            }
        }
        let plane = Plane {
            x: p.x,
            y: p.y,
            by: p.by,
        };
        if plane.is_paper() {
            return Err(cx.err(&key, "the (alpha, beta) plane is the paper's: always drawn"));
        }
        if out.contains(&plane) {
            return Err(cx.err(&key, "asked for twice"));
        }
        out.push(plane);
    }
    Ok(out)
}
