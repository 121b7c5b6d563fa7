//! The paper's general power law, eq 4: F = k h^α, k = E_eff R_eff^(2−α),
//! 1 ≤ α ≤ 3 (α = 1 linear, 3/2 Hertz; the registry bounds the range).

use super::NormalSubModel;
use crate::contact::{calibration::power_law_free_contact, ContactHistory};
use crate::material::PairProperties;

/// F = k h |h|^(α−1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLaw {
    /// k = E_eff R_eff^(2−α), N/m^α.
    pub stiffness: f64,
    /// Exponent α.
    pub exponent: f64,
}

impl NormalSubModel for PowerLaw {
    /// `params` = \[α\].
    fn new(params: &[f64], pair: &PairProperties) -> Self {
        let exponent = params[0];
        Self {
            stiffness: pair.modulus * pair.radius.powf(2.0 - exponent),
            exponent,
        }
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap * overlap.abs().powf(self.exponent - 1.0)
    }

    /// k h^(α+1)/(α+1).
    fn elastic_energy(&self, overlap: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap.abs().powf(self.exponent + 1.0) / (self.exponent + 1.0)
    }

    fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// 2 (h_max/v) B(1/(α+1), 1/2)/(α+1) ([`power_law_free_contact`]).
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        power_law_free_contact(self.stiffness, self.exponent, mass, impact_speed).1
    }
}
