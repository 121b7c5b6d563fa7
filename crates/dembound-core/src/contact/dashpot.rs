//! Linear spring–dashpot (Cundall & Strack 1979; the LAMMPS/LIGGGHTS
//! `hooke` model): F = k h + c ḣ.
//!
//! With k = E_eff R_eff (the linear law of eq 4) the contact is a damped
//! oscillator, h'' + 2ξω ḣ + ω² h = g, ω² = k/m, ξ = c/(2√(k m)). Allowing
//! attraction, a gravity-free impact rebounds at h = 0 with
//! e = exp(−πξ/√(1−ξ²)) after T_c = π/(ω√(1−ξ²)); so a target e gives
//! ξ = −ln e/√(π² + ln² e) and c = 2ξ√(k m) (e.g. Schwager & Pöschel,
//! Phys. Rev. E 57, 650 (1998); LIGGGHTS `hooke`: γ_n = −2 β √(k m),
//! β = ln e/√(ln² e + π²)). With attraction forbidden the force returns to
//! zero before the overlap does and the rebound is faster:
//! e = exp(−ξ(π − 2 asin ξ)/√(1−ξ²)) (Schwager & Pöschel, Granular Matter
//! 9, 465 (2007)), e.g. 0.550 for ξ(0.5): LIGGGHTS does not correct the
//! target for that. [`Calibration::Exact`] (the default) does:
//! [`LinearDashpot::calibrated`] inverts [`free_restitution`], the exact
//! gravity-free relation of the law as it is run, clamped or not;
//! [`Calibration::Formula`] keeps the published ξ(e) above.

use super::{Calibration, Dissipation, NormalContactLaw};
use crate::material::ContactPair;
use std::f64::consts::PI;

/// The closed-form e(ξ) relations and their inverses live in the physics
/// crate (once, shared with the many-body engine); re-exported here.
pub use dembound_physics::contact::{
    damping_ratio_for, free_restitution, restitution_to_damping_ratio,
};

/// F = k h + c ḣ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearDashpot {
    /// Stiffness k = E_eff R_eff, N/m.
    pub stiffness: f64,
    /// Damping coefficient c, N s/m.
    pub damping: f64,
}

impl LinearDashpot {
    /// For `pair` and the body's `mass` (kg): c = 2ξ(e)√(k m) for a target
    /// restitution, or c given (N s/m).
    pub fn for_pair(pair: &ContactPair, mass: f64, dissipation: Dissipation) -> Self {
        let stiffness = pair.power_law_stiffness(1.0);
        let damping = match dissipation {
            Dissipation::Restitution(e) => {
                2.0 * restitution_to_damping_ratio(e) * (stiffness * mass).sqrt()
            }
            Dissipation::Coefficient(c) => c,
        };
        Self { stiffness, damping }
    }

    /// As [`Self::for_pair`], with a target restitution turned into c by
    /// `calibration`: [`Calibration::Exact`] solves [`free_restitution`] for
    /// the law as run (`attractive` or clamped), so that a gravity-free
    /// contact rebounds with exactly e; [`Calibration::Formula`] uses the
    /// published ξ(e), exact only when attraction is allowed.
    pub fn calibrated(
        pair: &ContactPair,
        mass: f64,
        dissipation: Dissipation,
        calibration: Calibration,
        attractive: bool,
    ) -> Self {
        match (dissipation, calibration, attractive) {
            (Dissipation::Restitution(e), Calibration::Exact, false) => {
                let law = Self::for_pair(pair, mass, Dissipation::Coefficient(0.0));
                let xi = damping_ratio_for(e, false);
                Self {
                    damping: 2.0 * xi * (law.stiffness * mass).sqrt(),
                    ..law
                }
            }
            _ => Self::for_pair(pair, mass, dissipation),
        }
    }

    /// ξ = c/(2√(k m)).
    pub fn damping_ratio(&self, mass: f64) -> f64 {
        self.damping / (2.0 * (self.stiffness * mass).sqrt())
    }
}

impl NormalContactLaw for LinearDashpot {
    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
            damping: self.damping * factor,
        }
    }

    /// F = k h + c ḣ is analytic in (h, ḣ): no grading needed.
    fn onset(&self) -> super::Onset {
        super::Onset::Smooth
    }

    type History = ();

    fn name(&self) -> &'static str {
        "linear-dashpot"
    }

    /// Already a polynomial in (h, ḣ): its own smooth continuation.
    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        self.stiffness * overlap + self.damping * overlap_rate
    }

    fn depends_on_rate(&self) -> bool {
        true
    }

    /// A time scale for Δt: the damped half period π/(ω√(1−ξ²)) up to
    /// ξ = 1/√2; beyond, π/(ω(ξ + √(max(ξ² − 1, 0)))), continuous there,
    /// which follows the fast rate ω(ξ + √(ξ²−1)) of the overdamped
    /// oscillator instead of the half period, which diverges at ξ = 1
    /// (a clamped contact, reachable near and beyond critical damping with
    /// the exact calibration, lasts only ≤ 2/ω to its force zero there;
    /// measured at η = 1/50: 1 % in e at e = 0.14 and 6 % at e = 0.02 with
    /// the half period, ≤ 2e−7 with this scale).
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        let omega = (self.stiffness / mass).sqrt();
        let xi = self.damping_ratio(mass);
        if xi < std::f64::consts::FRAC_1_SQRT_2 {
            PI / (omega * (1.0 - xi * xi).sqrt())
        } else {
            PI / (omega * (xi + (xi * xi - 1.0).max(0.0).sqrt()))
        }
    }

    /// From ḧ = g − ω² h − (c/m) ḣ: each further derivative is
    /// h⁽ⁿ⁺¹⁾ = −ω² h⁽ⁿ⁻¹⁾ − (c/m) h⁽ⁿ⁾.
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        let (p2, q) = (self.stiffness / mass, self.damping / mass);
        let h3 = -p2 * overlap_rate - q * overlap_accel;
        let h4 = -p2 * overlap_accel - q * h3;
        [h3, h4, -p2 * h3 - q * h4]
    }
}
