use super::NormalContactLaw;
use crate::material::ContactPair;
use std::f64::consts::PI;

/// Linear spring, α = 1 in eq 4: F = k h with k = E_eff R_eff.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearSpring {
    /// Stiffness k, N/m.
    pub stiffness: f64,
}

impl LinearSpring {
    pub fn for_pair(pair: &ContactPair) -> Self {
        Self {
            stiffness: pair.power_law_stiffness(1.0),
        }
    }
}

impl NormalContactLaw for LinearSpring {
    type History = ();

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
        }
    }

    fn name(&self) -> &'static str {
        "linear"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &()) -> f64 {
        self.stiffness * overlap
    }

    /// Half period of the spring, π/p (eq 27), independent of the speed.
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        PI * (mass / self.stiffness).sqrt()
    }

    fn onset(&self) -> super::Onset {
        super::Onset::Smooth
    }

    /// From ḧ = g − p² h: h''' = −p² ḣ, h'''' = −p² ḧ, h''''' = −p² h'''.
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        let p2 = self.stiffness / mass;
        let h3 = -p2 * overlap_rate;
        [h3, -p2 * overlap_accel, -p2 * h3]
    }
}
