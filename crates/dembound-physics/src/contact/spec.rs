//! A contact model given by names and values, as a configuration file
//! spells it, checked against the registry ([`ContactModel::from_spec`]).

use super::registry::{self, DampingKind};
use super::{Calibration, ContactModel, Damping, Dissipation, NormalLaw};
use crate::error::PhysicsError;

/// A contact model by names and values (keys under `contact.`).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSpec {
    /// `law`: a normal law's registry name (`"linear"`, `"hertz"`,
    /// `"power"`, `"walton-braun"`, …).
    pub law: String,
    /// The law's parameters by key (`exponent` for `"power"`, …); a
    /// parameter may also come from the model-level key of the same name
    /// (`restitution` for `"walton-braun"`).
    pub law_params: Vec<(String, f64)>,
    /// `damping`: a damping model's registry name; `"none"` by default.
    pub damping: String,
    /// `restitution`: target restitution e.
    pub restitution: Option<f64>,
    /// `damping_coefficient`: the damping model's raw coefficient.
    pub damping_coefficient: Option<f64>,
    /// `calibration`: `"exact"` (default) or `"formula"`.
    pub calibration: String,
    /// `attractive`: let the force pull (no clamp); `false` by default.
    pub attractive: bool,
    /// `reference_speed`: impact speed (m/s) of a speed-dependent calibration.
    pub reference_speed: Option<f64>,
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            law: "hertz".into(),
            law_params: Vec::new(),
            damping: "none".into(),
            restitution: None,
            damping_coefficient: None,
            calibration: Calibration::Exact.name().into(),
            attractive: false,
            reference_speed: None,
        }
    }
}

impl ContactSpec {
    /// A spec of law `law` with the defaults otherwise.
    pub fn law(law: &str) -> Self {
        Self {
            law: law.into(),
            ..Self::default()
        }
    }

    /// `law = { name = value }`: the law `name` with `value` as its first
    /// parameter (`{ power = 1.25 }` is the power law with α = 1.25).
    pub fn law_with_value(name: &str, value: f64) -> Self {
        let key = registry::normal_row(name)
            .and_then(|r| r.params.first())
            .map_or(name, |p| p.key);
        Self {
            law_params: vec![(key.into(), value)],
            ..Self::law(name)
        }
    }
}

impl ContactModel {
    /// The model `spec` describes, checked against the registry: unknown
    /// names, missing or out-of-range parameters, a damping that does not
    /// combine with the law, both a restitution and a coefficient — each an
    /// error naming the key, the value and what is allowed.
    pub fn from_spec(spec: &ContactSpec) -> Result<ContactModel, PhysicsError> {
        let quoted = |s: &str| format!("\"{s}\"");
        let row = registry::normal_row(&spec.law).ok_or_else(|| {
            PhysicsError::new(
                "contact.law",
                quoted(&spec.law),
                format!("one of {}", registry::normal_names()),
            )
        })?;
        for (n, (key, value)) in spec.law_params.iter().enumerate() {
            if spec.law_params[..n].iter().any(|(k, _)| k == key) {
                return Err(PhysicsError::new(
                    format!("contact.{key}"),
                    value,
                    format!("given once (law = {{ {} = … }} gives it already)", row.name),
                ));
            }
            if !row.params.iter().any(|p| p.key == key) {
                let allowed = if row.params.is_empty() {
                    format!("no parameters for law = \"{}\"", row.name)
                } else {
                    let keys: Vec<&str> = row.params.iter().map(|p| p.key).collect();
                    format!("one of {} for law = \"{}\"", keys.join(", "), row.name)
                };
                return Err(PhysicsError::new(format!("contact.{key}"), value, allowed));
            }
        }
        let mut used_restitution = false;
        let mut params = Vec::with_capacity(row.params.len());
        for p in row.params {
            let given = spec
                .law_params
                .iter()
                .find(|(k, _)| k == p.key)
                .map(|kv| kv.1);
            let value = match given {
                Some(v) => v,
                None if p.key == registry::RESTITUTION.key && spec.restitution.is_some() => {
                    used_restitution = true;
                    spec.restitution.unwrap_or(f64::NAN)
                }
                None => {
                    return Err(PhysicsError::new(
                        format!("contact.{}", p.key),
                        "missing",
                        format!(
                            "{} ({}, {}), required by law = \"{}\"",
                            p.range, p.symbol, p.unit, row.name
                        ),
                    ))
                }
            };
            params.push(p.check(value)?);
        }
        let normal = NormalLaw::from_params(row.name, &params).ok_or_else(|| {
            PhysicsError::new(
                "contact.law",
                quoted(&spec.law),
                "a complete parameter list",
            )
        })?;
        let kind = DampingKind::from_name(&spec.damping).ok_or_else(|| {
            PhysicsError::new(
                "contact.damping",
                quoted(&spec.damping),
                format!("one of {}", registry::damping_names()),
            )
        })?;
        let calibration = Calibration::from_name(&spec.calibration).ok_or_else(|| {
            PhysicsError::new(
                "contact.calibration",
                quoted(&spec.calibration),
                "\"exact\" or \"formula\"",
            )
        })?;
        let restitution = if used_restitution {
            None
        } else {
            spec.restitution
        };
        let dissipation = match (restitution, spec.damping_coefficient) {
            (Some(_), Some(c)) => {
                return Err(PhysicsError::new(
                    "contact.damping_coefficient",
                    c,
                    "absent when contact.restitution is given (give one of them)",
                ))
            }
            (Some(e), None) => Some(Dissipation::Restitution(e)),
            (None, Some(c)) => Some(Dissipation::Coefficient(c)),
            (None, None) => None,
        };
        let mut damping = match dissipation {
            Some(d) => Damping::new(kind, d),
            None => Damping {
                kind,
                ..Damping::NONE
            },
        };
        if let Some(v) = spec.reference_speed {
            damping = damping.with_reference_speed(v);
        }
        let model = ContactModel {
            normal,
            attractive: spec.attractive,
            damping,
            calibration,
        };
        model.validate()?;
        Ok(model)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(spec: &ContactSpec) -> PhysicsError {
        ContactModel::from_spec(spec).expect_err("invalid spec")
    }

    #[test]
    fn specs_round_trip_to_models() {
        let m = ContactModel::from_spec(&ContactSpec::law("hertz")).unwrap();
        assert_eq!(m, ContactModel::elastic(NormalLaw::Hertz));
        let m = ContactModel::from_spec(&ContactSpec::law_with_value("power", 1.25)).unwrap();
        assert_eq!(m.normal, NormalLaw::Power { exponent: 1.25 });
        assert_eq!(m.label(), "power (α = 1.25)");
        // Walton–Braun takes its e from the model-level key, as the CLI
        // spells it; it is then the law's parameter, not a damping.
        let spec = ContactSpec {
            restitution: Some(0.7),
            ..ContactSpec::law("walton-braun")
        };
        let m = ContactModel::from_spec(&spec).unwrap();
        assert_eq!(m.normal, NormalLaw::WaltonBraun { restitution: 0.7 });
        assert_eq!(m.damping, Damping::NONE);
        let spec = ContactSpec {
            damping: "viscous".into(),
            restitution: Some(0.5),
            calibration: "formula".into(),
            attractive: true,
            ..ContactSpec::law("linear")
        };
        let m = ContactModel::from_spec(&spec).unwrap();
        assert_eq!(m.damping.kind(), DampingKind::Viscous);
        assert_eq!(m.damping.dissipation(), Some(Dissipation::Restitution(0.5)));
        assert_eq!(m.calibration, Calibration::Formula);
        assert!(m.attractive && m.depends_on_rate());
        assert_eq!(m.label(), "linear + viscous");
    }

    #[test]
    fn errors_name_key_value_and_range() {
        let e = err(&ContactSpec::law("hooke-like"));
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.law", "\"hooke-like\"")
        );
        assert!(e.allowed.contains("\"walton-braun\""), "{e}");

        let e = err(&ContactSpec::law_with_value("power", 3.5));
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.exponent", "3.5")
        );
        assert!(e.allowed.contains("1 ≤ x ≤ 3"), "{e}");

        let e = err(&ContactSpec::law("power"));
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.exponent", "missing")
        );

        let e = err(&ContactSpec::law("walton-braun"));
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.restitution", "missing")
        );

        let e = err(&ContactSpec {
            law_params: vec![("exponent".into(), 2.0)],
            ..ContactSpec::law("hertz")
        });
        assert_eq!(e.key, "contact.exponent");
        assert!(e.allowed.contains("no parameters"), "{e}");

        // A parameter given twice (`law = { hooke = … }` and the key):
        // refused, not one of them silently dropped.
        let mut spec = ContactSpec::law_with_value("hooke", 1.0e5);
        spec.law_params.push(("stiffness".into(), 2.0e5));
        let e = err(&spec);
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.stiffness", "200000")
        );
        assert!(e.allowed.contains("given once"), "{e}");

        let e = err(&ContactSpec {
            damping: "viscous".into(),
            restitution: Some(0.5),
            ..ContactSpec::law("hertz")
        });
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.damping", "\"viscous\"")
        );
        assert!(e.allowed.contains("\"tsuji\""), "{e}");

        let e = err(&ContactSpec {
            damping: "tsuji".into(),
            ..ContactSpec::law("hertz")
        });
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.restitution", "missing")
        );

        let e = err(&ContactSpec {
            damping: "tsuji".into(),
            restitution: Some(0.5),
            damping_coefficient: Some(1.0),
            ..ContactSpec::law("hertz")
        });
        assert_eq!(e.key, "contact.damping_coefficient");

        let e = err(&ContactSpec {
            damping: "tsuji".into(),
            restitution: Some(1.2),
            ..ContactSpec::law("hertz")
        });
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.restitution", "1.2")
        );

        let e = err(&ContactSpec {
            damping: "tsuji".into(),
            damping_coefficient: Some(-1.0),
            ..ContactSpec::law("hertz")
        });
        assert_eq!(e.key, "contact.damping_coefficient");
        assert!(e.allowed.contains("N s/m^(5/4)"), "{e}");

        let e = err(&ContactSpec {
            restitution: Some(0.5),
            ..ContactSpec::law("linear")
        });
        assert_eq!(e.key, "contact.restitution");
        assert!(e.allowed.contains("absent"), "{e}");

        let e = err(&ContactSpec {
            damping: "dashpot".into(),
            ..ContactSpec::law("linear")
        });
        assert_eq!(e.key, "contact.damping");

        let e = err(&ContactSpec {
            calibration: "closest".into(),
            ..ContactSpec::law("linear")
        });
        assert_eq!(e.key, "contact.calibration");

        let e = err(&ContactSpec {
            damping: "viscoelastic".into(),
            restitution: Some(0.9),
            calibration: "formula".into(),
            ..ContactSpec::law("hertz")
        });
        assert_eq!(
            (e.key.as_str(), e.value.as_str()),
            ("contact.reference_speed", "missing")
        );
    }
}
