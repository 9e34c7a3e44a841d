//! The numbers a report states, computed once: beta* per column of each diagram (the column
//! model's, with the interpolated one beside), the line over all spacings at sigma = 5 and at
//! sigma = 0, and the measured shift of the line between the two, by the model and by the
//! paper's interpolation; and the collapse test: one line through every shown column, each at
//! its own alpha~/L~ (its own R0, L and sigma).

use cellsweep_stats::{fit_columns, fit_line, measure_shift, Column, Fit, Method, NoFit, Shift};

use crate::collapse::Placed;

use crate::collection::{Collection, DiagramKey};
use crate::planes::{asked_planes, AskedPlane};
use crate::Results;

/// Bootstrap resamples of every interval in a report (seeded: a report is reproducible).
pub const RESAMPLES: usize = 1000;
const SEED: u64 = 1;

/// Everything a report states, from its results.
#[derive(Debug, Clone)]
pub struct Analysis<'a> {
    pub collection: Collection<'a>,
    /// Per diagram: its columns (beta* with interval, or why none) and its own line, if one.
    pub per_diagram: Vec<(DiagramKey, Vec<Column>, Option<Fit>)>,
    /// The line over all spacings at sigma = 5 (the paper's global fit) and at sigma = 0.
    pub line_sigma5: Result<Fit, NoFit>,
    pub line_sigma0: Result<Fit, NoFit>,
    pub shift: Option<Shift>,
    /// The same three by the paper's reading (beta* interpolated between grid rows), beside.
    pub line_sigma5_interpolated: Result<Fit, NoFit>,
    pub line_sigma0_interpolated: Result<Fit, NoFit>,
    pub shift_interpolated: Option<Shift>,
    /// Every shown column with its sweep's scales, and the line through all of them.
    pub collapse_columns: Vec<Placed>,
    pub collapse: Result<Fit, NoFit>,
    /// The diagrams on other axes the shown sweeps ask for.
    pub planes: Vec<AskedPlane>,
}

impl<'a> Analysis<'a> {
    pub fn of(all: &'a [Results]) -> Analysis<'a> {
        let collection = Collection::of(all);
        let per_diagram: Vec<(DiagramKey, Vec<Column>, Option<Fit>)> = collection
            .diagrams
            .iter()
            .map(|s| {
                let counts: Vec<_> = s.counts().cloned().collect();
                match fit_line(&counts, &s.results.scales, RESAMPLES, SEED, Method::Model) {
                    Ok(f) => (s.key.clone(), f.columns.clone(), Some(f)),
                    Err(no) => (s.key.clone(), no.columns, None),
                }
            })
            .collect();
        let collapse_columns: Vec<Placed> = collection
            .diagrams
            .iter()
            .zip(&per_diagram)
            .flat_map(|(s, (_, cols, _))| cols.iter().map(|c| (s.results.scales, c.clone())))
            .collect();
        let pooled = collapse_columns.iter().map(|(_, c)| c.clone()).collect();
        let (c5, scales5) = collection.counts_at(Some(5.0));
        let (c0, scales0) = collection.counts_at(Some(0.0));
        let (call, scales) = collection.counts_at(None);
        Analysis {
            line_sigma5: fit_line(&c5, &scales5, RESAMPLES, SEED, Method::Model),
            line_sigma0: fit_line(&c0, &scales0, RESAMPLES, SEED, Method::Model),
            shift: measure_shift(&call, &scales, RESAMPLES, SEED, Method::Model),
            line_sigma5_interpolated: fit_line(&c5, &scales5, RESAMPLES, SEED, Method::Interpolate),
            line_sigma0_interpolated: fit_line(&c0, &scales0, RESAMPLES, SEED, Method::Interpolate),
            shift_interpolated: measure_shift(&call, &scales, RESAMPLES, SEED, Method::Interpolate),
            collapse: fit_columns(pooled, RESAMPLES, SEED),
            collapse_columns,
            per_diagram,
            planes: asked_planes(&collection),
            collection,
        }
    }

    /// The columns of the paper's diagram (L, sigma), if it is shown.
    pub fn columns(&self, l: u32, sigma: f64) -> Option<&[Column]> {
        let key = DiagramKey::paper(l, sigma);
        self.per_diagram
            .iter()
            .find(|(k, _, _)| *k == key)
            .map(|(_, c, _)| c.as_slice())
    }
}
