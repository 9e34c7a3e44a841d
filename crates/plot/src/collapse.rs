//! The collapse figure: every column's beta* with its 95% interval against x = alpha~/L~, one
//! series (colour and marker) per group of columns (a spacing, R0 and sigma), with straight
//! lines beta = a x + b across it (the fit over every column, the paper's). If beta* depends on
//! the parameters only through alpha~/L~, as the paper's theory says, every series falls on one
//! line.

use crate::figure::{Anchor, Color, Figure, Shape};
use crate::panel::{clip, text_width, Panel};

/// One column's crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct Crossing {
    /// alpha~/L~ of the column.
    pub x: f64,
    pub beta_star: f64,
    /// Its 95% interval, where it has one.
    pub ci: Option<[f64; 2]>,
    /// The tooltip: the column and its numbers.
    pub title: String,
}

/// The crossings of one group of columns, drawn alike.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub color: Color,
    pub crossings: Vec<Crossing>,
}

/// A line beta = a x + b across the figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    pub label: String,
    pub color: Color,
    pub a: f64,
    pub b: f64,
    /// Dash length, for a line drawn dashed.
    pub dash: Option<f64>,
}

/// Colours that stay apart for colour-blind readers (Okabe and Ito), then repeat.
pub const PALETTE: [Color; 7] = [
    Color(0, 114, 178),
    Color(213, 94, 0),
    Color(0, 158, 115),
    Color(204, 121, 167),
    Color(230, 159, 0),
    Color(86, 180, 233),
    Color(90, 90, 90),
];

/// beta* against alpha~/L~ for every series, with `lines` across.
pub fn collapse_figure(title: &str, series: &[Series], lines: &[Line]) -> Figure {
    let legend = series
        .iter()
        .map(|s| text_width(&s.label, 12.0))
        .chain(lines.iter().map(|l| text_width(&l.label, 12.0)))
        .fold(0.0, f64::max);
    let mut fig = Figure::new((600.0 + legend + 60.0) as u32, 460);
    fig.text(20.0, 28.0, 16.0, Anchor::Start, title);
    let all: Vec<&Crossing> = series
        .iter()
        .flat_map(|s| &s.crossings)
        .filter(|c| c.x.is_finite() && c.beta_star.is_finite())
        .collect();
    if all.is_empty() {
        let text = "no column has a walk-past/training crossing yet";
        fig.text(300.0, 230.0, 16.0, Anchor::Middle, text);
        return fig;
    }
    let p = Panel {
        x: 90.0,
        y: 60.0,
        w: 460.0,
        h: 320.0,
        ax: room(all.iter().map(|c| c.x)),
        by: room(all.iter().flat_map(|c| {
            let [lo, hi] = c.ci.unwrap_or([c.beta_star; 2]);
            [lo, hi, c.beta_star]
        })),
    };
    frame(&mut fig, &p);
    for l in lines {
        if let Some(((x0, y0), (x1, y1))) = clip(l.a, l.b, p.ax, p.by) {
            fig.push(Shape::Line {
                x1: p.px(x0),
                y1: p.py(y0),
                x2: p.px(x1),
                y2: p.py(y1),
                color: l.color,
                width: 2.0,
                dash: l.dash,
            });
        }
    }
    for (k, s) in series.iter().enumerate() {
        for c in &s.crossings {
            fig.push(crossing(&p, c, s.color, k));
        }
    }
    let mut row = 0;
    for (k, s) in series.iter().enumerate() {
        let (lx, ly) = (p.x + p.w + 20.0, p.y + 10.0 + 20.0 * row as f64);
        fig.push(marker(lx + 10.0, ly, s.color, k));
        fig.text(lx + 26.0, ly + 4.0, 12.0, Anchor::Start, s.label.clone());
        row += 1;
    }
    for l in lines {
        let (lx, ly) = (p.x + p.w + 20.0, p.y + 10.0 + 20.0 * row as f64);
        fig.push(Shape::Line {
            x1: lx,
            y1: ly,
            x2: lx + 20.0,
            y2: ly,
            color: l.color,
            width: 2.0,
            dash: l.dash,
        });
        fig.text(lx + 26.0, ly + 4.0, 12.0, Anchor::Start, l.label.clone());
        row += 1;
    }
    fig
}

/// The range of `v` with 8% of room on each side.
fn room(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| x.is_finite())
        .fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
    let pad = 0.08 * (hi - lo).max(1e-9 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// The frame, ticks and axis labels (alpha~/L~ across, beta* up).
fn frame(fig: &mut Figure, p: &Panel) {
    p.frame_with_round_ticks(fig, 8, 7);
    let (cx, cy) = (p.x + p.w / 2.0, p.y + p.h / 2.0);
    fig.text(cx, p.y + p.h + 42.0, 15.0, Anchor::Middle, "α̃ / L̃");
    fig.vtext(p.x - 52.0, cy, 15.0, "β*");
}

/// Column `c` of the k-th series: its interval as a bar with caps, its marker, its tooltip.
fn crossing(p: &Panel, c: &Crossing, color: Color, k: usize) -> Shape {
    let (x, y) = (p.px(c.x), p.py(c.beta_star));
    let mut shapes = Vec::new();
    if let Some([lo, hi]) = c.ci.filter(|ci| ci.iter().all(|v| v.is_finite())) {
        let (ylo, yhi) = (p.py(lo), p.py(hi));
        for (x1, y1, x2, y2) in [
            (x, ylo, x, yhi),
            (x - 4.0, ylo, x + 4.0, ylo),
            (x - 4.0, yhi, x + 4.0, yhi),
        ] {
            shapes.push(bar(x1, y1, x2, y2, color));
        }
    }
    shapes.push(marker(x, y, color, k));
    Shape::Group {
        title: c.title.clone(),
        shapes,
    }
}

fn bar(x1: f64, y1: f64, x2: f64, y2: f64, color: Color) -> Shape {
    Shape::Line {
        x1,
        y1,
        x2,
        y2,
        color,
        width: 1.5,
        dash: None,
    }
}

/// The k-th series' marker at (x, y): a circle, a square, a triangle, a diamond, in turn.
fn marker(x: f64, y: f64, color: Color, k: usize) -> Shape {
    let (fill, stroke) = (Some(color), Some(Color::BLACK));
    let r = 5.0;
    match k % 4 {
        0 => Shape::Circle {
            cx: x,
            cy: y,
            r,
            fill,
            stroke,
        },
        1 => Shape::Rect {
            x: x - r,
            y: y - r,
            w: 2.0 * r,
            h: 2.0 * r,
            fill,
            stroke,
        },
        2 => Shape::Polygon {
            points: vec![(x, y - 1.2 * r), (x + r, y + 0.8 * r), (x - r, y + 0.8 * r)],
            fill,
            stroke,
        },
        _ => Shape::Polygon {
            points: vec![(x, y - 1.3 * r), (x + r, y), (x, y + 1.3 * r), (x - r, y)],
            fill,
            stroke,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(label: &str, pts: &[(f64, f64)]) -> Series {
        Series {
            label: label.into(),
            color: PALETTE[0],
            crossings: pts
                .iter()
                .map(|&(x, b)| Crossing {
                    x,
                    beta_star: b,
                    ci: Some([b - 1.0, b + 1.0]),
                    title: format!("x = {x}"),
                })
                .collect(),
        }
    }

    #[test]
    fn every_crossing_is_drawn_with_its_tooltip_and_lines_stay_inside() {
        let s = [
            series("R_{0} = 40", &[(50.0, 18.0), (70.0, 28.0)]),
            series("R_{0} = 32 <&>", &[(60.0, 23.0)]),
        ];
        let line = Line {
            label: "paper".into(),
            color: Color::BLACK,
            a: 0.6,
            b: -12.0,
            dash: Some(6.0),
        };
        let svg = collapse_figure("collapse", &s, &[line]).to_svg();
        assert_eq!(svg.matches("<title>x = ").count(), 3, "{svg}");
        assert!(svg.contains("stroke-dasharray"));
        assert!(svg.contains("&lt;&amp;&gt;"), "labels are escaped");
        let empty = collapse_figure("collapse", &[series("none", &[])], &[]).to_svg();
        assert!(empty.contains("no column has"));
    }
}
