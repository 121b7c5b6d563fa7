//! The bouncing-particle scenario: every input of a run (the schema, this
//! file), with the paper's validation case (section 4.2, ERRATA item 4) as
//! the default; the checks that turn bad input into an error naming the
//! field, the value and the allowed range (`validate.rs`, [`Error::Input`](crate::Error::Input),
//! with the ranges in [`limits`]); the two-body mechanics of a free
//! boundary (`two_body.rs`: masses, relative motion, each sphere's
//! velocities).
//!
//! Shared by the bounce simulator, the exact references and the studies;
//! it depends on none of them.

pub mod limits;
mod two_body;
mod validate;

use crate::contact::{
    Calibration, ContactLawKind, ContactModel, DampingKind, Dissipation, LawParams,
};
use crate::integrate::Scheme;
use crate::material::{Boundary, ContactPair, Particle};
use serde::{Deserialize, Serialize};
pub use two_body::TwoBody;

/// How the run advances in time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stepping {
    /// Free flight in closed form, onset solved exactly, only the contact integrated.
    Event,
    /// One constant Δt through the whole path (the paper's way); events are
    /// still located inside the step.
    Fixed,
}

/// `[particle]`: the mobile sphere.
pub type ParticleSection = Particle;

/// `[boundary]`: the boundary sphere, relative to the particle. Fixed by
/// default (the paper); `fixed = false` makes it a free sphere that the
/// particle meets head-on (see [`Scenario::two_body`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySection {
    /// r = R_b/R_m; `"inf"` for an elastic half-space.
    #[serde(with = "crate::serde_inf")]
    pub radius_ratio: f64,
    /// ζ = E_b/E_m; `"inf"` for a rigid boundary.
    #[serde(with = "crate::serde_inf")]
    pub modulus_ratio: f64,
    /// ν_b; omitted means the particle's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
    /// True (default): the boundary is held in place. False: a free sphere
    /// of mass ρ_b 4/3 π (r R_m)³ that moves under the contact force (and
    /// gravity, with `motion.gravity_on = "both"`).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub fixed: bool,
    /// ρ_b, kg/m³, of a free boundary; omitted means the particle's. Only
    /// with `fixed = false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Initial velocity of a free boundary, m/s, upward positive; omitted
    /// means 0. Only with `fixed = false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
}

fn yes() -> bool {
    true
}

fn is_true(x: &bool) -> bool {
    *x
}

/// Which spheres gravity acts on (TOML `motion.gravity_on`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GravityOn {
    /// The particle only (default; the paper's case). A free boundary then
    /// floats weightless and the pair feels g relative to each other.
    #[default]
    Particle,
    /// Both spheres (needs `boundary.fixed = false`): they fall together,
    /// and their relative motion feels no gravity at all.
    Both,
    /// Neither: `motion.gravity` is ignored.
    None,
}

impl GravityOn {
    pub fn name(&self) -> &'static str {
        match self {
            GravityOn::Particle => "particle",
            GravityOn::Both => "both",
            GravityOn::None => "none",
        }
    }
}

/// `[contact]`: the normal contact law and its dissipation. Every key but
/// `law` has a default, so elastic scenarios need only `law`. Unknown keys
/// are refused by [`LawParams`], which takes the rest of the table (a
/// flattened field cannot be combined with `deny_unknown_fields`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactSection {
    /// `"linear"`, `"hertz"`, `"walton-braun"`, `{ power = α }`, or any
    /// other law of the physics registry (`"hooke"`, `"hertz-kn"`).
    pub law: ContactLawKind,
    /// `"none"` (default), `"viscous"` (with `linear`), `"tsuji"` or
    /// `"viscoelastic"` (with `hertz`).
    #[serde(default, skip_serializing_if = "is_default")]
    pub damping: DampingKind,
    /// Target coefficient of restitution, 0 < e ≤ 1 (dissipative laws and
    /// Walton–Braun).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// Raw damping coefficient ≥ 0 instead of `restitution`: c in N s/m
    /// (viscous), γ in N s/m^(5/4) (tsuji), A in s (viscoelastic).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_coefficient: Option<f64>,
    /// Allow an attractive normal force (default false: F = max(F, 0)).
    /// No effect on the elastic laws, whose force is never negative.
    #[serde(default, skip_serializing_if = "is_default")]
    pub attractive: bool,
    /// How `restitution` becomes the damping coefficient: `"exact"` (the
    /// default when omitted: a gravity-free contact of the law as run,
    /// clamped or not, rebounds with exactly e) or `"formula"` (the
    /// published mapping, as LIGGGHTS/LAMMPS; see [`Calibration`]). No
    /// effect without `restitution` (a base scenario of `dembound
    /// restitution` sets it for the study's targets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<Calibration>,
    /// The registry laws' parameters, by the keys of their rows
    /// (`stiffness`: k_n, N/m for `"hooke"` (F = k_n h), Pa for
    /// `"hertz-kn"` (F = k_n √R_eff h^(3/2))).
    #[serde(flatten)]
    pub params: LawParams,
}

fn is_default<T: Default + PartialEq>(x: &T) -> bool {
    *x == T::default()
}

impl ContactSection {
    /// An elastic law with every other key at its default.
    pub fn elastic(law: ContactLawKind) -> Self {
        ContactSection {
            law,
            damping: DampingKind::None,
            restitution: None,
            damping_coefficient: None,
            attractive: false,
            calibration: None,
            params: LawParams::default(),
        }
    }

    /// The contact model these keys describe (unchecked; see [`Scenario::validate`]).
    pub fn model(&self) -> ContactModel {
        let dissipation = match (self.restitution, self.damping_coefficient) {
            (Some(e), _) => Some(Dissipation::Restitution(e)),
            (None, Some(c)) => Some(Dissipation::Coefficient(c)),
            (None, None) => None,
        };
        ContactModel {
            law: self.law,
            damping: self.damping,
            dissipation,
            attractive: self.attractive,
            calibration: self.calibration.unwrap_or_default(),
            params: self.params,
        }
    }
}

/// `[motion]`: initial conditions and how long to run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motion {
    /// Initial distance between the surfaces, m.
    pub gap: f64,
    /// Initial velocity, m/s, upward positive.
    pub velocity: f64,
    /// Gravitational acceleration g, m/s², acting downward.
    pub gravity: f64,
    /// Number of rebounds after which the run stops.
    pub contacts: u32,
    /// Which spheres gravity acts on: `"particle"` (default), `"both"`
    /// (free boundary only) or `"none"`.
    #[serde(default, skip_serializing_if = "is_default")]
    pub gravity_on: GravityOn,
}

/// `[integration]`: scheme, step and stepping mode.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Integration {
    pub scheme: Scheme,
    /// Δt = η T_c, with T_c the law's contact-time estimate at the first
    /// impact speed. Give either `eta` or `dt`; neither means η = 1/50.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<f64>,
    /// Δt in seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Accuracy target instead of `eta` or `dt`: the largest relative error
    /// wanted in h_max, T_c and v_r of a contact; Δt is then chosen from
    /// pilot runs of the first contact (see [`crate::bounce::tolerance`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    pub stepping: Stepping,
}

/// Range of `integration.tolerance`.
pub const MIN_TOLERANCE: f64 = 1e-13;
pub const MAX_TOLERANCE: f64 = 1e-2;

/// The paper's choice η₂ = 1/50 (section 4.2).
pub const DEFAULT_ETA: f64 = 0.02;

/// Everything a run needs. `Default` is the paper's validation case.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub particle: ParticleSection,
    pub boundary: BoundarySection,
    pub contact: ContactSection,
    pub motion: Motion,
    pub integration: Integration,
}

impl Default for Scenario {
    /// The paper's validation case (section 4.2 with ERRATA item 4): c² = 1e7
    /// m²/s², ν = 0.3, R_m = 0.5 mm, r = ζ = 100, a 5 mm gap dropped from rest
    /// under g = 9.81 m/s², Hertz, Gear5, η = 1/50, event stepping, 2 contacts.
    fn default() -> Self {
        Scenario {
            particle: Particle::PAPER,
            boundary: BoundarySection {
                radius_ratio: 100.0,
                modulus_ratio: 100.0,
                poisson_ratio: None,
                fixed: true,
                density: None,
                velocity: None,
            },
            contact: ContactSection::elastic(ContactLawKind::Hertz),
            motion: Motion {
                gap: 5.0e-3,
                velocity: 0.0,
                gravity: 9.81,
                contacts: 2,
                gravity_on: GravityOn::Particle,
            },
            integration: Integration {
                scheme: Scheme::Gear5,
                eta: None,
                dt: None,
                tolerance: None,
                stepping: Stepping::Event,
            },
        }
    }
}

/// How Δt is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepRule {
    /// Δt = η · T_c estimate.
    Fraction(f64),
    /// Δt given, s.
    Fixed(f64),
    /// Δt chosen for a relative accuracy target.
    Tolerance(f64),
}

impl Scenario {
    /// The particle–boundary pair.
    pub fn pair(&self) -> ContactPair {
        ContactPair::new(
            self.particle,
            Boundary {
                radius_ratio: self.boundary.radius_ratio,
                modulus_ratio: self.boundary.modulus_ratio,
                poisson_ratio: self.boundary.poisson_ratio,
            },
        )
    }

    /// How Δt is chosen.
    pub fn step_rule(&self) -> StepRule {
        if let Some(tol) = self.integration.tolerance {
            return StepRule::Tolerance(tol);
        }
        match (self.integration.dt, self.integration.eta) {
            (Some(dt), _) => StepRule::Fixed(dt),
            (None, eta) => StepRule::Fraction(eta.unwrap_or(DEFAULT_ETA)),
        }
    }

    /// The scenario with every default written out (η when no Δt is given;
    /// a free boundary's density and velocity).
    pub fn resolved(&self) -> Scenario {
        let mut s = *self;
        if s.integration.dt.is_none()
            && s.integration.eta.is_none()
            && s.integration.tolerance.is_none()
        {
            s.integration.eta = Some(DEFAULT_ETA);
        }
        if !s.boundary.fixed {
            s.boundary.density.get_or_insert(s.particle.density);
            s.boundary.velocity.get_or_insert(0.0);
        }
        s
    }
}
