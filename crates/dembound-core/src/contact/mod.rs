//! Normal contact laws, one small unit per law behind [`NormalContactLaw`]
//! (after the LAMMPS granular refactor: each law knows its force, whether it
//! needs the overlap rate, and its contact-time estimate; the model that owns
//! it does the rest).
//!
//! A law sees one particle pair: overlap `h ≥ 0` and overlap rate `ḣ`
//! (positive while the spheres approach). It knows nothing of gravity, the
//! integrator or the number of bodies, so dissipative laws (spring–dashpot,
//! Tsuji, Kuwabara–Kono, hysteretic) plug in without touching either.

mod hertz;
mod linear;
mod power;

pub use hertz::Hertz;
pub use linear::LinearSpring;
pub use power::PowerLaw;

use crate::material::ContactPair;
use serde::{Deserialize, Serialize};

/// A normal contact law for one pair of spheres.
pub trait NormalContactLaw: Send + Sync + std::fmt::Debug {
    /// What the law remembers of the current contact (the largest overlap
    /// so far, for a hysteretic law); `()` for history-free laws. A fresh
    /// `Default` value starts each contact.
    type History: Copy + Default + std::fmt::Debug;

    /// Short name used in reports (`"linear"`, `"hertz"`, ...).
    fn name(&self) -> &'static str;

    /// Normal force on the particle, N, repulsive positive, for overlap
    /// `overlap` (m) and overlap rate `overlap_rate` (m/s).
    ///
    /// For `overlap < 0` a law returns the smooth continuation of its
    /// in-contact force (the odd extension, F(−h) = −F(h) for elastic power
    /// laws). It is used only inside the one step that straddles the
    /// rebound, so that the step's polynomial is smooth there and locates
    /// h = 0 to the scheme's order; the physical force after separation is 0.
    fn force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64;

    /// Updates the history after an accepted step ending at (`overlap`,
    /// `overlap_rate`).
    #[inline(always)]
    fn update_history(&self, _overlap: f64, _overlap_rate: f64, _history: &mut Self::History) {}

    /// The same law with every force multiplied by `factor` (the integration
    /// loop uses `scaled(1/m)` so that it reads accelerations directly,
    /// one multiplication fewer on the latency chain of every step).
    fn scaled(&self, factor: f64) -> Self
    where
        Self: Sized;

    /// True when the force depends on the overlap rate; the Gear corrector
    /// then uses 3/20 instead of 3/16 for its first coefficient.
    fn depends_on_rate(&self) -> bool {
        false
    }

    /// Contact duration (s) of a gravity-free impact at `impact_speed` (m/s)
    /// of a body of `mass` (kg): the scale of the time step Δt = η T_c.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64;

    /// True when the overlap is a smooth (analytic) function of time at the
    /// contact onset, so a uniform step keeps the integrator's full order
    /// there; false (the default) asks event stepping for a graded mesh at
    /// both ends of the contact ([`crate::bounce::schedule`]).
    fn smooth_onset(&self) -> bool {
        false
    }

    /// One-sided time derivatives (h''', h'''', h''''') of the overlap at the
    /// contact onset h = 0⁺, given ḣ and ḧ there and the mass. They seed the
    /// Gear Nordsieck vector so that no stale (free-flight) derivatives cross
    /// the force discontinuity. A law returns 0 for a derivative that is
    /// infinite or unknown at h = 0 (Hertz: h'''' ∝ h^(-1/2)).
    fn onset_derivatives(&self, _mass: f64, _overlap_rate: f64, _overlap_accel: f64) -> [f64; 3] {
        [0.0; 3]
    }
}

/// Which contact law a scenario uses (TOML: `law = "linear"`, `"hertz"` or
/// `{ power = 1.25 }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactLawKind {
    /// α = 1: F = E_eff R_eff h (eq 4).
    Linear,
    /// α = 3/2: F = E_eff R_eff^(1/2) h^(3/2) (eq 4).
    Hertz,
    /// General exponent α ≥ 1: F = E_eff R_eff^(2−α) h^α (eq 4).
    Power(f64),
}

impl ContactLawKind {
    /// The exponent α of eq 4.
    pub fn exponent(&self) -> f64 {
        match *self {
            ContactLawKind::Linear => 1.0,
            ContactLawKind::Hertz => 1.5,
            ContactLawKind::Power(alpha) => alpha,
        }
    }

    pub fn name(&self) -> String {
        match *self {
            ContactLawKind::Linear => "linear".into(),
            ContactLawKind::Hertz => "hertz".into(),
            ContactLawKind::Power(alpha) => format!("power {alpha}"),
        }
    }
}

/// Calls `f` with the concrete law of `kind` for `pair`, so that the
/// integration loop is monomorphised for each law (no dynamic dispatch in
/// the inner loop).
pub fn with_law<R>(kind: ContactLawKind, pair: &ContactPair, f: impl LawVisitor<Output = R>) -> R {
    match kind {
        ContactLawKind::Linear => f.visit(LinearSpring::for_pair(pair)),
        ContactLawKind::Hertz => f.visit(Hertz::for_pair(pair)),
        ContactLawKind::Power(alpha) => f.visit(PowerLaw::for_pair(pair, alpha)),
    }
}

/// A generic computation over a concrete law type (see [`with_law`]).
pub trait LawVisitor {
    type Output;
    fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output;
}

/// Gravity-free contact of the power law F = k h^α at impact speed v for a
/// body of mass m: maximum overlap from the energy balance
/// k h^(α+1)/(α+1) = m v²/2, and duration
/// T_c = 2 (h_max/v) ∫₀¹ ds/√(1 − s^(α+1)) = 2 (h_max/v) B(1/(α+1), 1/2)/(α+1).
///
/// Written by hand because it is the physics itself; the Beta function comes
/// from `libm::tgamma`.
pub(crate) fn power_law_free_contact(
    stiffness: f64,
    alpha: f64,
    mass: f64,
    speed: f64,
) -> (f64, f64) {
    let beta = alpha + 1.0;
    let max_overlap = (beta * mass * speed * speed / (2.0 * stiffness)).powf(1.0 / beta);
    let b = libm::tgamma(1.0 / beta) * libm::tgamma(0.5) / libm::tgamma(1.0 / beta + 0.5);
    let duration = 2.0 * max_overlap / speed * b / beta;
    (max_overlap, duration)
}
