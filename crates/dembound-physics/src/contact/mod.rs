//! Per-pair contact models, after LAMMPS GRANULAR's 2022 design
//! (`granular_model.cpp`): small sub-models with the same few methods
//! ([`normal`], [`damping`]), one registry row per sub-model
//! ([`registry`]), and one model object that combines the normal law with
//! damping and applies the no-attraction clamp once, as
//! `GranularModel::calculate_forces` does (`Fntot = Fne + Fdamp`, then
//! `if (limit_damping && Fntot < 0) Fntot = 0`).
//!
//! Two levels:
//! - [`ContactModel`]: what the user configures (normal law, damping,
//!   restitution or coefficient, calibration, clamp). Material-independent;
//!   built from names and values by [`ContactModel::from_spec`], checked
//!   against the registry by [`ContactModel::validate`].
//! - [`PairLaw`]: the model for one pair of bodies, its coefficients
//!   computed once from the pair's [`PairProperties`]
//!   ([`ContactModel::pair`]). `force` and `update` are all a time loop
//!   needs; the law keeps its own [`ContactHistory`] correct from those two
//!   calls alone (no event location required), so any loop can drive it.
//!
//! [`model`] composes the normal law with the tangential and rolling
//! sub-models ([`tangential`], [`rolling`]) into one contact
//! ([`ContactLaw::calculate_forces`]), the one place that says what a
//! contact exerts.
//!
//! Sign conventions: overlap h ≥ 0 (m) while in contact, overlap rate ḣ
//! (m/s) positive while the bodies approach, normal force F (N) repulsive
//! positive.

pub mod calibration;
pub mod damping;
pub mod law_params;
pub mod model;
pub mod normal;
pub mod peak;
pub mod registry;
mod spec;
#[cfg(test)]
mod tests;

pub use calibration::{
    damping_ratio_for, free_restitution, heavy_damping_scale, power_law_free_contact,
    restitution_to_damping_ratio, tsuji_beta,
};
pub use damping::{Calibration, Dissipation};
pub use law_params::LawParams;
pub use model::{ContactForces, ContactLaw, ContactState, Geometry, Side};
pub use normal::hertz::HERTZ_CONTACT_TIME_FACTOR;
pub use registry::{DampingKind, DampingPair, NormalLaw, NormalPair};
pub use spec::ContactSpec;
pub use torque_arm::TorqueArm;

use crate::error::PhysicsError;
use crate::material::PairProperties;
use damping::DampingSetup;

/// What a pair remembers of its current contact. One type for every law so
/// that a many-body store keeps one plain record per contacting pair; a new
/// contact starts from `Default`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContactHistory {
    /// Largest overlap of this contact so far, m (hysteretic laws).
    pub max_overlap: f64,
    /// True once the overlap has started to decrease (hysteretic laws:
    /// the unloading branch).
    pub unloading: bool,
}

/// The damping part of a [`ContactModel`]: which model and how strong.
/// Built by [`Damping::new`], which solves the pair-independent part of an
/// exact calibration once, so that [`ContactModel::pair`] stays cheap.
#[derive(Debug, Clone, Copy)]
pub struct Damping {
    kind: DampingKind,
    dissipation: Option<Dissipation>,
    reference_speed: Option<f64>,
    /// ξ of the clamped oscillator for a target e ([`damping_ratio_for`]).
    clamped_ratio: f64,
}

impl Damping {
    /// No damping.
    pub const NONE: Damping = Damping {
        kind: DampingKind::None,
        dissipation: None,
        reference_speed: None,
        clamped_ratio: f64::NAN,
    };

    /// `kind` with strength `dissipation`.
    pub fn new(kind: DampingKind, dissipation: Dissipation) -> Self {
        let clamped_ratio = match dissipation {
            Dissipation::Restitution(e) if e > 0.0 && e <= 1.0 => damping_ratio_for(e, false),
            _ => f64::NAN,
        };
        Self {
            kind,
            dissipation: Some(dissipation),
            reference_speed: None,
            clamped_ratio,
        }
    }

    /// The same, with the impact speed (m/s) a speed-dependent calibration
    /// (the viscoelastic law's) refers to.
    pub fn with_reference_speed(self, speed: f64) -> Self {
        Self {
            reference_speed: Some(speed),
            ..self
        }
    }

    /// Which damping model.
    pub fn kind(&self) -> DampingKind {
        self.kind
    }

    /// Its strength, if any.
    pub fn dissipation(&self) -> Option<Dissipation> {
        self.dissipation
    }

    /// The reference impact speed, m/s, if any.
    pub fn reference_speed(&self) -> Option<f64> {
        self.reference_speed
    }
}

/// Equal when the configurations are (the cached ratio follows from them).
impl PartialEq for Damping {
    fn eq(&self, other: &Self) -> bool {
        self.kind == other.kind
            && self.dissipation == other.dissipation
            && self.reference_speed == other.reference_speed
    }
}

impl Default for Damping {
    fn default() -> Self {
        Self::NONE
    }
}

/// A configured contact model (normal law, damping, clamp).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactModel {
    /// The normal law and its parameters.
    pub normal: NormalLaw,
    /// `false`: F = max(F, 0), the force never pulls (LAMMPS
    /// `limit_damping`, LIGGGHTS `limitForce`).
    pub attractive: bool,
    /// The damping added to the normal law.
    pub damping: Damping,
    /// How a target restitution becomes a damping coefficient.
    pub calibration: Calibration,
}

impl ContactModel {
    /// An elastic model of `normal` law.
    pub fn elastic(normal: NormalLaw) -> Self {
        Self {
            normal,
            attractive: false,
            damping: Damping::NONE,
            calibration: Calibration::Exact,
        }
    }

    /// `normal` with `damping`, clamped, exact calibration.
    pub fn damped(normal: NormalLaw, damping: Damping) -> Self {
        Self {
            damping,
            ..Self::elastic(normal)
        }
    }

    /// Checks the model against the registry: parameter ranges, the
    /// law–damping compatibility, the dissipation a damping needs. An error
    /// names the key, the value and the allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let law = self.normal.row();
        for (spec, value) in law.params.iter().zip(self.normal.params()) {
            spec.check(value)?;
        }
        let damping = self.damping.kind.row();
        if !damping.combines(law) {
            return Err(PhysicsError::new(
                "contact.damping",
                format!("\"{}\"", damping.name),
                format!(
                    "{} with law = \"{}\"",
                    registry::dampings_for(law),
                    law.name
                ),
            ));
        }
        match (damping.coefficient, self.damping.dissipation) {
            (None, None) => Ok(()),
            (None, Some(d)) => {
                let (key, value) = match d {
                    Dissipation::Restitution(e) => ("contact.restitution", e),
                    Dissipation::Coefficient(c) => ("contact.damping_coefficient", c),
                };
                Err(PhysicsError::new(
                    key,
                    value,
                    format!("absent with damping = \"{}\"", damping.name),
                ))
            }
            (Some(_), None) => Err(PhysicsError::new(
                "contact.restitution",
                "missing",
                format!(
                    "0 < e ≤ 1 (or contact.damping_coefficient), required by damping = \"{}\"",
                    damping.name
                ),
            )),
            (Some(coefficient), Some(d)) => {
                match d {
                    Dissipation::Restitution(e) => registry::RESTITUTION.check(e)?,
                    Dissipation::Coefficient(c) => coefficient.check(c)?,
                };
                self.damping
                    .kind
                    .check(d, self.calibration, self.damping.reference_speed)
            }
        }
    }

    /// The model for one pair: its coefficients from the pair's properties.
    /// Cheap (a few square roots; the exact calibration's root solve is
    /// done once in [`Damping::new`]). The model should have passed
    /// [`Self::validate`]; an invalid one gives NaN coefficients, not a panic.
    pub fn pair(&self, pair: &PairProperties) -> PairLaw {
        let normal = self.normal.resolve(pair);
        let damping = match self.damping.dissipation {
            None => DampingPair::None(damping::none::NoDamping),
            Some(dissipation) => self.damping.kind.resolve(&DampingSetup {
                stiffness: normal.stiffness(),
                mass: pair.mass,
                dissipation,
                calibration: self.calibration,
                attractive: self.attractive,
                reference_speed: self.damping.reference_speed,
                clamped_ratio: self.damping.clamped_ratio,
            }),
        };
        PairLaw {
            normal,
            damping,
            mass: pair.mass,
            attractive: self.attractive,
        }
    }

    /// True when the force depends on the overlap rate (damping).
    pub fn depends_on_rate(&self) -> bool {
        self.normal.row().capabilities.rate_dependent
            || self.damping.kind.row().capabilities.rate_dependent
    }

    /// A short label: `hertz`, `power (α = 1.25)`, `linear + viscous`.
    pub fn label(&self) -> String {
        let row = self.normal.row();
        let mut s = row.name.to_string();
        if !row.params.is_empty() {
            let values: Vec<String> = row
                .params
                .iter()
                .zip(self.normal.params())
                .map(|(p, v)| format!("{} = {v}", p.symbol))
                .collect();
            s = format!("{s} ({})", values.join(", "));
        }
        if self.damping.kind != DampingKind::None {
            s = format!("{s} + {}", self.damping.kind.row().name);
        }
        s
    }
}

/// The contact model of one pair, coefficients resolved. `Copy`, small: a
/// many-body loop may cache it per pair or per pair of material classes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairLaw {
    normal: NormalPair,
    damping: DampingPair,
    /// Effective mass, kg.
    mass: f64,
    attractive: bool,
}

impl PairLaw {
    /// Normal force (N, repulsive positive) at overlap `overlap` > 0 (m)
    /// and overlap rate `overlap_rate` (m/s), given the contact's history:
    /// normal law plus damping, then the clamp F = max(F, 0) unless the
    /// model is attractive. Callers evaluate it only in contact (h > 0).
    #[inline(always)]
    pub fn force(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64 {
        let f = self.normal.force(overlap, overlap_rate, history)
            + self.damping.force(overlap, overlap_rate);
        if self.attractive {
            f
        } else {
            f.max(0.0)
        }
    }

    /// The dashpot's share of [`Self::force`] (N): the force less what the
    /// normal law alone gives after the same clamp. Its product with the
    /// overlap rate is the power the contact's damping takes out (the
    /// scene's dissipated energy summed contact by contact).
    #[inline]
    pub fn damping_share(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64 {
        let elastic = self.normal.force(overlap, overlap_rate, history);
        let elastic = if self.attractive {
            elastic
        } else {
            elastic.max(0.0)
        };
        self.force(overlap, overlap_rate, history) - elastic
    }

    /// Updates the history after an accepted step that ends at
    /// (`overlap`, `overlap_rate`) with the pair still in contact.
    #[inline(always)]
    pub fn update(&self, overlap: f64, overlap_rate: f64, history: &mut ContactHistory) {
        self.normal.update(overlap, overlap_rate, history);
    }

    /// Elastic energy stored in the contact at `overlap` (J), for energy
    /// balances: the normal law's ([`NormalPair::elastic_energy`]); the
    /// damping stores none.
    #[inline]
    pub fn elastic_energy(&self, overlap: f64, history: &ContactHistory) -> f64 {
        self.normal.elastic_energy(overlap, history)
    }

    /// Duration (s) of a gravity-free impact of this pair at
    /// `impact_speed` (m/s): the time-step scale Δt = η T_c. The normal
    /// law's elastic time, shortened beyond heavy damping
    /// ([`heavy_damping_scale`]; the damped half period for viscous damping).
    pub fn contact_time_estimate(&self, impact_speed: f64) -> f64 {
        self.normal.contact_time_estimate(self.mass, impact_speed)
            * self.damping.time_factor(self.mass, impact_speed)
    }

    /// True when the force depends on the overlap rate (damping).
    pub fn depends_on_rate(&self) -> bool {
        self.normal.row().capabilities.rate_dependent
            || self.damping.row().capabilities.rate_dependent
    }

    /// True when the force depends on the contact's history.
    pub fn has_history(&self) -> bool {
        self.normal.row().capabilities.history
    }

    /// The resolved normal law.
    pub fn normal(&self) -> &NormalPair {
        &self.normal
    }

    /// The resolved damping.
    pub fn damping(&self) -> &DampingPair {
        &self.damping
    }

    /// Effective mass of the pair, kg.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Whether the force may pull (no clamp).
    pub fn attractive(&self) -> bool {
        self.attractive
    }
}

// Friction (issue 13): tangential springs with the Coulomb limit, and
// rolling resistance, as sub-models of their own.
pub mod rolling;
pub mod tangential;
pub mod torque_arm;
