//! The paper's symbol of each [`Label`] of a point (star walk-past, cross training, plus
//! reversal, dot unstable, diamond breakup, star over cross for coexistence), and how each is
//! drawn and named in a legend.

pub use cellsweep_stats::Label;

use crate::figure::{Anchor, Color, Figure, Shape};

/// A label's name in a figure's legend.
pub fn name(label: Label) -> &'static str {
    match label {
        Label::WalkPast => "walk-past",
        Label::Train => "training",
        Label::Reversal => "reversal",
        Label::Coexist => "coexistence",
        Label::Unstable => "unstable",
        Label::Breakup => "breakup",
        Label::Undetermined => "undetermined",
        Label::Mixed => "mixed",
    }
}

/// Draw a symbol centred at (x, y) with radius r.
pub fn draw_mark(fig: &mut Figure, label: Label, x: f64, y: f64, r: f64) {
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
    match label {
        Label::WalkPast => star(fig),
        Label::Train => cross(fig, Color::BLUE),
        Label::Reversal => {
            fig.line(x - r, y, x + r, y, Color::GREEN, 2.5);
            fig.line(x, y - r, x, y + r, Color::GREEN, 2.5);
        }
        Label::Coexist => {
            star(fig);
            cross(fig, Color::BLUE);
        }
        Label::Unstable => fig.push(Shape::Circle {
            cx: x,
            cy: y,
            r: r * 0.4,
            fill: Some(Color::BLUE),
            stroke: None,
        }),
        Label::Breakup => fig.push(Shape::Polygon {
            points: vec![(x, y - r), (x + r * 0.7, y), (x, y + r), (x - r * 0.7, y)],
            fill: None,
            stroke: Some(Color::CYAN),
        }),
        Label::Undetermined => fig.text(x, y + 5.0, 16.0, Anchor::Middle, "?"),
        Label::Mixed => fig.push(Shape::Circle {
            cx: x,
            cy: y,
            r: r * 0.5,
            fill: None,
            stroke: Some(Color::GREY),
        }),
    }
}
