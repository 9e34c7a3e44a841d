//! The free speed of the prepped cells against beta, one curve per series.

use crate::figure::{Anchor, Color, Figure, Shape};
use crate::panel::{axis, span, text_width, Panel};

/// A curve of the speed figure: points (beta, value) with an optional error bar each.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub color: Color,
    pub points: Vec<(f64, f64)>,
    /// Half-heights of the error bars, one per point (empty: none).
    pub errors: Vec<f64>,
}

/// Free speed of the prepped cells against beta, one curve per series.
pub fn speed_figure(title: &str, series: &[Series]) -> Figure {
    let legend = series
        .iter()
        .map(|s| text_width(&s.label, 12.0))
        .fold(0.0, f64::max);
    let mut fig = Figure::new((560.0 + legend + 60.0) as u32, 440);
    fig.text(20.0, 28.0, 16.0, Anchor::Start, title);
    let all: Vec<(f64, f64, f64)> = series
        .iter()
        .flat_map(|s| {
            s.points
                .iter()
                .enumerate()
                .map(move |(k, p)| (p.0, p.1, error_bar(s, k).unwrap_or(0.0)))
        })
        .filter(|p| p.1.is_finite())
        .collect();
    if all.is_empty() {
        fig.text(
            280.0,
            220.0,
            16.0,
            Anchor::Middle,
            "no free speeds recorded",
        );
        return fig;
    }
    let betas = axis(all.iter().map(|p| p.0));
    let bx = span(&betas);
    let vmax = all.iter().map(|p| p.1 + p.2).fold(f64::MIN, f64::max);
    let vmin = all
        .iter()
        .map(|p| p.1 - p.2)
        .fold(f64::MAX, f64::min)
        .min(0.0);
    let vmax = vmax + 0.08 * (vmax - vmin).max(1e-9);
    let p = Panel {
        x: 90.0,
        y: 60.0,
        w: 420.0,
        h: 300.0,
        ax: bx,
        by: (vmin, vmax),
    };
    axes(&mut fig, &p);
    for (k, s) in series.iter().enumerate() {
        curve(&mut fig, &p, s, k);
    }
    fig
}

/// The half-height of point k's error bar, if it has a finite one.
fn error_bar(s: &Series, k: usize) -> Option<f64> {
    s.errors.get(k).copied().filter(|e| e.is_finite())
}

/// The frame, ticks and axis labels of the panel (beta across, the speed up).
fn axes(fig: &mut Figure, p: &Panel) {
    p.frame_with_round_ticks(fig, 8, 6);
    fig.text(p.x + p.w / 2.0, p.y + p.h + 42.0, 17.0, Anchor::Middle, "β");
    fig.vtext(p.x - 52.0, p.y + p.h / 2.0, 14.0, "free speed (l_0/τ_0)");
}

/// Series `s` (the k-th) as dots joined in beta order, with its error bars and a legend row.
fn curve(fig: &mut Figure, p: &Panel, s: &Series, k: usize) {
    let mut pts: Vec<(f64, f64, Option<f64>)> = s
        .points
        .iter()
        .enumerate()
        .map(|(i, q)| (q.0, q.1, error_bar(s, i)))
        .filter(|q| q.1.is_finite())
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in pts.windows(2) {
        fig.line(
            p.px(w[0].0),
            p.py(w[0].1),
            p.px(w[1].0),
            p.py(w[1].1),
            s.color,
            2.0,
        );
    }
    for (b, v, e) in &pts {
        if let Some(e) = e {
            let x = p.px(*b);
            fig.line(x, p.py(v - e), x, p.py(v + e), s.color, 1.5);
            for y in [p.py(v - e), p.py(v + e)] {
                fig.line(x - 4.0, y, x + 4.0, y, s.color, 1.5);
            }
        }
        fig.push(Shape::Circle {
            cx: p.px(*b),
            cy: p.py(*v),
            r: 4.0,
            fill: Some(s.color),
            stroke: None,
        });
    }
    let ly = p.y + 10.0 + 20.0 * k as f64;
    fig.line(p.x + p.w + 14.0, ly, p.x + p.w + 36.0, ly, s.color, 2.0);
    fig.text(
        p.x + p.w + 42.0,
        ly + 4.0,
        12.0,
        Anchor::Start,
        s.label.clone(),
    );
}
