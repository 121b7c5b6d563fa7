use super::{power_law_free_contact, NormalContactLaw};
use crate::material::ContactPair;

/// Hertz, α = 3/2 in eq 4: F = k h^(3/2) with k = E_eff √R_eff.
///
/// h^(3/2) is evaluated as `h * sqrt(|h|)`: one square root, no `powf`, and
/// the odd continuation for h < 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// Stiffness k, N/m^(3/2).
    pub stiffness: f64,
}

impl Hertz {
    pub fn for_pair(pair: &ContactPair) -> Self {
        Self {
            stiffness: pair.power_law_stiffness(1.5),
        }
    }
}

impl NormalContactLaw for Hertz {
    type History = ();

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
        }
    }

    fn name(&self) -> &'static str {
        "hertz"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &()) -> f64 {
        self.stiffness * overlap * overlap.abs().sqrt()
    }

    /// Gravity-free Hertz contact time, T_c = 2.9432… h_max/v (the constant
    /// is 0.8 B(2/5, 1/2)); the exact form behind eq 30.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        power_law_free_contact(self.stiffness, 1.5, mass, impact_speed).1
    }

    // h''' = −(3/2) p² h^(1/2) ḣ vanishes at h = 0 and h'''' is infinite there:
    // the trait's default (all zero) is the honest seed.
}
