//! Any law of the physics registry in the bounce: the physics crate's
//! per-pair model ([`PairLaw`]: normal law, damping, clamp; enum-dispatched
//! over the registry's rows) with the bounce's extension
//! ([`NormalContactLaw`]) in its generic form. A law added to the registry
//! runs here with no edit to this crate.
//!
//! The generic extras are the conservative ones: the onset is taken as
//! non-smooth (event stepping grades the mesh at both ends of the contact,
//! which keeps the scheme's order for any bounded force), or singular when
//! the damping depends on the rate; the onset seeds are zero (unknown); a
//! history-dependent law keeps its history from `update` alone (the physics
//! contract), with no branch switch at the located maximum. The paper's
//! laws and `hooke` have exact extras of their own (`physics_laws`,
//! [`super::Damped`]).

use super::{ContactModel, Dissipation, NormalContactLaw, Onset};
use crate::material::ContactPair;
use crate::{Error, Result};
use dembound_physics::contact::peak::Linearization;
use dembound_physics::contact::registry::NormalLaw;
use dembound_physics::contact::{self as physics, ContactHistory, Damping, PairLaw};

/// The physics crate's per-pair model, its forces times `scale`; F =
/// max(F, 0) when `CLAMPED`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Registered<const CLAMPED: bool> {
    law: PairLaw,
    scale: f64,
}

impl<const CLAMPED: bool> Registered<CLAMPED> {
    /// The elastic law `law` for `pair`, a body of `mass` (kg).
    pub fn elastic(law: &NormalLaw, pair: &ContactPair, mass: f64) -> Self {
        let model = physics::ContactModel {
            attractive: !CLAMPED,
            ..physics::ContactModel::elastic(*law)
        };
        Self::from_model(&model, pair, mass)
    }

    /// `model`'s normal law with its damping of raw `coefficient` (c, γ or
    /// A, as the damping's registry row has it) for `pair` and `mass` (kg).
    pub fn damped(
        model: &ContactModel,
        pair: &ContactPair,
        mass: f64,
        coefficient: f64,
    ) -> Result<Self> {
        let normal = model.normal().ok_or_else(|| missing(model))?;
        let physics_model = physics::ContactModel {
            normal,
            attractive: !CLAMPED,
            damping: Damping::new(
                model.damping.to_physics(),
                Dissipation::Coefficient(coefficient),
            ),
            calibration: physics::Calibration::Exact,
        };
        Ok(Self::from_model(&physics_model, pair, mass))
    }

    fn from_model(model: &physics::ContactModel, pair: &ContactPair, mass: f64) -> Self {
        let properties = dembound_physics::material::PairProperties {
            mass,
            ..pair.properties()
        };
        Self {
            law: model.pair(&properties),
            scale: 1.0,
        }
    }
}

/// The error of a law whose parameter is missing.
pub(crate) fn missing(model: &ContactModel) -> Error {
    let row = model.law.row();
    let keys: Vec<String> = row
        .params
        .iter()
        .map(|p| format!("contact.{} ({}, {})", p.key, p.range, p.unit))
        .collect();
    Error::Model(format!(
        "law = \"{}\" needs {}",
        row.name,
        keys.join(" and ")
    ))
}

impl<const CLAMPED: bool> NormalContactLaw for Registered<CLAMPED> {
    type History = ContactHistory;

    const NON_ATTRACTIVE: bool = CLAMPED;

    fn name(&self) -> &'static str {
        self.law.normal().row().name
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64 {
        let f = self.unclamped_force(overlap, overlap_rate, history);
        if CLAMPED {
            f.max(0.0)
        } else {
            f
        }
    }

    #[inline(always)]
    fn unclamped_force(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64 {
        self.scale
            * (self.law.normal().force(overlap, overlap_rate, history)
                + self.law.damping().force(overlap, overlap_rate))
    }

    #[inline(always)]
    fn update_history(&self, overlap: f64, overlap_rate: f64, history: &mut ContactHistory) {
        self.law.update(overlap, overlap_rate, history)
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            scale: self.scale * factor,
            ..*self
        }
    }

    fn depends_on_rate(&self) -> bool {
        self.law.depends_on_rate()
    }

    /// The normal law's elastic time times the damping's factor.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        self.law.normal().contact_time_estimate(mass, impact_speed)
            * self.law.damping().time_factor(mass, impact_speed)
    }

    /// The physics pair's own ([`PairLaw::peak_linearization`]), at the
    /// pair's mass; `None` without a rate-dependent force.
    fn damped_peak(&self, _mass: f64, impact_speed: f64, gravity: f64) -> Option<Linearization> {
        self.law
            .depends_on_rate()
            .then(|| self.law.peak_linearization(impact_speed, gravity))
    }

    /// Non-smooth (graded at both ends), singular with a rate-dependent
    /// damping (whose h-power may make the derivatives infinite at h = 0⁺).
    fn onset(&self) -> Onset {
        if self.law.damping().row().capabilities.rate_dependent {
            Onset::Singular
        } else {
            Onset::NonSmooth
        }
    }
}
