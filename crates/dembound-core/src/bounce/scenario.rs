//! The bouncing-particle scenario: every input of a run, with the paper's
//! validation case (section 4.2, ERRATA item 4) as the default, and the
//! checks that turn bad input into an error naming the field, the value and
//! the allowed range.

use super::limits;
use crate::contact::{Calibration, ContactLawKind, ContactModel, DampingKind, Dissipation};
use crate::integrate::Scheme;
use crate::material::{Boundary, ContactPair, Particle};
use serde::{Deserialize, Serialize};
use std::fmt;

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

/// The two spheres of a free-boundary run, for recovering each sphere's
/// motion from the relative coordinate: the centre of mass moves
/// ballistically (the contact force is internal), so with the relative
/// velocity v = v_m − v_b, v_m = V + (m_b/M) v and v_b = V − (m_m/M) v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoBody {
    /// m_m, kg.
    pub particle_mass: f64,
    /// m_b, kg.
    pub boundary_mass: f64,
    /// Centre-of-mass velocity at t = 0, m/s, upward positive.
    pub cm_velocity: f64,
    /// Its constant acceleration, m/s² (−g, −g m_m/M or 0).
    pub cm_acceleration: f64,
}

impl TwoBody {
    /// (v_m, v_b) at time `t` (s) for the relative velocity `relative` (m/s).
    pub fn velocities(&self, t: f64, relative: f64) -> (f64, f64) {
        let total = self.particle_mass + self.boundary_mass;
        let cm = self.cm_velocity + self.cm_acceleration * t;
        (
            cm + self.boundary_mass / total * relative,
            cm - self.particle_mass / total * relative,
        )
    }
}

/// `[contact]`: the normal contact law and its dissipation. Every key but
/// `law` has a default, so elastic scenarios need only `law`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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
    /// k_n of the registry laws that take a given stiffness: N/m for
    /// `"hooke"` (F = k_n h), Pa for `"hertz-kn"` (F = k_n √R_eff h^(3/2)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
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
            stiffness: None,
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
            stiffness: self.stiffness,
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

/// A field with a value outside its allowed range.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// `section.key`.
    pub field: String,
    /// The offending value as the user wrote it.
    pub value: String,
    /// The allowed range or set, with units.
    pub allowed: String,
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid value for `{}`: {} (allowed: {})",
            self.field, self.value, self.allowed
        )
    }
}

impl std::error::Error for InputError {}

/// `value` and `allowed` are formatted only when the check fails: the
/// batched sweep validates every case, and formatting the ranges of every
/// key each time cost ~50k instructions a case (76 % of the batched path).
fn check(
    ok: bool,
    field: &str,
    value: impl fmt::Display,
    allowed: impl fmt::Display,
) -> Result<(), InputError> {
    if ok {
        Ok(())
    } else {
        Err(InputError {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        })
    }
}

fn positive(field: &str, x: f64, unit: &str) -> Result<(), InputError> {
    if x.is_finite() && x > 0.0 {
        return Ok(());
    }
    check(
        false,
        field,
        limits::Shown(x),
        format_args!("finite and > 0, in {unit}"),
    )
}

/// `range.0 ≤ x ≤ range.1` ([`limits`]).
fn within(field: &str, x: f64, range: (f64, f64), unit: &str) -> Result<(), InputError> {
    check(
        x >= range.0 && x <= range.1,
        field,
        limits::Shown(x),
        limits::Described(range, unit),
    )
}

fn ratio(field: &str, x: f64) -> Result<(), InputError> {
    check(
        x == f64::INFINITY || (x >= limits::RATIO.0 && x <= limits::RATIO.1),
        field,
        limits::Shown(x),
        format_args!("{}, or \"inf\"", limits::Described(limits::RATIO, "")),
    )
}

fn poisson(field: &str, x: f64) -> Result<(), InputError> {
    check(x > -1.0 && x < 0.5, field, x, "-1 < ν < 0.5")
}

impl Scenario {
    /// Checks every field; the first error names the field, value and range.
    pub fn validate(&self) -> Result<(), InputError> {
        let p = &self.particle;
        within("particle.radius", p.radius, limits::RADIUS, "m")?;
        within("particle.density", p.density, limits::DENSITY, "kg/m³")?;
        within(
            "particle.youngs_modulus",
            p.youngs_modulus,
            limits::YOUNGS_MODULUS,
            "Pa",
        )?;
        poisson("particle.poisson_ratio", p.poisson_ratio)?;
        let b = &self.boundary;
        ratio("boundary.radius_ratio", b.radius_ratio)?;
        ratio("boundary.modulus_ratio", b.modulus_ratio)?;
        if let Some(nu) = b.poisson_ratio {
            poisson("boundary.poisson_ratio", nu)?;
        }
        self.validate_free_boundary()?;
        if let ContactLawKind::Power(alpha) = self.contact.law {
            check(
                (1.0..=3.0).contains(&alpha),
                "contact.law.power",
                alpha,
                "1 ≤ α ≤ 3",
            )?;
        }
        self.validate_contact()?;
        let m = &self.motion;
        within("motion.gap", m.gap, limits::GAP, "m")?;
        check(
            m.velocity.abs() <= limits::MAX_SPEED,
            "motion.velocity",
            limits::Shown(m.velocity),
            format_args!("-{0:e} to {0:e} m/s", limits::MAX_SPEED),
        )?;
        check(
            m.gravity == 0.0 || (m.gravity >= limits::GRAVITY.0 && m.gravity <= limits::GRAVITY.1),
            "motion.gravity",
            limits::Shown(m.gravity),
            format_args!("0, or {}", limits::Described(limits::GRAVITY, "m/s²")),
        )?;
        check(
            (1..=1_000_000).contains(&m.contacts),
            "motion.contacts",
            m.contacts,
            "1 to 1000000",
        )?;
        if self.relative_gravity() == 0.0 {
            let why = match m.gravity_on {
                GravityOn::Particle => "when motion.gravity = 0",
                GravityOn::Both => {
                    "when motion.gravity_on = \"both\" (no gravity in the relative motion)"
                }
                GravityOn::None => "when motion.gravity_on = \"none\"",
            };
            if b.fixed {
                check(
                    m.velocity < 0.0,
                    "motion.velocity",
                    m.velocity,
                    format_args!("< 0 (moving towards the boundary) {why}"),
                )?;
            } else {
                check(
                    self.relative_velocity() < 0.0,
                    "motion.velocity",
                    m.velocity,
                    format_args!(
                        "< boundary.velocity = {} (the spheres approaching) {why}",
                        b.velocity.unwrap_or(0.0)
                    ),
                )?;
            }
            check(
                m.contacts == 1,
                "motion.contacts",
                m.contacts,
                format_args!("1 {why} (the spheres never meet again)"),
            )?;
        }
        let i = &self.integration;
        if let Some(eta) = i.eta {
            check(
                eta >= limits::ETA.0 && eta <= limits::ETA.1,
                "integration.eta",
                limits::Shown(eta),
                format_args!(
                    "{} (Δt = η T_c; above 0.1 the first contact's e, h_max, T_c are off by more \
                     than ~1 % and from 0.125 the integrator diverges)",
                    limits::Described(limits::ETA, "")
                ),
            )?;
        }
        if let Some(dt) = i.dt {
            positive("integration.dt", dt, "s")?;
            check(
                i.eta.is_none(),
                "integration.eta",
                i.eta.unwrap_or(0.0),
                "absent when integration.dt is given (give one of them)",
            )?;
        }
        if let Some(tol) = i.tolerance {
            check(
                (MIN_TOLERANCE..=MAX_TOLERANCE).contains(&tol),
                "integration.tolerance",
                tol,
                "1e-13 ≤ tolerance ≤ 0.01 (a relative error as a plain fraction: 0.01 = 1 %)",
            )?;
            check(
                i.eta.is_none() && i.dt.is_none(),
                "integration.tolerance",
                tol,
                "absent when integration.eta or integration.dt is given (give one of them)",
            )?;
        }
        Ok(())
    }

    /// `boundary.fixed`, `boundary.density`, `boundary.velocity` and
    /// `motion.gravity_on`: ranges and combinations.
    fn validate_free_boundary(&self) -> Result<(), InputError> {
        let b = &self.boundary;
        if b.fixed {
            check(
                b.density.is_none(),
                "boundary.density",
                b.density.unwrap_or(0.0),
                "absent unless boundary.fixed = false (a fixed boundary has no mass in the problem)",
            )?;
            check(
                b.velocity.is_none(),
                "boundary.velocity",
                b.velocity.unwrap_or(0.0),
                "absent unless boundary.fixed = false (a fixed boundary does not move)",
            )?;
            check(
                self.motion.gravity_on != GravityOn::Both,
                "motion.gravity_on",
                "\"both\"",
                "\"particle\" or \"none\" with a fixed boundary (\"both\" needs boundary.fixed = false)",
            )?;
            return Ok(());
        }
        check(
            b.radius_ratio.is_finite(),
            "boundary.radius_ratio",
            b.radius_ratio,
            "finite when boundary.fixed = false (a free half-space would have infinite mass)",
        )?;
        if let Some(rho) = b.density {
            within("boundary.density", rho, limits::DENSITY, "kg/m³")?;
        }
        if let Some(v) = b.velocity {
            check(
                v.abs() <= limits::MAX_SPEED,
                "boundary.velocity",
                limits::Shown(v),
                format_args!("-{0:e} to {0:e} m/s", limits::MAX_SPEED),
            )?;
        }
        Ok(())
    }

    /// The `[contact]` keys: ranges, and which combinations make sense.
    /// The parameters a registry law takes (`contact.stiffness`), from
    /// its row: each given and in the row's range; and no such key for a
    /// law that does not take it. (The paper's laws keep their own checks:
    /// the power law's exponent, Walton–Braun's restitution.)
    fn validate_law_params(&self) -> Result<(), InputError> {
        use dembound_physics::contact::registry::NORMAL_LAWS;
        let c = &self.contact;
        let row = c.law.row();
        let model = c.model();
        if let ContactLawKind::Registry(_) = c.law {
            for p in row.params {
                let Some(value) = model.param(p.key) else {
                    return Err(InputError {
                        field: format!("contact.{}", p.key),
                        value: "missing".into(),
                        allowed: format!(
                            "{} ({}, {}), required by law = \"{}\"",
                            p.range, p.symbol, p.unit, row.name
                        ),
                    });
                };
                p.check(value).map_err(|e| InputError {
                    field: e.key,
                    value: e.value,
                    allowed: e.allowed,
                })?;
            }
        }
        if let Some(k) = c.stiffness {
            let takes = |r: &dembound_physics::contact::registry::NormalRow| {
                r.params.iter().any(|p| p.key == "stiffness")
            };
            let laws: Vec<String> = NORMAL_LAWS
                .iter()
                .filter(|r| takes(r))
                .map(|r| format!("\"{}\"", r.name))
                .collect();
            check(
                takes(row),
                "contact.stiffness",
                k,
                format_args!("absent unless law is {}", laws.join(" or ")),
            )?;
        }
        Ok(())
    }

    fn validate_contact(&self) -> Result<(), InputError> {
        let c = &self.contact;
        if let Some(e) = c.restitution {
            check(
                e > 0.0 && e <= 1.0,
                "contact.restitution",
                e,
                "0 < e ≤ 1 (rebound speed / impact speed)",
            )?;
        }
        if let Some(x) = c.damping_coefficient {
            check(
                x.is_finite() && x >= 0.0,
                "contact.damping_coefficient",
                x,
                "finite and ≥ 0 (N s/m viscous, N s/m^(5/4) tsuji, s viscoelastic)",
            )?;
            check(
                c.restitution.is_none(),
                "contact.damping_coefficient",
                x,
                "absent when contact.restitution is given (give one of them)",
            )?;
        }
        let quoted = |s: &str| format!("\"{s}\"");
        self.validate_law_params()?;
        let law = c.law.name();
        match (c.law, c.damping) {
            (ContactLawKind::WaltonBraun, DampingKind::None) => {
                check(
                    c.damping_coefficient.is_none(),
                    "contact.damping_coefficient",
                    c.damping_coefficient.unwrap_or(0.0),
                    "absent for law = \"walton-braun\" (set contact.restitution: k2 = k1/e²)",
                )?;
                check(
                    c.restitution.is_some(),
                    "contact.restitution",
                    "missing",
                    "0 < e ≤ 1, required by law = \"walton-braun\" (k2 = k1/e²)",
                )?;
                check(
                    !c.attractive,
                    "contact.attractive",
                    c.attractive,
                    "false for law = \"walton-braun\" (the law has no tensile branch)",
                )?;
            }
            (_, DampingKind::None) => {
                check(
                    c.restitution.is_none(),
                    "contact.restitution",
                    c.restitution.unwrap_or(0.0),
                    "absent unless contact.damping is \"viscous\", \"tsuji\" or \"viscoelastic\" or law = \"walton-braun\"",
                )?;
                check(
                    c.damping_coefficient.is_none(),
                    "contact.damping_coefficient",
                    c.damping_coefficient.unwrap_or(0.0),
                    "absent unless contact.damping is \"viscous\", \"tsuji\" or \"viscoelastic\"",
                )?;
            }
            // The physics registry's compatibility table.
            (law, damping) if damping.combines_with(law) => {
                check(
                    c.restitution.is_some() || c.damping_coefficient.is_some(),
                    "contact.restitution",
                    "missing",
                    format_args!(
                        "0 < e ≤ 1 (or contact.damping_coefficient ≥ 0), required by contact.damping = {}",
                        quoted(c.damping.name())
                    ),
                )?;
                if c.damping == DampingKind::Viscoelastic && c.restitution.is_some() {
                    let v = self.impact_speed();
                    check(
                        v > 0.0 && v.is_finite(),
                        "contact.restitution",
                        c.restitution.unwrap_or(0.0),
                        "usable with damping = \"viscoelastic\" only when the first impact speed > 0 (A is solved for at that speed); give contact.damping_coefficient instead",
                    )?;
                }
            }
            (_, damping) => check(
                false,
                "contact.damping",
                quoted(damping.name()),
                format_args!(
                    "with law = {}: {}",
                    quoted(&law),
                    dembound_physics::contact::registry::dampings_for(c.law.row())
                ),
            )?,
        }
        Ok(())
    }

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

    /// Mass of a free boundary, ρ_b 4/3 π (r R_m)³, kg; `None` when fixed.
    pub fn boundary_mass(&self) -> Option<f64> {
        let b = &self.boundary;
        (!b.fixed).then(|| {
            let radius = b.radius_ratio * self.particle.radius;
            let density = b.density.unwrap_or(self.particle.density);
            4.0 / 3.0 * std::f64::consts::PI * density * radius.powi(3)
        })
    }

    /// The mass of the relative motion, kg: the particle's against a fixed
    /// boundary, m* = m_m m_b/(m_m + m_b) against a free one.
    pub fn reduced_mass(&self) -> f64 {
        let m = self.particle.mass();
        match self.boundary_mass() {
            None => m,
            Some(mb) => m * mb / (m + mb),
        }
    }

    /// Gravity in the relative motion (the particle's minus the
    /// boundary's), m/s², acting to close the gap: g with gravity on the
    /// particle only, 0 with gravity on both or none.
    pub fn relative_gravity(&self) -> f64 {
        match self.motion.gravity_on {
            GravityOn::Particle => self.motion.gravity,
            GravityOn::Both | GravityOn::None => 0.0,
        }
    }

    /// Initial relative velocity v_m − v_b, m/s (the particle's velocity
    /// against a fixed boundary).
    pub fn relative_velocity(&self) -> f64 {
        if self.boundary.fixed {
            self.motion.velocity
        } else {
            self.motion.velocity - self.boundary.velocity.unwrap_or(0.0)
        }
    }

    /// The two spheres of a free-boundary run; `None` when the boundary is fixed.
    pub fn two_body(&self) -> Option<TwoBody> {
        let mb = self.boundary_mass()?;
        let mm = self.particle.mass();
        let total = mm + mb;
        let g = self.motion.gravity;
        let vb = self.boundary.velocity.unwrap_or(0.0);
        let cm_acceleration = match self.motion.gravity_on {
            GravityOn::Particle => -g * mm / total,
            GravityOn::Both => -g,
            GravityOn::None => 0.0,
        };
        Some(TwoBody {
            particle_mass: mm,
            boundary_mass: mb,
            cm_velocity: (mm * self.motion.velocity + mb * vb) / total,
            cm_acceleration,
        })
    }

    /// Relative speed at the first contact, m/s (≥ 0): √(v₀² + 2 g H₀) with
    /// v₀ and g those of the relative motion ([`Self::relative_velocity`],
    /// [`Self::relative_gravity`]), |v₀| without gravity (ERRATA item 7).
    pub fn impact_speed(&self) -> f64 {
        let v = self.relative_velocity();
        (v * v + 2.0 * self.relative_gravity() * self.motion.gap).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_valid_and_impact_speed_is_the_papers() {
        let s = Scenario::default();
        s.validate().unwrap();
        // v_c = −0.313 m/s (section 4.2); √(2·9.81·0.005) = 0.3132091953…
        assert!((s.impact_speed() - 0.313_209_195_3).abs() < 1e-10);
    }

    #[test]
    fn each_bad_field_is_named() {
        type Spoil = fn(&mut Scenario);
        let cases: Vec<(&str, Spoil)> = vec![
            ("particle.radius", |s| s.particle.radius = -1.0),
            ("particle.density", |s| s.particle.density = 0.0),
            ("particle.youngs_modulus", |s| {
                s.particle.youngs_modulus = f64::NAN
            }),
            ("particle.poisson_ratio", |s| s.particle.poisson_ratio = 0.5),
            ("boundary.radius_ratio", |s| s.boundary.radius_ratio = 0.0),
            ("boundary.modulus_ratio", |s| {
                s.boundary.modulus_ratio = -2.0
            }),
            ("boundary.poisson_ratio", |s| {
                s.boundary.poisson_ratio = Some(-1.0)
            }),
            ("contact.law.power", |s| {
                s.contact.law = ContactLawKind::Power(0.5)
            }),
            ("contact.restitution", |s| {
                s.contact.law = ContactLawKind::Linear;
                s.contact.damping = DampingKind::Viscous;
                s.contact.restitution = Some(1.5);
            }),
            ("contact.restitution", |s| {
                s.contact.law = ContactLawKind::Linear;
                s.contact.damping = DampingKind::Viscous;
            }),
            ("contact.restitution", |s| s.contact.restitution = Some(0.5)),
            ("contact.damping_coefficient", |s| {
                s.contact.damping = DampingKind::Tsuji;
                s.contact.damping_coefficient = Some(-1.0);
            }),
            ("contact.damping_coefficient", |s| {
                s.contact.damping = DampingKind::Tsuji;
                s.contact.restitution = Some(0.5);
                s.contact.damping_coefficient = Some(1.0);
            }),
            ("contact.damping", |s| {
                s.contact.damping = DampingKind::Viscous;
                s.contact.restitution = Some(0.5);
            }),
            ("contact.damping", |s| {
                s.contact.law = ContactLawKind::Linear;
                s.contact.damping = DampingKind::Tsuji;
                s.contact.restitution = Some(0.5);
            }),
            ("contact.damping", |s| {
                s.contact.law = ContactLawKind::WaltonBraun;
                s.contact.damping = DampingKind::Viscous;
                s.contact.restitution = Some(0.5);
            }),
            ("contact.restitution", |s| {
                s.contact.law = ContactLawKind::WaltonBraun;
            }),
            ("contact.attractive", |s| {
                s.contact.law = ContactLawKind::WaltonBraun;
                s.contact.restitution = Some(0.5);
                s.contact.attractive = true;
            }),
            ("contact.restitution", |s| {
                s.contact.damping = DampingKind::Viscoelastic;
                s.contact.restitution = Some(0.5);
                s.motion.gap = 0.0;
            }),
            ("motion.gap", |s| s.motion.gap = -1e-3),
            ("motion.gravity", |s| s.motion.gravity = -9.81),
            ("motion.contacts", |s| s.motion.contacts = 0),
            ("integration.eta", |s| s.integration.eta = Some(1.5)),
            ("integration.dt", |s| s.integration.dt = Some(0.0)),
            ("boundary.density", |s| s.boundary.density = Some(2000.0)),
            ("boundary.velocity", |s| s.boundary.velocity = Some(0.1)),
            ("motion.gravity_on", |s| {
                s.motion.gravity_on = GravityOn::Both
            }),
            ("boundary.radius_ratio", |s| {
                s.boundary.fixed = false;
                s.boundary.radius_ratio = f64::INFINITY;
            }),
            ("boundary.density", |s| {
                s.boundary.fixed = false;
                s.boundary.density = Some(-1.0);
            }),
            ("boundary.velocity", |s| {
                s.boundary.fixed = false;
                s.boundary.velocity = Some(f64::NAN);
            }),
            ("motion.velocity", |s| {
                s.boundary.fixed = false;
                s.motion.gravity_on = GravityOn::Both;
                s.motion.contacts = 1;
                s.motion.velocity = -0.1;
                s.boundary.velocity = Some(-0.2);
            }),
            ("motion.contacts", |s| {
                s.boundary.fixed = false;
                s.motion.gravity_on = GravityOn::None;
                s.motion.velocity = -0.3;
            }),
            ("integration.tolerance", |s| {
                s.integration.tolerance = Some(0.5)
            }),
            ("integration.tolerance", |s| {
                s.integration.tolerance = Some(1e-8);
                s.integration.eta = Some(0.02);
            }),
            ("integration.tolerance", |s| {
                s.integration.tolerance = Some(1e-8);
                s.integration.dt = Some(1e-9);
            }),
        ];
        for (field, spoil) in cases {
            let mut s = Scenario::default();
            spoil(&mut s);
            let err = s.validate().unwrap_err();
            assert_eq!(err.field, field);
        }
    }
}
