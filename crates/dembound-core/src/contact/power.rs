use super::{power_law_free_contact, NormalContactLaw};
use crate::material::ContactPair;

/// General power law, eq 4: F = k h^α with k = E_eff R_eff^(2−α), α ≥ 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLaw {
    /// Stiffness k, N/m^α.
    pub stiffness: f64,
    /// Exponent α.
    pub exponent: f64,
}

impl PowerLaw {
    pub fn for_pair(pair: &ContactPair, exponent: f64) -> Self {
        Self {
            stiffness: pair.power_law_stiffness(exponent),
            exponent,
        }
    }
}

impl NormalContactLaw for PowerLaw {
    type History = ();

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
            ..*self
        }
    }

    fn name(&self) -> &'static str {
        "power"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, _history: &()) -> f64 {
        self.stiffness * overlap * overlap.abs().powf(self.exponent - 1.0)
    }

    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        power_law_free_contact(self.stiffness, self.exponent, mass, impact_speed).1
    }

    /// Integer exponents give an analytic force, hence a smooth onset.
    fn onset(&self) -> super::Onset {
        if self.exponent.fract() == 0.0 {
            super::Onset::Smooth
        } else {
            super::Onset::NonSmooth
        }
    }

    /// h''' = −α p² h^(α−1) ḣ: −p² ḣ for α = 1, 0 for α > 1; higher
    /// derivatives are seeded only for α = 1 (they are singular for 1 < α < 2).
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        if self.exponent == 1.0 {
            let p2 = self.stiffness / mass;
            let h3 = -p2 * overlap_rate;
            [h3, -p2 * overlap_accel, -p2 * h3]
        } else {
            [0.0; 3]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{Hertz, LinearSpring};
    use crate::material::{Boundary, ContactPair, Particle};

    fn pair() -> ContactPair {
        ContactPair::new(Particle::PAPER, Boundary::PAPER)
    }

    #[test]
    fn power_law_reduces_to_linear_and_hertz() {
        // Same formula, different code paths (powf vs h·√h): agree to rounding.
        let p = pair();
        let h = 3.7e-7;
        let lin = LinearSpring::for_pair(&p).force(h, 0.0, &());
        let her = Hertz::for_pair(&p).force(h, 0.0, &());
        assert!((PowerLaw::for_pair(&p, 1.0).force(h, 0.0, &()) / lin - 1.0).abs() < 1e-15);
        assert!((PowerLaw::for_pair(&p, 1.5).force(h, 0.0, &()) / her - 1.0).abs() < 1e-14);
    }

    #[test]
    fn contact_time_estimates_match_closed_forms() {
        let p = pair();
        let m = p.particle.mass();
        let v = 0.313;
        // Linear: the Beta-function form must reduce to π/p (B(1/2,1/2) = π).
        let lin = LinearSpring::for_pair(&p);
        let via_beta = PowerLaw::for_pair(&p, 1.0).contact_time_estimate(m, v);
        assert!((via_beta / lin.contact_time_estimate(m, v) - 1.0).abs() < 1e-13);
        // Hertz: T_c = 2.943275 h_max/v with h_max = (5 v² m/(4k))^(2/5)
        // (the constant to the 7 digits quoted in the literature).
        let her = Hertz::for_pair(&p);
        let h_max = (5.0 * v * v * m / (4.0 * her.stiffness)).powf(0.4);
        let t = her.contact_time_estimate(m, v);
        assert!((t / (2.943275 * h_max / v) - 1.0).abs() < 5e-7);
    }
}
