//! Serde for floats that may be NaN or infinite: JSON has no such numbers (serde_json writes
//! them as `null`, which then fails to read back as a float), so they travel as the strings
//! "NaN", "inf" and "-inf". Finite values stay plain numbers. A prep that blew up keeps its
//! NaN summaries in transit and in the store (`#[serde(with = "crate::nonfinite")]`).

use serde::{Deserialize, Deserializer, Serializer};

#[derive(Deserialize)]
#[serde(untagged)]
enum Wire {
    Number(f64),
    Text(String),
}

fn decode<E: serde::de::Error>(w: Wire) -> Result<f64, E> {
    match w {
        Wire::Number(x) => Ok(x),
        Wire::Text(s) => match s.as_str() {
            "NaN" => Ok(f64::NAN),
            "inf" => Ok(f64::INFINITY),
            "-inf" => Ok(f64::NEG_INFINITY),
            _ => Err(E::custom(format!("{s:?} is not a number"))),
        },
    }
}

fn text(x: f64) -> &'static str {
    if x.is_nan() {
        "NaN"
    } else if x > 0.0 {
        "inf"
    } else {
        "-inf"
    }
}

pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_str(text(*x))
    }
}

pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    decode(Wire::deserialize(d)?)
}

/// The same for `Option<f64>` (`None` is `null`).
pub mod option {
    use super::*;

    pub fn serialize<S: Serializer>(x: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match x {
            Some(x) => super::serialize(x, s),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        Option::<Wire>::deserialize(d)?.map(decode).transpose()
    }
}

#[cfg(test)]
mod tests {
    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct T {
        #[serde(with = "crate::nonfinite")]
        x: f64,
        #[serde(with = "crate::nonfinite::option")]
        y: Option<f64>,
    }

    #[test]
    fn non_finite_values_round_trip_through_json() {
        for x in [1.5, f64::INFINITY, f64::NEG_INFINITY] {
            let t = T { x, y: Some(x) };
            let back: T = serde_json::from_str(&serde_json::to_string(&t).unwrap()).unwrap();
            assert_eq!(back, t);
        }
        let json = serde_json::to_string(&T {
            x: f64::NAN,
            y: None,
        })
        .unwrap();
        assert_eq!(json, r#"{"x":"NaN","y":null}"#);
        let back: T = serde_json::from_str(&json).unwrap();
        assert!(back.x.is_nan() && back.y.is_none());
        assert!(serde_json::from_str::<T>(r#"{"x":"nope","y":null}"#).is_err());
    }
}
