//! Serde for f64 metrics that may be infinite or undefined. JSON has no infinity or NaN
//! (serde_json would write `null` and lose which one it was), so a finite value is written as
//! a number and the others as the strings `"inf"`, `"-inf"` and `"nan"`; reading accepts both.
//! CSV and Markdown output use the same spellings through [`format`](fn@format).

use serde::Serializer;
use serde::de::{self, Deserializer, Visitor};

/// Writes `v` as a number when it is finite, else as the string `"inf"`, `"-inf"` or
/// `"nan"` (use with `#[serde(with = "nonfinite")]`).
pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_str(spell(*v))
    }
}

/// Reads a number, or one of the strings `"inf"`, `"-inf"` and `"nan"`, as an f64.
pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    struct V;
    impl Visitor<'_> for V {
        type Value = f64;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a number or one of \"inf\", \"-inf\", \"nan\"")
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
            Ok(v)
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
            Ok(v as f64)
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
            Ok(v as f64)
        }
        fn visit_str<E: de::Error>(self, v: &str) -> Result<f64, E> {
            match v {
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                "nan" => Ok(f64::NAN),
                _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
            }
        }
    }
    d.deserialize_any(V)
}

fn spell(v: f64) -> &'static str {
    if v.is_nan() {
        "nan"
    } else if v > 0.0 {
        "inf"
    } else {
        "-inf"
    }
}

/// `v` with `decimals` digits, or its spelling when it is not finite.
pub fn format(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        spell(v).to_string()
    }
}

#[cfg(test)]
mod tests {
    #[derive(serde::Serialize, serde::Deserialize, Debug)]
    struct T {
        #[serde(with = "super")]
        v: f64,
    }

    #[test]
    fn round_trips_finite_and_non_finite_values() {
        for v in [0.5, f64::INFINITY, f64::NEG_INFINITY] {
            let s = serde_json::to_string(&T { v }).unwrap();
            assert_eq!(serde_json::from_str::<T>(&s).unwrap().v, v, "{s}");
        }
        assert_eq!(
            serde_json::to_string(&T { v: f64::INFINITY }).unwrap(),
            r#"{"v":"inf"}"#
        );
        assert!(
            serde_json::from_str::<T>(r#"{"v":"nan"}"#)
                .unwrap()
                .v
                .is_nan()
        );
        assert_eq!(super::format(f64::INFINITY, 2), "inf");
        assert_eq!(super::format(1.23456, 2), "1.23");
    }
}
