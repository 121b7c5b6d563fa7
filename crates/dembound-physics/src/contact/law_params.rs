//! The normal laws' parameters as a configuration gives them, one
//! `contact.` key each (`contact.stiffness`, `contact.exponent`, …): the
//! keys, their symbols, units and ranges are read from the registry rows
//! ([`given_parameters`]), so that a schema names no parameter itself and
//! a new law's parameter is a key of every schema with no edit there.
//!
//! The target restitution is not one of them: it is a model-level key of
//! its own (`contact.restitution`, shared by Walton–Braun and the
//! dampings; [`super::registry::RESTITUTION`]).

use std::sync::OnceLock;

use super::registry::{ParamSpec, NORMAL_LAWS, RESTITUTION};

/// Most distinct parameter keys the registry may have ([`LawParams`] is a
/// fixed array, so that configurations holding it stay `Copy`); a test
/// checks the registry against it.
pub const MAX_GIVEN_PARAMETERS: usize = 8;

/// One parameter key of the normal laws, with every law that takes it.
#[derive(Debug, Clone, PartialEq)]
pub struct GivenParameter {
    /// The parameter as the first row that takes it declares it (key,
    /// symbol, unit, range).
    pub spec: ParamSpec,
    /// Each law taking it: the law's registry name and the parameter's
    /// unit there (`stiffness`: N/m for `hooke`, Pa for `hertz-kn`).
    pub laws: Vec<(&'static str, &'static str)>,
}

impl GivenParameter {
    /// The units with their laws: `N/m (hooke), Pa (hertz-kn)`, or the one
    /// unit when every law agrees.
    pub fn units(&self) -> String {
        if self.laws.iter().all(|(_, u)| *u == self.spec.unit) {
            return self.spec.unit.to_string();
        }
        self.laws
            .iter()
            .map(|(law, unit)| format!("{unit} ({law})"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Every parameter key of the registry's normal laws but the restitution,
/// in registry order, each once.
pub fn given_parameters() -> &'static [GivenParameter] {
    static PARAMETERS: OnceLock<Vec<GivenParameter>> = OnceLock::new();
    PARAMETERS.get_or_init(|| {
        let mut out: Vec<GivenParameter> = Vec::new();
        for row in NORMAL_LAWS {
            for p in row.params.iter().filter(|p| p.key != RESTITUTION.key) {
                match out.iter_mut().find(|g| g.spec.key == p.key) {
                    Some(g) => g.laws.push((row.name, p.unit)),
                    None => out.push(GivenParameter {
                        spec: *p,
                        laws: vec![(row.name, p.unit)],
                    }),
                }
            }
        }
        out
    })
}

/// The parameter of key `key`, if the registry has one.
pub fn given_parameter(key: &str) -> Option<(usize, &'static GivenParameter)> {
    given_parameters()
        .iter()
        .enumerate()
        .find(|(_, g)| g.spec.key == key)
}

/// Law parameter values given by key, as a configuration's `[contact]`
/// holds them (`stiffness = 1e5`). `Copy`; only registry keys can be
/// stored ([`LawParams::set`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LawParams {
    /// By index into [`given_parameters`].
    values: [Option<f64>; MAX_GIVEN_PARAMETERS],
}

impl LawParams {
    /// The value given for `key`, if any.
    pub fn get(&self, key: &str) -> Option<f64> {
        given_parameter(key).and_then(|(k, _)| self.values.get(k).copied().flatten())
    }

    /// Sets `key` to `value`; `false` (nothing stored) when `key` is not a
    /// parameter of the registry.
    pub fn set(&mut self, key: &str, value: f64) -> bool {
        match given_parameter(key).and_then(|(k, _)| self.values.get_mut(k)) {
            Some(slot) => {
                *slot = Some(value);
                true
            }
            None => false,
        }
    }

    /// The values given, with their keys, in registry order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        given_parameters()
            .iter()
            .zip(&self.values)
            .filter_map(|(g, v)| v.map(|v| (g.spec.key, v)))
    }

    /// Whether no value is given.
    pub fn is_empty(&self) -> bool {
        self.values.iter().all(Option::is_none)
    }
}

/// The law parameter keys, quoted and comma-separated (`` `exponent`,
/// `stiffness` ``): for the message of an unknown key.
pub fn given_keys() -> String {
    given_parameters()
        .iter()
        .map(|g| format!("`{}`", g.spec.key))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(feature = "serde")]
mod serde_impl {
    use super::{given_keys, LawParams};
    use serde::de::{self, MapAccess, Visitor};
    use serde::ser::SerializeMap;
    use std::fmt;

    /// As a map of the given keys to their values (flattened into the
    /// `[contact]` table: `stiffness = 1e5`).
    impl serde::Serialize for LawParams {
        fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
            let mut map = serializer.serialize_map(None)?;
            for (key, value) in self.iter() {
                map.serialize_entry(key, &value)?;
            }
            map.end()
        }
    }

    /// From a map whose keys are registry parameter keys; any other key is
    /// refused as an unknown field (the message names the section's law
    /// parameter keys).
    impl<'de> serde::Deserialize<'de> for LawParams {
        fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            struct Params;
            impl<'de> Visitor<'de> for Params {
                type Value = LawParams;
                fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                    write!(f, "law parameters by key ({})", given_keys())
                }
                fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<LawParams, A::Error> {
                    let mut params = LawParams::default();
                    while let Some(key) = map.next_key::<String>()? {
                        if super::given_parameter(&key).is_none() {
                            return Err(de::Error::custom(format!(
                                "unknown field `{key}`, expected a key of the section (`dembound \
                                 keys` lists them) or a law parameter of the registry ({})",
                                given_keys()
                            )));
                        }
                        let value: f64 = map.next_value().map_err(|e| {
                            de::Error::custom(format!(
                                "invalid value for law parameter `{key}`: {e}"
                            ))
                        })?;
                        params.set(&key, value);
                    }
                    Ok(params)
                }
            }
            deserializer.deserialize_map(Params)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_parameters_are_the_given_keys() {
        let keys: Vec<&str> = given_parameters().iter().map(|g| g.spec.key).collect();
        // Every row parameter but the restitution is a key, once.
        for row in NORMAL_LAWS {
            for p in row.params {
                assert_eq!(keys.contains(&p.key), p.key != RESTITUTION.key, "{}", p.key);
            }
        }
        let mut unique = keys.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), keys.len());
        assert!(keys.len() <= MAX_GIVEN_PARAMETERS);
        // `hooke` and `hertz-kn` share `stiffness` in different units.
        let (_, k) = given_parameter("stiffness").unwrap();
        assert_eq!(k.units(), "N/m (hooke), Pa (hertz-kn)");
        let (_, a) = given_parameter("exponent").unwrap();
        assert_eq!(a.units(), "1");
    }

    #[test]
    fn values_are_stored_only_under_registry_keys() {
        let mut p = LawParams::default();
        assert!(p.is_empty());
        assert!(p.set("stiffness", 1.0e5));
        assert!(!p.set("restitution", 0.5));
        assert!(!p.set("stifness", 1.0));
        assert_eq!(p.get("stiffness"), Some(1.0e5));
        assert_eq!(p.get("exponent"), None);
        assert_eq!(p.iter().collect::<Vec<_>>(), vec![("stiffness", 1.0e5)]);
    }
}
