//! The bounce's extension of the physics crate's per-pair normal laws.
//!
//! The force, the history update and the contact-time estimate are the
//! physics sub-models' own ([`NormalSubModel`]): one implementation of each
//! law, shared with the many-particle engine. What only the event-resolved
//! single contact needs is added here, outside the physics trait
//! ([`NormalContactLaw`]): the scaling by 1/m and by the integrator's force
//! gain (a latency trick: one multiplication fewer on every step's
//! dependency chain), the smoothness at the onset, the one-sided onset
//! derivatives that seed the Gear restart, and the branch switch at the
//! located maximum overlap with its continuation derivatives.

use super::{NormalContactLaw, Onset};
use dembound_physics::contact::normal::{
    hertz::Hertz, hooke::Hooke, linear::Linear, power::PowerLaw, walton_braun::WaltonBraun,
    NormalSubModel,
};
use dembound_physics::contact::ContactHistory;

/// The history-free laws evaluate the physics force with an empty history
/// (a constant; the optimiser drops it).
const NO_HISTORY: ContactHistory = ContactHistory {
    max_overlap: 0.0,
    unloading: false,
};

/// (h''', h'''', h''''') of a linear spring of stiffness `k` (already per
/// unit of `mass` times `mass`): h⁽ⁿ⁺²⁾ = −(k/m) h⁽ⁿ⁾.
fn linear_derivatives(k: f64, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
    let p2 = k / mass;
    let h3 = -p2 * overlap_rate;
    [h3, -p2 * overlap_accel, -p2 * h3]
}

/// F = k h (k = E_eff R_eff): analytic, so a uniform step keeps full order.
impl NormalContactLaw for Linear {
    type History = ();

    fn name(&self) -> &'static str {
        "linear"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        NormalSubModel::force(self, overlap, overlap_rate, &NO_HISTORY)
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
        }
    }

    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        NormalSubModel::contact_time_estimate(self, mass, impact_speed)
    }

    fn onset(&self) -> Onset {
        Onset::Smooth
    }

    /// ḧ = g − ω² h: h''' = −ω² ḣ, h'''' = −ω² ḧ, h''''' = −ω² h'''.
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        linear_derivatives(self.stiffness, mass, overlap_rate, overlap_accel)
    }
}

/// F = k_n h with k_n given: the linear law's extras.
impl NormalContactLaw for Hooke {
    type History = ();

    fn name(&self) -> &'static str {
        "hooke"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        NormalSubModel::force(self, overlap, overlap_rate, &NO_HISTORY)
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
        }
    }

    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        NormalSubModel::contact_time_estimate(self, mass, impact_speed)
    }

    fn onset(&self) -> Onset {
        Onset::Smooth
    }

    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        linear_derivatives(self.stiffness, mass, overlap_rate, overlap_accel)
    }
}

/// F = k h^(3/2) as `h * sqrt(|h|)`: one square root, the odd continuation
/// for h < 0 (used inside the step that straddles the rebound).
impl NormalContactLaw for Hertz {
    type History = ();

    fn name(&self) -> &'static str {
        "hertz"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        NormalSubModel::force(self, overlap, overlap_rate, &NO_HISTORY)
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
        }
    }

    /// T_c = 0.8 B(2/5, 1/2) h_max/v, the exact form behind eq 30.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        NormalSubModel::contact_time_estimate(self, mass, impact_speed)
    }

    // h''' = −(3/2) p² h^(1/2) ḣ vanishes at h = 0 and h'''' is infinite
    // there: the trait's defaults (non-smooth onset, zero seeds) are honest.
}

/// F = k h^α, general α (eq 4).
impl NormalContactLaw for PowerLaw {
    type History = ();

    fn name(&self) -> &'static str {
        "power"
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        NormalSubModel::force(self, overlap, overlap_rate, &NO_HISTORY)
    }

    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
            ..*self
        }
    }

    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        NormalSubModel::contact_time_estimate(self, mass, impact_speed)
    }

    /// Integer exponents are analytic at h = 0.
    fn onset(&self) -> Onset {
        if self.exponent.fract() == 0.0 {
            Onset::Smooth
        } else {
            Onset::NonSmooth
        }
    }

    /// The linear spring's seeds at α = 1; 0 (unknown or infinite) otherwise.
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        if self.exponent == 1.0 {
            linear_derivatives(self.stiffness, mass, overlap_rate, overlap_accel)
        } else {
            [0.0; 3]
        }
    }
}

/// Walton–Braun: the physics law keeps its history from `update` alone
/// (it switches to unloading at the first step end past the maximum);
/// the bounce, which locates the maximum overlap, switches exactly there
/// ([`NormalContactLaw::at_max_overlap`]) and restarts the integrator on
/// the unloading branch, so that no step straddles the kink.
impl NormalContactLaw for WaltonBraun {
    type History = ContactHistory;

    fn name(&self) -> &'static str {
        "walton-braun"
    }

    /// The law has no tensile branch.
    const NON_ATTRACTIVE: bool = true;

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, history: &ContactHistory) -> f64 {
        self.unclamped_force(overlap, overlap_rate, history)
            .max(0.0)
    }

    /// Loading: k₁ h (continued smoothly past the maximum inside the step
    /// that contains it); unloading: min(k₁ h, k₂ (h − h₀)), continued
    /// linearly below h₀ (the physics force without its final max(·, 0)).
    #[inline(always)]
    fn unclamped_force(&self, overlap: f64, _rate: f64, history: &ContactHistory) -> f64 {
        let load = self.loading * overlap;
        if history.unloading {
            load.min(self.unloading * (overlap - self.residual_overlap(history)))
        } else {
            load
        }
    }

    #[inline(always)]
    fn update_history(&self, overlap: f64, overlap_rate: f64, history: &mut ContactHistory) {
        NormalSubModel::update(self, overlap, overlap_rate, history)
    }

    /// Both stiffnesses times `factor`; h₀/h_max = 1 − k₁/k₂ recomputed from
    /// the scaled pair, as the bounce has always formed it (1 − e² differs
    /// from it in the last bit, which the 1e−12 equality of
    /// `tests/refactor_equality.rs` notices after a 3-contact fixed-step run).
    fn scaled(&self, factor: f64) -> Self {
        let (loading, unloading) = (self.loading * factor, self.unloading * factor);
        Self {
            loading,
            unloading,
            residual_fraction: 1.0 - loading / unloading,
        }
    }

    /// π/2 (1/ω₁ + 1/ω₂): loading quarter period plus unloading quarter period.
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        NormalSubModel::contact_time_estimate(self, mass, impact_speed)
    }

    /// k₂ = k₁/e²: for a small e its quarter period is a sliver of T_c.
    fn loading_unloading(&self) -> Option<[f64; 2]> {
        Some([self.loading, self.unloading])
    }

    /// Linear branches: smooth away from the kink, which is restarted at.
    fn onset(&self) -> Onset {
        Onset::Smooth
    }

    /// Loading branch: h''' = −ω₁² ḣ, h'''' = −ω₁² ḧ, h''''' = −ω₁² h'''.
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        linear_derivatives(self.loading, mass, overlap_rate, overlap_accel)
    }

    fn at_max_overlap(&self, overlap: f64, history: &mut ContactHistory) -> bool {
        history.max_overlap = overlap;
        history.unloading = true;
        self.unloading != self.loading
    }

    /// The branch in force at `overlap`: ω² = k₂/m on unloading above h₀,
    /// 0 below h₀ (free flight), k₁/m while loading.
    fn branch_derivatives(
        &self,
        mass: f64,
        overlap: f64,
        overlap_rate: f64,
        overlap_accel: f64,
        history: &ContactHistory,
    ) -> [f64; 3] {
        let k = if !history.unloading {
            self.loading
        } else if overlap > self.residual_overlap(history) {
            self.unloading
        } else {
            0.0
        };
        linear_derivatives(k, mass, overlap_rate, overlap_accel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Boundary, ContactPair, Particle};

    fn pair() -> ContactPair {
        ContactPair::new(Particle::PAPER, Boundary::PAPER)
    }

    #[test]
    fn power_law_reduces_to_linear_and_hertz() {
        // Same formula, different code paths (powf vs h·√h): agree to rounding.
        let p = pair();
        let h = 3.7e-7;
        let force = |law: &dyn Fn(f64) -> f64| law(h);
        let lin = force(&|h| NormalContactLaw::force(&p.law::<Linear>(&[]), h, 0.0, &()));
        let her = force(&|h| NormalContactLaw::force(&p.law::<Hertz>(&[]), h, 0.0, &()));
        let pow = |a: f64| NormalContactLaw::force(&p.law::<PowerLaw>(&[a]), h, 0.0, &());
        assert!((pow(1.0) / lin - 1.0).abs() < 1e-15);
        assert!((pow(1.5) / her - 1.0).abs() < 1e-14);
    }

    #[test]
    fn contact_time_estimates_match_closed_forms() {
        let p = pair();
        let m = p.particle.mass();
        let v = 0.313;
        // Linear: the Beta-function form must reduce to π/p (B(1/2,1/2) = π).
        let lin = NormalContactLaw::contact_time_estimate(&p.law::<Linear>(&[]), m, v);
        let via_beta = NormalContactLaw::contact_time_estimate(&p.law::<PowerLaw>(&[1.0]), m, v);
        assert!((via_beta / lin - 1.0).abs() < 1e-13);
        // Hertz: T_c = 2.943275 h_max/v with h_max = (5 v² m/(4k))^(2/5)
        // (the constant to the 7 digits quoted in the literature).
        let her: Hertz = p.law(&[]);
        let h_max = (5.0 * v * v * m / (4.0 * her.stiffness)).powf(0.4);
        let t = NormalContactLaw::contact_time_estimate(&her, m, v);
        assert!((t / (2.943275 * h_max / v) - 1.0).abs() < 5e-7);
    }

    #[test]
    fn scaling_scales_every_force_and_keeps_the_residual_fraction() {
        let p = pair();
        let h = 2.0e-7;
        let wb: WaltonBraun = p.law(&[0.6]);
        let mut history = ContactHistory::default();
        assert!(wb.at_max_overlap(3.0e-7, &mut history));
        let f = NormalContactLaw::force(&wb, h, -0.1, &history);
        let g = NormalContactLaw::force(&wb.scaled(0.25), h, -0.1, &history);
        // A power-of-two factor is exact in binary arithmetic.
        assert_eq!(g, 0.25 * f);
        // On the unloading line: k₂ (h − h_max (1 − e²)), e = 0.6.
        let expected = wb.unloading * (h - 3.0e-7 * (1.0 - 0.36));
        assert!((f / expected - 1.0).abs() < 1e-12, "{f} vs {expected}");
    }
}
