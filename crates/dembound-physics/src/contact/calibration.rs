//! Closed-form relations between a damping coefficient and the restitution
//! of one gravity-free contact, shared by the damping sub-models and by the
//! bounce study (`dembound-core` re-exports them; they exist once, here).
//!
//! The linear spring–dashpot F = k h + c ḣ is the damped oscillator
//! h'' + 2ξω ḣ + ω² h = 0, ω² = k/m, ξ = c/(2√(k m)). Allowing attraction,
//! an impact rebounds at h = 0 with e = exp(−πξ/√(1−ξ²)), so a target e gives
//! ξ = −ln e/√(π² + ln² e) (e.g. Schwager & Pöschel, Phys. Rev. E 57, 650
//! (1998); LIGGGHTS `hooke`: γ_n = −2 β √(k m), β = ln e/√(ln² e + π²)).
//! With attraction forbidden the force returns to zero before the overlap
//! does and the rebound is faster: e = exp(−ξ(π − 2 asin ξ)/√(1−ξ²))
//! (Schwager & Pöschel, Granular Matter 9, 465 (2007)); [`damping_ratio_for`]
//! inverts that exactly. Tsuji's Hertz damping maps onto the same
//! oscillator (Antypov & Elliott, EPL 94, 50004 (2011)), so these relations
//! serve it too.

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
pub(crate) struct Ulps;

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

/// LIGGGHTS' β = ln e/√(ln² e + π²) (≤ 0), the Tsuji damping's published
/// restitution mapping.
pub fn tsuji_beta(e: f64) -> f64 {
    let l = e.ln();
    l / (l * l + std::f64::consts::PI.powi(2)).sqrt()
}

/// Factor on the elastic contact time of a damped Hertz law with damping
/// ratio ξ (Tsuji's ξ = γ/√(5 k m), or its equivalent): 1 up to ξ = 1/√2,
/// 1/(√2 ξ) beyond. A heavily damped contact decelerates at a rate ~ ξ
/// times the elastic one, so Δt = η T_c must shrink with it; the common
/// range (e ≳ 0.05 with the published ξ(e)) keeps the elastic time.
/// Measured at η = 1/50 (Tsuji, clamped, exact calibration): e = 0.05 and
/// 0.02 were off by 1.2e−4 and 8e−4 with the elastic time alone.
pub fn heavy_damping_scale(xi: f64) -> f64 {
    if xi <= std::f64::consts::FRAC_1_SQRT_2 {
        1.0
    } else {
        std::f64::consts::FRAC_1_SQRT_2 / xi
    }
}

/// Gravity-free contact of the power law F = k h^α at impact speed v for a
/// body of mass m: maximum overlap from the energy balance
/// k h^(α+1)/(α+1) = m v²/2, and duration
/// T_c = 2 (h_max/v) ∫₀¹ ds/√(1 − s^(α+1)) = 2 (h_max/v) B(1/(α+1), 1/2)/(α+1)
/// (paper eqs 29–30 for α = 3/2). Returns (h_max in m, T_c in s).
///
/// Written by hand because it is the physics itself; the Beta function comes
/// from `libm::tgamma`.
pub fn power_law_free_contact(stiffness: f64, alpha: f64, mass: f64, speed: f64) -> (f64, f64) {
    let beta = alpha + 1.0;
    let max_overlap = (beta * mass * speed * speed / (2.0 * stiffness)).powf(1.0 / beta);
    let b = libm::tgamma(1.0 / beta) * libm::tgamma(0.5) / libm::tgamma(1.0 / beta + 0.5);
    let duration = 2.0 * max_overlap / speed * b / beta;
    (max_overlap, duration)
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

    #[test]
    fn tsuji_beta_is_minus_the_oscillator_ratio() {
        // Two spellings of one formula (LIGGGHTS' β and Schwager–Pöschel's ξ).
        for e in [0.1_f64, 0.5, 0.9] {
            assert!((tsuji_beta(e) + restitution_to_damping_ratio(e)).abs() < 1e-16);
        }
    }

    #[test]
    fn power_law_contact_time_reduces_to_the_closed_forms() {
        let (k, m, v) = (3.0e4, 2.0e-6, 0.3);
        // α = 1: B(1/2, 1/2) = π, so T_c = π √(m/k) and h_max = v √(m/k).
        let (h, t) = power_law_free_contact(k, 1.0, m, v);
        assert!((t / (PI * (m / k).sqrt()) - 1.0).abs() < 1e-13);
        assert!((h / (v * (m / k).sqrt()) - 1.0).abs() < 1e-14);
        // α = 3/2: 2.943275 h_max/v, the constant to the 7 digits quoted in
        // the literature (eq 30), so 5e−7.
        let (h, t) = power_law_free_contact(k, 1.5, m, v);
        assert!((t / (2.943275 * h / v) - 1.0).abs() < 5e-7);
    }
}
