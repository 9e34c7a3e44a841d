//! The collapse test drawn: every column's beta* (the column model's, with its 95% interval)
//! against x = alpha~/L~, one series per (R0, d, L, sigma), with the line fitted over all of them
//! ([`cellsweep_stats::fit_columns`]) and the paper's. `cellsweep plot` draws it for one sweep,
//! the report over every diagram it shows.

use cellsweep_plot::collapse::{collapse_figure, Crossing, Line, Series, PALETTE};
use cellsweep_plot::{Color, Figure};
use cellsweep_stats::fit::{PAPER_A, PAPER_B};
use cellsweep_stats::{Column, Fit, Scales};

/// A column with the scales of the sweep it came from (its own R0 and d, where its sweep
/// varies them, come from its axes).
pub type Placed = (Scales, Column);

/// The group a column is drawn in: its R0, d, L and sigma.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(non_snake_case)]
pub struct Group {
    pub R0: f64,
    pub d: f64,
    pub L: u32,
    pub sigma: f64,
}

impl Group {
    pub fn of((scales, c): &Placed) -> Group {
        let at = scales.at(&c.others);
        Group {
            R0: at.R0,
            d: at.d,
            L: c.L,
            sigma: c.sigma,
        }
    }

    /// "R0 = 40, L = 90, σ = 5", with d where it is not the SPEC's sqrt(20).
    pub fn label(&self) -> String {
        let d = if (self.d - Scales::default().d).abs() > 1e-12 {
            format!(", d = {}", self.d)
        } else {
            String::new()
        };
        format!(
            "R_{{0}} = {}{d}, L = {}, σ = {}",
            self.R0, self.L, self.sigma
        )
    }
}

/// The groups of `columns` in drawing order: R0 rising, then L falling, then sigma falling.
pub fn groups(columns: &[Placed]) -> Vec<Group> {
    let mut out: Vec<Group> = Vec::new();
    for p in columns {
        let g = Group::of(p);
        if !out.contains(&g) {
            out.push(g);
        }
    }
    out.sort_by(|a, b| {
        (a.R0.total_cmp(&b.R0))
            .then(a.d.total_cmp(&b.d))
            .then(b.L.cmp(&a.L))
            .then(b.sigma.total_cmp(&a.sigma))
    });
    out
}

/// The collapse figure of `columns`, with `fitted` (the line over them) and the paper's line.
pub fn collapse_of(columns: &[Placed], fitted: Option<&Fit>) -> Figure {
    let series: Vec<Series> = groups(columns)
        .into_iter()
        .enumerate()
        .map(|(k, g)| Series {
            label: g.label(),
            color: PALETTE[k % PALETTE.len()],
            crossings: columns
                .iter()
                .filter(|p| Group::of(p) == g)
                .filter_map(|(_, c)| crossing(&g, c))
                .collect(),
        })
        .collect();
    let mut lines = Vec::new();
    if let Some(f) = fitted {
        lines.push(Line {
            label: format!("fit over these columns: a = {:.3}, b = {:.1}", f.a, f.b),
            color: Color::BLACK,
            a: f.a,
            b: f.b,
            dash: None,
        });
    }
    lines.push(Line {
        label: format!("paper: a = {PAPER_A}, b = {PAPER_B}"),
        color: Color::GREY,
        a: PAPER_A,
        b: PAPER_B,
        dash: Some(6.0),
    });
    collapse_figure(
        "β* of every column against α̃/L̃ (one line where the theory holds)",
        &series,
        &lines,
    )
}

/// Column `c` of group `g` as a crossing with its tooltip, if it has a beta*.
fn crossing(g: &Group, c: &Column) -> Option<Crossing> {
    let beta_star = c.beta_star?;
    let ci = c
        .beta_ci
        .map_or(String::new(), |[lo, hi]| format!(" [{lo:.2}, {hi:.2}]"));
    Some(Crossing {
        x: c.x,
        beta_star,
        ci: c.beta_ci,
        title: format!(
            "R0 = {}, L = {}, σ = {}, α = {}: β* = {beta_star:.2}{ci} ({}), α̃/L̃ = {:.2}",
            g.R0,
            g.L,
            g.sigma,
            c.alpha,
            c.method.as_str(),
            c.x
        ),
    })
}
