//! Walton & Braun (J. Rheol. 30, 949 (1986)) hysteretic linear law:
//! loading F = k₁ h, unloading F = k₂ (h − h₀) with
//! h₀ = h_max (1 − k₁/k₂), h_max the largest overlap so far, and F = 0
//! below h₀ (no tension). Energy balance gives e = √(k₁/k₂) exactly for a
//! gravity-free impact, measured where the force returns to zero (h = h₀);
//! the particle then flies free to h = 0. Here k₁ = E_eff R_eff (the linear
//! law of eq 4) and k₂ = k₁/e².
//!
//! The force has a kink at the maximum overlap: the contact loop locates it
//! and restarts the integrator on the unloading branch
//! ([`NormalContactLaw::at_max_overlap`]). Reloading (h rising again above
//! the current h_max, possible only near rest under gravity) follows
//! F = min(k₁ h, k₂ (h − h₀)) with h_max updated.

use super::NormalContactLaw;
use crate::material::ContactPair;
use std::f64::consts::PI;

/// Loading k₁ h; unloading min(k₁ h, k₂ (h − h₀)); never negative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaltonBraun {
    /// Loading stiffness k₁ = E_eff R_eff, N/m.
    pub loading: f64,
    /// Unloading stiffness k₂ = k₁/e², N/m.
    pub unloading: f64,
}

/// What the law remembers of a contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WaltonBraunHistory {
    /// Largest overlap so far, m.
    pub max_overlap: f64,
    /// True once the maximum overlap has been passed.
    pub unloading: bool,
}

impl WaltonBraun {
    /// k₁ = E_eff R_eff, k₂ = k₁/e² (0 < e ≤ 1).
    pub fn for_pair(pair: &ContactPair, restitution: f64) -> Self {
        let loading = pair.power_law_stiffness(1.0);
        Self {
            loading,
            unloading: loading / (restitution * restitution),
        }
    }

    /// Plastic overlap h₀ = h_max (1 − k₁/k₂) of the history.
    pub fn residual_overlap(&self, history: &WaltonBraunHistory) -> f64 {
        history.max_overlap * (1.0 - self.loading / self.unloading)
    }
}

impl NormalContactLaw for WaltonBraun {
    fn scaled(&self, factor: f64) -> Self {
        Self {
            loading: self.loading * factor,
            unloading: self.unloading * factor,
        }
    }

    /// Linear branches: smooth away from the kink, which is restarted at.
    fn onset(&self) -> super::Onset {
        super::Onset::Smooth
    }

    type History = WaltonBraunHistory;

    fn name(&self) -> &'static str {
        "walton-braun"
    }

    /// The law has no tensile branch.
    const NON_ATTRACTIVE: bool = true;

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, history: &WaltonBraunHistory) -> f64 {
        self.unclamped_force(overlap, overlap_rate, history)
            .max(0.0)
    }

    /// Loading: k₁ h (continued smoothly past the maximum inside the step
    /// that contains it); unloading: min(k₁ h, k₂ (h − h₀)), continued
    /// linearly below h₀.
    #[inline(always)]
    fn unclamped_force(&self, overlap: f64, _rate: f64, history: &WaltonBraunHistory) -> f64 {
        let load = self.loading * overlap;
        if history.unloading {
            load.min(self.unloading * (overlap - self.residual_overlap(history)))
        } else {
            load
        }
    }

    fn update_history(&self, overlap: f64, _rate: f64, history: &mut WaltonBraunHistory) {
        if history.unloading && overlap > history.max_overlap {
            history.max_overlap = overlap;
        }
    }

    fn at_max_overlap(&self, overlap: f64, history: &mut WaltonBraunHistory) -> bool {
        history.max_overlap = overlap;
        history.unloading = true;
        self.unloading != self.loading
    }

    /// π/2 (1/ω₁ + 1/ω₂): loading quarter period plus unloading quarter period.
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        0.5 * PI * ((mass / self.loading).sqrt() + (mass / self.unloading).sqrt())
    }

    /// Loading branch: h''' = −ω₁² ḣ, h'''' = −ω₁² ḧ, h''''' = −ω₁² h'''.
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        let p2 = self.loading / mass;
        let h3 = -p2 * overlap_rate;
        [h3, -p2 * overlap_accel, -p2 * h3]
    }

    /// The branch in force at `overlap`: ω² = k₂/m on unloading above h₀,
    /// 0 below h₀ (free flight), k₁/m while loading.
    fn branch_derivatives(
        &self,
        mass: f64,
        overlap: f64,
        overlap_rate: f64,
        overlap_accel: f64,
        history: &WaltonBraunHistory,
    ) -> [f64; 3] {
        let k = if !history.unloading {
            self.loading
        } else if overlap > self.residual_overlap(history) {
            self.unloading
        } else {
            0.0
        };
        let p2 = k / mass;
        let h3 = -p2 * overlap_rate;
        [h3, -p2 * overlap_accel, -p2 * h3]
    }
}
