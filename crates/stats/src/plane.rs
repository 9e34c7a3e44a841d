//! A diagram on any two axes: [`Plane`] names the axis drawn across (`x`) and the one drawn up
//! (`y`), and which axes tell one diagram from another (`by`: by default every other axis the
//! points have). The paper's diagrams are the plane (alpha, beta) by (L, sigma); a sweep over
//! R0 or E0 can be read as (R0, beta) at fixed alpha, or (beta, E0).
//!
//! An axis is one of the paper's four (alpha, beta, L, sigma), any other axis a sweep varies
//! (R0, E0, geometry, ...), or `xt`, the point's alpha~/L~ with the adhesion shift (SPEC
//! section 6, at its own R0 and d): the coordinate the sharp-interface theory says the crossing
//! depends on, so that `--x R0 --y beta --by xt,sigma` sets cells of different sizes side by
//! side where the theory says they should look alike; `Lt`, L~ = L / R0, tells the paper's
//! geometry scaled (R0 = 32 at L = 72, 40 at 90, 48 at 108: L~ = 2.25) from its other spacings.

use std::collections::HashMap;

use crate::counts::Counts;
use crate::fit::Scales;

/// The derived axis alpha~/L~ (with the adhesion shift).
pub const XT: &str = "xt";
/// The derived axis L~ = L / R0 (SPEC section 6), at the point's own R0: cells of different
/// sizes at the same L~ are the paper's geometry scaled.
pub const LT: &str = "Lt";
/// The derived axes, functions of the others.
pub const DERIVED: [&str; 2] = [XT, LT];

/// Why a plane cannot be drawn: one line naming the axis or the points.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaneError {
    #[error("--x and --y are both {0}: a diagram needs two different axes")]
    Same(String),
    #[error("{axis} is not an axis of these points (they have {have})")]
    Unknown { axis: String, have: String },
    #[error(
        "{count} points fall in one cell ({x_name} = {x}, {y_name} = {y}) of the diagram at {at}: \
         they differ in {differ}; add it to --by"
    )]
    Crowded {
        count: usize,
        x_name: String,
        x: f64,
        y_name: String,
        y: f64,
        at: String,
        differ: String,
    },
}

/// Two axes of a diagram and the axes that name each diagram (also as a sweep file's
/// `[report] planes` asks for it: `{ x = "R0", y = "beta", by = ["xt", "sigma"] }`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    pub x: String,
    pub y: String,
    /// The axes that tell diagrams apart; None: every axis of the points but x and y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub by: Option<Vec<String>>,
}

/// One diagram of a plane: the values of its `by` axes and its points (indices into the
/// counts it was drawn from).
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneDiagram {
    pub fixed: Vec<(String, f64)>,
    pub points: Vec<usize>,
}

impl PlaneDiagram {
    /// `L = 90, sigma = 5` (or `xt = 49.95, sigma = 5`).
    pub fn title(&self) -> String {
        self.fixed
            .iter()
            .map(|(n, v)| format!("{n} = {}", shown(n, *v)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A value as a title or a header shows it: xt to 2 decimals, the rest as written.
pub fn shown(axis: &str, v: f64) -> String {
    match axis {
        XT => format!("{v:.2}"),
        LT => {
            let s = format!("{v:.4}");
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        }
        "geometry" if v == 1.0 => "one".into(),
        "geometry" if v == 2.0 => "two".into(),
        _ => format!("{v}"),
    }
}

impl Default for Plane {
    fn default() -> Self {
        Plane::paper()
    }
}

impl Plane {
    /// The paper's plane: alpha across, beta up, one diagram per (L, sigma) and other axes.
    pub fn paper() -> Plane {
        Plane {
            x: "alpha".into(),
            y: "beta".into(),
            by: None,
        }
    }

    /// Whether this is the paper's plane (the diagrams every other reader draws).
    pub fn is_paper(&self) -> bool {
        self.x == "alpha" && self.y == "beta" && self.by.is_none()
    }

    /// The value of axis `name` at point `c` (None where the point does not have it); `xt` at
    /// the point's own R0 and d over `scales`.
    pub fn value(c: &Counts, name: &str, scales: &Scales) -> Option<f64> {
        match name {
            "alpha" => Some(c.alpha),
            "beta" => Some(c.beta),
            "L" => Some(f64::from(c.L)),
            "sigma" => Some(c.sigma),
            XT => Some(scales.at(&c.others).x(c.alpha, c.L, c.sigma)),
            LT => Some(f64::from(c.L) / scales.at(&c.others).R0),
            other => c.others.get(other),
        }
    }

    /// Every axis the points have (the paper's four, their other axes, xt).
    fn axes_of(counts: &[Counts]) -> Vec<String> {
        let mut out: Vec<String> = ["alpha", "beta", "L", "sigma"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        for c in counts {
            for (n, _) in &c.others.0 {
                if !out.contains(n) {
                    out.push(n.clone());
                }
            }
        }
        out.extend(DERIVED.map(String::from));
        out
    }

    /// The points of `counts` grouped by the `by` axes (sorted by their values), two points
    /// in one cell allowed: [`Plane::diagrams`] refuses those.
    pub fn groups(
        &self,
        counts: &[Counts],
        scales: &Scales,
    ) -> Result<Vec<PlaneDiagram>, PlaneError> {
        if self.x == self.y {
            return Err(PlaneError::Same(self.x.clone()));
        }
        let have = Self::axes_of(counts);
        let by: Vec<String> = match &self.by {
            Some(by) => by.clone(),
            // Every axis but x, y and the derived xt (a function of the others).
            None => have
                .iter()
                .filter(|a| **a != self.x && **a != self.y && !DERIVED.contains(&a.as_str()))
                .cloned()
                .collect(),
        };
        for axis in [&self.x, &self.y].into_iter().chain(&by) {
            let everywhere = counts
                .iter()
                .all(|c| Self::value(c, axis, scales).is_some());
            if !everywhere {
                return Err(PlaneError::Unknown {
                    axis: axis.clone(),
                    have: have.join(", "),
                });
            }
        }
        // xt comes out of float arithmetic: columns meant alike agree to about 1e-10.
        let key = |axis: &str, v: f64| match axis {
            XT | LT => (v * 1e6).round().to_bits(),
            _ => v.to_bits(),
        };
        let mut groups: Vec<PlaneDiagram> = Vec::new();
        let mut index: HashMap<Vec<u64>, usize> = HashMap::new();
        for (i, c) in counts.iter().enumerate() {
            let fixed: Vec<(String, f64)> = by
                .iter()
                .map(|a| (a.clone(), Self::value(c, a, scales).unwrap_or(f64::NAN)))
                .collect();
            let k: Vec<u64> = fixed.iter().map(|(a, v)| key(a, *v)).collect();
            let g = *index.entry(k).or_insert_with(|| {
                groups.push(PlaneDiagram {
                    fixed,
                    points: Vec::new(),
                });
                groups.len() - 1
            });
            groups[g].points.push(i);
        }
        groups.sort_by(|a, b| {
            a.fixed
                .iter()
                .zip(&b.fixed)
                .map(|((_, x), (_, y))| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        Ok(groups)
    }

    /// The diagrams of `counts` in this plane: grouped by the `by` axes (sorted by their
    /// values), each cell holding at most one point.
    pub fn diagrams(
        &self,
        counts: &[Counts],
        scales: &Scales,
    ) -> Result<Vec<PlaneDiagram>, PlaneError> {
        let groups = self.groups(counts, scales)?;
        let have = Self::axes_of(counts);
        for g in &groups {
            self.one_point_per_cell(g, counts, scales, &have)?;
        }
        Ok(groups)
    }

    /// Refuse a diagram two of whose points share an (x, y) cell, naming an axis they differ in.
    fn one_point_per_cell(
        &self,
        g: &PlaneDiagram,
        counts: &[Counts],
        scales: &Scales,
        have: &[String],
    ) -> Result<(), PlaneError> {
        let mut cells: HashMap<(u64, u64), Vec<usize>> = HashMap::new();
        for &i in &g.points {
            let c = &counts[i];
            let (x, y) = (
                Self::value(c, &self.x, scales).unwrap_or(f64::NAN),
                Self::value(c, &self.y, scales).unwrap_or(f64::NAN),
            );
            cells.entry((x.to_bits(), y.to_bits())).or_default().push(i);
        }
        let mut crowded: Vec<_> = cells.into_iter().filter(|(_, v)| v.len() > 1).collect();
        crowded.sort_by_key(|(_, v)| v[0]);
        let Some(((x, y), pts)) = crowded.into_iter().next() else {
            return Ok(());
        };
        let differ = have
            .iter()
            .filter(|a| {
                let v0 = Self::value(&counts[pts[0]], a, scales);
                pts.iter()
                    .any(|&i| Self::value(&counts[i], a, scales) != v0)
            })
            .cloned()
            .collect::<Vec<_>>();
        Err(PlaneError::Crowded {
            count: pts.len(),
            x_name: self.x.clone(),
            x: f64::from_bits(x),
            y_name: self.y.clone(),
            y: f64::from_bits(y),
            at: g.title(),
            differ: if differ.is_empty() {
                "nothing (the same point twice)".into()
            } else {
                differ.join(", ")
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axes::Others;

    fn point(alpha: f64, beta: f64, l: u32, others: &[(&str, f64)]) -> Counts {
        Counts {
            others: Others(others.iter().map(|(n, v)| (n.to_string(), *v)).collect()),
            ..Counts::none(alpha, beta, l, 5.0)
        }
    }

    #[test]
    fn the_paper_plane_groups_by_spacing_and_sigma_and_any_plane_by_the_rest() {
        let pts = vec![
            point(0.1, 10.0, 90, &[("R0", 32.0)]),
            point(0.1, 14.0, 90, &[("R0", 48.0)]),
            point(0.12, 10.0, 90, &[("R0", 32.0)]),
            point(0.1, 10.0, 70, &[("R0", 32.0)]),
        ];
        let s = Scales::default();
        let paper = Plane::paper().diagrams(&pts, &s).unwrap();
        // (L, sigma, R0): L70 R0 32, L90 R0 32, L90 R0 48.
        assert_eq!(paper.len(), 3);
        assert_eq!(paper[0].title(), "L = 70, sigma = 5, R0 = 32");
        let r0 = Plane {
            x: "R0".into(),
            y: "beta".into(),
            by: None,
        };
        let d = r0.diagrams(&pts, &s).unwrap();
        // By (alpha, L, sigma): alpha 0.1 at L 70 and 90, alpha 0.12 at L 90.
        assert_eq!(
            d.iter().map(|g| g.points.clone()).collect::<Vec<_>>(),
            vec![vec![3], vec![0, 1], vec![2]]
        );
        assert_eq!(d[1].title(), "alpha = 0.1, L = 90, sigma = 5");
    }

    #[test]
    fn cells_of_different_sizes_at_one_xt_share_a_diagram() {
        // x = alpha~/L~ = 2 pi d alpha R0^2 / L: alike at R0 32 (alpha 0.125, L 72) and R0 48
        // (alpha 0.0833..., L 108), written to 12 decimals as a sweep file would.
        let pts = vec![
            point(0.125, 10.0, 72, &[("R0", 32.0)]),
            point(0.083333333333, 10.0, 108, &[("R0", 48.0)]),
        ];
        let plane = Plane {
            x: "R0".into(),
            y: "beta".into(),
            by: Some(vec![XT.into(), "sigma".into()]),
        };
        let d = plane.diagrams(&pts, &Scales::default()).unwrap();
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].points, vec![0, 1]);
        assert_eq!(d[0].title(), "xt = 49.95, sigma = 5");
    }

    #[test]
    fn a_crowded_cell_an_unknown_axis_and_one_axis_twice_are_refused() {
        let pts = vec![point(0.1, 10.0, 90, &[]), point(0.12, 10.0, 90, &[])];
        let s = Scales::default();
        let by_l = Plane {
            x: "L".into(),
            y: "beta".into(),
            by: Some(vec!["sigma".into()]),
        };
        let e = by_l.diagrams(&pts, &s).unwrap_err().to_string();
        assert!(e.contains("they differ in alpha"), "{e}");
        let e = Plane {
            x: "E0".into(),
            ..Plane::paper()
        }
        .diagrams(&pts, &s)
        .unwrap_err();
        assert!(matches!(e, PlaneError::Unknown { .. }), "{e}");
        let e = Plane {
            x: "beta".into(),
            ..Plane::paper()
        }
        .diagrams(&pts, &s)
        .unwrap_err();
        assert_eq!(e, PlaneError::Same("beta".into()));
    }
}
