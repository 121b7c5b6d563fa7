//! Hertz with viscoelastic damping (Kuwabara & Kono, Jpn. J. Appl. Phys. 26,
//! 1230 (1987); Brilliantov, Spahn, Hertzsch & Pöschel, Phys. Rev. E 53,
//! 5382 (1996)): F = k (h^(3/2) + (3/2) A h^(1/2) ḣ), A in seconds (a
//! dissipative time of the material).
//!
//! The restitution depends on the impact speed: scaling h by v T and t by
//! T = (m/k)^(2/5) v^(−1/5) leaves u'' = −(u^(3/2) + (3/2) δ u^(1/2) u'),
//! u(0) = 0, u'(0) = 1, so e is a function of δ = A (k/m)^(2/5) v^(1/5)
//! alone; for small δ, e = 1 − C₁ (3δ/2) + (3/5) C₁² (3δ/2)² + …, with
//! C₁ = Γ(3/5)√π/(2^(1/5) 5^(2/5) Γ(21/10)) ≈ 1.15345 (Schwager & Pöschel,
//! Phys. Rev. E 57, 650 (1998); Ramírez et al., Phys. Rev. E 60, 4465
//! (1999); checked in `reference::dissipative`).
//!
//! **Target restitution:** A is *solved for* so that a gravity-free impact
//! at the scenario's first impact speed rebounds with the target e (with
//! the attraction setting of the run): e(δ) is computed by the adaptive
//! reference integrator ([`crate::reference::dissipative`]) and inverted by
//! bisection in ln δ ([`HertzViscoelastic::for_pair`], in
//! [`crate::calibration`], which sits above both this module and the
//! references). Later (slower) impacts of the same run then rebound
//! with a larger e, as they physically should. Alternatively A is given
//! raw (`contact.damping_coefficient`, seconds). With
//! [`Calibration::Formula`] A is solved for the unclamped law even when
//! the run forbids attraction (there is no published closed form; this is
//! the counterpart of the other laws' published mappings, which ignore the
//! clamp too).

use super::{power_law_free_contact, NormalContactLaw};

/// F = k (h^(3/2) + (3/2) A h^(1/2) ḣ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzViscoelastic {
    /// k = E_eff √R_eff, N/m^(3/2).
    pub stiffness: f64,
    /// Dissipative constant A, s.
    pub a: f64,
}

impl NormalContactLaw for HertzViscoelastic {
    fn scaled(&self, factor: f64) -> Self {
        Self {
            stiffness: self.stiffness * factor,
            ..*self
        }
    }

    type History = ();

    fn name(&self) -> &'static str {
        "hertz-viscoelastic"
    }

    /// Continued to h < 0 as k (h|h|^(1/2) + (3/2) A |h|^(1/2) ḣ).
    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, _history: &()) -> f64 {
        let r = overlap.abs().sqrt();
        self.stiffness * r * (overlap + 1.5 * self.a * overlap_rate)
    }

    fn depends_on_rate(&self) -> bool {
        true
    }

    fn onset(&self) -> super::Onset {
        super::Onset::Singular
    }

    /// The elastic Hertz contact time: a time scale for Δt; divided by √2 ξ
    /// beyond an equivalent damping ratio ξ = 1/√2
    /// ([`super::heavy_damping_scale`]). ξ is Tsuji's γ h^(1/4)/(√5 √(k m)) with
    /// the damping rate (3/2) k A h^(1/2)/m of this law at the elastic h_max:
    /// ξ = (3/2) A ω_h/√5, ω_h = √(k/m) h_max^(1/4).
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        let (h_max, elastic) = power_law_free_contact(self.stiffness, 1.5, mass, impact_speed);
        let omega_h = (self.stiffness / mass).sqrt() * h_max.powf(0.25);
        let xi = 1.5 * self.a * omega_h / 5f64.sqrt();
        elastic * super::heavy_damping_scale(xi)
    }

    // h''' ∝ h^(−1/2) at the onset: the default (zeros) is the honest seed.
}
