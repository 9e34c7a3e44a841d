//! Counts into drawings: one (L, sigma) phase diagram with its four panels, and the free speed
//! against beta. `cellsweep plot` writes them as files, `cellsweep report` inline.

use cellsweep_plot::phase::{diagram_figure, BetaLine, Diagram, Point};
use cellsweep_plot::speed::{speed_figure, Series};
use cellsweep_plot::{Color, Figure};
use cellsweep_stats::fit::{PAPER_A, PAPER_B};
use cellsweep_stats::{wilson, Assessment, Counts, End, Fit, Plane, PlaneError, Scales, Standing};

use crate::collection::DiagramKey;
use crate::Results;

/// beta = a x(alpha) + b as a line in the (alpha, beta) plane of diagram (L, sigma).
pub fn beta_line(
    scales: &Scales,
    (a, b): (f64, f64),
    (spacing, sigma): (u32, f64),
    label: String,
    color: Color,
) -> BetaLine {
    let x0 = scales.x(0.0, spacing, sigma);
    let x1 = scales.x(1.0, spacing, sigma);
    BetaLine {
        label,
        color,
        slope: a * (x1 - x0),
        intercept: a * x0 + b,
    }
}

/// The diagrams of `counts`: per (L, sigma) and per value of every other axis, widest spacing
/// and largest sigma first, then the other axes' values rising.
pub fn diagrams(counts: &[Counts]) -> Vec<DiagramKey> {
    let mut keys: Vec<DiagramKey> = Vec::new();
    for c in counts {
        if !keys.iter().any(|k| k.holds(c)) {
            keys.push(DiagramKey::of(c));
        }
    }
    keys.sort_by(|a, b| {
        (b.L.cmp(&a.L))
            .then(b.sigma.total_cmp(&a.sigma))
            .then(a.others.bits().cmp(&b.others.bits()))
    });
    keys
}

/// The adaptive assessment of point `i` of `results`, if the sweep is adaptive.
pub fn assessment(results: &Results, i: usize) -> Option<&Assessment> {
    results.standings.as_ref().and_then(|st| st.get(i))
}

/// Diagram `key` of `results` with the paper's line and, if given, a fitted one (each at the
/// diagram's own R0 and d where its sweep varies them).
pub fn diagram(results: &Results, key: &DiagramKey, fit: Option<&Fit>) -> Diagram {
    let (l, sigma) = (key.L, key.sigma);
    let scales = results.scales.at(&key.others);
    let points = results
        .counts
        .iter()
        .enumerate()
        .filter(|(_, c)| key.holds(c))
        .map(|(i, c)| point(results, i, c.alpha, c.beta))
        .collect();
    let mut lines = vec![beta_line(
        &scales,
        (PAPER_A, PAPER_B),
        (l, sigma),
        "paper\u{2019}s β_{crit}".into(),
        Color::BLACK,
    )];
    if let Some(fit) = fit {
        lines.push(beta_line(
            &scales,
            (fit.a, fit.b),
            (l, sigma),
            format!("fit: a = {:.2}, b = {:.1}", fit.a, fit.b),
            Color::ORANGE,
        ));
    }
    let um = l as f64 * cellsweep_plot::frames::SITE_UM;
    Diagram {
        axes: Diagram::paper_axes(),
        title: match key.others.is_empty() {
            true => format!("{}: L = {l} ({um} µm), σ = {sigma}", results.name),
            false => format!(
                "{}: L = {l} ({um} µm), σ = {sigma}, {}",
                results.name, key.others
            ),
        },
        points,
        lines,
    }
}

/// Point `i` of `results` drawn at (x, y): its mark, frequencies, replicates, standing and
/// tooltip.
fn point(results: &Results, i: usize, x: f64, y: f64) -> Point {
    let c = &results.counts[i];
    let n = c.collisions() as f64;
    let f = |k: u64| {
        if c.collided() && n > 0.0 {
            k as f64 / n
        } else {
            f64::NAN
        }
    };
    let a = assessment(results, i);
    Point {
        x,
        y,
        mark: c.label(),
        freq: [f(c.n_train()), f(c.n_walk()), f(c.tally[End::Reversal])],
        n: c.total(),
        open: a.is_some_and(|a| a.standing == Standing::Open),
        boxed: c.box_limited,
        detail: detail(c, a),
    }
}

/// The name an axis is labelled with in a figure.
fn axis_label(name: &str) -> String {
    match name {
        "alpha" => "α".into(),
        "beta" => "β".into(),
        "sigma" => "σ".into(),
        cellsweep_stats::plane::XT => "α̃/L̃".into(),
        cellsweep_stats::plane::LT => "L̃".into(),
        other => other.into(),
    }
}

/// Every diagram of `results` in `plane` (`plot --x R0 --y beta`), each with the stem of its
/// picture files (`plane-beta-R0-xt_49.95-sigma_5`). No beta_crit line: it lives in the
/// (alpha, beta) plane.
pub fn plane_diagrams(
    results: &Results,
    plane: &Plane,
) -> Result<Vec<(String, Diagram)>, PlaneError> {
    let diagrams = plane.diagrams(&results.counts, &results.scales)?;
    Ok(diagrams
        .into_iter()
        .map(|d| {
            let at = |c: &Counts, a: &str| Plane::value(c, a, &results.scales).unwrap_or(f64::NAN);
            let points = d
                .points
                .iter()
                .map(|&i| {
                    let c = &results.counts[i];
                    point(results, i, at(c, &plane.x), at(c, &plane.y))
                })
                .collect();
            let mut stem = format!("plane-{}-{}", plane.y, plane.x);
            for (n, v) in &d.fixed {
                stem += &format!("-{n}_{}", cellsweep_stats::plane::shown(n, *v));
            }
            let diagram = Diagram {
                title: format!("{}: {}", results.name, d.title()),
                axes: [axis_label(&plane.x), axis_label(&plane.y)],
                points,
                lines: Vec::new(),
            };
            (stem, diagram)
        })
        .collect())
}

/// The four-panel figure of diagram `key`.
pub fn diagram_of(results: &Results, key: &DiagramKey, fit: Option<&Fit>) -> Figure {
    diagram_figure(&diagram(results, key, fit))
}

/// Free speed against beta, one curve per (L, alpha) (sigma does not change the prep), with
/// the standard error over a point's prepped cells where there are several.
pub fn speed_series(results: &Results) -> Vec<Series> {
    let palette = [
        Color::BLUE,
        Color::RED,
        Color::GREEN,
        Color::ORANGE,
        Color::CYAN,
        Color(120, 60, 160),
        Color::GREY,
        Color::BLACK,
    ];
    let mut keys: Vec<(u32, f64)> = Vec::new();
    for c in &results.counts {
        if c.free_speed.is_some() && !keys.contains(&(c.L, c.alpha)) {
            keys.push((c.L, c.alpha));
        }
    }
    keys.iter()
        .enumerate()
        .map(|(k, &(l, alpha))| {
            let mut points: Vec<(f64, f64)> = Vec::new();
            let mut errors: Vec<f64> = Vec::new();
            for (i, c) in results.counts.iter().enumerate() {
                if c.L != l || c.alpha != alpha || points.iter().any(|p| p.0 == c.beta) {
                    continue;
                }
                if let Some(v) = c.free_speed {
                    points.push((c.beta, v));
                    let cells = results.prep_speeds.as_ref().map_or(&[][..], |s| &s[i][..]);
                    errors.push(standard_error(cells));
                }
            }
            let several = errors.iter().any(|e| e.is_finite());
            Series {
                label: format!("L = {l}, α = {alpha}"),
                color: palette[k % palette.len()],
                points,
                errors: if several { errors } else { Vec::new() },
            }
        })
        .collect()
}

/// The free-speed figure of `results`.
pub fn speed_of(results: &Results) -> Figure {
    let series = speed_series(results);
    let title = if series.iter().any(|s| !s.errors.is_empty()) {
        format!(
            "{}: mean free speed of the prepped cells ± standard error",
            results.name
        )
    } else {
        format!("{}: free speed of the prepped cell", results.name)
    };
    speed_figure(&title, &series)
}

/// A point's tooltip: where it is, its counts, its label, and its adaptive standing.
pub fn detail(c: &Counts, a: Option<&Assessment>) -> String {
    let mut out = format!(
        "α = {}, β = {}, L = {}, σ = {}: n = {} ({}",
        c.alpha,
        c.beta,
        c.L,
        c.sigma,
        c.total(),
        c.tally.line(End::words, ", ")
    );
    out += ")";
    let collided = c.collisions();
    if collided > 0 {
        let f = |k: u64| {
            let w = wilson(k, collided);
            format!("{:.2} [{:.2}, {:.2}]", w.value, w.low, w.high)
        };
        out += &format!(
            "; fractions with 95% Wilson intervals: training {}, walk-past {}, reversal {}",
            f(c.n_train()),
            f(c.n_walk()),
            f(c.tally[End::Reversal])
        );
    }
    if let Some(label) = c.label() {
        out += &format!("; label {}", label.as_str());
    }
    if let Some(a) = a {
        out += &format!("; adaptive: {}", a.standing.as_str());
        if let Some(b) = &a.bounds {
            out += &format!(
                "; bounds at the stated error: p_train [{:.2}, {:.2}], p_walk [{:.2}, {:.2}], \
                 p_walk - p_train [{:.2}, {:.2}]",
                b.ends[End::Train][0],
                b.ends[End::Train][1],
                b.ends[End::WalkPast][0],
                b.ends[End::WalkPast][1],
                b.walk_minus_train[0],
                b.walk_minus_train[1]
            );
        }
    }
    out
}

/// The mean of `xs` and its standard error (NaN error for fewer than two).
pub fn mean_and_error(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    (mean, standard_error(xs))
}

/// The standard error of the mean of `xs` (NaN for fewer than two).
pub fn standard_error(xs: &[f64]) -> f64 {
    let n = xs.len() as f64;
    if xs.len() < 2 {
        return f64::NAN;
    }
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (var / n).sqrt()
}

#[cfg(test)]
mod tests {
    use super::standard_error;

    #[test]
    fn the_standard_error_is_of_the_mean() {
        // Sample sd of 1, 2, 3, 4 is sqrt(5/3); over sqrt(4).
        let se = standard_error(&[1.0, 2.0, 3.0, 4.0]);
        assert!((se - (5.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-12);
        assert!(standard_error(&[1.0]).is_nan());
    }
}
