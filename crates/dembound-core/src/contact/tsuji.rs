//! Hertz with Tsuji-type damping, as in LIGGGHTS `model hertz` and EDEM's
//! Hertz–Mindlin: F = k h^(3/2) + γ h^(1/4) ḣ.
//!
//! LIGGGHTS (`normal_model_hertz.h`): S_n = 2 E* √(R* h),
//! γ_n = −2 √(5/6) β √(S_n m*), β = ln e/√(ln² e + π²) (< 0, so γ_n > 0),
//! F_n = (4/3) E* √(R* h) h − γ_n v_n with v_n < 0 while approaching.
//! The core's E_eff is (4/3) E* (eq 6), so k = E_eff √R_eff and
//! S_n = (3/2) E_eff √(R_eff h) = (3/2) k h^(1/2) = dF_el/dh; hence
//! γ_n = 2√(5/6)|β|√((3/2) k m) h^(1/4) = √5 |β| √(k m) h^(1/4) and
//! γ = √5 |β| √(k m) (Tsuji, Tanaka & Ishida, Powder Technol. 71, 239
//! (1992): η = α √(m k) h^(1/4), with α read from their chart; here
//! α = √5 |β|).
//!
//! The damping ∝ h^(1/4) makes e independent of the impact speed. Without
//! gravity the phase-space substitution w ∝ h^(5/4) maps the law exactly
//! onto a linear spring–dashpot with ξ = α/√5 (Antypov & Elliott, EPL 94,
//! 50004 (2011)): so β above gives e *exactly* when attraction is allowed;
//! with attraction forbidden e = exp(−ξ(π − 2 asin ξ)/√(1−ξ²)), ξ = |β|
//! (see `reference::dissipative`): 0.550 for a target of 0.5. That is what
//! LIGGGHTS does ([`Calibration::Formula`]); [`Calibration::Exact`] (the
//! default) solves the clamped relation instead, γ = ξ √(5 k m) with ξ from
//! [`damping_ratio_for`], the same inversion as the spring–dashpot's.

use super::{
    damping_ratio_for, power_law_free_contact, Calibration, Dissipation, NormalContactLaw,
};
use crate::material::ContactPair;

/// LIGGGHTS' β = ln e/√(ln² e + π²) (≤ 0), from the physics crate.
pub use dembound_physics::contact::tsuji_beta;

/// F = k h^(3/2) + γ h^(1/4) ḣ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzTsuji {
    /// k = E_eff √R_eff, N/m^(3/2).
    pub stiffness: f64,
    /// γ, N s/m^(5/4).
    pub damping: f64,
}

impl HertzTsuji {
    /// γ = √5 |β(e)| √(k m) for a target restitution, or γ given (N s/m^(5/4)).
    pub fn for_pair(pair: &ContactPair, mass: f64, dissipation: Dissipation) -> Self {
        let stiffness = pair.power_law_stiffness(1.5);
        let damping = match dissipation {
            Dissipation::Restitution(e) => {
                // The LIGGGHTS form, written as it is there.
                // S_n/h^(1/2) = (3/2) k, so √(S_n m) = √(1.5 k m) h^(1/4).
                let s_n_per_root_h = 1.5 * stiffness;
                2.0 * (5.0_f64 / 6.0).sqrt() * (-tsuji_beta(e)) * (s_n_per_root_h * mass).sqrt()
            }
            Dissipation::Coefficient(gamma) => gamma,
        };
        Self { stiffness, damping }
    }

    /// As [`Self::for_pair`], with a target restitution turned into γ by
    /// `calibration` ([`Calibration::Exact`]: the exact gravity-free
    /// relation of the law as run, `attractive` or clamped, through the
    /// phase-space map onto the spring–dashpot, ξ = γ/√(5 k m)).
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
                    damping: xi * (5.0 * law.stiffness * mass).sqrt(),
                    ..law
                }
            }
            _ => Self::for_pair(pair, mass, dissipation),
        }
    }
}

impl NormalContactLaw for HertzTsuji {
    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
            damping: self.damping * factor,
        }
    }

    type History = ();

    fn name(&self) -> &'static str {
        "hertz-tsuji"
    }

    /// Continued to h < 0 as k h|h|^(1/2) + γ |h|^(1/4) ḣ.
    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        let r = overlap.abs().sqrt();
        self.stiffness * overlap * r + self.damping * r.sqrt() * overlap_rate
    }

    fn depends_on_rate(&self) -> bool {
        true
    }

    fn onset(&self) -> super::Onset {
        super::Onset::Singular
    }

    /// The elastic Hertz contact time (damping lengthens it by a few per cent
    /// at most for e ≥ 0.5): a time scale for Δt; divided by √2 ξ beyond
    /// ξ = γ/√(5 k m) = 1/√2 ([`super::heavy_damping_scale`]).
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        let elastic = power_law_free_contact(self.stiffness, 1.5, mass, impact_speed).1;
        let xi = self.damping / (5.0 * self.stiffness * mass).sqrt();
        elastic * super::heavy_damping_scale(xi)
    }

    // h''' ∝ h^(−3/4) at the onset: the default (zeros) is the honest seed.
}
