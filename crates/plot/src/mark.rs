//! The paper's symbols for a point's outcome, and how each is drawn.

use crate::figure::{Anchor, Color, Figure, Shape};

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
