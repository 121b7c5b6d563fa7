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
//! 9, 465 (2007)); the target is *not* corrected for that, as in LIGGGHTS.

use super::{Dissipation, NormalContactLaw};
use crate::material::ContactPair;
use std::f64::consts::PI;

/// ξ = −ln e/√(π² + ln² e): the damping ratio of a linear oscillator that
/// rebounds at h = 0 with restitution e (0 < e ≤ 1; e = 1 gives 0).
pub fn restitution_to_damping_ratio(e: f64) -> f64 {
    let l = e.ln();
    -l / (PI * PI + l * l).sqrt()
}

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

    /// Damped half period π/(ω√(1−ξ²)); π/ω when overdamped (a time scale only).
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        let omega = (self.stiffness / mass).sqrt();
        let xi = self.damping_ratio(mass);
        if xi < 1.0 {
            PI / (omega * (1.0 - xi * xi).sqrt())
        } else {
            PI / omega
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_ratio_inverts_the_oscillator_restitution() {
        for e in [0.05_f64, 0.5, 0.9, 0.999] {
            let xi = restitution_to_damping_ratio(e);
            let back = (-PI * xi / (1.0 - xi * xi).sqrt()).exp();
            assert!((back / e - 1.0).abs() < 1e-14, "{e}");
        }
        assert_eq!(restitution_to_damping_ratio(1.0), 0.0);
    }
}
