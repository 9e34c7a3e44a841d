//! `cellsweep table`: each (L, sigma) phase diagram as a grid, and every point's counts,
//! fractions with 95% Wilson intervals, and label; as text, CSV or JSON.

use cellsweep_stats::{wilson, Assessment, Counts, End, Label};
use serde_json::json;

use crate::cli::{Format, TableArgs};

use cellsweep_report::text::{
    fraction_cell, fractions, grids_text, legend, plane_grids_text, share_ends, BOX_LEGEND,
};

pub fn run(args: TableArgs) -> anyhow::Result<()> {
    let loaded = args.select.apply(args.source.load()?)?;
    let counts = loaded.counts;
    if counts.is_empty() {
        anyhow::bail!("no points in {}", loaded.name);
    }
    // An adaptive sweep's standing of each point.
    let standings = loaded.standings.as_deref();
    let plane = args.plane.plane();
    // A plane is checked whatever the format, so that a bad axis is one line, never ignored.
    let grids = if plane.is_paper() {
        grids_text(&counts)
    } else {
        plane_grids_text(&counts, &plane, &loaded.scales)?
    };
    match args.format {
        Format::Text => print_text(&grids, &counts, standings),
        Format::Csv => print_csv(&counts, standings),
        Format::Json => print_json(&counts, standings)?,
    }
    Ok(())
}

/// The standing of the `i`-th kept point, for an adaptive sweep.
fn standing_of(standings: Option<&[Assessment]>, i: usize) -> Option<&Assessment> {
    standings.map(|s| &s[i])
}

/// Each diagram's grid, then every point's counts, fractions and label.
fn print_text(grids: &str, counts: &[Counts], standings: Option<&[Assessment]>) {
    let standing = |i| standing_of(standings, i);
    print!("{grids}");
    println!("{}", legend());
    let boxed = counts.iter().filter(|c| c.box_limited).count();
    if boxed > 0 {
        println!(
            "{BOX_LEGEND} ({})",
            cellsweep_report::text::counted(boxed, "point")
        );
    }
    println!();
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
    println!("{head}  label{adaptive}");
    for (i, c) in counts.iter().enumerate() {
        let n = c.total();
        let mut line = format!(
            "{:>6} {:>6} {:>4} {:>5} {:>4} ",
            c.alpha, c.beta, c.L, c.sigma, n
        );
        for (k, _) in fractions(c) {
            line += &format!(" {:>24}", fraction_cell(k, n));
        }
        let st = standing(i).map_or(String::new(), |a| {
            format!("  {:<9} (at n = {})", a.standing.as_str(), a.n)
        });
        let label = c.label().map_or("-", Label::as_str);
        let boxed = if c.box_limited { " [box]" } else { "" };
        print!("{line}  {:<12}{st}", format!("{label}{boxed}"));
        if !c.others.is_empty() {
            print!("  {}", c.others);
        }
        println!();
    }
}

/// One CSV row per point (fractions with their Wilson intervals; an adaptive sweep's standing).
fn print_csv(counts: &[Counts], standings: Option<&[Assessment]>) {
    let standing = |i| standing_of(standings, i);
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
    println!("{header}");
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
        if let Some(a) = standing(i) {
            st = format!(",{},{}", a.standing.as_str(), a.n);
            let b = a.bounds.as_ref();
            let pairs = share_ends()
                .map(|e| b.map(|b| b.ends[e]))
                .chain([b.map(|b| b.walk_minus_train)]);
            for pair in pairs {
                st += &pair.map_or(",,".into(), |[lo, hi]| format!(",{lo:.6},{hi:.6}"));
            }
        }
        println!(
            "{row},{speed},{label},{},{}{st}",
            c.box_limited, c.sheddings
        );
    }
}

/// A JSON array of the points.
fn print_json(counts: &[Counts], standings: Option<&[Assessment]>) -> anyhow::Result<()> {
    let standing = |i| standing_of(standings, i);
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
            if let Some(a) = standing(i) {
                row["standing"] = json!(a.standing);
                row["assessed_n"] = json!(a.n);
                row["certain_label"] = json!(a.certain_label);
                row["certain_sign"] = json!(a.certain_sign);
                row["bounds"] = json!(a.bounds);
            }
            row
        })
        .collect();
    println!("{}", serde_json::to_string_pretty(&rows)?);
    Ok(())
}
