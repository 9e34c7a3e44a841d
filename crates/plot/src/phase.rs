//! Phase diagrams as in the paper's figures: (a) the dominant outcome of each point with the
//! paper's symbols ([`Label`] drawn by [`draw_mark`]), (b)-(d) heat maps of the train, walk-past and reversal
//! frequencies, with beta_crit lines dashed.

use crate::figure::{viridis, Anchor, Color, Figure, Shape};
use crate::mark::{self, draw_mark, Label};
use crate::panel::{axis, clip, span, text_width, Panel};

/// One grid point of a diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// Its place across (alpha in the paper's diagrams) and up (beta).
    pub x: f64,
    pub y: f64,
    pub mark: Option<Label>,
    /// Frequencies of train, walk-past, reversal (NaN where no collision ran).
    pub freq: [f64; 3],
    /// Replicates with a result.
    pub n: u64,
    /// An adaptive point that takes more rounds (its mark may still change).
    pub open: bool,
    /// A box-limited point (SPEC 4.5: its outcome depends on the pair lattice): a square
    /// drawn round its mark.
    pub boxed: bool,
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

/// One diagram: the paper's (alpha across, beta up, one per (L, sigma)) or one on any two axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagram {
    pub title: String,
    /// The names of the axes across and up, as the frame labels them ("α", "β", "R0").
    pub axes: [String; 2],
    pub points: Vec<Point>,
    pub lines: Vec<BetaLine>,
}

impl Diagram {
    /// The names the paper's diagrams label their axes with.
    pub fn paper_axes() -> [String; 2] {
        ["α".into(), "β".into()]
    }
}

fn frame(
    fig: &mut Figure,
    p: &Panel,
    (alphas, betas): (&[f64], &[f64]),
    [x_name, y_name]: &[String; 2],
    title: &str,
) {
    p.frame(fig);
    fig.text(p.x + p.w / 2.0, p.y - 12.0, 15.0, Anchor::Middle, title);
    // A tick at every grid value; labels thinned to at most 6 across and 11 down.
    let every = alphas.len().div_ceil(6).max(1);
    for (k, a) in alphas.iter().enumerate() {
        p.x_tick(fig, *a, k % every == 0);
    }
    // Ticks at the grid's betas only (values a refinement added, a few tenths apart, would
    // pile up into a black bar): an even axis labels every k-th, an uneven one a label where
    // it keeps 16 px from the last, from the bottom up.
    let even = betas.len() < 2
        || betas
            .windows(2)
            .all(|w| ((w[1] - w[0]) - (betas[1] - betas[0])).abs() <= 1e-9 * w[1].abs().max(1.0));
    let every = betas.len().div_ceil(11).max(1);
    let mut last = f64::INFINITY;
    for (k, b) in betas.iter().enumerate() {
        let y = p.py(*b);
        let labelled = (even && k % every == 0) || (!even && last - y >= 16.0);
        p.y_tick(fig, *b, labelled);
        if labelled {
            last = y;
        }
    }
    fig.text(
        p.x + p.w / 2.0,
        p.y + p.h + 40.0,
        17.0,
        Anchor::Middle,
        x_name.clone(),
    );
    fig.text(
        p.x - 36.0,
        p.y + p.h / 2.0 + 6.0,
        17.0,
        Anchor::End,
        y_name.clone(),
    );
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

/// The grid's beta values: those held by more than half of the diagram's columns (a value a
/// refinement added lies in one column or two). All of them where that leaves fewer than two.
fn grid_betas(points: &[Point]) -> Vec<f64> {
    let alphas = axis(points.iter().map(|p| p.x));
    let all = axis(points.iter().map(|p| p.y));
    let grid: Vec<f64> = all
        .iter()
        .copied()
        .filter(|&b| {
            let columns = alphas
                .iter()
                .filter(|&&a| points.iter().any(|p| p.x == a && p.y == b))
                .count();
            2 * columns > alphas.len()
        })
        .collect();
    if grid.len() < 2 {
        all
    } else {
        grid
    }
}

/// Each point's cell along beta, in data units: from halfway to the next lower beta of its
/// column to halfway to the next higher one, the ends at the panel's edges. On an even grid
/// every cell is one step high; a refined column's added values get thinner cells.
fn beta_cells(points: &[Point], (lo, hi): (f64, f64)) -> Vec<(f64, f64)> {
    points
        .iter()
        .map(|pt| {
            let column = points.iter().filter(|q| q.x == pt.x).map(|q| q.y);
            let below = column
                .clone()
                .filter(|&b| b < pt.y)
                .fold(f64::NAN, f64::max);
            let above = column.filter(|&b| b > pt.y).fold(f64::NAN, f64::min);
            let down = if below.is_nan() {
                lo
            } else {
                0.5 * (below + pt.y)
            };
            let up = if above.is_nan() {
                hi
            } else {
                0.5 * (above + pt.y)
            };
            (down, up)
        })
        .collect()
}

/// One point in panel `k` (0: its mark and replicate count, 1-3: its cell of the heat map of
/// train, walk-past, reversal), grouped under its tooltip; `cw` is a grid cell's width in
/// pixels, (b0, b1) the point's cell along beta.
fn point_shapes(
    p: &Panel,
    pt: &Point,
    k: usize,
    cw: f64,
    (b0, b1): (f64, f64),
    added: bool,
) -> Shape {
    let mut shapes = Figure::new(0, 0);
    let (x, y) = (p.px(pt.x), p.py(pt.y));
    // (py runs down the page: the cell's top is at its higher beta.)
    let (top, ch) = (p.py(b1), p.py(b0) - p.py(b1));
    if k == 0 {
        // A value a refinement added: a small mark (several lie a few tenths apart, where the
        // column crosses); a grid point's fills its cell.
        let r = if added {
            3.5
        } else {
            (cw.min(ch) * 0.38).clamp(2.5, 14.0)
        };
        if let Some(m) = pt.mark {
            draw_mark(&mut shapes, m, x, y, r);
        }
        if pt.boxed {
            box_round(&mut shapes, x, y, r);
        }
        // Replicates per point, lower right of the mark; '+': an open adaptive point. Cells
        // too thin for it (refined values) leave it to the tooltip.
        if ch >= 10.0 && !added {
            let n = format!("{}{}", pt.n, if pt.open { "+" } else { "" });
            shapes.text(x + r - 1.0, y + r + 3.0, 9.0, Anchor::Start, n);
        }
    } else {
        let f = pt.freq[k - 1];
        shapes.push(Shape::Rect {
            x: x - cw / 2.0,
            y: top,
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
    Shape::Group {
        title: pt.detail.clone(),
        shapes: shapes.shapes,
    }
}

/// The colour bar of the frequencies at (bx, by0), `bh` high, ticked at quarters.
fn colour_bar(fig: &mut Figure, bx: f64, by0: f64, bh: f64) {
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
}

/// The square drawn round a box-limited point's mark (of radius `r`, centred at x, y).
fn box_round(fig: &mut Figure, x: f64, y: f64, r: f64) {
    let side = 2.0 * r + 4.0;
    fig.push(Shape::Rect {
        x: x - side / 2.0,
        y: y - side / 2.0,
        w: side,
        h: side,
        fill: None,
        stroke: Some(Color::GREY),
    });
}

/// The legend from height `y` down: the symbols present and grey cells if any; the lines on a
/// second row; a third explains n.
fn legend(fig: &mut Figure, d: &Diagram, y: f64) {
    let mut x = 70.0;
    for m in Label::ALL {
        if d.points.iter().any(|p| p.mark == Some(m)) {
            draw_mark(fig, m, x, y - 5.0, 9.0);
            fig.text(x + 14.0, y, 12.0, Anchor::Start, mark::name(m));
            x += 34.0 + text_width(mark::name(m), 12.0);
        }
    }
    if d.points.iter().any(|p| p.boxed) {
        box_round(fig, x, y - 5.0, 7.0);
        let label = "box-limited (SPEC 4.5)";
        fig.text(x + 14.0, y, 12.0, Anchor::Start, label);
        x += 34.0 + text_width(label, 12.0);
    }
    // A grey cell has no collision: its prep decided the point (it carries that mark), or it
    // has not run yet (no mark): the legend names the cases the diagram has.
    let empty = |p: &&Point| p.freq.iter().any(|f| !f.is_finite());
    let decided = d.points.iter().filter(empty).any(|p| p.mark.is_some());
    let waiting = d.points.iter().filter(empty).any(|p| p.mark.is_none());
    if decided || waiting {
        fig.push(Shape::Rect {
            x,
            y: y - 12.0,
            w: 14.0,
            h: 14.0,
            fill: Some(Color::LIGHT),
            stroke: Some(Color::GREY),
        });
        let label = match (decided, waiting) {
            (true, false) => "no collision (prep unstable or broke up)",
            (false, _) => "not run yet",
            (true, true) => "no collision (prep unstable or broke up, or not run yet)",
        };
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
        format!(
            "numbers: replicates per point (n){}{}",
            if d.points.iter().any(|p| p.open) {
                "; n+ : an adaptive point still taking rounds"
            } else {
                ""
            },
            if grid_betas(&d.points).len() < axis(d.points.iter().map(|p| p.y)).len() {
                "; small marks: beta values a refinement added (ticks at the grid's)"
            } else {
                ""
            }
        ),
    );
}

/// The four-panel figure of one diagram.
pub fn diagram_figure(d: &Diagram) -> Figure {
    let alphas = axis(d.points.iter().map(|p| p.x));
    let betas = axis(d.points.iter().map(|p| p.y));
    let grid = grid_betas(&d.points);
    let (pw, ph) = (240.0, 300.0);
    let mut fig = Figure::new(4 * 310 + 110, 540);
    fig.text(20.0, 28.0, 18.0, Anchor::Start, d.title.clone());
    if alphas.is_empty() {
        return fig;
    }
    let (ax, by) = (span(&alphas), span(&betas));
    let cw = pw / alphas.len() as f64;
    let cells = beta_cells(&d.points, by);
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
        for (pt, &cell) in d.points.iter().zip(&cells) {
            let added = !grid.contains(&pt.y);
            fig.push(point_shapes(&p, pt, k, cw, cell, added));
        }
        lines(&mut fig, &p, d);
        frame(&mut fig, &p, (&alphas, &grid), &d.axes, title);
    }
    colour_bar(&mut fig, 4.0 * 310.0 + 20.0, 76.0, ph);
    legend(&mut fig, d, 462.0);
    fig
}
