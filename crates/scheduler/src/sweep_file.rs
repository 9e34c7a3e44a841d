//! A sweep file as written: every table and key typed and deserialized by serde, unknown keys
//! refused (`deny_unknown_fields`), each error naming its dotted key.
//!
//! [`SweepFile`] is only the file's shape: ranges, limits and the model's validity are checked
//! in one place, [`crate::Sweep::parse`]. Types here are as wide as TOML allows ([`Whole`] is
//! any TOML integer, [`Real`] any number) so that a value out of range gets that function's
//! message ("10001 is more than 10000"), not a type error.

use std::fmt;

use cellsweep_solver::{ClassifierSettings, Geometry, Params, Precision, PARAM_NAMES};
use serde::de::{self, DeserializeOwned, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use toml::{Table, Value};

use crate::error::SweepError;

/// The top level of a sweep file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    pub name: Option<String>,
    /// Free text for people; not part of the sweep.
    #[allow(dead_code)]
    pub description: Option<String>,
    pub seed: Option<Whole>,
    pub replicates: Option<Whole>,
    pub preps_per_point: Option<Whole>,
    pub geometry: Option<Geometry>,
    /// Kept as a table until its paper axes and any other are told apart (see [`grid`]).
    pub grid: Option<Table>,
    /// Kept as a table until its keys are checked against the grid axes (see [`params`]).
    pub params: Option<Table>,
    pub protocol: Option<ProtocolFile>,
    pub classifier: Option<ClassifierSettings>,
    pub adaptive: Option<AdaptiveFile>,
    pub refine: Option<RefineFile>,
    pub run: Option<RunFile>,
    pub report: Option<ReportFile>,
}

/// `[grid]`'s paper axes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct GridFile {
    pub alpha: Option<AxisFile>,
    pub beta: Option<AxisFile>,
    pub L: Option<AxisFile>,
    pub sigma: Option<AxisFile>,
}

/// One grid axis: a number, a list of numbers, or `{ from, to, step }`.
#[derive(Debug, Clone, PartialEq)]
pub enum AxisFile {
    One(f64),
    List(Vec<f64>),
    Range { from: f64, to: f64, step: f64 },
}

/// `[protocol]`: lattices, stage durations (tau0), the collision's windows and float type.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProtocolFile {
    pub single_lattice: Option<[Whole; 2]>,
    pub pair_lattice: Option<[Whole; 2]>,
    pub relax_time: Option<Real>,
    pub free_time: Option<Real>,
    pub collide_time: Option<Real>,
    pub record_interval: Option<Real>,
    pub check_interval: Option<Real>,
    pub stop_early: Option<bool>,
    pub patch_bound: Option<Real>,
    pub precision: Option<Precision>,
    /// Resolution k (SPEC section 6): a lattice k times finer, every value still in the
    /// paper's units.
    pub resolution: Option<Whole>,
}

/// `[adaptive]`: replicates in rounds until each point's label is settled.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveFile {
    pub batch: Option<Whole>,
    pub min_replicates: Option<Whole>,
    pub max_replicates: Option<Whole>,
    pub error: Option<Real>,
}

/// `[refine]`: beta values added where a column's crossing lies (SPEC section 6).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineFile {
    pub axis: Option<String>,
    pub width: Option<Real>,
    pub step: Option<Real>,
    pub max_new_per_column: Option<Whole>,
    pub per_round: Option<Whole>,
    pub extend_to: Option<Real>,
    pub extend_step: Option<Real>,
}

/// `[report]`: what the report draws beyond the paper's diagrams.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReportFile {
    pub planes: Option<Vec<PlaneFile>>,
}

/// One plane the report draws: `{ x = "R0", y = "beta", by = ["xt", "sigma"] }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneFile {
    pub x: String,
    pub y: String,
    pub by: Option<Vec<String>>,
}

/// `[run]`: fault handling.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunFile {
    pub job_timeout: Option<Real>,
    pub max_attempts: Option<Whole>,
}

/// A whole number as written (TOML integers are 64-bit signed); its range is checked later.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Whole(pub i64);

/// A number as written, integer or float (non-finite floats are refused before serde).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Real(pub f64);

impl<'de> Deserialize<'de> for Whole {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Whole;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a whole number")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Whole, E> {
                Ok(Whole(v))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Whole, E> {
                i64::try_from(v)
                    .map(Whole)
                    .map_err(|_| E::custom(format!("{v} is too large")))
            }
        }
        d.deserialize_i64(V)
    }
}

impl<'de> Deserialize<'de> for Real {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = Real;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Real, E> {
                Ok(Real(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Real, E> {
                Ok(Real(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Real, E> {
                Ok(Real(v as f64))
            }
        }
        d.deserialize_f64(V)
    }
}

impl<'de> Deserialize<'de> for AxisFile {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = AxisFile;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number, a list of numbers, or { from, to, step }")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<AxisFile, E> {
                Ok(AxisFile::One(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<AxisFile, E> {
                Ok(AxisFile::One(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<AxisFile, E> {
                Ok(AxisFile::One(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<AxisFile, A::Error> {
                let mut values = Vec::new();
                while let Some(Real(x)) = seq.next_element()? {
                    // Bounded here so that a huge list is refused before it is all held.
                    if values.len() == crate::limits::MAX_AXIS_POINTS {
                        return Err(de::Error::custom(format!(
                            "more than {} values",
                            crate::limits::MAX_AXIS_POINTS
                        )));
                    }
                    values.push(x);
                }
                Ok(AxisFile::List(values))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<AxisFile, A::Error> {
                #[derive(Deserialize)]
                #[serde(deny_unknown_fields)]
                struct Range {
                    from: Real,
                    to: Real,
                    step: Real,
                }
                let r = Range::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(AxisFile::Range {
                    from: r.from.0,
                    to: r.to.0,
                    step: r.step.0,
                })
            }
        }
        d.deserialize_any(V)
    }
}

/// The file's text parsed into [`SweepFile`]; `file` names it in errors.
pub fn read(text: &str, file: &str) -> Result<SweepFile, SweepError> {
    let top: Table = text.parse().map_err(|e: toml::de::Error| {
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].lines().count().max(1))
            .map_or("syntax".to_string(), |l| format!("line {l}"));
        SweepError::new(file, line, toml_problem(e.message()))
    })?;
    finite(&Value::Table(top.clone()), "")
        .map_err(|(key, x)| SweepError::new(file, key, format!("{x} is not a finite number")))?;
    typed(Value::Table(top), "", file)
}

/// An axis of `[grid]` beyond the paper's four, as written: a SPEC parameter's name and its
/// values (numbers as an [`AxisFile`]; geometry as one or more of `"one"`, `"two"`).
#[derive(Debug, Clone, PartialEq)]
pub enum OtherAxisFile {
    Numbers(AxisFile),
    Geometries(Vec<Geometry>),
}

/// `[grid]` split into the paper's four axes and any other, in the file's order. A name that
/// is no SPEC parameter is refused here, naming the ones there are.
pub fn grid(
    table: Table,
    file: &str,
) -> Result<(GridFile, Vec<(String, OtherAxisFile)>), SweepError> {
    let paper = |k: &str| matches!(k, "alpha" | "beta" | "L" | "sigma");
    let (four, rest): (Table, Table) = table.into_iter().partition(|(k, _)| paper(k));
    let grid: GridFile = typed(Value::Table(four), "grid.", file)?;
    let mut others = Vec::new();
    for (key, value) in rest {
        if !PARAM_NAMES.contains(&key.as_str()) {
            let known: Vec<&str> = PARAM_NAMES.iter().copied().filter(|k| !paper(k)).collect();
            return Err(SweepError::new(
                file,
                format!("grid.{key}"),
                format!(
                    "unknown parameter (known: alpha, beta, L, sigma, {})",
                    known.join(", ")
                ),
            ));
        }
        let one = |v: Value| {
            let mut t = Table::new();
            t.insert(key.clone(), v);
            Value::Table(t)
        };
        let axis = if key == "geometry" {
            let list = match value {
                Value::Array(_) => value,
                v => Value::Array(vec![v]),
            };
            let mut g: std::collections::BTreeMap<String, Vec<Geometry>> =
                typed(one(list), "grid.", file)?;
            OtherAxisFile::Geometries(g.remove(&key).unwrap_or_default())
        } else {
            let mut a: std::collections::BTreeMap<String, AxisFile> =
                typed(one(value), "grid.", file)?;
            match a.remove(&key) {
                Some(a) => OtherAxisFile::Numbers(a),
                None => continue,
            }
        };
        others.push((key, axis));
    }
    Ok((grid, others))
}

/// `[params]` as the model's parameters (defaults for every key not given). The grid axes and
/// the geometry have their own places and are refused here with a pointer to them.
pub fn params(table: Table, file: &str) -> Result<Params, SweepError> {
    let placed = |k: &str| matches!(k, "alpha" | "beta" | "L" | "sigma" | "geometry");
    let settable: Vec<&str> = PARAM_NAMES.iter().copied().filter(|k| !placed(k)).collect();
    let unknown = format!("unknown parameter (known: {})", settable.join(", "));
    for key in table.keys() {
        let problem = match key.as_str() {
            "alpha" | "beta" | "L" | "sigma" => "is a grid axis: set it in [grid]",
            "geometry" => "set geometry at the top level",
            k if PARAM_NAMES.contains(&k) => continue,
            _ => &*unknown,
        };
        return Err(SweepError::new(file, format!("params.{key}"), problem));
    }
    typed(Value::Table(table), "params.", file)
}

/// A value deserialized into `T`, an error naming its dotted key (after `prefix`); for an
/// unknown key that is the key itself.
fn typed<T: DeserializeOwned>(value: Value, prefix: &str, file: &str) -> Result<T, SweepError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let key = match e.path().to_string() {
            p if p.is_empty() || p == "." => "file".to_string(),
            p => format!("{prefix}{p}"),
        };
        SweepError::new(file, key, in_toml_words(&e.inner().to_string()))
    })
}

/// serde's message in the words of a TOML file: keys, tables, numbers (not fields, structs,
/// f64).
fn in_toml_words(message: &str) -> String {
    let mut m = first_line(message).replacen("unknown field ", "unknown key ", 1);
    if let Some(at) = m.find("expected struct ") {
        m.replace_range(at.., "expected a table");
    }
    m.replace("expected f64", "expected a number")
        .replace("expected u32", "expected a whole number")
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() || path == "." {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// The TOML parser's message in a user's words: an integer beyond 64 bits is reported by the
/// parser as a type error "integer `N` as i128", which says nothing to someone writing a seed.
fn toml_problem(message: &str) -> String {
    let line = first_line(message);
    if let Some(rest) = line.strip_prefix("invalid type: integer `") {
        if let Some((n, tail)) = rest.split_once('`') {
            if tail.starts_with(" as i128") {
                return format!(
                    "the integer {n} is too large (TOML integers are 64-bit, at most {})",
                    i64::MAX
                );
            }
        }
    }
    line
}

fn first_line(s: &str) -> String {
    s.lines()
        .next()
        .unwrap_or("malformed TOML")
        .trim()
        .to_string()
}

/// Every float in `v` finite, else the dotted key of the first that is not.
fn finite(v: &Value, path: &str) -> Result<(), (String, f64)> {
    match v {
        Value::Float(x) if !x.is_finite() => Err((path.to_string(), *x)),
        Value::Table(t) => t.iter().try_for_each(|(k, v)| finite(v, &join(path, k))),
        Value::Array(items) => items.iter().try_for_each(|v| finite(v, path)),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        read(text, "f.toml").unwrap_err().to_string()
    }

    #[test]
    fn unknown_keys_are_named_with_their_table() {
        assert!(err("name = \"a\"\nreplicate = 3")
            .starts_with("f.toml: replicate: unknown key `replicate`"));
        assert!(err("[protocol]\nwindows = 3").starts_with("f.toml: protocol.windows: "));
        // `[grid]` is split into its axes after reading.
        let grid_err = |text: &str| {
            grid(read(text, "f.toml").unwrap().grid.unwrap(), "f.toml")
                .unwrap_err()
                .to_string()
        };
        assert!(grid_err("[grid]\ngamma = [1]").starts_with(
            "f.toml: grid.gamma: unknown parameter (known: alpha, beta, L, sigma, geometry, d,"
        ));
        assert!(grid_err("[grid]\nalpha = { from = 1, to = 2, by = 1 }").contains("grid.alpha"));
        assert!(err("[param]\nR0 = 2").starts_with("f.toml: param: "));
    }

    #[test]
    fn types_and_nonfinite_values_are_named() {
        assert!(err("seed = 1.5").starts_with("f.toml: seed: invalid type: floating point"));
        assert!(err("[run]\njob_timeout = \"1h\"").contains("run.job_timeout: invalid type"));
        assert!(
            err("[classifier]\nsustain_window = nan").contains("classifier.sustain_window: NaN")
        );
        assert!(err("[grid]\nbeta = [1, inf]").contains("grid.beta: inf is not a finite"));
        assert!(err("[protocol]\nsingle_lattice = [96]").contains("protocol.single_lattice: "));
        assert!(err("[protocol]\nprecision = \"f16\"").contains("unknown variant `f16`"));
        assert!(err("geometry = \"three\"").starts_with("f.toml: geometry: "));
    }

    #[test]
    fn axes_take_three_forms() {
        let f = read(
            "[grid]\nalpha = 0.1\nbeta = [10, 14.5]\nL = { from = 70, to = 90, step = 10 }",
            "f",
        )
        .unwrap();
        let g = grid(f.grid.unwrap(), "f").unwrap().0;
        assert_eq!(g.alpha, Some(AxisFile::One(0.1)));
        assert_eq!(g.beta, Some(AxisFile::List(vec![10.0, 14.5])));
        assert_eq!(
            g.L,
            Some(AxisFile::Range {
                from: 70.0,
                to: 90.0,
                step: 10.0
            })
        );
        assert_eq!(g.sigma, None);
    }

    #[test]
    fn params_default_and_refuse_the_axes() {
        let p = params(toml::from_str("tau = 100").unwrap(), "f").unwrap();
        assert_eq!(p.tau, 100.0);
        assert_eq!(p.R0, Params::default().R0);
        let e = params(toml::from_str("alpha = 0.1").unwrap(), "f").unwrap_err();
        assert!(e.to_string().contains("params.alpha: is a grid axis"));
        let e = params(toml::from_str("radius = 1").unwrap(), "f").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("f: params.radius: unknown parameter (known: d, R0,"));
        let e = params(toml::from_str("R0 = \"big\"").unwrap(), "f").unwrap_err();
        assert!(e.to_string().starts_with("f: params.R0: invalid type"));
    }
}
