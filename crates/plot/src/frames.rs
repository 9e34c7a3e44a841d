//! Snapshots of a collision as a [`Figure`]: (a) both cells' phi (cell 1 red, cell 2 blue) with
//! their phi = 1/2 contours and the fibers, with a scale bar; (b) the polarity weighted by phi,
//! P1 phi1 + P2 phi2, with its colour bar; the time in tau0 and in minutes above.

use crate::figure::{Anchor, Color, Figure, Shape};

/// The paper's physical scales: a lattice site is 0.25 um, tau0 is 0.5 min.
pub const SITE_UM: f64 = 0.25;
pub const TAU0_MIN: f64 = 0.5;

/// The fields of one instant on an `nx x ny` lattice (row-major, y up).
pub struct Snapshot<'a> {
    pub nx: usize,
    pub ny: usize,
    pub phi: [&'a [f64]; 2],
    pub p: [&'a [f64]; 2],
    pub fiber_rows: &'a [usize],
    /// Time since the start of the collision, tau0.
    pub time: f64,
    /// A second line under the time (e.g. the outcome once it is decided), may be empty.
    pub note: String,
}

const LEFT: f64 = 44.0;
const TOP: f64 = 52.0;
const GAP: f64 = 34.0;
const RIGHT: f64 = 96.0;

const RED: Color = Color(215, 40, 40);
const BLUE: Color = Color(40, 70, 215);
const FIBER: Color = Color(60, 60, 60);

/// Blue (negative) through white to red (positive), for `v` in [-1, 1].
fn diverging(v: f64) -> Color {
    if v >= 0.0 {
        Color::WHITE.mix(Color(200, 20, 20), v)
    } else {
        Color::WHITE.mix(Color(20, 50, 200), -v)
    }
}

/// The snapshot as a figure, one SVG pixel per lattice site (render it at scale 2 for print).
pub fn figure(s: &Snapshot) -> Figure {
    let (w, h) = (s.nx as f64, s.ny as f64);
    // Wide enough for the captions on small test lattices too.
    let mut fig = Figure::new(
        (LEFT + w + RIGHT).max(560.0) as u32,
        (TOP + 2.0 * h + GAP + 40.0) as u32,
    );
    let minutes = s.time * TAU0_MIN;
    fig.text(
        LEFT,
        20.0,
        14.0,
        Anchor::Start,
        format!(
            "t = {:.0} τ_0 ({minutes:.0} min) after the start of the collision",
            s.time
        ),
    );
    if !s.note.is_empty() {
        fig.text(LEFT, 38.0, 12.0, Anchor::Start, s.note.clone());
    }
    let (cells, polarity, pmax, signed) = pixels(s);
    let panels = [
        (
            TOP,
            cells,
            "(a) φ_1 (red), φ_2 (blue); black: φ = 1/2; grey: fibers",
        ),
        (
            TOP + h + GAP,
            polarity,
            "(b) polarity weighted by the cell, P_1 φ_1 + P_2 φ_2",
        ),
    ];
    for (y, rgb, label) in panels {
        fig.push(Shape::Image {
            x: LEFT,
            y,
            w,
            h,
            cols: s.nx,
            rows: s.ny,
            rgb,
        });
        fig.push(Shape::Rect {
            x: LEFT,
            y,
            w,
            h,
            fill: None,
            stroke: Some(Color::BLACK),
        });
        fig.text(LEFT, y + h + 14.0, 11.0, Anchor::Start, label);
    }
    scale_bar(&mut fig, h);
    colour_bar(&mut fig, (LEFT + w + 14.0, TOP + h + GAP, h), pmax, signed);
    fig
}

/// The pixels of both panels, rows from the top: (a) the cells' colours with their contours
/// and the fibers, (b) P phi in colour; with the largest |P phi| and whether it takes negative
/// values worth a diverging scale.
fn pixels(s: &Snapshot) -> (Vec<Color>, Vec<Color>, f64, bool) {
    let is_fiber = |j: usize| s.fiber_rows.contains(&j);
    let weighted = |k: usize| s.p[0][k] * s.phi[0][k] + s.p[1][k] * s.phi[1][k];
    let pmax = (0..s.nx * s.ny)
        .map(|k| weighted(k).abs())
        .fold(0.0f64, f64::max)
        .max(1e-9);
    // Diverging colours only if P phi takes negative values worth seeing; else white to red.
    let pmin = (0..s.nx * s.ny).map(weighted).fold(0.0f64, f64::min);
    let signed = pmin < -0.02 * pmax;
    let shade = |v: f64| {
        if signed {
            diverging(v)
        } else {
            diverging(v.max(0.0))
        }
    };
    let mut cells = Vec::with_capacity(s.nx * s.ny);
    let mut polarity = Vec::with_capacity(s.nx * s.ny);
    // Image rows from the top: lattice row j = ny - 1 first (y up).
    for j in (0..s.ny).rev() {
        for i in 0..s.nx {
            let k = j * s.nx + i;
            let (a, b) = (s.phi[0][k].clamp(0.0, 1.0), s.phi[1][k].clamp(0.0, 1.0));
            let mut c = Color::WHITE.mix(RED, a * 0.85).mix(BLUE, b * 0.85);
            if is_fiber(j) {
                c = c.mix(FIBER, 0.55);
            }
            // The phi = 1/2 contour: phi crosses 0.5 towards the right or upper neighbour.
            let right = j * s.nx + (i + 1) % s.nx;
            let up = ((j + 1) % s.ny) * s.nx + i;
            for f in s.phi {
                if (f[k] - 0.5) * (f[right] - 0.5) <= 0.0 && f[k] != f[right]
                    || (f[k] - 0.5) * (f[up] - 0.5) <= 0.0 && f[k] != f[up]
                {
                    c = Color::BLACK;
                }
            }
            cells.push(c);
            let mut q = shade(weighted(k) / pmax);
            if is_fiber(j) {
                q = q.mix(FIBER, 0.35);
            }
            polarity.push(q);
        }
    }
    (cells, polarity, pmax, signed)
}

/// A 10 um scale bar in the lower left of panel (a), `h` high.
fn scale_bar(fig: &mut Figure, h: f64) {
    let bar = 10.0 / SITE_UM;
    let (bx, by) = (LEFT + 8.0, TOP + h - 10.0);
    fig.push(Shape::Rect {
        x: bx - 4.0,
        y: by - 16.0,
        w: bar + 8.0,
        h: 22.0,
        fill: Some(Color::WHITE),
        stroke: None,
    });
    fig.line(bx, by, bx + bar, by, Color::BLACK, 3.0);
    fig.text(bx + bar / 2.0, by - 5.0, 11.0, Anchor::Middle, "10 µm");
}

/// The colour bar of panel (b) at (cx, cy), `ch` high, from -pmax (if signed) or 0 to pmax.
fn colour_bar(fig: &mut Figure, (cx, cy, ch): (f64, f64, f64), pmax: f64, signed: bool) {
    let steps = 60;
    let low = if signed { -1.0 } else { 0.0 };
    for k in 0..steps {
        let v = 1.0 - (1.0 - low) * (k as f64 + 0.5) / steps as f64;
        fig.push(Shape::Rect {
            x: cx,
            y: cy + ch * k as f64 / steps as f64,
            w: 12.0,
            h: ch / steps as f64 + 0.6,
            fill: Some(diverging(v)),
            stroke: None,
        });
    }
    fig.push(Shape::Rect {
        x: cx,
        y: cy,
        w: 12.0,
        h: ch,
        fill: None,
        stroke: Some(Color::BLACK),
    });
    let ticks = if signed {
        vec![(0.0, pmax), (0.5, 0.0), (1.0, -pmax)]
    } else {
        vec![(0.0, pmax), (0.5, pmax / 2.0), (1.0, 0.0)]
    };
    for (t, v) in ticks {
        let y = cy + ch * t;
        fig.line(cx + 12.0, y, cx + 16.0, y, Color::BLACK, 1.0);
        fig.text(cx + 19.0, y + 4.0, 11.0, Anchor::Start, format!("{v:.2}"));
    }
    fig.text(cx, cy - 6.0, 11.0, Anchor::Start, "Pφ");
}
