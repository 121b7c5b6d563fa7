//! Zhou, Xu, Yu & Zulli (2002, Powder Technol. 125, 45–54, "An
//! experimental and numerical study of the angle of repose of coarse
//! spheres"): the power law their DEM heaps are fitted by.
//!
//! Their Eq. 5, for a heap without front and rear walls (container
//! thickness w → ∞):
//!
//! θ₀ = 68.61 μ_s,pp^0.27 μ_s,pw^0.22 μ_r,pp^0.06 μ_r,pw^0.12 d^−0.2
//!
//! in degrees, with d and the rolling coefficients in mm (their rolling
//! torque is μ_r |F_n|, μ_r a length); their Eq. 3, for w = 4 d between
//! walls, has 102 for 68.61. pp: particle–particle, pw: particle–wall.
//! The points scatter about the fit with a standard deviation of 2°.
//! Their heaps: 10 mm spheres on a plate 30 d wide, left by discharging a
//! settled bed over both edges of the plate.
//!
//! Where these numbers come from: the paper itself could not be reached
//! from here; the equations, the 2° scatter and the set-up are as
//! transcribed from it in the docstring of a public DEM code's
//! angle-of-repose example (found by its text, "Angle of repose of coarse
//! spheres (Zhou, Xu, Yu & Zulli 2002 …)"; its repository could not be
//! named). One transcription, not checked against the paper: the
//! benchmark compares only the exponents (ratios of angles, in which the
//! prefactor and d cancel), and draws the absolute law for information.

/// Their standard deviation of the DEM points about the fit, degrees.
pub(super) const SCATTER_DEGREES: f64 = 2.0;

/// The exponent of μ_s,pp, the grains' sliding friction, with the
/// wall's held (Eq. 5: 0.27). The benchmark's heaps stand on a base of
/// fixed grains whose friction changes with the grains' but was measured
/// to leave the angle unchanged (`repose`'s notes): its heaps are Eq. 5's
/// with μ_s,pw held, not with μ_s,pw = μ_s,pp (0.27 + 0.22 = 0.49). Their
/// particle–wall term is a flat wall's (their base plate and, at w = 4 d
/// where the exponents were fitted, the front and rear walls).
pub(super) const SLIDING_EXPONENT: f64 = 0.27;

/// The exponent of μ_r,pp likewise, μ_r,pw held (Eq. 5: 0.06; with
/// μ_r,pw = μ_r,pp it would be 0.06 + 0.12 = 0.18).
pub(super) const ROLLING_EXPONENT: f64 = 0.06;

/// θ₀ of Eq. 5 (w → ∞), degrees: `mu_r_*_mm` and `d_mm` in mm.
pub(super) fn angle_without_walls(
    mu_s_pp: f64,
    mu_s_pw: f64,
    mu_r_pp_mm: f64,
    mu_r_pw_mm: f64,
    d_mm: f64,
) -> f64 {
    68.61
        * mu_s_pp.powf(0.27)
        * mu_s_pw.powf(0.22)
        * mu_r_pp_mm.powf(0.06)
        * mu_r_pw_mm.powf(0.12)
        * d_mm.powf(-0.2)
}

/// Zhou's rolling coefficient (mm) of the engine's dimensionless `mu_r`
/// between two spheres of radius `radius` (m): the engine caps the
/// rolling torque at μ_r R_eff |F_n| (`contact::rolling`), theirs at
/// μ_r |F_n|, and R_eff = R/2 for equal spheres. The caps are what a heap
/// at rest tests, so matching them is the comparison the law allows (their
/// torque is a constant one against a grain's spin, the engine's an
/// elastic spring up to the cap: the same limit, not the same model).
pub(super) fn rolling_length_mm(mu_r: f64, radius: f64) -> f64 {
    mu_r * 0.5 * radius * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With every argument 1 the law is its prefactor, 68.61° (Eq. 5).
    #[test]
    fn the_prefactor_is_eq_5s() {
        assert_eq!(angle_without_walls(1.0, 1.0, 1.0, 1.0, 1.0), 68.61);
    }

    /// Doubling μ_s,pp alone multiplies θ by 2^0.27, both μ_s by
    /// 2^(0.27 + 0.22); μ_r,pp alone by 2^0.06, both μ_r by
    /// 2^(0.06 + 0.12); d by 2^−0.2: the power law's exponents, each
    /// checked alone (1e-12: rounding of powf). The checks' exponents are
    /// the particle–particle ones (0.27 and 0.06 in Eq. 5).
    #[test]
    fn the_ratios_are_the_exponents() {
        let base = angle_without_walls(0.4, 0.4, 0.05, 0.05, 2.0);
        let cases = [
            (angle_without_walls(0.8, 0.4, 0.05, 0.05, 2.0), 0.27),
            (angle_without_walls(0.8, 0.8, 0.05, 0.05, 2.0), 0.49),
            (angle_without_walls(0.4, 0.4, 0.1, 0.05, 2.0), 0.06),
            (angle_without_walls(0.4, 0.4, 0.1, 0.1, 2.0), 0.18),
            (angle_without_walls(0.4, 0.4, 0.05, 0.05, 4.0), -0.2),
        ];
        for (theta, exponent) in cases {
            assert!(((theta / base) / 2f64.powf(exponent) - 1.0).abs() < 1e-12);
        }
        assert_eq!((SLIDING_EXPONENT, ROLLING_EXPONENT), (0.27, 0.06));
    }

    /// μ_r = 0.2 between spheres of R = 1 mm: a torque arm of 0.1 mm.
    #[test]
    fn the_rolling_length_is_mu_r_times_half_the_radius() {
        assert!((rolling_length_mm(0.2, 1e-3) - 0.1).abs() < 1e-15);
    }
}
