//! The boundary in both forms: the ratios r = R_b/R_m and ζ = E_b/E_m the
//! paper (and the core) work with, and the SI values R_b (m) and E_b (Pa)
//! a DEM user enters. Every report that shows r or ζ shows these beside.

use super::format::sig;
use dembound_core::bounce::Scenario;
use serde::Serialize;

/// R_b = r R_m, m (∞ for a half-space).
pub fn radius(s: &Scenario, r: f64) -> f64 {
    r * s.particle.radius
}

/// E_b = ζ E_m, Pa (∞ for a rigid boundary).
pub fn youngs_modulus(s: &Scenario, zeta: f64) -> f64 {
    zeta * s.particle.youngs_modulus
}

/// A value in SI for text: up to six significant digits, trailing zeros
/// dropped, scientific outside 1e−3 … 1e5; `∞` for infinity.
pub fn si_text(x: f64) -> String {
    if x.is_infinite() {
        return if x > 0.0 {
            "∞".into()
        } else {
            "−∞".into()
        };
    }
    let a = x.abs();
    if x == 0.0 || (1e-3..1e5).contains(&a) {
        let s = sig(x, 6);
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        let s = format!("{x:.5e}");
        match s.split_once('e') {
            Some((m, e)) => {
                let m = m.trim_end_matches('0').trim_end_matches('.');
                format!("{m}e{e}")
            }
            None => s,
        }
    }
}

/// "R_b = 0.05 m" or "R_b = ∞ (half-space)".
pub fn radius_text(x: f64) -> String {
    if x.is_infinite() {
        "R_b = ∞ m (half-space)".into()
    } else {
        format!("R_b = {} m", si_text(x))
    }
}

/// "E_b = 2e11 Pa" or "E_b = ∞ (rigid)".
pub fn modulus_text(x: f64) -> String {
    if x.is_infinite() {
        "E_b = ∞ Pa (rigid)".into()
    } else {
        format!("E_b = {} Pa", si_text(x))
    }
}

/// The line of a run's header that states the boundary in both forms.
pub fn header_line(s: &Scenario) -> String {
    let b = &s.boundary;
    let nu = b.poisson_ratio.unwrap_or(s.particle.poisson_ratio);
    format!(
        "boundary: r = {} ({}), ζ = {} ({}), ν_b = {}\n",
        ratio_text(b.radius_ratio),
        radius_text(radius(s, b.radius_ratio)),
        ratio_text(b.modulus_ratio),
        modulus_text(youngs_modulus(s, b.modulus_ratio)),
        nu
    )
}

/// A ratio for text: `∞` or up to six significant digits.
pub fn ratio_text(x: f64) -> String {
    si_text(x)
}

/// ∞ as "inf", as the scenario's ratios are written.
pub fn inf_as_text<S: serde::Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_infinite() && *x > 0.0 {
        s.serialize_str("inf")
    } else {
        s.serialize_f64(*x)
    }
}

/// The two SI values for JSON, beside r and ζ.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SiBoundary {
    /// R_b, m.
    #[serde(serialize_with = "inf_as_text")]
    pub boundary_radius: f64,
    /// E_b, Pa.
    #[serde(serialize_with = "inf_as_text")]
    pub boundary_youngs_modulus: f64,
}

impl SiBoundary {
    pub fn new(s: &Scenario, r: f64, zeta: f64) -> Self {
        SiBoundary {
            boundary_radius: radius(s, r),
            boundary_youngs_modulus: youngs_modulus(s, zeta),
        }
    }
}

/// Serialises a scenario with `boundary_radius` (m) and
/// `boundary_youngs_modulus` (Pa) added to its `boundary` object, beside
/// `radius_ratio` and `modulus_ratio` (for `serialize_with`).
pub fn serialize_scenario<S: serde::Serializer>(s: &&Scenario, ser: S) -> Result<S::Ok, S::Error> {
    use serde::ser::Error;
    let mut v = serde_json::to_value(*s).map_err(S::Error::custom)?;
    let si = SiBoundary::new(s, s.boundary.radius_ratio, s.boundary.modulus_ratio);
    let extra = serde_json::to_value(si).map_err(S::Error::custom)?;
    if let (Some(b), serde_json::Value::Object(extra)) =
        (v.get_mut("boundary").and_then(|b| b.as_object_mut()), extra)
    {
        b.extend(extra);
    }
    v.serialize(ser)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn si_text_is_short() {
        assert_eq!(si_text(0.05), "0.05");
        assert_eq!(si_text(2.0e11), "2e11");
        assert_eq!(si_text(6.3e10), "6.3e10");
        assert_eq!(si_text(100.0), "100");
        assert_eq!(si_text(f64::INFINITY), "∞");
        assert_eq!(si_text(1.234567e-5), "1.23457e-5");
    }

    #[test]
    fn the_json_scenario_carries_both_forms() {
        // Default: R_m = 0.5 mm, E_m = 1e10 Pa, r = ζ = 100.
        let s = Scenario::default();
        let v = serde_json::to_value(Wrapper { s: &s }).unwrap();
        let b = &v["s"]["boundary"];
        assert_eq!(b["radius_ratio"], 100.0);
        assert!((b["boundary_radius"].as_f64().unwrap() - 0.05).abs() < 1e-15);
        assert_eq!(b["boundary_youngs_modulus"], 1e12);
        let mut s = s;
        s.boundary.radius_ratio = f64::INFINITY;
        let v = serde_json::to_value(Wrapper { s: &s }).unwrap();
        assert_eq!(v["s"]["boundary"]["boundary_radius"], "inf");
    }

    #[derive(Serialize)]
    struct Wrapper<'a> {
        #[serde(serialize_with = "serialize_scenario")]
        s: &'a Scenario,
    }
}
