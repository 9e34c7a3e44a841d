//! What `cellsweep table` prints: each (L, sigma) phase diagram as a grid, and every point's
//! counts, fractions with 95% Wilson intervals, label and (for an adaptive sweep) standing;
//! as text ([`text`]), CSV ([`csv`]) or JSON ([`json`]).

use std::fmt::Write;

use cellsweep_stats::{wilson, Assessment, Counts, End, Label};
use serde_json::json;

use crate::text::{counted, fraction_cell, fractions, legend, share_ends, BOX_LEGEND};

/// The standing of the `i`-th point, for an adaptive sweep.
fn standing_of(standings: Option<&[Assessment]>, i: usize) -> Option<&Assessment> {
    standings.map(|s| &s[i])
}

/// Each diagram's grid (`grids`, from [`crate::text::grids_text`] or
/// [`crate::text::plane_grids_text`]), the legend, then every point's counts, fractions and
/// label.
pub fn text(grids: &str, counts: &[Counts], standings: Option<&[Assessment]>) -> String {
    let mut out = format!("{grids}{}\n", legend());
    let boxed = counts.iter().filter(|c| c.box_limited).count();
    if boxed > 0 {
        let _ = writeln!(out, "{BOX_LEGEND} ({})", counted(boxed, "point"));
    }
    out.push('\n');
    let mut head = format!(
        "{:>6} {:>6} {:>4} {:>5} {:>4} ",
        "alpha", "beta", "L", "sigma", "n"
    );
    for e in share_ends() {
        head += &format!(" {:>24}", e.words());
    }
    let adaptive = if standings.is_some() {
        "  standing (adaptive)"
    } else {
        ""
    };
    let _ = writeln!(out, "{head}  label{adaptive}");
    for (i, c) in counts.iter().enumerate() {
        let n = c.total();
        let mut line = format!(
            "{:>6} {:>6} {:>4} {:>5} {:>4} ",
            c.alpha, c.beta, c.L, c.sigma, n
        );
        for (k, _) in fractions(c) {
            line += &format!(" {:>24}", fraction_cell(k, n));
        }
        let st = standing_of(standings, i).map_or(String::new(), |a| {
            format!("  {:<9} (at n = {})", a.standing.as_str(), a.n)
        });
        let label = c.label().map_or("-", Label::as_str);
        let boxed = if c.box_limited { " [box]" } else { "" };
        let _ = write!(out, "{line}  {:<12}{st}", format!("{label}{boxed}"));
        if !c.others.is_empty() {
            let _ = write!(out, "  {}", c.others);
        }
        out.push('\n');
    }
    out
}

/// One CSV row per point (fractions with their Wilson intervals; an adaptive sweep's
/// standing), with its header.
pub fn csv(counts: &[Counts], standings: Option<&[Assessment]>) -> String {
    // A sweep's other axes, each a column after sigma (every point has the same ones).
    let others: Vec<&str> = counts.first().map_or(Vec::new(), |c| {
        c.others.0.iter().map(|(n, _)| n.as_str()).collect()
    });
    let mut header = "alpha,beta,L,sigma,".to_string();
    for name in &others {
        header += &format!("{name},");
    }
    for e in End::ALL {
        header += &format!("{},", e.count_key());
    }
    header += "n";
    for f in share_ends().map(End::name) {
        header += &format!(",f_{f},f_{f}_low,f_{f}_high");
    }
    header += ",free_speed,label,box_limited,sheddings";
    if standings.is_some() {
        header += ",standing,assessed_n";
        for f in share_ends().map(End::name) {
            header += &format!(",{f}_lo,{f}_hi");
        }
        header += ",walk_minus_train_lo,walk_minus_train_hi";
    }
    let mut out = format!("{header}\n");
    for (i, c) in counts.iter().enumerate() {
        let n = c.total();
        let mut row = format!("{},{},{},{},", c.alpha, c.beta, c.L, c.sigma);
        for (_, v) in &c.others.0 {
            row += &format!("{v},");
        }
        for (_, k) in c.tally.iter() {
            row += &format!("{k},");
        }
        row += &n.to_string();
        for (k, _) in fractions(c) {
            // (Empty cells for a point with no replicate: no fraction to give.)
            row += &match n {
                0 => ",,,".to_string(),
                _ => {
                    let f = wilson(k, n);
                    format!(",{:.6},{:.6},{:.6}", f.value, f.low, f.high)
                }
            };
        }
        let speed = c.free_speed.map_or(String::new(), |v| format!("{v:.6}"));
        let label = match (c.verdict, c.label()) {
            (Some(v), _) => v.as_str(),
            (None, Some(l)) => l.as_str(),
            (None, None) => "",
        };
        let mut st = String::new();
        if let Some(a) = standing_of(standings, i) {
            st = format!(",{},{}", a.standing.as_str(), a.n);
            let b = a.bounds.as_ref();
            let pairs = share_ends()
                .map(|e| b.map(|b| b.ends[e]))
                .chain([b.map(|b| b.walk_minus_train)]);
            for pair in pairs {
                st += &pair.map_or(",,".into(), |[lo, hi]| format!(",{lo:.6},{hi:.6}"));
            }
        }
        let _ = writeln!(
            out,
            "{row},{speed},{label},{},{}{st}",
            c.box_limited, c.sheddings
        );
    }
    out
}

/// A JSON array of the points (`"box_limited": true` on each flagged point).
pub fn json(counts: &[Counts], standings: Option<&[Assessment]>) -> serde_json::Value {
    let rows: Vec<_> = counts
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let n = c.total();
            let mut f = serde_json::Map::new();
            for (k, end) in fractions(c) {
                let w = wilson(k, n);
                // (JSON has no NaN: null for a point with no replicate.)
                f.insert(
                    end.name().into(),
                    if n == 0 {
                        json!(null)
                    } else {
                        json!({ "value": w.value, "low": w.low, "high": w.high })
                    },
                );
            }
            let mut row = json!({
                "alpha": c.alpha, "beta": c.beta, "L": c.L, "sigma": c.sigma,
                "n": n, "fractions": f,
                "free_speed": c.free_speed,
                "label": c.label().map(Label::as_str),
            });
            for (e, k) in c.tally.iter() {
                row[e.count_key()] = json!(k);
            }
            if c.box_limited {
                row["box_limited"] = json!(true);
            }
            row["sheddings"] = json!(c.sheddings);
            // A sweep's other axes, each a key beside sigma's.
            for (name, v) in &c.others.0 {
                row[name] = json!(v);
            }
            if let Some(a) = standing_of(standings, i) {
                row["standing"] = json!(a.standing);
                row["assessed_n"] = json!(a.n);
                row["certain_label"] = json!(a.certain_label);
                row["certain_sign"] = json!(a.certain_sign);
                row["bounds"] = json!(a.bounds);
            }
            row
        })
        .collect();
    serde_json::Value::Array(rows)
}
