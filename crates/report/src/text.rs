//! Results as text for a terminal: a diagram's grid of labels with its legend, fractions
//! with their intervals as table cells, and every point's outcome counts.

use std::fmt::Write as _;

use cellsweep_stats::{wilson, Counts, End, Label, Plane, PlaneError, Scales};
use cellsweep_store::PointCounts;

/// Sorted distinct values.
pub fn axis(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v.dedup();
    v
}

/// The ends whose shares tables show: every collision outcome, in the order of [`End::ALL`].
pub fn share_ends() -> impl Iterator<Item = End> {
    End::ALL.into_iter().filter(|e| e.is_collision())
}

/// Each collision end's count, in the order of [`share_ends`].
pub fn fractions(c: &Counts) -> Vec<(u64, End)> {
    share_ends().map(|e| (c.tally[e], e)).collect()
}

/// A fraction with its interval as a table cell; a point with no replicate has none.
pub fn fraction_cell(k: u64, n: u64) -> String {
    if n == 0 {
        return format!("{k:>3} -");
    }
    let f = wilson(k, n);
    format!("{k:>3} {:.2} [{:.2}, {:.2}]", f.value, f.low, f.high)
}

/// Every diagram's grid of labels: one per (L, sigma) as in the paper and, in a sweep with
/// other axes, per combination of their values (named in the grid's title).
pub fn grids_text(counts: &[Counts]) -> String {
    let mut s = String::new();
    for key in crate::figures::diagrams(counts) {
        let pts: Vec<&Counts> = counts.iter().filter(|c| key.holds(c)).collect();
        let mut title = format!("L = {}, sigma = {}", key.L, key.sigma);
        if !key.others.is_empty() {
            let _ = write!(title, ", {}", key.others);
        }
        let cells: Vec<(f64, f64, &Counts)> = pts.iter().map(|c| (c.alpha, c.beta, *c)).collect();
        let _ = writeln!(s, "{}", grid_of(&cells, ["alpha", "beta"], &title));
    }
    s
}

/// Every diagram's grid of labels in `plane` (`table --x R0 --y beta`): one per value of its
/// `by` axes, named in the grid's title.
pub fn plane_grids_text(
    counts: &[Counts],
    plane: &Plane,
    scales: &Scales,
) -> Result<String, PlaneError> {
    let mut s = String::new();
    for d in plane.diagrams(counts, scales)? {
        let cells: Vec<(f64, f64, &Counts)> = d
            .points
            .iter()
            .map(|&i| {
                let c = &counts[i];
                let at = |a: &str| Plane::value(c, a, scales).unwrap_or(f64::NAN);
                (at(&plane.x), at(&plane.y), c)
            })
            .collect();
        let _ = writeln!(s, "{}", grid_of(&cells, [&plane.x, &plane.y], &d.title()));
    }
    Ok(s)
}

/// The grid of one diagram's points, each at its (x, y): x across, y down (largest on top,
/// as in the paper).
fn grid_of(cells: &[(f64, f64, &Counts)], [x_name, y_name]: [&str; 2], title: &str) -> String {
    let xs = axis(cells.iter().map(|c| c.0));
    let ys = axis(cells.iter().map(|c| c.1));
    let n = cells.iter().map(|c| c.2.total()).max().unwrap_or(0);
    // Columns as wide as their widest value (xt has two decimals, R0 two digits).
    let shown = |v: f64| cellsweep_stats::plane::shown(x_name, v);
    let w = xs.iter().map(|&v| shown(v).len()).max().unwrap_or(0).max(5);
    let corner = format!("{y_name} \\ {x_name}");
    let left = corner.len().max(10);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{title} (up to {} per point)",
        counted(n as usize, "replicate")
    );
    let _ = write!(s, "{corner:>left$} |");
    for &a in &xs {
        let _ = write!(s, " {:>w$}", shown(a));
    }
    let _ = writeln!(s);
    let _ = writeln!(s, "{}", "-".repeat(left + 1 + (w + 1) * xs.len()));
    // Each cell by its (x, y), bit for bit: a search of every point per cell was quadratic (6 s
    // for the table of a 96,000-point sweep).
    let mut at: std::collections::HashMap<(u64, u64), &Counts> = std::collections::HashMap::new();
    for (x, y, c) in cells {
        at.entry((x.to_bits(), y.to_bits())).or_insert(c);
    }
    for b in ys.iter().rev() {
        let _ = write!(
            s,
            "{:>w2$} |",
            cellsweep_stats::plane::shown(y_name, *b),
            w2 = left
        );
        for a in &xs {
            let sym = at
                .get(&(a.to_bits(), b.to_bits()))
                .and_then(|c| c.label())
                .map_or("", Label::symbol);
            let _ = write!(s, " {sym:>w$}");
        }
        let _ = writeln!(s);
    }
    s
}

/// The symbols of the text diagrams, one per label
/// (`legend: * walk_past  x train  + reversal  *x coexist (...)  . unstable ...`).
pub fn legend() -> String {
    let entries: Vec<String> = Label::ALL
        .iter()
        .map(|l| match l {
            Label::Coexist => format!(
                "{} {} (walk-past and training within 10%)",
                l.symbol(),
                l.as_str()
            ),
            _ => format!("{} {}", l.symbol(), l.as_str()),
        })
        .collect();
    format!("legend: {}", entries.join("  "))
}

/// What `[box]` beside a label means (SPEC section 4.5).
pub const BOX_LEGEND: &str = "[box] box-limited: a prepped cell longer than 0.65 of its box (the \
     fronts start less than 0.35 Nx_s apart; SPEC 4.5): the outcome depends on the pair lattice";

/// Outcome counts of each point of a sweep, one line per point.
pub fn point_counts_text(points: &[PointCounts], name: &str, version: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "outcome counts of {name:?} ({version}):");
    // One column per end, as wide as its name.
    let width = |e: End| e.short().len().max(5);
    let mut head = format!("  {:>6} {:>6} {:>4} {:>6} ", "alpha", "beta", "L", "sigma");
    for e in End::ALL {
        head += &format!(" {:>w$}", e.short(), w = width(e));
    }
    let _ = writeln!(s, "{head}  {:>6}  {:>10}", "failed", "free speed");
    for p in points {
        let pending = p.jobs.pending + p.jobs.running;
        let mut line = format!("  {:>6} {:>6} {:>4} {:>6} ", p.alpha, p.beta, p.L, p.sigma);
        for (e, n) in p.outcomes.iter() {
            line += &format!(" {:>w$}", n, w = width(e));
        }
        let _ = writeln!(
            s,
            "{line}  {:>6}  {:>10}{}",
            p.jobs.failed,
            p.free_speed.map_or("-".into(), |v| format!("{v:.3}")),
            if pending > 0 {
                format!("  ({pending} to run)")
            } else {
                String::new()
            }
        );
    }
    s
}

/// `n` and its noun, singular or plural as English has it: "1 job", "12 jobs", "0 preps".
pub fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point whose replicates all ended in training (`train`) or walk-past.
    fn point(alpha: f64, beta: f64, train: bool) -> Counts {
        let mut c = Counts::none(alpha, beta, 90, 5.0);
        if train {
            c.tally[End::Train] = 10;
        } else {
            c.tally[End::WalkPast] = 10;
        }
        c
    }

    #[test]
    fn each_point_s_symbol_lands_in_its_own_cell() {
        // Uneven columns: (0.12, 14) is missing, (0.1, 12) is only in the first column.
        let pts = [
            point(0.1, 10.0, true),
            point(0.12, 10.0, false),
            point(0.1, 14.0, false),
            point(0.1, 12.0, true),
        ];
        let text = grids_text(&pts);
        let rows: Vec<&str> = text.lines().skip(3).take(3).collect();
        assert_eq!(
            rows,
            [
                "          14 |     *      ",
                "          12 |     x      ",
                "          10 |     x     *",
            ],
            "{text}"
        );
    }
}
