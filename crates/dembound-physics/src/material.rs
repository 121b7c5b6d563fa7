//! Materials and the effective properties of a contacting pair (paper eqs
//! 5–8; eq 6 in the general form of ERRATA item 2, each body with its own
//! E and ν).
//!
//! Infinite moduli (rigid bodies), infinite radii (planes, half-spaces) and
//! infinite masses (fixed bodies) are `f64::INFINITY`; every mixing rule is
//! written in reciprocal form so that these limits are evaluated exactly
//! (1/∞ = 0) rather than as ∞/∞.

use std::f64::consts::PI;

/// An isotropic elastic material, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Density ρ, kg/m³.
    pub density: f64,
    /// Young's modulus E, Pa; `f64::INFINITY` for a rigid material.
    pub youngs_modulus: f64,
    /// Poisson ratio ν, dimensionless.
    pub poisson_ratio: f64,
}

impl Material {
    /// A rigid material (E = ∞) of density `density`; ν does not matter
    /// for a rigid body (its compliance is 0) and is set to 0.
    pub fn rigid(density: f64) -> Self {
        Self {
            density,
            youngs_modulus: f64::INFINITY,
            poisson_ratio: 0.0,
        }
    }

    /// Elastic compliance (1 − ν²)/E, 1/Pa; exactly 0 for a rigid material.
    pub fn compliance(&self) -> f64 {
        (1.0 - self.poisson_ratio * self.poisson_ratio) / self.youngs_modulus
    }

    /// Mass of a sphere of `radius` (m) of this material, 4/3 π ρ R³ (eq 2), kg.
    pub fn sphere_mass(&self, radius: f64) -> f64 {
        4.0 / 3.0 * PI * self.density * radius * radius * radius
    }
}

/// Effective modulus of two materials in contact, the paper's
/// E_eff = 4/3 · 1/((1−ν₁²)/E₁ + (1−ν₂²)/E₂) (eq 6 as corrected in ERRATA
/// item 2; with ν₁ = ν₂ and E₂ = ζ E₁ it is eq 8), Pa. The Hertz force is
/// F = E_eff √R_eff h^(3/2) (eq 4 with α = 3/2).
pub fn effective_modulus(a: &Material, b: &Material) -> f64 {
    4.0 / 3.0 / (a.compliance() + b.compliance())
}

/// Effective radius R₁R₂/(R₁ + R₂) (eqs 5, 7) as 1/(1/R₁ + 1/R₂), m; a
/// plane is `f64::INFINITY` and gives exactly R₁.
pub fn effective_radius(a: f64, b: f64) -> f64 {
    1.0 / (1.0 / a + 1.0 / b)
}

/// Effective (reduced) mass m₁m₂/(m₁ + m₂) as 1/(1/m₁ + 1/m₂), kg; a fixed
/// body (`f64::INFINITY`) gives exactly m₁.
pub fn effective_mass(a: f64, b: f64) -> f64 {
    1.0 / (1.0 / a + 1.0 / b)
}

/// What a contact model needs to know of one contacting pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairProperties {
    /// Effective radius R_eff, m.
    pub radius: f64,
    /// Effective modulus E_eff (4/3 included, [`effective_modulus`]), Pa.
    pub modulus: f64,
    /// Effective mass m_eff, kg (the mass of the relative motion).
    pub mass: f64,
}

impl PairProperties {
    /// Two spheres of radii `radius_a`, `radius_b` (m), masses `mass_a`,
    /// `mass_b` (kg; ∞ for a fixed body) and materials `a`, `b`.
    pub fn spheres(
        radius_a: f64,
        mass_a: f64,
        a: &Material,
        radius_b: f64,
        mass_b: f64,
        b: &Material,
    ) -> Self {
        Self {
            radius: effective_radius(radius_a, radius_b),
            modulus: effective_modulus(a, b),
            mass: effective_mass(mass_a, mass_b),
        }
    }

    /// A sphere of `radius` (m), `mass` (kg) and material `a` against a
    /// fixed plane (an elastic half-space) of material `wall`: R_eff = R,
    /// m_eff = m, the paper's r = ∞ with ζ = E_wall/E.
    pub fn sphere_plane(radius: f64, mass: f64, a: &Material, wall: &Material) -> Self {
        Self {
            radius,
            modulus: effective_modulus(a, wall),
            mass,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRAIN: Material = Material {
        density: 1000.0,
        youngs_modulus: 1.0e10,
        poisson_ratio: 0.3,
    };

    #[test]
    fn eq_8_for_equal_poisson_ratios() {
        // eq 8: E_eff = 4/3 ζ̄ E_m/(1 − ν²) with ζ̄ = ζ/(ζ+1); ζ = 100.
        let b = Material {
            youngs_modulus: 100.0 * GRAIN.youngs_modulus,
            ..GRAIN
        };
        let expected = 4.0 / 3.0 * (100.0 / 101.0) * 1.0e10 / (1.0 - 0.09);
        // Two roundings apart: a few ulps.
        assert!((effective_modulus(&GRAIN, &b) / expected - 1.0).abs() < 1e-15);
    }

    #[test]
    fn rigid_and_plane_limits_are_exact() {
        let rigid = Material::rigid(7800.0);
        assert_eq!(rigid.compliance(), 0.0);
        let e = effective_modulus(&GRAIN, &rigid);
        assert!((e / (4.0 / 3.0 * 1.0e10 / 0.91) - 1.0).abs() < 1e-15);
        assert_eq!(effective_radius(0.5e-3, f64::INFINITY), 0.5e-3);
        assert_eq!(effective_mass(2.0, f64::INFINITY), 2.0);
        let p = PairProperties::sphere_plane(0.5e-3, 1.0, &GRAIN, &rigid);
        assert_eq!(p.radius, 0.5e-3);
    }

    #[test]
    fn mixing_is_symmetric() {
        let b = Material {
            density: 2500.0,
            youngs_modulus: 3.0e10,
            poisson_ratio: 0.2,
        };
        let compliance = (1.0 - 0.04) / 3.0e10 + (1.0 - 0.09) / 1.0e10;
        assert!((effective_modulus(&b, &GRAIN) * compliance / (4.0 / 3.0) - 1.0).abs() < 1e-15);
        assert_eq!(effective_modulus(&b, &GRAIN), effective_modulus(&GRAIN, &b));
    }

    #[test]
    fn equal_spheres_halve_radius_and_mass() {
        // Two equal free spheres: R_eff = R/2, m_eff = m/2 (eqs 5, 7), and
        // E_eff = (4/3) E/(2(1−ν²)). Halving is exact in binary.
        let r = 0.5e-3;
        let m = GRAIN.sphere_mass(r);
        let p = PairProperties::spheres(r, m, &GRAIN, r, m, &GRAIN);
        assert_eq!(p.radius, r / 2.0);
        assert_eq!(p.mass, m / 2.0);
        let expected = 4.0 / 3.0 * 1.0e10 / (2.0 * 0.91);
        assert!((p.modulus / expected - 1.0).abs() < 1e-15);
        // A fixed second sphere (m = ∞): the mass of the first, exactly.
        let q = PairProperties::spheres(r, m, &GRAIN, r, f64::INFINITY, &GRAIN);
        assert_eq!(q.mass, m);
    }
}
