//! Demonstration law (reverted): F = k_n h³ with k_n given (N/m³).

use super::NormalSubModel;
use crate::contact::{calibration::power_law_free_contact, ContactHistory};
use crate::material::PairProperties;

/// F = k_n h² |h| (odd in h).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicKn {
    /// k_n, N/m³.
    pub stiffness: f64,
}

impl NormalSubModel for CubicKn {
    fn new(params: &[f64], _pair: &PairProperties) -> Self {
        Self {
            stiffness: params[0],
        }
    }

    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap * overlap * overlap
    }

    fn elastic_energy(&self, overlap: f64, _history: &ContactHistory) -> f64 {
        0.25 * self.stiffness * overlap.powi(4)
    }

    fn stiffness(&self) -> f64 {
        self.stiffness
    }

    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        power_law_free_contact(self.stiffness, 3.0, mass, impact_speed).1
    }
}
