//! Studies built on the scenario and the exact references: the paper's
//! validation (Tables 1–2) and convergence in the time step, the parametric
//! sweep over the boundary (section 5), the paper's indicators and
//! convergence laws (eqs 32–33), and recommended boundary parameters; the restitution study of the dissipative
//! laws against boundary particles; `paper`, all of the paper's section 5
//! reproduction that is computed (cases, quoted numbers, scaling).

pub mod indicators;
mod longest_first;
pub mod paper;
pub mod recommend;
pub mod restitution;
pub mod sweep;
pub mod validation;

use crate::bounce::ContactRecord;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::fmt;

/// A per-contact quantity whose approach to the rigid half-space is studied.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Maximum overlap h_max, m.
    MaxOverlap,
    /// Contact duration T_c, s.
    Duration,
    /// Maximum net acceleration a_max, m/s² (gravity included).
    MaxAcceleration,
}

impl Quantity {
    /// The three quantities of the paper's conclusions, in this order.
    pub const ALL: [Quantity; 3] = [
        Quantity::MaxOverlap,
        Quantity::Duration,
        Quantity::MaxAcceleration,
    ];

    /// The quantity's value in a contact record (SI).
    pub fn of(&self, c: &ContactRecord) -> f64 {
        match self {
            Quantity::MaxOverlap => c.max_overlap,
            Quantity::Duration => c.duration,
            Quantity::MaxAcceleration => c.max_acceleration,
        }
    }

    /// The key used in files and on the command line.
    pub fn key(&self) -> &'static str {
        match self {
            Quantity::MaxOverlap => "max_overlap",
            Quantity::Duration => "duration",
            Quantity::MaxAcceleration => "max_acceleration",
        }
    }

    /// The paper's symbol.
    pub fn symbol(&self) -> &'static str {
        match self {
            Quantity::MaxOverlap => "h_max",
            Quantity::Duration => "T_c",
            Quantity::MaxAcceleration => "a_max",
        }
    }

    /// Reads a key or symbol (`max_overlap`/`h_max`, `duration`/`T_c`/`contact_time`,
    /// `max_acceleration`/`a_max`), any case.
    pub fn parse(s: &str) -> Option<Quantity> {
        match s.trim().to_ascii_lowercase().as_str() {
            "max_overlap" | "h_max" | "hmax" | "overlap" => Some(Quantity::MaxOverlap),
            "duration" | "t_c" | "tc" | "contact_time" => Some(Quantity::Duration),
            "max_acceleration" | "a_max" | "amax" | "acceleration" => {
                Some(Quantity::MaxAcceleration)
            }
            _ => None,
        }
    }

    /// Gravity-free exponent of q/q(∞, ∞) in ζ̄ (ERRATA 16): −1/(α+1) for
    /// h_max and T_c, +1/(α+1) for a_max.
    pub fn modulus_exponent(&self, alpha: f64) -> f64 {
        self.sign() / (alpha + 1.0)
    }

    /// Gravity-free exponent of q/q(∞, ∞) in r̄ (ERRATA 16): −(2−α)/(α+1)
    /// for h_max and T_c, +(2−α)/(α+1) for a_max.
    pub fn radius_exponent(&self, alpha: f64) -> f64 {
        self.sign() * (2.0 - alpha) / (alpha + 1.0)
    }

    /// Exponent in the axis' barred ratio (ζ̄ or r̄).
    pub fn exponent(&self, axis: Axis, alpha: f64) -> f64 {
        match axis {
            Axis::Modulus => self.modulus_exponent(alpha),
            Axis::Radius => self.radius_exponent(alpha),
        }
    }

    fn sign(&self) -> f64 {
        match self {
            Quantity::MaxAcceleration => 1.0,
            _ => -1.0,
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.key())
    }
}

/// One of the two boundary parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// r = R_b/R_m (`boundary.radius_ratio`).
    Radius,
    /// ζ = E_b/E_m (`boundary.modulus_ratio`).
    Modulus,
}

impl Axis {
    /// The paper's symbol.
    pub fn symbol(&self) -> &'static str {
        match self {
            Axis::Radius => "r",
            Axis::Modulus => "ζ",
        }
    }

    /// The scenario field.
    pub fn field(&self) -> &'static str {
        match self {
            Axis::Radius => "boundary.radius_ratio",
            Axis::Modulus => "boundary.modulus_ratio",
        }
    }

    /// The other parameter.
    pub fn other(&self) -> Axis {
        match self {
            Axis::Radius => Axis::Modulus,
            Axis::Modulus => Axis::Radius,
        }
    }

    /// Sets this parameter in a scenario.
    pub fn set(&self, s: &mut crate::bounce::Scenario, value: f64) {
        match self {
            Axis::Radius => s.boundary.radius_ratio = value,
            Axis::Modulus => s.boundary.modulus_ratio = value,
        }
    }

    /// This parameter of a scenario.
    pub fn get(&self, s: &crate::bounce::Scenario) -> f64 {
        match self {
            Axis::Radius => s.boundary.radius_ratio,
            Axis::Modulus => s.boundary.modulus_ratio,
        }
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// Where a quantity comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Model {
    /// The exact reference ([`crate::exact`]).
    Exact,
    /// The integrator, as the scenario asks (scheme, Δt, stepping).
    Simulated,
}

/// The first contact of a scenario, exact or integrated.
pub fn first_contact(s: &crate::bounce::Scenario, model: Model) -> Result<ContactRecord> {
    let mut s = *s;
    s.motion.contacts = 1;
    let contacts = match model {
        Model::Exact => crate::exact::scenario_contacts(&s).map_err(Error::exact)?,
        Model::Simulated => {
            crate::bounce::simulate(&s, &mut ())
                .map_err(Error::simulation)?
                .contacts
        }
    };
    contacts
        .into_iter()
        .next()
        .ok_or(Error::exact(Error::Numerical("no contact")))
}

/// The scenario with gravity switched off and the same impact speed: the
/// particle starts at the surface moving down at √(v₀² + 2 g H₀), one contact.
/// The gravity-free theory of ERRATA 16 is exact for it.
pub fn gravity_free(s: &crate::bounce::Scenario) -> crate::bounce::Scenario {
    let mut g = *s;
    g.motion.velocity = -s.impact_speed();
    g.motion.gap = 0.0;
    g.motion.gravity = 0.0;
    g.motion.contacts = 1;
    g
}

/// `x/(x+1)`, 1 at infinity (eq 14).
pub fn bar(x: f64) -> f64 {
    crate::material::bar(x)
}

/// `x` with `digits` significant digits, for the text a study writes
/// (labels, notes): fixed notation for moderate magnitudes, scientific
/// otherwise.
pub fn sig(x: f64, digits: usize) -> String {
    let digits = digits.max(1);
    if !x.is_finite() {
        return x.to_string();
    }
    if x == 0.0 {
        return "0".into();
    }
    let exponent = x.abs().log10().floor() as i32;
    if (-4..=9).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{:.*e}", digits - 1, x)
    }
}

/// A ratio for tables and labels: `∞` or the shortest number (4
/// significant digits when the shortest is long).
pub fn show(x: f64) -> String {
    if x.is_infinite() {
        "∞".into()
    } else {
        let s = format!("{x}");
        if s.len() > 8 {
            sig(x, 4)
        } else {
            s
        }
    }
}
