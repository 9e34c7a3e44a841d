//! [`Results`] loaded from their three sources, for every reader of them (`table`, `fit`,
//! `plot`, `report`, `run`'s summary): a store, an export file, or a counts CSV file. A store
//! and an export of it give the very same results.

use std::path::Path;

use cellsweep_scheduler::export_file::{read_export, ExportFileError};
use cellsweep_scheduler::Sweep;
use cellsweep_solver::{Params, SOLVER_VERSION};
use cellsweep_stats::adaptive::{assess, kinds, PointEnds};
use cellsweep_stats::{box_limited, Axes, Counts, End, Label, PerEnd, Scales, Tally};
use cellsweep_store::export::ExportRow;
use cellsweep_store::{Store, StoreError};

use crate::{Cost, Provenance, Results};

/// Why results could not be loaded: one line naming the source and the problem.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error(transparent)]
    Export(#[from] ExportFileError),
    #[error("{0}")]
    Invalid(String),
}

macro_rules! invalid {
    ($($t:tt)*) => { return Err(LoadError::Invalid(format!($($t)*))) };
}

/// The results of sweep `sweep` (or the store's only one) in the store at `db`, read only.
pub fn from_store(db: &Path, sweep: Option<&str>) -> Result<Results, LoadError> {
    let (sweep, rows) = rows_of_store(db, sweep)?;
    from_rows(&db.display().to_string(), &sweep, &rows)
}

/// The definition and finished rows of sweep `sweep` (or the store's only one) in the store at
/// `db`, read only, exactly as an export of them would hold them.
pub fn rows_of_store(db: &Path, sweep: Option<&str>) -> Result<(Sweep, Vec<ExportRow>), LoadError> {
    let store = Store::open_read(db)?;
    let name = store.choose_sweep(sweep)?;
    let id = store.sweep_id(&name)?;
    let sweep = Sweep::stored(&store, id)
        .map_err(|e| LoadError::Invalid(format!("{}: {e}", db.display())))?;
    let defaults = serde_json::to_value(Params::default())
        .map_err(|e| LoadError::Invalid(format!("the default parameters: {e}")))?;
    // The store's finished replicates read exactly as an export of them would be.
    let rows = store.export_rows(id, SOLVER_VERSION, &defaults)?;
    Ok((sweep, rows))
}

/// Counts of every point of an export file (`cellsweep export`), and, for an adaptive sweep,
/// each point's standing under its rule, exactly as the store would give them.
pub fn from_export(path: &Path) -> Result<Results, LoadError> {
    Ok(from_export_with_sweep(path)?.1)
}

/// An export file's sweep definition (its header) and its results, reading the file once.
pub fn from_export_with_sweep(path: &Path) -> Result<(Sweep, Results), LoadError> {
    let (sweep, rows) = read_export(path)?;
    let results = from_rows(&path.display().to_string(), &sweep, &rows)?;
    Ok((sweep, results))
}

/// Counts, standings, each prep's free speed and provenance of a sweep's finished rows (from
/// an export file or a store, named `source` in every message).
pub(crate) fn from_rows(
    source: &str,
    sweep: &Sweep,
    rows: &[ExportRow],
) -> Result<Results, LoadError> {
    // The grid's points, then any its refinement added.
    let axes: Vec<Axes> = rows
        .iter()
        .map(|r| sweep.axes_of_row(r))
        .collect::<Result<_, _>>()
        .map_err(|why| LoadError::Invalid(format!("{source}: {why}")))?;
    let points = sweep
        .points_with(axes.iter().cloned())
        .map_err(|why| LoadError::Invalid(format!("{source}: {why}")))?;
    let (mut ends, index) = PointEnds::grid(points.iter().map(|p| sweep.axes_of(p)));
    // Each distinct prep's free speed (a point's replicates share their preps round-robin).
    let mut speeds: Vec<Vec<(u64, f64)>> = vec![Vec::new(); ends.len()];
    for (r, at) in rows.iter().zip(&axes) {
        let Some(i) = index.of(at) else {
            invalid!(
                "{}: a row at {at} is not a point of sweep {:?}",
                source,
                sweep.name
            );
        };
        let (k, end) = replicate_end(source, sweep, r)?;
        if !ends[i].record(k, end) {
            invalid!(
                "{}: replicate {k} at alpha = {}, beta = {} appears twice",
                source,
                r.alpha,
                r.beta
            );
        }
        if let Some(v) = r.free_speed.filter(|v| v.is_finite()) {
            if !speeds[i].iter().any(|(seed, _)| *seed == r.prep_seed) {
                speeds[i].push((r.prep_seed, v));
            }
        }
    }
    let mut counts = counts_of(&ends, &speeds);
    // SPEC 4.5: a point is box-limited where one of its prepped cells that collided is, on its
    // own lattices (a prep that broke up or let go of a fiber decides its point with no
    // collision: no pair lattice is involved); and the drops its collisions shed.
    for (r, at) in rows.iter().zip(&axes) {
        if let Some(i) = index.of(at) {
            counts[i].sheddings += u64::from(r.sheddings);
            if let Some(extent) = r.prep_extent.filter(|_| r.verdict == "ok") {
                let protocol = sweep.protocol_for(&points[i]);
                let [single, pair] = [protocol.single_lattice[0], protocol.pair_lattice[0]];
                counts[i].box_limited |= box_limited(extent, single as f64, pair as f64);
            }
        }
    }
    let standings = sweep
        .adaptive
        .map(|rule| assess(&ends, &rule, kinds(sweep.preps_per_point)));
    Ok(Results {
        name: sweep.name.clone(),
        counts,
        scales: Scales {
            R0: sweep.params.R0,
            d: sweep.params.d,
        },
        standings,
        prep_speeds: Some(
            speeds
                .into_iter()
                .map(|p| p.into_iter().map(|s| s.1).collect())
                .collect(),
        ),
        provenance: Some(provenance(source, sweep, rows, points.len())),
    })
}

/// The replicate index of an export row and its end, checked against the sweep.
fn replicate_end(source: &str, sweep: &Sweep, r: &ExportRow) -> Result<(u32, End), LoadError> {
    let Some(end) = End::of(&r.verdict, r.outcome.as_deref()) else {
        invalid!(
            "{}: replicate {} at alpha = {}, beta = {}: verdict {:?} with outcome {:?} is not a \
             result (an ok prep's outcome is one of {}; other verdicts have none)",
            source,
            r.replicate,
            r.alpha,
            r.beta,
            r.verdict,
            r.outcome.as_deref().unwrap_or(""),
            End::stored_outcomes()
        );
    };
    let k = r.replicate;
    if k >= sweep.replicates {
        invalid!(
            "{}: replicate {k} is beyond the sweep's {} per point",
            source,
            sweep.replicates
        );
    }
    Ok((k, end))
}

/// Each point's counts over every finished replicate (an export of a running sweep may have
/// gaps), with the mean free speed of its distinct preps.
fn counts_of(ends: &[PointEnds], speeds: &[Vec<(u64, f64)>]) -> Vec<Counts> {
    ends.iter()
        .zip(speeds)
        .map(|(p, preps)| {
            let speed = (!preps.is_empty())
                .then(|| preps.iter().map(|s| s.1).sum::<f64>() / preps.len() as f64);
            Counts {
                free_speed: speed,
                ..p.counts(p.ends.len() as u32)
            }
        })
        .collect()
}

/// What the sweep is and what its finished rows cost, at the grid's points and at the points
/// its refinement added (each prep's time counted once); `points` counts both.
fn provenance(source: &str, sweep: &Sweep, rows: &[ExportRow], points: usize) -> Provenance {
    let mut versions: Vec<String> = Vec::new();
    let mut preps = std::collections::HashSet::new();
    let (mut grid, mut added) = (Cost::default(), Cost::default());
    for r in rows {
        if !versions.contains(&r.solver_version) {
            versions.push(r.solver_version.clone());
        }
        // Refinement adds beta values only: a row off the grid's betas is at an added point.
        let cost = match sweep.grid.beta.contains(&r.beta) {
            true => &mut grid,
            false => &mut added,
        };
        cost.rows += 1;
        if r.collision_steps > 0 {
            cost.collisions += 1;
            match r.wall_s {
                Some(w) => cost.collision_s += w,
                None => cost.untimed += 1,
            }
        }
        if preps.insert(r.prep_seed) {
            cost.prep_s += r.prep_wall_s.unwrap_or(0.0);
        }
    }
    let grid_points = sweep.points().len();
    Provenance {
        source: source.to_string(),
        seed: sweep.seed,
        two_fibers: sweep.params.geometry == cellsweep_solver::Geometry::Two,
        replicates: sweep.replicates,
        preps_per_point: sweep.preps_per_point,
        adaptive: sweep.adaptive,
        refine: sweep.refine,
        planes: sweep.planes.clone(),
        precision: sweep.protocol.precision.as_str().to_string(),
        collide_time: sweep.protocol.collide_time,
        solver_versions: versions,
        grid_points: grid_points as u64,
        added_points: points.saturating_sub(grid_points) as u64,
        grid,
        added,
    }
}

/// The counts of a counts CSV file (see [`read_csv`]): no standings, no provenance.
pub fn from_counts_csv(path: &Path) -> Result<Results, LoadError> {
    Ok(Results {
        name: path.display().to_string(),
        counts: read_csv(path)?,
        scales: Scales::default(),
        standings: None,
        prep_speeds: None,
        provenance: None,
    })
}

/// Most replicates one point of a counts file may hold (a bound that keeps sums exact).
const MAX_COUNT: u64 = 1_000_000_000;

/// Parse a counts CSV (the `csv` crate: quoting, a UTF-8 byte-order mark): a header naming the
/// columns (any order, extra columns ignored), lines starting with `#` skipped. Every value is
/// checked: finite axes in range, whole counts below [`MAX_COUNT`], each point once.
fn read_csv(path: &Path) -> Result<Vec<Counts>, LoadError> {
    let file = path.display().to_string();
    let bytes =
        std::fs::read(path).map_err(|e| LoadError::Invalid(format!("cannot read {file}: {e}")))?;
    let text = String::from_utf8(bytes)
        .map_err(|e| LoadError::Invalid(format!("{file}: not UTF-8 text: {e}")))?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let names: Vec<String> = reader
        .headers()
        .map_err(|e| LoadError::Invalid(format!("{file}: line 1: {e}")))?
        .iter()
        .map(String::from)
        .collect();
    if names.iter().all(|c| c.is_empty()) {
        invalid!("{file}: empty file");
    }
    let cols = CountsColumns::find(&names, &file)?;
    let mut out: Vec<Counts> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for record in reader.records() {
        let record = record.map_err(|e| LoadError::Invalid(format!("{file}: {e}")))?;
        let row = CsvRow {
            file: &file,
            line: record.position().map_or(0, |p| p.line()),
            names: &names,
            record: &record,
        };
        let c = cols.counts(&row)?;
        // (+ 0.0 makes -0 and 0 one point, as == does.)
        let key = [c.alpha + 0.0, c.beta + 0.0, c.L as f64, c.sigma + 0.0].map(f64::to_bits);
        if !seen.insert(key) {
            invalid!(
                "{file}: line {}: the point alpha = {}, beta = {}, L = {}, sigma = {} appears twice",
                row.line, c.alpha, c.beta, c.L, c.sigma
            );
        }
        out.push(c);
    }
    if out.is_empty() {
        invalid!("{file}: no data rows");
    }
    Ok(out)
}

/// Where a counts file keeps each of its columns: the axes and the paper's four outcomes it
/// must have, the other ends' counts where it has them, and the optional label and free speed.
struct CountsColumns {
    axes: [usize; 4],
    ends: PerEnd<Option<usize>>,
    label: Option<usize>,
    free_speed: Option<usize>,
}

impl CountsColumns {
    const AXES: [&'static str; 4] = ["alpha", "beta", "L", "sigma"];

    fn find(names: &[String], file: &str) -> Result<Self, LoadError> {
        let find = |name: &str| names.iter().position(|c| c == name);
        let missing = |r: &str| LoadError::Invalid(format!("{file}: line 1: missing column {r:?}"));
        let mut axes = [0; 4];
        for (slot, r) in axes.iter_mut().zip(Self::AXES) {
            *slot = find(r).ok_or_else(|| missing(r))?;
        }
        let mut ends = PerEnd::default();
        for e in End::ALL {
            ends[e] = find(e.count_key());
            if ends[e].is_none() && e.always_shown() {
                return Err(missing(e.count_key()));
            }
        }
        Ok(CountsColumns {
            axes,
            ends,
            label: find("label"),
            free_speed: find("free_speed"),
        })
    }

    /// One data row as a point's counts, every cell checked.
    fn counts(&self, row: &CsvRow) -> Result<Counts, LoadError> {
        let idx = &self.axes;
        let l = row.number(idx[2], 0.0, 4096.0)?;
        if l.fract() != 0.0 {
            invalid!(
                "{}: line {}: L = {l} is not a whole number",
                row.file,
                row.line
            );
        }
        let verdict = match self.label.map(|c| row.cell(c)).unwrap_or("") {
            "" => None,
            s => match Label::parse(s) {
                Some(v @ (Label::Unstable | Label::Breakup)) => Some(v),
                Some(_) => None, // outcome labels are recomputed from the counts
                None => invalid!("{}: line {}: unknown label {s:?}", row.file, row.line),
            },
        };
        Ok(Counts {
            alpha: row.number(idx[0], 0.0, 100.0)?,
            beta: row.number(idx[1], -1e6, 1e6)?,
            L: l as u32,
            sigma: row.number(idx[3], 0.0, 1e6)?,
            others: Default::default(),
            tally: self.tally(row)?,
            verdict,
            box_limited: false,
            sheddings: 0,
            free_speed: self
                .free_speed
                .and_then(|c| row.cell(c).parse().ok())
                .filter(|x: &f64| x.is_finite()),
        })
    }
}

impl CountsColumns {
    /// The row's count of each end (0 where the file has no column for it).
    fn tally(&self, row: &CsvRow) -> Result<Tally, LoadError> {
        let mut t = Tally::default();
        for e in End::ALL {
            t[e] = match (self.ends[e], e.always_shown()) {
                (Some(c), true) => row.count(c)?,
                (c, _) => row.optional_count(c)?,
            };
        }
        Ok(t)
    }
}

/// One data row of a counts file, with what its errors must name.
struct CsvRow<'a> {
    file: &'a str,
    line: u64,
    names: &'a [String],
    record: &'a csv::StringRecord,
}

impl CsvRow<'_> {
    fn cell(&self, c: usize) -> &str {
        self.record.get(c).unwrap_or("")
    }

    /// Column c as a finite number in [lo, hi].
    fn number(&self, c: usize, lo: f64, hi: f64) -> Result<f64, LoadError> {
        let (file, n, name, cell) = (self.file, self.line, &self.names[c], self.cell(c));
        match cell.parse::<f64>() {
            Ok(x) if x.is_finite() && (lo..=hi).contains(&x) => Ok(x),
            Ok(_) => invalid!("{file}: line {n}: {name} = {cell:?} is outside [{lo}, {hi}]"),
            Err(_) => invalid!("{file}: line {n}: {name} = {cell:?} is not a number"),
        }
    }

    /// Column c as a count up to MAX_COUNT.
    fn count(&self, c: usize) -> Result<u64, LoadError> {
        let (file, n, name, cell) = (self.file, self.line, &self.names[c], self.cell(c));
        match cell.parse::<u64>() {
            Ok(k) if k <= MAX_COUNT => Ok(k),
            Ok(_) => invalid!("{file}: line {n}: {name} = {cell:?} is more than {MAX_COUNT}"),
            Err(_) => invalid!("{file}: line {n}: {name} = {cell:?} is not a count"),
        }
    }

    /// An optional count column: 0 where the column or its cell is missing.
    fn optional_count(&self, c: Option<usize>) -> Result<u64, LoadError> {
        c.filter(|&c| !self.cell(c).is_empty())
            .map_or(Ok(0), |c| self.count(c))
    }
}
