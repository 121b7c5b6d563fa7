//! Walton & Braun (J. Rheol. 30, 949 (1986)) hysteretic linear law:
//! loading F = k₁ h, unloading F = k₂ (h − h₀) with h₀ = h_max (1 − k₁/k₂),
//! h_max the largest overlap so far, F = 0 below h₀ (never pulling).
//! k₁ = E_eff R_eff (the linear law of eq 4), k₂ = k₁/e²; energy balance
//! gives e = √(k₁/k₂) exactly for a gravity-free impact.
//!
//! The law keeps its own history from `update` alone, with no event
//! location: the contact switches to unloading at the first accepted step
//! whose overlap rate is negative or whose overlap is below the largest
//! so far, and h_max is the largest overlap sampled at step ends. The
//! sampled maximum misses the true one by at most a Δt²/8 (a the
//! deceleration at the peak), which shifts e by O((ωΔt)²): the order of a
//! second-order scheme (test in `contact::tests`). Reloading (h rising
//! above h_max again) follows F = min(k₁ h, k₂ (h − h₀)) with h_max updated;
//! reloading below h_max runs elastically along the k₂ line, as in the
//! original model.

use super::NormalSubModel;
use crate::contact::ContactHistory;
use crate::material::PairProperties;
use std::f64::consts::PI;

/// The largest ω₂ Δt (ω₂ = √(k₂/m), the unloading line's frequency) that
/// Gear5 resolves: the rebound within 0.76 % of e (measured over e =
/// 0.01–0.3, η = 0.005–0.1 in session 34; `dembound_core::scenario::limits`
/// has the table). `dembound run` and `dembound scene` refuse beyond it.
pub const MAX_UNLOADING_STEP_GEAR5: f64 = 0.9;
/// The same for velocity Verlet (0.5–0.75 % at 0.5).
pub const MAX_UNLOADING_STEP_VERLET: f64 = 0.5;

/// Loading k₁ h; unloading min(k₁ h, k₂ (h − h₀)); never negative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaltonBraun {
    /// Loading stiffness k₁ = E_eff R_eff, N/m.
    pub loading: f64,
    /// Unloading stiffness k₂ = k₁/e², N/m.
    pub unloading: f64,
    /// 1 − k₁/k₂ = 1 − e²: h₀ = h_max · this.
    pub residual_fraction: f64,
}

impl WaltonBraun {
    /// Plastic overlap h₀ = h_max (1 − k₁/k₂) of `history`, m.
    pub fn residual_overlap(&self, history: &ContactHistory) -> f64 {
        history.max_overlap * self.residual_fraction
    }
}

impl NormalSubModel for WaltonBraun {
    /// `params` = \[e\], 0 < e ≤ 1.
    fn new(params: &[f64], pair: &PairProperties) -> Self {
        let e = params[0];
        let loading = pair.modulus * pair.radius;
        let unloading = loading / (e * e);
        Self {
            loading,
            unloading,
            // 1 − k₁/k₂ (= 1 − e² up to the last bit; formed as the bounce
            // study always has).
            residual_fraction: 1.0 - loading / unloading,
        }
    }

    #[inline(always)]
    fn force(&self, overlap: f64, _overlap_rate: f64, history: &ContactHistory) -> f64 {
        let load = self.loading * overlap;
        let f = if history.unloading {
            load.min(self.unloading * (overlap - self.residual_overlap(history)))
        } else {
            load
        };
        f.max(0.0)
    }

    #[inline(always)]
    fn update(&self, overlap: f64, overlap_rate: f64, history: &mut ContactHistory) {
        if overlap_rate < 0.0 || overlap < history.max_overlap {
            history.unloading = true;
        }
        history.max_overlap = history.max_overlap.max(overlap);
    }

    /// k₁ h²/2 while loading; on unloading the energy the k₂ line returns,
    /// k₂ (h − h₀)²/2 above h₀ (0 below), or k₁ h²/2 where the law follows
    /// the loading line (h above h_max).
    fn elastic_energy(&self, overlap: f64, history: &ContactHistory) -> f64 {
        let load = 0.5 * self.loading * overlap * overlap;
        if !history.unloading || overlap >= history.max_overlap {
            return load;
        }
        let d = (overlap - self.residual_overlap(history)).max(0.0);
        // At or below h₀ the k₂ line holds nothing: 0, also where k₂ is
        // ∞ (e² below f64::MIN_POSITIVE, perfectly plastic unloading, h₀ =
        // h_max), where k₂ d²/2 would be ∞ × 0 = NaN. For a finite k₂
        // this is the +0 the product gives (the same bits).
        if d > 0.0 {
            0.5 * self.unloading * d * d
        } else {
            0.0
        }
    }

    fn stiffness(&self) -> f64 {
        self.loading
    }

    /// π/2 (1/ω₁ + 1/ω₂): loading quarter period plus unloading quarter period.
    fn contact_time_estimate(&self, mass: f64, _impact_speed: f64) -> f64 {
        0.5 * PI * ((mass / self.loading).sqrt() + (mass / self.unloading).sqrt())
    }
}
