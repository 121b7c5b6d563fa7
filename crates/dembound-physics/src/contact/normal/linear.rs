//! The paper's linear law, eq 4 with α = 1: F = k h, k = E_eff R_eff.

use super::NormalSubModel;
use crate::contact::ContactHistory;
use crate::material::PairProperties;

/// F = k h with k = E_eff R_eff (N/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Linear {
    /// k = E_eff R_eff, N/m.
    pub stiffness: f64,
}

impl NormalSubModel for Linear {
    fn new(_params: &[f64], pair: &PairProperties) -> Self {
        Self {
            stiffness: pair.modulus * pair.radius,
        }
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap
    }

    /// k h²/2.
    fn elastic_energy(&self, overlap: f64, _history: &ContactHistory) -> f64 {
        0.5 * self.stiffness * overlap * overlap
    }

    fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// Half a period of the harmonic oscillator, π √(m/k) (eq 27).
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        std::f64::consts::PI * (mass / self.stiffness).sqrt()
    }
}
