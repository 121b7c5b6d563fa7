//! Damping sub-models (LAMMPS GRANULAR `gran_sub_mod_damping.cpp`): one file
//! per model, each a small `Copy` type with the same few methods
//! ([`DampingSubModel`]). The damping force is added to the normal law's by
//! the model ([`super::PairLaw::force`]), which then applies the clamp once.
//! Which models exist and which normal laws each combines with are rows of
//! [`super::registry`].

use super::calibration::restitution_to_damping_ratio;
use crate::error::PhysicsError;

pub mod none;
pub mod tsuji;
pub mod viscoelastic;
pub mod viscous;

/// How strong the dissipation is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dissipation {
    /// A target coefficient of restitution 0 < e ≤ 1 of one gravity-free
    /// contact; each model documents how it maps e to its coefficient.
    Restitution(f64),
    /// The model's raw damping coefficient, ≥ 0, in the unit of its
    /// registry row (c in N s/m, γ in N s/m^(5/4), A in s).
    Coefficient(f64),
}

/// How a target restitution becomes a damping coefficient (configured as
/// `contact.calibration = "exact"` or `"formula"`: with the `serde`
/// feature it reads and writes those lowercase names). Both aim at one
/// gravity-free contact; gravity during the contact moves the rebound
/// slightly either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum Calibration {
    /// The model's exact gravity-free relation for the law as it is run,
    /// clamped or not: one gravity-free contact rebounds with exactly e
    /// (spring–dashpot and Tsuji: [`super::calibration::damping_ratio_for`]).
    #[default]
    Exact,
    /// The published mapping (LIGGGHTS/LAMMPS), exact only with attraction
    /// allowed: with the clamp a target e = 0.5 rebounds with 0.550.
    Formula,
}

impl Calibration {
    /// Both, in the order of their names.
    pub const ALL: [Calibration; 2] = [Calibration::Exact, Calibration::Formula];

    /// The name used in configurations, `"exact"` or `"formula"`.
    pub fn name(&self) -> &'static str {
        match self {
            Calibration::Exact => "exact",
            Calibration::Formula => "formula",
        }
    }

    /// The calibration called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }

    /// One line saying what the calibration means (for lists and reports).
    pub fn description(&self) -> &'static str {
        match self {
            Calibration::Exact => {
                "the law's exact gravity-free relation, solved for the law as run (clamped or not): one gravity-free contact rebounds with exactly e"
            }
            Calibration::Formula => {
                "the published mapping (LIGGGHTS/LAMMPS), exact only with attraction allowed: with the clamp e = 0.5 rebounds with 0.550"
            }
        }
    }
}

/// What a damping sub-model is built from for one pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampingSetup {
    /// The normal law's stiffness k of F = k h^α, N/m^α.
    pub stiffness: f64,
    /// Effective mass of the pair, kg.
    pub mass: f64,
    /// The configured dissipation.
    pub dissipation: Dissipation,
    /// How a target restitution becomes a coefficient.
    pub calibration: Calibration,
    /// Whether the model lets the force pull (no clamp).
    pub attractive: bool,
    /// Impact speed (m/s) a speed-dependent calibration refers to.
    pub reference_speed: Option<f64>,
    /// ξ of the clamped oscillator for the target e, solved once per model
    /// ([`super::calibration::damping_ratio_for`]); NaN without a target.
    pub clamped_ratio: f64,
}

impl DampingSetup {
    /// The oscillator damping ratio ξ for target `e`: the exact clamped
    /// inversion when calibrating exactly a clamped model, else the
    /// published ξ = −ln e/√(π² + ln² e) (exact with attraction).
    pub fn oscillator_ratio(&self, e: f64) -> f64 {
        match (self.calibration, self.attractive) {
            (Calibration::Exact, false) => self.clamped_ratio,
            _ => restitution_to_damping_ratio(e),
        }
    }
}

/// A damping model resolved for one pair.
pub trait DampingSubModel: Copy + std::fmt::Debug {
    /// The model for one pair (its configuration already validated).
    fn new(setup: &DampingSetup) -> Self;

    /// Damping force, N (positive opposing approach), at overlap h (m) and
    /// overlap rate ḣ (m/s).
    fn force(&self, overlap: f64, overlap_rate: f64) -> f64;

    /// The same model with every force multiplied by `factor` (a loop that
    /// reads accelerations uses `scaled(1/m)`). [`Self::time_factor`] is
    /// unchanged: it still refers to the unscaled forces and the true mass.
    fn scaled(&self, factor: f64) -> Self;

    /// Factor on the normal law's elastic contact time (≤ 1 beyond heavy
    /// damping), for a pair of effective `mass` (kg) hit at `impact_speed` (m/s).
    fn time_factor(&self, _mass: f64, _impact_speed: f64) -> f64 {
        1.0
    }

    /// Checks beyond the registry's ranges (e.g. a calibration this crate
    /// cannot do); `None` when `dissipation` is absent.
    fn check(
        _dissipation: Dissipation,
        _calibration: Calibration,
        _reference_speed: Option<f64>,
    ) -> Result<(), PhysicsError> {
        Ok(())
    }
}
