//! Results sorted into what the paper shows: six (L, sigma) phase diagrams on two fibers, the
//! free speed against beta (several free-motion cells per point), and the spindle check (one
//! fiber).

use cellsweep_stats::{Counts, Others, Scales};

use crate::Results;

/// One phase diagram (alpha across, beta up): a spacing, a sigma and the values of the sweep's
/// other axes (none for the paper's).
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)]
pub struct DiagramKey {
    pub L: u32,
    pub sigma: f64,
    pub others: Others,
}

impl DiagramKey {
    /// The paper's diagram (L, sigma): no other axis.
    pub const fn paper(l: u32, sigma: f64) -> DiagramKey {
        DiagramKey {
            L: l,
            sigma,
            others: Others(Vec::new()),
        }
    }

    /// The diagram that point `c` belongs to.
    pub fn of(c: &Counts) -> DiagramKey {
        DiagramKey {
            L: c.L,
            sigma: c.sigma,
            others: c.others.clone(),
        }
    }

    /// Whether point `c` belongs to this diagram.
    pub fn holds(&self, c: &Counts) -> bool {
        c.L == self.L && c.sigma == self.sigma && c.others == self.others
    }

    /// The stem of its picture files: phase-L90-sigma5, then -NAME_VALUE per other axis.
    pub fn file_stem(&self) -> String {
        let mut stem = format!("phase-L{}-sigma{}", self.L, self.sigma);
        for (name, v) in &self.others.0 {
            stem += &format!("-{name}_{v}");
        }
        stem
    }

    /// The paper's figure of this diagram (main text or appendix), if it has one.
    pub fn paper_figure(&self) -> Option<&'static str> {
        if !self.others.is_empty() {
            return None;
        }
        Some(match (self.L, self.sigma as i64) {
            (90, 5) => "Fig. 3",
            (70, 5) => "Fig. 4",
            (90, 0) => "Fig. 5",
            (80, 5) => "Fig. A1",
            (70, 0) => "Fig. A2",
            (80, 0) => "Fig. A3",
            _ => return None,
        })
    }

    pub fn title(&self) -> String {
        match self.others.is_empty() {
            true => format!("L = {}, σ = {}", self.L, self.sigma),
            false => format!("L = {}, σ = {}, {}", self.L, self.sigma, self.others),
        }
    }
}

/// The paper's six diagrams, in its order of discussion.
pub const PAPER_DIAGRAMS: [DiagramKey; 6] = [
    DiagramKey::paper(90, 5.0),
    DiagramKey::paper(80, 5.0),
    DiagramKey::paper(70, 5.0),
    DiagramKey::paper(90, 0.0),
    DiagramKey::paper(80, 0.0),
    DiagramKey::paper(70, 0.0),
];

/// A diagram and the results that show it.
#[derive(Debug, Clone)]
pub struct Shown<'a> {
    pub key: DiagramKey,
    pub results: &'a Results,
    /// The diagram's points within `results`, by index.
    pub points: Vec<usize>,
}

impl Shown<'_> {
    pub fn counts(&self) -> impl Iterator<Item = &Counts> {
        self.points.iter().map(|&i| &self.results.counts[i])
    }

    /// Replicates with a result, and of them the ones that collided.
    pub fn replicates(&self) -> (u64, u64) {
        self.counts().fold((0, 0), |(n, k), c| {
            let collided = c.collisions();
            (n + c.total(), k + collided)
        })
    }
}

/// Every result set of a report, sorted by role.
#[derive(Debug, Clone)]
pub struct Collection<'a> {
    /// One result set per (L, sigma) diagram on two fibers (the one with most replicates
    /// where several show the same diagram), in the order of [`PAPER_DIAGRAMS`], other
    /// diagrams after.
    pub diagrams: Vec<Shown<'a>>,
    /// The spindle check: a sweep on one fiber.
    pub spindle: Option<&'a Results>,
    /// The speed figure: a sweep with several prepped cells per point.
    pub speed: Option<&'a Results>,
    /// Result sets not shown, and why.
    pub unused: Vec<(&'a Results, String)>,
}

impl<'a> Collection<'a> {
    pub fn of(all: &'a [Results]) -> Collection<'a> {
        let mut c = Collection {
            diagrams: Vec::new(),
            spindle: None,
            speed: None,
            unused: Vec::new(),
        };
        let mut bigger = |slot: &mut Option<&'a Results>, r: &'a Results, role: &str| match slot {
            Some(old)
                if old.counts.iter().map(Counts::total).sum::<u64>()
                    >= r.counts.iter().map(Counts::total).sum::<u64>() =>
            {
                c.unused
                    .push((r, format!("another {role} sweep has more replicates")))
            }
            _ => {
                if let Some(old) = slot.replace(r) {
                    c.unused
                        .push((old, format!("another {role} sweep has more replicates")));
                }
            }
        };
        let mut diagram_sets: Vec<&'a Results> = Vec::new();
        for r in all {
            match &r.provenance {
                Some(p) if !p.two_fibers => bigger(&mut c.spindle, r, "one-fiber"),
                Some(p) if p.preps_per_point > 1 => bigger(&mut c.speed, r, "speed"),
                _ => diagram_sets.push(r),
            }
        }
        let mut keys: Vec<DiagramKey> = PAPER_DIAGRAMS.to_vec();
        for r in &diagram_sets {
            for k in r.counts.iter() {
                let key = DiagramKey::of(k);
                if !keys.contains(&key) {
                    keys.push(key);
                }
            }
        }
        for key in keys {
            let best = diagram_sets
                .iter()
                .map(|r| {
                    let points: Vec<usize> = (0..r.counts.len())
                        .filter(|&i| key.holds(&r.counts[i]))
                        .collect();
                    Shown {
                        key: key.clone(),
                        results: r,
                        points,
                    }
                })
                .filter(|s| !s.points.is_empty())
                .max_by_key(|s| s.replicates().0);
            if let Some(s) = best {
                c.diagrams.push(s);
            }
        }
        for r in diagram_sets {
            if !c.diagrams.iter().any(|s| std::ptr::eq(s.results, r)) {
                c.unused.push((
                    r,
                    "another sweep shows its diagrams with more replicates".into(),
                ));
            }
        }
        c
    }

    /// The paper's diagram (L, sigma) (no other axis), if a result set shows it.
    pub fn diagram(&self, l: u32, sigma: f64) -> Option<&Shown<'a>> {
        self.shown(&DiagramKey::paper(l, sigma))
    }

    /// Diagram `key`, if a result set shows it.
    pub fn shown(&self, key: &DiagramKey) -> Option<&Shown<'a>> {
        self.diagrams.iter().find(|s| s.key == *key)
    }

    /// Every shown point at `sigma` (all L) of the diagrams without other axes (the paper's
    /// kind: a sweep over R0 or E0 is the collapse figure's, not the paper's line), with the
    /// scales of the first set: what the fit over all spacings reads.
    pub fn counts_at(&self, sigma: Option<f64>) -> (Vec<Counts>, Scales) {
        let mut out = Vec::new();
        let mut scales = None;
        for s in self
            .diagrams
            .iter()
            .filter(|s| s.key.others.is_empty())
            .filter(|s| sigma.is_none_or(|v| s.key.sigma == v))
        {
            scales.get_or_insert(s.results.scales);
            out.extend(s.counts().cloned());
        }
        (out, scales.unwrap_or_default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Provenance;

    fn results(name: &str, l: u32, n: u64, two_fibers: bool, preps: u32) -> Results {
        let c = Counts {
            tally: [(cellsweep_stats::End::Train, n)].into_iter().collect(),
            ..Counts::none(0.1, 10.0, l, 5.0)
        };
        Results {
            name: name.into(),
            counts: vec![c],
            scales: Scales::default(),
            standings: None,
            prep_speeds: None,
            provenance: Some(Provenance {
                source: name.into(),
                seed: 1,
                two_fibers,
                replicates: n as u32,
                preps_per_point: preps,
                adaptive: None,
                planes: Vec::new(),
                refine: None,
                precision: "f32".into(),
                collide_time: 400.0,
                solver_versions: vec![],
                grid_points: 1,
                added_points: 0,
                grid: crate::Cost {
                    rows: n,
                    collisions: n,
                    ..Default::default()
                },
                added: crate::Cost::default(),
            }),
        }
    }

    #[test]
    fn each_sweep_goes_where_it_belongs_and_the_larger_of_two_diagrams_is_shown() {
        let all = [
            results("fixed24", 90, 24, true, 1),
            results("adaptive", 90, 96, true, 1),
            results("spindle", 90, 48, false, 1),
            results("speed", 90, 20, true, 20),
            results("other", 60, 8, true, 1),
        ];
        let c = Collection::of(&all);
        assert_eq!(c.spindle.unwrap().name, "spindle");
        assert_eq!(c.speed.unwrap().name, "speed");
        assert_eq!(c.diagram(90, 5.0).unwrap().results.name, "adaptive");
        // The paper's diagrams first, then the others.
        let keys: Vec<(u32, &str)> = c
            .diagrams
            .iter()
            .map(|s| (s.key.L, s.results.name.as_str()))
            .collect();
        assert_eq!(keys, [(90, "adaptive"), (60, "other")]);
        let unused: Vec<&str> = c.unused.iter().map(|(r, _)| r.name.as_str()).collect();
        assert_eq!(unused, ["fixed24"]);
    }
}
