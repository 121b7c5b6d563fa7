//! Tsuji-type Hertz damping, as in LIGGGHTS `model hertz` and EDEM's
//! Hertz–Mindlin: F_d = γ h^(1/4) ḣ, with the Hertz law
//! F = k h^(3/2) + γ h^(1/4) ḣ.
//!
//! LIGGGHTS (`normal_model_hertz.h`): S_n = 2 E* √(R* h),
//! γ_n = −2 √(5/6) β √(S_n m*), β = ln e/√(ln² e + π²). With E_eff =
//! (4/3) E* (eq 6), k = E_eff √R_eff and S_n = (3/2) k h^(1/2), so
//! γ_n = √5 |β| √(k m) h^(1/4) and γ = √5 |β| √(k m) (Tsuji, Tanaka &
//! Ishida, Powder Technol. 71, 239 (1992)). The gravity-free law maps
//! exactly onto the spring–dashpot with ξ = γ/√(5 k m) (Antypov & Elliott,
//! EPL 94, 50004 (2011)): [`Calibration::Formula`](super::Calibration) is
//! the LIGGGHTS β, exact with attraction; [`Calibration::Exact`](super::Calibration)
//! solves the clamped relation, γ = ξ √(5 k m). The conventions are those
//! of `dembound-core`'s `contact/tsuji.rs`, written the same way.

use super::{DampingSetup, DampingSubModel, Dissipation};
use crate::contact::calibration::{heavy_damping_scale, tsuji_beta};

/// F_d = γ h^(1/4) ḣ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tsuji {
    /// γ, N s/m^(5/4).
    pub coefficient: f64,
    /// ξ = γ/√(5 k m).
    pub ratio: f64,
}

impl DampingSubModel for Tsuji {
    fn new(setup: &DampingSetup) -> Self {
        let (k, m) = (setup.stiffness, setup.mass);
        let coefficient = match (setup.dissipation, setup.calibration, setup.attractive) {
            (Dissipation::Coefficient(gamma), _, _) => gamma,
            (Dissipation::Restitution(_), super::Calibration::Exact, false) => {
                setup.clamped_ratio * (5.0 * k * m).sqrt()
            }
            (Dissipation::Restitution(e), _, _) => {
                // The LIGGGHTS form, written as it is there:
                // S_n/h^(1/2) = (3/2) k, so √(S_n m) = √(1.5 k m) h^(1/4).
                let s_n_per_root_h = 1.5 * k;
                2.0 * (5.0_f64 / 6.0).sqrt() * (-tsuji_beta(e)) * (s_n_per_root_h * m).sqrt()
            }
        };
        Self {
            coefficient,
            ratio: coefficient / (5.0 * k * m).sqrt(),
        }
    }

    /// γ |h|^(1/4) ḣ.
    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64) -> f64 {
        self.coefficient * overlap.abs().sqrt().sqrt() * overlap_rate
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            coefficient: self.coefficient * factor,
            ..*self
        }
    }

    /// 1 up to ξ = 1/√2, 1/(√2 ξ) beyond ([`heavy_damping_scale`]).
    fn time_factor(&self, _mass: f64, _impact_speed: f64) -> f64 {
        heavy_damping_scale(self.ratio)
    }
}
