//! `cellsweep compare`: two result sets side by side, point by point and replicate by
//! replicate, with a test of whether their outcome statistics differ (`cellsweep_store::compare`).

use std::path::Path;

use anyhow::bail;
use cellsweep_solver::SOLVER_VERSION;
use cellsweep_stats::{compare, Comparison, End, Label, PointComparison, Tally, Test};
use cellsweep_store::Store;
use serde_json::json;

use crate::cli::{CompareArgs, Format};

/// One side of the comparison: a sweep's results under one solver version.
struct Side {
    name: String,
    version: String,
    db: String,
    replicates: Vec<cellsweep_stats::Replicate>,
}

fn load(db: &Path, name: &str, version: Option<&str>) -> anyhow::Result<Side> {
    let store = Store::open_read(db)?;
    let id = store.sweep_id(name)?;
    let version = version.unwrap_or(SOLVER_VERSION);
    let sweep = cellsweep_scheduler::Sweep::stored(&store, id)
        .map_err(|e| anyhow::anyhow!("{}: {e}", db.display()))?;
    let replicates = store.replicates(id, version, &|c| sweep.others_of_config(c))?;
    if replicates.is_empty() {
        let versions = store.result_versions(id)?;
        if versions.is_empty() {
            bail!("sweep {name:?} in {} has no results yet", db.display());
        }
        bail!(
            "sweep {name:?} in {} has no results under {version:?} (it has results under {}; \
             pass --version-a / --version-b)",
            db.display(),
            versions
                .iter()
                .map(|v| format!("{v:?}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(Side {
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

fn print_text(a: &Side, b: &Side, c: &Comparison) {
    for (tag, s) in [("A", a), ("B", b)] {
        println!(
            "{tag}: {} ({}, {}): {} replicates",
            s.name,
            s.version,
            s.db,
            s.replicates.len()
        );
    }
    println!();
    println!(
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
        println!(
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
    println!(
        "\ntr train, wp walk-past, rv reversal, un undetermined, bu a cell broke up in the collision, v decided by the prep's verdict \
         (unstable or breakup);\n|dt|: difference in decision time of the pairs that end alike \
         (tau0); labels as in `cellsweep table`;\np: exact symmetry test of the discordant \
         pairs (McNemar's for two outcomes), or, marked *, a permutation\ntest of the counts \
         where the replicates do not all match. Small p: the statistics differ.\n"
    );
    if c.only_a + c.only_b > 0 {
        println!(
            "grid points in only one set (left out): {} in A, {} in B",
            c.only_a, c.only_b
        );
    }
    if c.matched > 0 {
        println!(
            "{} of {} matched pairs end alike ({:.1}%)",
            c.alike,
            c.matched,
            100.0 * c.alike as f64 / c.matched as f64
        );
    } else {
        println!("no matched pairs (the replicates ran from different seeds)");
    }
    println!(
        "labels differ at {} of {} points",
        c.labels_differ,
        c.points.len()
    );
    if let Some(p) = c.p_value_paired {
        println!("paired test over all points at once: p = {p:.3}");
    }
}

fn print_csv(c: &Comparison) {
    let mut header = "alpha,beta,L,sigma".to_string();
    for side in ["a", "b"] {
        for e in End::ALL {
            header += &format!(",{}_{side}", e.count_key());
        }
    }
    header += ",label_a,label_b,matched,alike,decision_shift_mean,decision_shift_max,test,p_value";
    println!("{header}");
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    let label = |l: Option<Label>| l.map_or("", Label::as_str);
    for p in &c.points {
        let counts: Vec<String> = p
            .counts_a
            .iter()
            .chain(p.counts_b.iter())
            .map(|(_, n)| n.to_string())
            .collect();
        println!(
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
}

pub fn run(args: CompareArgs) -> anyhow::Result<()> {
    let a = load(&args.db.db, &args.a, args.version_a.as_deref())?;
    let db_b = args.db_b.as_deref().unwrap_or(&args.db.db);
    let b = load(db_b, &args.b, args.version_b.as_deref())?;
    if a.name == b.name && a.version == b.version && a.db == b.db {
        bail!(
            "A and B are the same results ({} under {}); name two sweeps, or two solver versions \
             with --version-a / --version-b",
            a.name,
            a.version
        );
    }
    let c = compare(&a.replicates, &b.replicates);
    if c.points.is_empty() {
        bail!(
            "{} and {} have no grid point in common (points match by alpha, beta, L and sigma)",
            a.name,
            b.name
        );
    }
    match args.format {
        Format::Text => print_text(&a, &b, &c),
        Format::Csv => print_csv(&c),
        Format::Json => {
            let side = |s: &Side| {
                json!({"sweep": s.name, "solver_version": s.version, "db": s.db,
                       "replicates": s.replicates.len()})
            };
            let mut v = serde_json::to_value(&c)?;
            v["a"] = side(&a);
            v["b"] = side(&b);
            println!("{}", serde_json::to_string_pretty(&v)?);
        }
    }
    Ok(())
}
