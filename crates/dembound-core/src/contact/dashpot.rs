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
//! 9, 465 (2007)), e.g. 0.550 for ξ(0.5): LIGGGHTS does not correct the
//! target for that. [`Calibration::Exact`] (the default) does:
//! [`LinearDashpot::calibrated`] inverts [`free_restitution`], the exact
//! gravity-free relation of the law as it is run, clamped or not;
//! [`Calibration::Formula`] keeps the published ξ(e) above.

use super::{Calibration, Dissipation, NormalContactLaw};
use crate::material::ContactPair;
use roots::{find_root_brent, Convergency};
use std::f64::consts::PI;

/// ξ = −ln e/√(π² + ln² e): the damping ratio of a linear oscillator that
/// rebounds at h = 0 with restitution e (0 < e ≤ 1; e = 1 gives 0).
pub fn restitution_to_damping_ratio(e: f64) -> f64 {
    let l = e.ln();
    -l / (PI * PI + l * l).sqrt()
}

/// Gravity-free restitution of the oscillator h'' + 2ξω ḣ + ω² h = 0 hit
/// at speed v (any ξ ≥ 0; ω drops out), with the force k h + c ḣ allowed to
/// pull (`attractive`: e = exp(−πξ/√(1−ξ²)) for ξ < 1, 0 for ξ ≥ 1, the
/// overdamped body never returning to h = 0) or clamped at zero:
/// e = exp(−ξ φ(ξ)), φ = 2 acos ξ/√(1−ξ²) = (π − 2 asin ξ)/√(1−ξ²) for ξ < 1
/// (Schwager & Pöschel, Granular Matter 9, 465 (2007)), φ(1) = 2 and
/// φ = 2 acosh ξ/√(ξ²−1) for ξ > 1. The overdamped branch is derived here:
/// h ∝ e^(λ₁t) − e^(λ₂t), λ₁,₂ = ω(−ξ ± s), s = √(ξ²−1); the force vanishes
/// where e^(2sωt) = ((ξ+s)/(ξ−s))², i.e. ωt_f = 2 acosh(ξ)/s, and there
/// ḣ = −v e^(−ξωt_f), after which the body flies free (checked against the
/// adaptive reference through the Tsuji law, which maps onto this
/// oscillator exactly). e falls monotonically from 1 (ξ = 0) through
/// e⁻² ≈ 0.135 (ξ = 1) to 0 (e ≈ 1/(4ξ²) for ξ → ∞).
pub fn free_restitution(xi: f64, attractive: bool) -> f64 {
    if attractive {
        return if xi < 1.0 {
            (-PI * xi / ((1.0 - xi) * (1.0 + xi)).sqrt()).exp()
        } else {
            0.0
        };
    }
    (-xi * clamped_phase(xi)).exp()
}

/// φ(ξ) of [`free_restitution`] (ω t at the force zero), written so that it
/// stays accurate near ξ = 1: 1 − ξ² as (1 − ξ)(1 + ξ), acos through atan2
/// and acosh through ln_1p.
fn clamped_phase(xi: f64) -> f64 {
    if xi < 1.0 {
        let w = ((1.0 - xi) * (1.0 + xi)).sqrt();
        2.0 * w.atan2(xi) / w
    } else if xi > 1.0 {
        let w = ((xi - 1.0) * (xi + 1.0)).sqrt();
        2.0 * ((xi - 1.0) + w).ln_1p() / w
    } else {
        2.0
    }
}

/// Brent convergence: x to a few ulp.
struct Ulps;

impl Convergency<f64> for Ulps {
    fn is_root_found(&mut self, y: f64) -> bool {
        y == 0.0
    }
    fn is_converged(&mut self, x1: f64, x2: f64) -> bool {
        (x1 - x2).abs() <= 4.0 * f64::EPSILON * x1.abs().max(x2.abs())
    }
    fn is_iteration_limit_reached(&mut self, iter: usize) -> bool {
        iter >= 200
    }
}

/// The damping ratio ξ ≥ 0 for which [`free_restitution`]`(ξ, attractive)`
/// is `e` (0 < e ≤ 1): the published ξ(e) with attraction, Brent's method
/// (`roots`) on ξ φ(ξ) = −ln e, which increases with ξ, without.
pub fn damping_ratio_for(e: f64, attractive: bool) -> f64 {
    if attractive || e >= 1.0 {
        return restitution_to_damping_ratio(e);
    }
    let target = -e.ln();
    let f = |xi: f64| xi * clamped_phase(xi) - target;
    // ξ φ(ξ) ≥ ξ·2 acosh(ξ)/ξ > 2 ln ξ for ξ > 1: the bracket closes by doubling.
    let mut hi: f64 = 1.0;
    while f(hi) < 0.0 && hi < 1e150 {
        hi *= 2.0;
    }
    find_root_brent(0.0, hi, f, &mut Ulps).unwrap_or(f64::NAN)
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

    /// As [`Self::for_pair`], with a target restitution turned into c by
    /// `calibration`: [`Calibration::Exact`] solves [`free_restitution`] for
    /// the law as run (`attractive` or clamped), so that a gravity-free
    /// contact rebounds with exactly e; [`Calibration::Formula`] uses the
    /// published ξ(e), exact only when attraction is allowed.
    pub fn calibrated(
        pair: &ContactPair,
        mass: f64,
        dissipation: Dissipation,
        calibration: Calibration,
        attractive: bool,
    ) -> Self {
        match (dissipation, calibration, attractive) {
            (Dissipation::Restitution(e), Calibration::Exact, false) => {
                let law = Self::for_pair(pair, mass, Dissipation::Coefficient(0.0));
                let xi = damping_ratio_for(e, false);
                Self {
                    damping: 2.0 * xi * (law.stiffness * mass).sqrt(),
                    ..law
                }
            }
            _ => Self::for_pair(pair, mass, dissipation),
        }
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

    /// A time scale for Δt: the damped half period π/(ω√(1−ξ²)) up to
    /// ξ = 1/√2; beyond, π/(ω(ξ + √(max(ξ² − 1, 0)))), continuous there,
    /// which follows the fast rate ω(ξ + √(ξ²−1)) of the overdamped
    /// oscillator instead of the half period, which diverges at ξ = 1
    /// (a clamped contact, reachable near and beyond critical damping with
    /// the exact calibration, lasts only ≤ 2/ω to its force zero there;
    /// measured at η = 1/50: 1 % in e at e = 0.14 and 6 % at e = 0.02 with
    /// the half period, ≤ 2e−7 with this scale).
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        let omega = (self.stiffness / mass).sqrt();
        let xi = self.damping_ratio(mass);
        if xi < std::f64::consts::FRAC_1_SQRT_2 {
            PI / (omega * (1.0 - xi * xi).sqrt())
        } else {
            PI / (omega * (xi + (xi * xi - 1.0).max(0.0).sqrt()))
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

    #[test]
    fn clamped_relation_is_continuous_at_critical_damping_and_inverts() {
        // φ(1) = 2 from both sides (the overdamped branch continues the
        // underdamped one analytically): 1e−7 away, φ differs from 2 by
        // ~ (2/3)·1e−7 (φ ≈ 2 − 2(ξ−1)/3 near 1), so 1e−6 checks both
        // the limit and the cancellation-free evaluation.
        for d in [1e-7, 1e-10] {
            assert!((clamped_phase(1.0 - d) - 2.0).abs() < 1e-6);
            assert!((clamped_phase(1.0 + d) - 2.0).abs() < 1e-6);
        }
        assert!((free_restitution(1.0, false) - (-2.0f64).exp()).abs() < 1e-16);
        // The Schwager–Pöschel form for ξ < 1, written as in the paper.
        for xi in [0.05_f64, 0.3, 0.9] {
            let sp = (-xi * (PI - 2.0 * xi.asin()) / (1.0 - xi * xi).sqrt()).exp();
            assert!((free_restitution(xi, false) / sp - 1.0).abs() < 1e-14);
        }
        // Large ξ: e → 1/(4ξ²) (ln((ξ+s)/(ξ−s)) → ln 4ξ²); at ξ = 1e3 the
        // correction is O(ln ξ/ξ²) ~ 1e−5 relative.
        let big = 1e3;
        assert!((free_restitution(big, false) * 4.0 * big * big - 1.0).abs() < 1e-4);
        // The inverse, to a few ulp of ξ, across both branches.
        for e in [0.01, 0.1, 0.135, 0.3, 0.5, 0.9, 0.999] {
            let xi = damping_ratio_for(e, false);
            assert!((free_restitution(xi, false) / e - 1.0).abs() < 1e-13, "{e}");
            let xa = damping_ratio_for(e, true);
            assert!((free_restitution(xa, true) / e - 1.0).abs() < 1e-13, "{e}");
            // Clamping shortens the contact: more damping is needed.
            assert!(xi > xa, "{e}");
        }
    }
}
