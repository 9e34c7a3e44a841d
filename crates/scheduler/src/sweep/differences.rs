//! What two sweeps do differently when they compute a trajectory: the parameters, protocol and
//! classifier settings that differ, each as `key: baseline -> variant`. How a convergence check
//! names its variant (dt halved, a wider pair lattice, f64 collisions, a finer lattice).

use serde_json::Value;

use super::Sweep;

impl Sweep {
    /// The settings of `variant` that differ from this sweep's, in the order params, protocol,
    /// classifier, as `(key, this value, variant's value)` (values in JSON).
    pub fn differences(&self, variant: &Sweep) -> Vec<(String, String, String)> {
        let mut out = Vec::new();
        let pairs = [
            ("", json(&self.params), json(&variant.params)),
            ("", protocol(self), protocol(variant)),
            (
                "classifier.",
                json(&self.classifier),
                json(&variant.classifier),
            ),
        ];
        for (prefix, a, b) in pairs {
            differ(prefix, &a, &b, &mut out);
        }
        if self.lattices_follow_r0 != variant.lattices_follow_r0 {
            out.push((
                "lattices_follow_r0".into(),
                self.lattices_follow_r0.to_string(),
                variant.lattices_follow_r0.to_string(),
            ));
        }
        out
    }
}

/// A sweep's protocol in JSON with its resolution always written (a stored definition leaves
/// k = 1 out, which would read as `resolution: null -> 2`).
fn protocol(sweep: &Sweep) -> Value {
    let mut v = json(&sweep.protocol);
    if let Value::Object(m) = &mut v {
        m.entry("resolution").or_insert(Value::from(1));
    }
    v
}

fn json<T: serde::Serialize>(v: &T) -> Value {
    serde_json::to_value(v).unwrap_or(Value::Null)
}

/// Every leaf where `a` and `b` differ, objects walked key by key.
fn differ(prefix: &str, a: &Value, b: &Value, out: &mut Vec<(String, String, String)>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let null = Value::Null;
                differ(
                    &format!("{prefix}{k}."),
                    x.get(k).unwrap_or(&null),
                    y.get(k).unwrap_or(&null),
                    out,
                );
            }
        }
        _ if a != b => out.push((
            prefix.trim_end_matches('.').to_string(),
            a.to_string(),
            b.to_string(),
        )),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use crate::Sweep;

    fn sweep(extra: &str) -> Sweep {
        Sweep::parse(
            &format!("name = \"s\"\nseed = 1\n[grid]\nalpha = [0.1]\nbeta = [10]\nL = [90]\nsigma = [5]\n{extra}"),
            "s.toml",
        )
        .unwrap()
    }

    #[test]
    fn only_what_changes_a_trajectory_is_named() {
        let base = sweep("");
        assert!(base.differences(&base).is_empty());
        let dt = sweep(
            "[params]\ndt = 0.001\n[protocol]\npair_lattice = [600, 200]\ncollide_time = 800\n",
        );
        let d = base.differences(&dt);
        let keys: Vec<&str> = d.iter().map(|(k, _, _)| k.as_str()).collect();
        assert_eq!(keys, ["dt", "collide_time", "pair_lattice"], "{d:?}");
        assert_eq!((d[0].1.as_str(), d[0].2.as_str()), ("0.002", "0.001"));
        assert_eq!(d[2].2, "[600,200]");
        // The seed, the grid and the replicates are not how a trajectory is computed.
        let other = sweep("").differences(&Sweep {
            seed: 9,
            replicates: 4,
            ..sweep("")
        });
        assert!(other.is_empty());
        // A finer lattice is named from the paper's resolution, which definitions leave out.
        let k2 = base.differences(&sweep("[protocol]\nresolution = 2\n"));
        assert_eq!(k2, [("resolution".into(), "1".into(), "2".into())]);
    }
}
