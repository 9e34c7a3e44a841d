//! # cellsweep-report
//!
//! The paper's results read off a sweep's counts: the figures of `cellsweep plot`, the paper's
//! claims checked one by one, and the one self-contained HTML page of `cellsweep report`.
//!
//! Main types: [`Results`] (one sweep's counts, standings and [`Provenance`] with the [`Cost`]
//! of its grid and of its refinement, loaded by [`load`] from a store, an export or a counts
//! file), [`Collection`] (results sorted into the paper's six diagrams, the speed figure and the
//! spindle check), [`analysis::Analysis`] (every number a report states, computed once),
//! [`claims::Claim`] with its [`claims::Verdict`], and [`render`], which writes the page.
//! [`figures`] turns counts into the drawings of `cellsweep-plot`.

pub mod analysis;
pub mod bench;
pub mod claims;
pub mod collapse;
pub mod collection;
pub mod compare;
pub mod converge;
pub mod dry_run;
pub mod engine_text;
pub mod figures;
pub mod fitted_line;
pub mod html;
pub mod load;
pub mod movie;
pub mod planes;
pub mod plot_files;
pub mod pool;
pub mod status;
pub mod table;
pub mod text;
pub mod whole_file;

use cellsweep_stats::{AdaptiveRule, Assessment, Counts, RefineRule, Scales};

pub use collection::{Collection, DiagramKey};
pub use html::render;

/// One sweep's results, as every reader of them sees them (table, fit, plot, report).
#[derive(Debug, Clone)]
pub struct Results {
    pub name: String,
    pub counts: Vec<Counts>,
    pub scales: Scales,
    /// An adaptive sweep's standing of each point, beside `counts`.
    pub standings: Option<Vec<Assessment>>,
    /// The free speed of each of a point's distinct prepped cells, beside `counts`, where the
    /// source has them one by one (an export); a store and a counts file give the mean only.
    pub prep_speeds: Option<Vec<Vec<f64>>>,
    /// Where the results came from and what they cost (absent for a counts file).
    pub provenance: Option<Provenance>,
}

impl Results {
    /// The points flagged box-limited (SPEC section 4.5: a prepped cell leaves its fronts
    /// under 0.35 Nx_s apart, so the outcome depends on the pair lattice), each as
    /// "alpha = 0.1, beta = 34, L = 70, sigma = 5": what `status`, the live page and the report
    /// list.
    pub fn box_limited_points(&self) -> Vec<String> {
        self.counts
            .iter()
            .filter(|c| c.box_limited)
            .map(|c| {
                format!(
                    "alpha = {}, beta = {}, L = {}, sigma = {}",
                    c.alpha, c.beta, c.L, c.sigma
                )
            })
            .collect()
    }

    /// Several sweeps' results read as one (`table --data A --data B`, a plane across files):
    /// their points side by side, named "A + B". A sweep that fixes R0 or d where another
    /// varies it gains that axis at its own value, so that `--x R0` reads the paper's R0 = 40
    /// beside a sweep over R0. Standings and prep speeds are kept where every set has them;
    /// the first set's scales and provenance stand for the whole. A point that two sets both
    /// hold is refused: its replicates would count twice (the same file given twice, or an
    /// extension beside the sweep whose trajectories it repeats).
    pub fn merged(sets: Vec<Results>) -> Result<Results, load::LoadError> {
        let axes: Vec<&str> = ["R0", "d"]
            .into_iter()
            .filter(|a| {
                sets.iter()
                    .any(|r| r.counts.iter().any(|c| c.others.get(a).is_some()))
            })
            .collect();
        let name = sets
            .iter()
            .map(|r| r.name.as_str())
            .collect::<Vec<_>>()
            .join(" + ");
        let all_standings = sets.iter().all(|r| r.standings.is_some());
        let all_speeds = sets.iter().all(|r| r.prep_speeds.is_some());
        let mut out = Results {
            name,
            counts: Vec::new(),
            scales: sets.first().map_or_else(Scales::default, |r| r.scales),
            standings: all_standings.then(Vec::new),
            prep_speeds: all_speeds.then(Vec::new),
            provenance: sets.first().and_then(|r| r.provenance.clone()),
        };
        let mut seen: std::collections::HashMap<_, String> = Default::default();
        for r in sets {
            for mut c in r.counts {
                for a in &axes {
                    if c.others.get(a).is_none() {
                        let v = if *a == "R0" { r.scales.R0 } else { r.scales.d };
                        c.others.0.push((a.to_string(), v));
                    }
                }
                let mut others: Vec<(String, u64)> = c
                    .others
                    .0
                    .iter()
                    .map(|(n, v)| (n.clone(), v.to_bits()))
                    .collect();
                others.sort();
                let key = (
                    c.alpha.to_bits(),
                    c.beta.to_bits(),
                    c.L,
                    c.sigma.to_bits(),
                    others,
                );
                if let Some(first) = seen.insert(key, r.name.clone()) {
                    return Err(load::LoadError::Invalid(format!(
                        "alpha = {}, beta = {}, L = {}, sigma = {}{}{} is in both {first:?} and \
                         {:?}: its replicates would count twice; read one of them",
                        c.alpha,
                        c.beta,
                        c.L,
                        c.sigma,
                        if c.others.is_empty() { "" } else { ", " },
                        c.others,
                        r.name
                    )));
                }
                out.counts.push(c);
            }
            if let (Some(all), Some(v)) = (out.standings.as_mut(), r.standings) {
                all.extend(v);
            }
            if let (Some(all), Some(v)) = (out.prep_speeds.as_mut(), r.prep_speeds) {
                all.extend(v);
            }
        }
        Ok(out)
    }

    /// These results with only the points `keep` holds (their standings and prep speeds
    /// follow them).
    pub fn only(self, keep: impl Fn(&Counts) -> bool) -> Results {
        let kept: Vec<bool> = self.counts.iter().map(&keep).collect();
        self.keep(&kept)
    }

    /// These results with only the points whose flag in `kept` is set (by index).
    pub fn keep(self, kept: &[bool]) -> Results {
        Results {
            counts: pick(self.counts, kept),
            standings: self.standings.map(|v| pick(v, kept)),
            prep_speeds: self.prep_speeds.map(|v| pick(v, kept)),
            ..self
        }
    }
}

/// The items of `v` whose flag in `kept` is set.
fn pick<T>(v: Vec<T>, kept: &[bool]) -> Vec<T> {
    v.into_iter()
        .zip(kept)
        .filter(|(_, k)| **k)
        .map(|(x, _)| x)
        .collect()
}

/// What a sweep is and what running it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    /// The export file or store read.
    pub source: String,
    pub seed: u64,
    /// One fiber or two.
    pub two_fibers: bool,
    /// The budget of replicates per point.
    pub replicates: u32,
    pub preps_per_point: u32,
    pub adaptive: Option<AdaptiveRule>,
    /// The sweep's refinement rule, if it has one.
    pub refine: Option<RefineRule>,
    /// Diagrams on other axes the sweep asks the report to draw (`[report] planes`).
    pub planes: Vec<cellsweep_stats::Plane>,
    /// "f32" or "f64" collisions.
    pub precision: String,
    /// tau0 of each collision.
    pub collide_time: f64,
    pub solver_versions: Vec<String>,
    /// The grid's points, and the points refinement added that have a result.
    pub grid_points: u64,
    pub added_points: u64,
    /// What the finished rows at the grid's points cost, and at the added points.
    pub grid: Cost,
    pub added: Cost,
}

impl Provenance {
    /// What every finished row cost: the grid's and the added points' together.
    pub fn total(&self) -> Cost {
        self.grid.plus(&self.added)
    }

    /// A fixed run of the grid at the full budget: its collisions (every replicate of every
    /// grid point, breakups and unstable preps aside).
    pub fn fixed_grid_replicates(&self) -> u64 {
        self.grid_points * self.replicates as u64
    }
}

/// What a set of finished rows cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Cost {
    /// Finished replicates, and of them the ones that ran a collision.
    pub rows: u64,
    pub collisions: u64,
    /// Seconds of collisions and of preps on their workers, over the rows that recorded them
    /// (each prep once).
    pub collision_s: f64,
    pub prep_s: f64,
    /// Rows without a recorded wall time (imported from an export of format 1).
    pub untimed: u64,
}

impl Cost {
    /// Core-hours recorded (collisions and preps).
    pub fn core_hours(&self) -> f64 {
        (self.collision_s + self.prep_s) / 3600.0
    }

    pub fn plus(&self, o: &Cost) -> Cost {
        Cost {
            rows: self.rows + o.rows,
            collisions: self.collisions + o.collisions,
            collision_s: self.collision_s + o.collision_s,
            prep_s: self.prep_s + o.prep_s,
            untimed: self.untimed + o.untimed,
        }
    }
}
