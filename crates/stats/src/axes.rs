//! Where a point sits in its sweep: the paper's four axes (alpha, beta, L, sigma) and the
//! values of any other parameter the sweep varies ([`Others`]). One point's identity, and its
//! column's (every axis but beta), bit for bit as the sweep wrote them.

use std::fmt;

use serde::{Deserialize, Serialize};

/// The values of a sweep's other grid axes at one point, by SPEC name in the sweep's order
/// (geometry as 1 or 2). Empty for a sweep of the paper's four axes. Serialized as a map,
/// `{"E0": 1000.0}`, in that order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Others(pub Vec<(String, f64)>);

impl Serialize for Others {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl<'de> Deserialize<'de> for Others {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Others;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a map of parameter names to numbers")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut m: A) -> Result<Others, A::Error> {
                let mut out = Vec::new();
                while let Some((k, v)) = m.next_entry::<String, f64>()? {
                    out.push((k, v));
                }
                Ok(Others(out))
            }
        }
        d.deserialize_map(V)
    }
}

impl Others {
    /// No other axis.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The value of axis `name`, if the sweep varies it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// The values bit for bit, for keys.
    pub fn bits(&self) -> Vec<u64> {
        self.0.iter().map(|(_, v)| v.to_bits()).collect()
    }
}

/// `E0 = 1000, geometry = one` (empty for none).
impl fmt::Display for Others {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (name, v)) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            match (name.as_str(), *v) {
                ("geometry", 1.0) => write!(f, "geometry = one")?,
                ("geometry", 2.0) => write!(f, "geometry = two")?,
                _ => write!(f, "{name} = {v}")?,
            }
        }
        Ok(())
    }
}

/// A point's axes.
#[derive(Debug, Clone, PartialEq)]
#[allow(non_snake_case)]
pub struct Axes {
    pub alpha: f64,
    pub beta: f64,
    pub L: u32,
    pub sigma: f64,
    pub others: Others,
}

/// A point's identity: its axes bit for bit.
pub type PointKey = (u64, u64, u32, u64, Vec<u64>);
/// A column's identity: every axis but beta, bit for bit.
pub type ColumnKey = (u64, u32, u64, Vec<u64>);

/// The identity of the column at `alpha`, `L`, `sigma` and the other axes' values.
#[allow(non_snake_case)]
pub fn column_key(alpha: f64, L: u32, sigma: f64, others: &Others) -> ColumnKey {
    (alpha.to_bits(), L, sigma.to_bits(), others.bits())
}

impl Axes {
    /// The point (alpha, beta, L, sigma) of a sweep with no other axis.
    #[allow(non_snake_case)]
    pub fn new(alpha: f64, beta: f64, L: u32, sigma: f64) -> Axes {
        Axes {
            alpha,
            beta,
            L,
            sigma,
            others: Others::default(),
        }
    }

    /// The value of axis `name` (alpha, beta, L, sigma, or one of the others), if the point
    /// has it.
    pub fn value(&self, name: &str) -> Option<f64> {
        match name {
            "alpha" => Some(self.alpha),
            "beta" => Some(self.beta),
            "L" => Some(f64::from(self.L)),
            "sigma" => Some(self.sigma),
            other => self.others.get(other),
        }
    }

    /// The point's identity.
    pub fn key(&self) -> PointKey {
        (
            self.alpha.to_bits(),
            self.beta.to_bits(),
            self.L,
            self.sigma.to_bits(),
            self.others.bits(),
        )
    }

    /// The identity of the point's column (every axis but beta).
    pub fn column(&self) -> ColumnKey {
        column_key(self.alpha, self.L, self.sigma, &self.others)
    }
}

/// `alpha = 0.1, beta = 10, L = 90, sigma = 5` and any other axis after them.
impl fmt::Display for Axes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "alpha = {}, beta = {}, L = {}, sigma = {}",
            self.alpha, self.beta, self.L, self.sigma
        )?;
        if !self.others.is_empty() {
            write!(f, ", {}", self.others)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn other_axes_make_other_points_and_columns_and_read_as_written() {
        let a = Axes::new(0.1, 10.0, 90, 5.0);
        let mut b = a.clone();
        b.others = Others(vec![("E0".into(), 1000.0), ("geometry".into(), 1.0)]);
        assert_ne!(a.key(), b.key());
        assert_ne!(a.column(), b.column());
        let mut c = b.clone();
        c.beta = 14.0;
        assert_eq!(b.column(), c.column());
        assert_eq!(a.to_string(), "alpha = 0.1, beta = 10, L = 90, sigma = 5");
        assert_eq!(
            b.to_string(),
            "alpha = 0.1, beta = 10, L = 90, sigma = 5, E0 = 1000, geometry = one"
        );
        assert_eq!(b.others.get("E0"), Some(1000.0));
        assert_eq!(b.others.get("R0"), None);
        let json = serde_json::to_string(&b.others).unwrap();
        assert_eq!(json, r#"{"E0":1000.0,"geometry":1.0}"#);
        assert_eq!(serde_json::from_str::<Others>(&json).unwrap(), b.others);
    }
}
