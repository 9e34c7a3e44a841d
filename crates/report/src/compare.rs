//! Two result sets side by side, point by point and replicate by replicate, with a test of
//! whether their outcome statistics differ ([`cellsweep_stats::compare`]): the sides read from
//! stores, and the comparison as text and CSV (`cellsweep compare`).

use std::fmt::Write as _;
use std::path::Path;

use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::{Comparison, End, Label, PointComparison, Tally, Test};
use cellsweep_store::Store;

/// Why a side could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error(transparent)]
    Store(#[from] cellsweep_store::StoreError),
    #[error("{db}: {source}")]
    Definition {
        db: String,
        source: cellsweep_scheduler::StoredSweepError,
    },
    #[error("sweep {name:?} in {db} has no results yet")]
    Empty { name: String, db: String },
    #[error("sweep {name:?} in {db} has no results under {version:?} (it has results under {others}; pass --version-a / --version-b)")]
    NoResults {
        name: String,
        db: String,
        version: String,
        others: String,
    },
}

/// One side of the comparison: a sweep's results under one solver version.
#[derive(Debug, Clone)]
pub struct CompareSide {
    pub name: String,
    pub version: String,
    pub db: String,
    pub replicates: Vec<cellsweep_stats::Replicate>,
}

/// The results of sweep `name` in the store `db` under solver `version` (this build's by
/// default).
pub fn load_side(
    db: &Path,
    name: &str,
    version: Option<&str>,
) -> Result<CompareSide, CompareError> {
    let store = Store::open_read(db)?;
    let id = store.sweep_id(name)?;
    let version = version.unwrap_or(SOLVER_VERSION);
    let sweep =
        cellsweep_scheduler::Sweep::stored(&store, id).map_err(|e| CompareError::Definition {
            db: db.display().to_string(),
            source: e,
        })?;
    let replicates = store.replicates(id, version, &|c| sweep.others_of_config(c))?;
    if replicates.is_empty() {
        let versions = store.result_versions(id)?;
        if versions.is_empty() {
            return Err(CompareError::Empty {
                name: name.to_string(),
                db: db.display().to_string(),
            });
        }
        return Err(CompareError::NoResults {
            name: name.to_string(),
            db: db.display().to_string(),
            version: version.to_string(),
            others: versions
                .iter()
                .map(|v| format!("{v:?}"))
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    Ok(CompareSide {
        name: name.to_string(),
        version: version.to_string(),
        db: db.display().to_string(),
        replicates,
    })
}

/// The ends' initials, in the order of [`End::ALL`], slash-separated (`tr/wp/rv/...`).
fn initials() -> String {
    End::ALL.map(End::initials).join("/")
}

/// Each end's count, in the order of [`End::ALL`], slash-separated.
fn counts_text(c: &Tally) -> String {
    let counts: Vec<String> = c.iter().map(|(_, n)| n.to_string()).collect();
    counts.join("/")
}

fn label_text(l: Option<Label>) -> &'static str {
    l.map_or("-", Label::symbol)
}

fn shift_text(p: &PointComparison) -> String {
    match (p.decision_shift_mean, p.decision_shift_max) {
        (Some(m), Some(x)) => format!("{m:.1} / {x:.1}"),
        _ => "-".to_string(),
    }
}

fn p_text(p: &PointComparison) -> String {
    let mark = if p.test == Test::Independent { "*" } else { "" };
    format!("{:.3}{mark}", p.p_value)
}

/// The comparison as aligned text: both sides, a line per point, the legend and the totals.
pub fn text(a: &CompareSide, b: &CompareSide, c: &Comparison) -> String {
    let mut out = String::new();
    for (tag, s) in [("A", a), ("B", b)] {
        let _ = writeln!(
            out,
            "{tag}: {} ({}, {}): {} replicates",
            s.name,
            s.version,
            s.db,
            s.replicates.len()
        );
    }
    out.push('\n');
    let _ = writeln!(
        out,
        "{:>6} {:>6} {:>4} {:>5}  {:>20} {:>20}  {:>9}  {:>13}  {:>7}  labels",
        "alpha",
        "beta",
        "L",
        "sigma",
        format!("A {}", initials()),
        format!("B {}", initials()),
        "alike",
        "|dt| mean/max",
        "p"
    );
    for p in &c.points {
        let alike = if p.matched > 0 {
            format!("{} of {}", p.alike, p.matched)
        } else {
            "-".to_string()
        };
        let differ = if p.label_a != p.label_b {
            "  <- differ"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "{:>6} {:>6} {:>4} {:>5}  {:>20} {:>20}  {:>9}  {:>13}  {:>7}  {:>2} {:>2}{differ}",
            p.alpha,
            p.beta,
            p.L,
            p.sigma,
            counts_text(&p.counts_a),
            counts_text(&p.counts_b),
            alike,
            shift_text(p),
            p_text(p),
            label_text(p.label_a),
            label_text(p.label_b),
        );
    }
    let _ = writeln!(
        out,
        "\n{};\n|dt|: difference in decision time of the pairs that end alike \
         (tau0); labels as in `cellsweep table`;\np: exact symmetry test of the discordant \
         pairs (McNemar's for two outcomes), or, marked *, a permutation\ntest of the counts \
         where the replicates do not all match. Small p: the statistics differ.\n",
        End::ALL
            .map(|e| format!("{} {}", e.initials(), e.meaning()))
            .join(", ")
    );
    if c.only_a + c.only_b > 0 {
        let _ = writeln!(
            out,
            "grid points in only one set (left out): {} in A, {} in B",
            c.only_a, c.only_b
        );
    }
    if c.matched > 0 {
        let _ = writeln!(
            out,
            "{} of {} matched pairs end alike ({:.1}%)",
            c.alike,
            c.matched,
            100.0 * c.alike as f64 / c.matched as f64
        );
    } else {
        let _ = writeln!(
            out,
            "no matched pairs (the replicates ran from different seeds)"
        );
    }
    let _ = writeln!(
        out,
        "labels differ at {} of {} points",
        c.labels_differ,
        c.points.len()
    );
    if let Some(p) = c.p_value_paired {
        let _ = writeln!(out, "paired test over all points at once: p = {p:.3}");
    }
    out
}

/// The comparison as CSV, a row per point.
pub fn csv(c: &Comparison) -> String {
    let mut out = String::new();
    let mut header = "alpha,beta,L,sigma".to_string();
    for side in ["a", "b"] {
        for e in End::ALL {
            header += &format!(",{}_{side}", e.count_key());
        }
    }
    header += ",label_a,label_b,matched,alike,decision_shift_mean,decision_shift_max,test,p_value";
    let _ = writeln!(out, "{header}");
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    let label = |l: Option<Label>| l.map_or("", Label::as_str);
    for p in &c.points {
        let counts: Vec<String> = p
            .counts_a
            .iter()
            .chain(p.counts_b.iter())
            .map(|(_, n)| n.to_string())
            .collect();
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            p.alpha,
            p.beta,
            p.L,
            p.sigma,
            counts.join(","),
            label(p.label_a),
            label(p.label_b),
            p.matched,
            p.alike,
            opt(p.decision_shift_mean),
            opt(p.decision_shift_max),
            if p.test == Test::Paired {
                "paired"
            } else {
                "independent"
            },
            p.p_value
        );
    }
    out
}
