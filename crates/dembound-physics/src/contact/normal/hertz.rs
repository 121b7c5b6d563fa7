//! The Hertz law, eq 4 with α = 3/2: F = k h^(3/2), k = E_eff √R_eff.

use super::NormalSubModel;
use crate::contact::{calibration::power_law_free_contact, ContactHistory};
use crate::material::PairProperties;

/// 0.8 B(2/5, 1/2) = 2.9432751843…: the gravity-free Hertz contact time in
/// units of h_max/v (eq 30).
pub const HERTZ_CONTACT_TIME_FACTOR: f64 = 2.943_275_184_3;

/// F = k h √h with k = E_eff √R_eff (N/m^(3/2)); no `powf`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// k = E_eff √R_eff, N/m^(3/2).
    pub stiffness: f64,
}

impl NormalSubModel for Hertz {
    fn new(_params: &[f64], pair: &PairProperties) -> Self {
        Self {
            stiffness: pair.modulus * pair.radius.sqrt(),
        }
    }

    /// k h √|h| (the odd continuation to h < 0, never NaN).
    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &ContactHistory) -> f64 {
        self.stiffness * overlap * overlap.abs().sqrt()
    }

    /// (2/5) k h^(5/2).
    #[inline]
    fn elastic_energy(&self, overlap: f64, _history: &ContactHistory) -> f64 {
        0.4 * self.stiffness * overlap * overlap * overlap.abs().sqrt()
    }

    fn stiffness(&self) -> f64 {
        self.stiffness
    }

    /// T_c = 2.9432… h_max/v with h_max = (5 m v²/(4 k))^(2/5) (eqs 29–30),
    /// the constant evaluated exactly as 0.8 B(2/5, 1/2)
    /// ([`power_law_free_contact`] with α = 3/2), as the bounce study has it.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        power_law_free_contact(self.stiffness, 1.5, mass, impact_speed).1
    }
}
