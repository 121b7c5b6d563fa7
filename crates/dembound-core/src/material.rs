//! Materials of the two spheres and the effective properties of their contact
//! (paper eqs 2, 5–8, 10–14; ERRATA item 2 for unequal Poisson ratios).
//!
//! Infinite boundary radius (`r = ∞`, elastic half-space) and infinite boundary
//! modulus (`ζ = ∞`, rigid boundary) are represented by `f64::INFINITY`; every
//! formula here is written in the reciprocal form that evaluates those limits
//! exactly rather than as `∞/∞`.

use dembound_physics::contact::normal::NormalSubModel;
use dembound_physics::material::PairProperties;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The mobile (bouncing) sphere, subscript `m` in the paper. SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Particle {
    /// Radius R_m, m.
    pub radius: f64,
    /// Density ρ, kg/m³.
    pub density: f64,
    /// Young's modulus E_m, Pa.
    pub youngs_modulus: f64,
    /// Poisson ratio ν_m, dimensionless.
    pub poisson_ratio: f64,
}

impl Particle {
    /// The paper's validation particle (section 4.2): ρ = 1000 kg/m³,
    /// E = 1e10 Pa (so c² = E/ρ = 1e7 m²/s²), ν = 0.3, R_m = 0.5 mm.
    pub const PAPER: Particle = Particle {
        radius: 0.5e-3,
        density: 1000.0,
        youngs_modulus: 1.0e10,
        poisson_ratio: 0.3,
    };

    /// Mass m_m = 4/3 π ρ R_m³ (eq 2), kg.
    pub fn mass(&self) -> f64 {
        4.0 / 3.0 * PI * self.density * self.radius.powi(3)
    }

    /// Material constant c = √(E_m/ρ) (eq 12), m/s.
    pub fn wave_speed(&self) -> f64 {
        (self.youngs_modulus / self.density).sqrt()
    }
}

/// The boundary sphere, subscript `b`, described relative to the particle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Boundary {
    /// r = R_b/R_m; `f64::INFINITY` for an elastic half-space.
    pub radius_ratio: f64,
    /// ζ = E_b/E_m; `f64::INFINITY` for a rigid boundary.
    pub modulus_ratio: f64,
    /// ν_b; `None` means "same as the particle" (the paper's assumption for eq 8).
    pub poisson_ratio: Option<f64>,
}

impl Boundary {
    /// The paper's validation boundary: r = ζ = 100.
    pub const PAPER: Boundary = Boundary {
        radius_ratio: 100.0,
        modulus_ratio: 100.0,
        poisson_ratio: None,
    };

    /// The rigid half-space r = ζ = ∞ against which the paper normalises.
    pub const RIGID_HALF_SPACE: Boundary = Boundary {
        radius_ratio: f64::INFINITY,
        modulus_ratio: f64::INFINITY,
        poisson_ratio: None,
    };
}

/// `x/(x+1)` written as `1/(1 + 1/x)` so that `x = ∞` gives exactly 1 (eq 14).
pub fn bar(ratio: f64) -> f64 {
    1.0 / (1.0 + 1.0 / ratio)
}

/// A particle against a boundary: the effective contact properties.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactPair {
    pub particle: Particle,
    pub boundary: Boundary,
}

impl ContactPair {
    pub fn new(particle: Particle, boundary: Boundary) -> Self {
        Self { particle, boundary }
    }

    /// The boundary's Poisson ratio (defaults to the particle's).
    pub fn boundary_poisson_ratio(&self) -> f64 {
        self.boundary
            .poisson_ratio
            .unwrap_or(self.particle.poisson_ratio)
    }

    /// Boundary radius R_b = r R_m, m (∞ for a half-space).
    pub fn boundary_radius(&self) -> f64 {
        self.boundary.radius_ratio * self.particle.radius
    }

    /// Boundary modulus E_b = ζ E_m, Pa (∞ for a rigid boundary).
    pub fn boundary_modulus(&self) -> f64 {
        self.boundary.modulus_ratio * self.particle.youngs_modulus
    }

    /// r̄ = r/(r+1) (eq 14); 1 for a half-space.
    pub fn radius_ratio_bar(&self) -> f64 {
        bar(self.boundary.radius_ratio)
    }

    /// ζ̄ = ζ/(ζ+1) (eq 14); 1 for a rigid boundary.
    pub fn modulus_ratio_bar(&self) -> f64 {
        bar(self.boundary.modulus_ratio)
    }

    /// Effective radius R_eff = R_m R_b/(R_m + R_b) = r̄ R_m (eqs 5, 7), m.
    pub fn effective_radius(&self) -> f64 {
        self.radius_ratio_bar() * self.particle.radius
    }

    /// Effective modulus, general Poisson ratios (eq 6 as corrected in ERRATA item 2):
    /// E_eff = 4/3 · 1/((1−ν_m²)/E_m + (1−ν_b²)/E_b), Pa.
    /// With ν_b = ν_m this is eq 8, 4/3 ζ̄ E_m/(1−ν²).
    pub fn effective_modulus(&self) -> f64 {
        let nu_m = self.particle.poisson_ratio;
        let nu_b = self.boundary_poisson_ratio();
        let compliance = (1.0 - nu_m * nu_m) / self.particle.youngs_modulus
            + (1.0 - nu_b * nu_b) / self.boundary_modulus();
        4.0 / 3.0 / compliance
    }

    /// Contact stiffness E_eff R_eff^(2−α) of the power law F = k h^α (eq 4),
    /// in N/m^α.
    pub fn power_law_stiffness(&self, alpha: f64) -> f64 {
        self.effective_modulus() * self.effective_radius().powf(2.0 - alpha)
    }

    /// The pair as the physics crate's per-pair laws see it: R_eff, E_eff
    /// and the particle's mass m_m (the boundary is fixed here).
    pub fn properties(&self) -> PairProperties {
        PairProperties {
            radius: self.effective_radius(),
            modulus: self.effective_modulus(),
            mass: self.particle.mass(),
        }
    }

    /// The physics crate's normal law `T` for this pair, with its
    /// parameters in the order of its registry row (`pair.law::<Hertz>(&[])`,
    /// `pair.law::<PowerLaw>(&[α])`, `pair.law::<WaltonBraun>(&[e])`).
    pub fn law<T: NormalSubModel>(&self, params: &[f64]) -> T {
        T::new(params, &self.properties())
    }

    /// p = √(E_eff R_eff^(2−α)/m_m) (eq 10), in s⁻¹ m^((1−α)/2).
    pub fn p(&self, alpha: f64) -> f64 {
        (self.power_law_stiffness(alpha) / self.particle.mass()).sqrt()
    }

    /// Dimensionless p̄ = √(ζ̄ r̄^(2−α)/(π(1−ν²))) (eq 13), generalised to
    /// unequal Poisson ratios so that p = p̄ c R_m^((−1−α)/2) (eq 11) holds exactly.
    pub fn p_bar(&self, alpha: f64) -> f64 {
        let c = self.particle.wave_speed();
        self.p(alpha) / (c * self.particle.radius.powf((-1.0 - alpha) / 2.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper_pair() -> ContactPair {
        ContactPair::new(Particle::PAPER, Boundary::PAPER)
    }

    #[test]
    fn p_matches_eq_11_and_13_for_equal_poisson_ratios() {
        // eq 13 written out independently of eq 10; only rounding separates them.
        let pair = paper_pair();
        let nu: f64 = 0.3;
        for alpha in [1.0, 1.5, 1.25] {
            let zb = 100.0 / 101.0;
            let rb: f64 = 100.0 / 101.0;
            let p_bar = (zb * rb.powf(2.0 - alpha) / (PI * (1.0 - nu * nu))).sqrt();
            let p = p_bar * 1.0e7_f64.sqrt() * 0.5e-3_f64.powf((-1.0 - alpha) / 2.0);
            assert!((pair.p(alpha) / p - 1.0).abs() < 1e-14, "alpha {alpha}");
            assert!((pair.p_bar(alpha) / p_bar - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn linear_contact_time_of_validation_case_is_848_ns() {
        // Paper section 4.2: T_cL = 848.3 ns, i.e. π/p to four digits (eq 27).
        let t = PI / paper_pair().p(1.0);
        assert!((t * 1e9 - 848.3).abs() < 0.05, "{t}");
    }

    #[test]
    fn infinite_ratios_give_half_space_limits() {
        let pair = ContactPair::new(Particle::PAPER, Boundary::RIGID_HALF_SPACE);
        assert_eq!(pair.effective_radius(), Particle::PAPER.radius);
        let e = 4.0 / 3.0 * 1.0e10 / (1.0 - 0.09);
        assert!((pair.effective_modulus() / e - 1.0).abs() < 1e-15);
    }

    #[test]
    fn eq_6_general_form_is_symmetric_in_the_two_materials() {
        // ERRATA item 2: swapping (E, ν) between the spheres leaves E_eff unchanged.
        let mut pair = paper_pair();
        pair.boundary.modulus_ratio = 3.0;
        pair.boundary.poisson_ratio = Some(0.2);
        let swapped_compliance = (1.0 - 0.04) / 3.0e10 + (1.0 - 0.09) / 1.0e10;
        let e = 4.0 / 3.0 / swapped_compliance;
        assert!((pair.effective_modulus() / e - 1.0).abs() < 1e-15);
    }
}
