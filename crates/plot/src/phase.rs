//! Phase diagrams as in the paper's figures: (a) the dominant outcome of each point with the
//! paper's symbols, (b)-(d) heat maps of the train, walk-past and reversal frequencies, with
//! beta_crit lines dashed; and the free speed of the prepped cells against beta.

use crate::figure::{viridis, Anchor, Color, Figure, Shape};

/// The symbol of a point (the paper's: star walk-past, cross training, plus reversal, dot
/// unstable, diamond breakup, star over cross for coexistence).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    WalkPast,
    Train,
    Reversal,
    Coexist,
    Unstable,
    Breakup,
    Undetermined,
    Mixed,
}

impl Mark {
    pub const ALL: [Mark; 8] = [
        Mark::WalkPast,
        Mark::Train,
        Mark::Reversal,
        Mark::Coexist,
        Mark::Unstable,
        Mark::Breakup,
        Mark::Undetermined,
        Mark::Mixed,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Mark::WalkPast => "walk-past",
            Mark::Train => "training",
            Mark::Reversal => "reversal",
            Mark::Coexist => "coexistence",
            Mark::Unstable => "unstable",
            Mark::Breakup => "breakup",
            Mark::Undetermined => "undetermined",
            Mark::Mixed => "mixed",
        }
    }
}

/// One grid point of a diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub alpha: f64,
    pub beta: f64,
    pub mark: Option<Mark>,
    /// Frequencies of train, walk-past, reversal (NaN where no collision ran).
    pub freq: [f64; 3],
    /// Replicates with a result.
    pub n: u64,
    /// An adaptive point that takes more rounds (its mark may still change).
    pub open: bool,
    /// The point's counts and intervals in words: the SVG's tooltip (`<title>`).
    pub detail: String,
}

/// A line beta(alpha), drawn dashed.
#[derive(Debug, Clone, PartialEq)]
pub struct BetaLine {
    pub label: String,
    pub color: Color,
    /// beta = slope * alpha + intercept in this diagram.
    pub slope: f64,
    pub intercept: f64,
}

/// One (L, sigma) diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagram {
    pub title: String,
    pub points: Vec<Point>,
    pub lines: Vec<BetaLine>,
}

fn axis(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut a: Vec<f64> = v.collect();
    a.sort_by(|x, y| x.total_cmp(y));
    a.dedup();
    a
}

/// Data range with half a grid step of room on each side.
fn span(values: &[f64]) -> (f64, f64) {
    let (lo, hi) = (values[0], values[values.len() - 1]);
    let step = if values.len() > 1 {
        (hi - lo) / (values.len() - 1) as f64
    } else {
        lo.abs().max(1.0) * 0.2
    };
    (lo - step / 2.0, hi + step / 2.0)
}

/// Clip the segment of y = m x + c over [x0, x1] to y in [y0, y1].
fn clip(
    m: f64,
    c: f64,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (mut a, mut b) = (x0, x1);
    if m.abs() < 1e-300 {
        return (c >= y0 && c <= y1).then_some(((x0, c), (x1, c)));
    }
    let (xa, xb) = ((y0 - c) / m, (y1 - c) / m);
    let (lo, hi) = (xa.min(xb), xa.max(xb));
    a = a.max(lo);
    b = b.min(hi);
    (a < b).then_some(((a, m * a + c), (b, m * b + c)))
}

struct Panel {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
    ax: (f64, f64),
    by: (f64, f64),
}

impl Panel {
    fn px(&self, alpha: f64) -> f64 {
        self.x + (alpha - self.ax.0) / (self.ax.1 - self.ax.0) * self.w
    }
    fn py(&self, beta: f64) -> f64 {
        self.y + self.h - (beta - self.by.0) / (self.by.1 - self.by.0) * self.h
    }
}

/// Draw a symbol centred at (x, y) with radius r.
pub fn draw_mark(fig: &mut Figure, mark: Mark, x: f64, y: f64, r: f64) {
    let star = |fig: &mut Figure| {
        let pts: Vec<(f64, f64)> = (0..10)
            .map(|k| {
                let ang = -std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI / 5.0;
                let rr = if k % 2 == 0 { r } else { r * 0.42 };
                (x + rr * ang.cos(), y + rr * ang.sin())
            })
            .collect();
        fig.push(Shape::Polygon {
            points: pts,
            fill: Some(Color::RED),
            stroke: None,
        });
    };
    let cross = |fig: &mut Figure, c: Color| {
        let d = r * 0.75;
        fig.line(x - d, y - d, x + d, y + d, c, 2.5);
        fig.line(x - d, y + d, x + d, y - d, c, 2.5);
    };
    match mark {
        Mark::WalkPast => star(fig),
        Mark::Train => cross(fig, Color::BLUE),
        Mark::Reversal => {
            fig.line(x - r, y, x + r, y, Color::GREEN, 2.5);
            fig.line(x, y - r, x, y + r, Color::GREEN, 2.5);
        }
        Mark::Coexist => {
            star(fig);
            cross(fig, Color::BLUE);
        }
        Mark::Unstable => fig.push(Shape::Circle {
            cx: x,
            cy: y,
            r: r * 0.4,
            fill: Some(Color::BLUE),
            stroke: None,
        }),
        Mark::Breakup => fig.push(Shape::Polygon {
            points: vec![(x, y - r), (x + r * 0.7, y), (x, y + r), (x - r * 0.7, y)],
            fill: None,
            stroke: Some(Color::CYAN),
        }),
        Mark::Undetermined => fig.text(x, y + 5.0, 16.0, Anchor::Middle, "?"),
        Mark::Mixed => fig.push(Shape::Circle {
            cx: x,
            cy: y,
            r: r * 0.5,
            fill: None,
            stroke: Some(Color::GREY),
        }),
    }
}

fn frame(fig: &mut Figure, p: &Panel, alphas: &[f64], betas: &[f64], title: &str) {
    fig.push(Shape::Rect {
        x: p.x,
        y: p.y,
        w: p.w,
        h: p.h,
        fill: None,
        stroke: Some(Color::BLACK),
    });
    fig.text(p.x + p.w / 2.0, p.y - 12.0, 15.0, Anchor::Middle, title);
    // A tick at every grid value; labels thinned to at most 6 across and 11 down.
    let every = alphas.len().div_ceil(6).max(1);
    for (k, a) in alphas.iter().enumerate() {
        let x = p.px(*a);
        fig.line(x, p.y + p.h, x, p.y + p.h + 5.0, Color::BLACK, 1.0);
        if k % every == 0 {
            fig.text(x, p.y + p.h + 19.0, 12.0, Anchor::Middle, format!("{a}"));
        }
    }
    let every = betas.len().div_ceil(11).max(1);
    for (k, b) in betas.iter().enumerate() {
        let y = p.py(*b);
        fig.line(p.x - 5.0, y, p.x, y, Color::BLACK, 1.0);
        if k % every == 0 {
            fig.text(p.x - 8.0, y + 4.0, 12.0, Anchor::End, format!("{b}"));
        }
    }
    fig.text(p.x + p.w / 2.0, p.y + p.h + 40.0, 17.0, Anchor::Middle, "α");
    fig.text(p.x - 36.0, p.y + p.h / 2.0 + 6.0, 17.0, Anchor::End, "β");
}

fn lines(fig: &mut Figure, p: &Panel, d: &Diagram) {
    for l in &d.lines {
        if let Some(((a0, b0), (a1, b1))) = clip(l.slope, l.intercept, p.ax, p.by) {
            fig.push(Shape::Line {
                x1: p.px(a0),
                y1: p.py(b0),
                x2: p.px(a1),
                y2: p.py(b1),
                color: l.color,
                width: 2.5,
                dash: Some(8.0),
            });
        }
    }
}

/// Width in pixels of `text` at font size `size` (DejaVu Sans averages about 0.6 em).
fn text_width(text: &str, size: f64) -> f64 {
    0.6 * size
        * text
            .chars()
            .filter(|c| !matches!(c, '_' | '{' | '}'))
            .count() as f64
}

/// The four-panel figure of one diagram.
pub fn diagram_figure(d: &Diagram) -> Figure {
    let alphas = axis(d.points.iter().map(|p| p.alpha));
    let betas = axis(d.points.iter().map(|p| p.beta));
    let (pw, ph) = (240.0, 300.0);
    let mut fig = Figure::new(4 * 310 + 110, 540);
    fig.text(20.0, 28.0, 18.0, Anchor::Start, d.title.clone());
    if alphas.is_empty() {
        return fig;
    }
    let (ax, by) = (span(&alphas), span(&betas));
    let (cw, ch) = (pw / alphas.len() as f64, ph / betas.len() as f64);
    let titles = [
        "(a) outcome",
        "(b) training",
        "(c) walk-past",
        "(d) reversal",
    ];
    for (k, title) in titles.iter().enumerate() {
        let p = Panel {
            x: 70.0 + k as f64 * 310.0,
            y: 76.0,
            w: pw,
            h: ph,
            ax,
            by,
        };
        for pt in &d.points {
            let mut shapes = Figure::new(0, 0);
            let (x, y) = (p.px(pt.alpha), p.py(pt.beta));
            if k == 0 {
                let r = (cw.min(ch) * 0.38).min(14.0);
                if let Some(m) = pt.mark {
                    draw_mark(&mut shapes, m, x, y, r);
                }
                // Replicates per point, lower right of the mark; '+': an open adaptive point.
                let n = format!("{}{}", pt.n, if pt.open { "+" } else { "" });
                shapes.text(x + r - 1.0, y + r + 3.0, 9.0, Anchor::Start, n);
            } else {
                let f = pt.freq[k - 1];
                shapes.push(Shape::Rect {
                    x: x - cw / 2.0,
                    y: y - ch / 2.0,
                    w: cw + 0.5,
                    h: ch + 0.5,
                    fill: Some(if f.is_finite() {
                        viridis(f)
                    } else {
                        Color::LIGHT
                    }),
                    stroke: None,
                });
            }
            fig.push(Shape::Group {
                title: pt.detail.clone(),
                shapes: shapes.shapes,
            });
        }
        lines(&mut fig, &p, d);
        frame(&mut fig, &p, &alphas, &betas, title);
    }
    // Colour bar of the frequencies, ticked at quarters.
    let (bx, by0, bh) = (4.0 * 310.0 + 20.0, 76.0, ph);
    for i in 0..100 {
        let t = (i as f64 + 0.5) / 100.0;
        fig.push(Shape::Rect {
            x: bx,
            y: by0 + bh * (1.0 - t) - bh / 200.0,
            w: 16.0,
            h: bh / 100.0 + 0.5,
            fill: Some(viridis(t)),
            stroke: None,
        });
    }
    fig.push(Shape::Rect {
        x: bx,
        y: by0,
        w: 16.0,
        h: bh,
        fill: None,
        stroke: Some(Color::BLACK),
    });
    for (t, s) in [
        (0.0, "0"),
        (0.25, "0.25"),
        (0.5, "0.5"),
        (0.75, "0.75"),
        (1.0, "1"),
    ] {
        let y = by0 + bh * (1.0 - t);
        fig.line(bx + 16.0, y, bx + 21.0, y, Color::BLACK, 1.0);
        fig.text(bx + 24.0, y + 4.0, 12.0, Anchor::Start, s);
    }
    fig.text(bx - 2.0, by0 - 12.0, 12.0, Anchor::Start, "frequency");
    // Legend: symbols present and grey cells if any; the lines on a second row; a third
    // explains n.
    let mut x = 70.0;
    let y = 462.0;
    for m in Mark::ALL {
        if d.points.iter().any(|p| p.mark == Some(m)) {
            draw_mark(&mut fig, m, x, y - 5.0, 9.0);
            fig.text(x + 14.0, y, 12.0, Anchor::Start, m.name());
            x += 34.0 + text_width(m.name(), 12.0);
        }
    }
    if d.points
        .iter()
        .any(|p| p.freq.iter().any(|f| !f.is_finite()))
    {
        fig.push(Shape::Rect {
            x,
            y: y - 12.0,
            w: 14.0,
            h: 14.0,
            fill: Some(Color::LIGHT),
            stroke: Some(Color::GREY),
        });
        let label = "no collision (prep unstable or broke up)";
        fig.text(x + 20.0, y, 12.0, Anchor::Start, label);
    }
    let (mut x, y) = (70.0, y + 24.0);
    for l in &d.lines {
        fig.push(Shape::Line {
            x1: x,
            y1: y - 4.0,
            x2: x + 30.0,
            y2: y - 4.0,
            color: l.color,
            width: 2.5,
            dash: Some(6.0),
        });
        fig.text(x + 36.0, y, 12.0, Anchor::Start, l.label.clone());
        x += 56.0 + text_width(&l.label, 12.0);
    }
    fig.text(
        70.0,
        y + 24.0,
        12.0,
        Anchor::Start,
        if d.points.iter().any(|p| p.open) {
            "numbers: replicates per point (n); n+ : an adaptive point still taking rounds"
        } else {
            "numbers: replicates per point (n)"
        },
    );
    fig
}

/// Round tick values covering [lo, hi]: steps of 1, 2 or 5 times a power of ten, at most
/// about `max` of them.
pub fn nice_ticks(lo: f64, hi: f64, max: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo || max == 0 {
        return vec![lo];
    }
    let raw = (hi - lo) / max as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            // Shed the float noise of k x step (0.30000000000000004).
            format!("{v:.10}").parse().unwrap_or(v)
        })
        .collect()
}

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
    let bar = |s: &Series, k: usize| s.errors.get(k).copied().filter(|e| e.is_finite());
    let all: Vec<(f64, f64, f64)> = series
        .iter()
        .flat_map(|s| {
            s.points
                .iter()
                .enumerate()
                .map(move |(k, p)| (p.0, p.1, bar(s, k).unwrap_or(0.0)))
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
    fig.push(Shape::Rect {
        x: p.x,
        y: p.y,
        w: p.w,
        h: p.h,
        fill: None,
        stroke: Some(Color::BLACK),
    });
    for b in nice_ticks(bx.0, bx.1, 8) {
        let x = p.px(b);
        fig.line(x, p.y + p.h, x, p.y + p.h + 5.0, Color::BLACK, 1.0);
        fig.text(x, p.y + p.h + 19.0, 12.0, Anchor::Middle, format!("{b}"));
    }
    for v in nice_ticks(p.by.0, p.by.1, 6) {
        fig.line(p.x - 5.0, p.py(v), p.x, p.py(v), Color::BLACK, 1.0);
        fig.text(p.x - 8.0, p.py(v) + 4.0, 12.0, Anchor::End, format!("{v}"));
    }
    fig.text(p.x + p.w / 2.0, p.y + p.h + 42.0, 17.0, Anchor::Middle, "β");
    fig.vtext(p.x - 52.0, p.y + p.h / 2.0, 14.0, "free speed (l_0/τ_0)");
    for (k, s) in series.iter().enumerate() {
        let mut pts: Vec<(f64, f64, Option<f64>)> = s
            .points
            .iter()
            .enumerate()
            .map(|(i, q)| (q.0, q.1, bar(s, i)))
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
    fig
}

#[cfg(test)]
mod tests {
    use super::nice_ticks;

    #[test]
    fn ticks_are_round() {
        assert_eq!(nice_ticks(0.0, 0.76, 6), vec![0.0, 0.2, 0.4, 0.6]);
        assert_eq!(nice_ticks(8.0, 52.0, 8), vec![10.0, 20.0, 30.0, 40.0, 50.0]);
        assert_eq!(nice_ticks(0.0, 1.0, 4), vec![0.0, 0.5, 1.0]);
    }
}
