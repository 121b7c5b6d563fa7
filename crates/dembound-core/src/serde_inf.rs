//! (De)serialises a ratio that may be infinite: a number, or the string
//! `"inf"` (also `"infinity"`, any case). TOML's own `inf` float is accepted
//! too. Infinite values are written back as `"inf"`.

use serde::{de, Deserializer, Serializer};
use std::fmt;

pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_infinite() && *x > 0.0 {
        s.serialize_str("inf")
    } else {
        s.serialize_f64(*x)
    }
}

pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    struct V;
    impl de::Visitor<'_> for V {
        type Value = f64;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("a positive number or \"inf\"")
        }
        fn visit_f64<E: de::Error>(self, x: f64) -> Result<f64, E> {
            Ok(x)
        }
        fn visit_i64<E: de::Error>(self, x: i64) -> Result<f64, E> {
            Ok(x as f64)
        }
        fn visit_u64<E: de::Error>(self, x: u64) -> Result<f64, E> {
            Ok(x as f64)
        }
        fn visit_str<E: de::Error>(self, s: &str) -> Result<f64, E> {
            match s.trim().to_ascii_lowercase().as_str() {
                "inf" | "+inf" | "infinity" | "+infinity" => Ok(f64::INFINITY),
                other => other.parse::<f64>().map_err(|_| {
                    E::custom(format!(
                        "expected a positive number or \"inf\", found \"{s}\""
                    ))
                }),
            }
        }
    }
    d.deserialize_any(V)
}
