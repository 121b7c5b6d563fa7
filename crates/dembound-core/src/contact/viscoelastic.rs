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
//! bisection in ln δ. Later (slower) impacts of the same run then rebound
//! with a larger e, as they physically should. Alternatively A is given
//! raw (`contact.damping_coefficient`, seconds). With
//! [`Calibration::Formula`] A is solved for the unclamped law even when
//! the run forbids attraction (there is no published closed form; this is
//! the counterpart of the other laws' published mappings, which ignore the
//! clamp too).

use super::{power_law_free_contact, Calibration, Dissipation, ModelError, NormalContactLaw};
use crate::material::ContactPair;
use crate::reference::dissipative::{damped_hertz, DampedHertz};

/// F = k (h^(3/2) + (3/2) A h^(1/2) ḣ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzViscoelastic {
    /// k = E_eff √R_eff, N/m^(3/2).
    pub stiffness: f64,
    /// Dissipative constant A, s.
    pub a: f64,
}

/// Restitution of a gravity-free impact at `speed` of a body of `mass` under
/// F = k (h^(3/2) + (3/2) A h^(1/2) ḣ), by the adaptive reference integrator.
pub fn viscoelastic_restitution(
    stiffness: f64,
    a: f64,
    mass: f64,
    speed: f64,
    attractive: bool,
) -> Result<f64, ModelError> {
    let model = DampedHertz::Viscoelastic { stiffness, a };
    damped_hertz(model, mass, speed, 0.0, attractive)
        .map(|r| r.restitution)
        .map_err(|e| ModelError(format!("viscoelastic calibration: {e}")))
}

impl HertzViscoelastic {
    /// As [`Self::for_pair`], calibrating for the law as run
    /// ([`Calibration::Exact`]) or for the unclamped law
    /// ([`Calibration::Formula`]).
    pub fn calibrated(
        pair: &ContactPair,
        mass: f64,
        dissipation: Dissipation,
        impact_speed: f64,
        calibration: Calibration,
        attractive: bool,
    ) -> Result<Self, ModelError> {
        let as_run = attractive || calibration == Calibration::Formula;
        Self::for_pair(pair, mass, dissipation, impact_speed, as_run)
    }

    /// A from a target restitution at `impact_speed` (see the module doc),
    /// or A given (s).
    pub fn for_pair(
        pair: &ContactPair,
        mass: f64,
        dissipation: Dissipation,
        impact_speed: f64,
        attractive: bool,
    ) -> Result<Self, ModelError> {
        let stiffness = pair.power_law_stiffness(1.5);
        let a = match dissipation {
            Dissipation::Coefficient(a) => a,
            Dissipation::Restitution(e) if e >= 1.0 => 0.0,
            Dissipation::Restitution(e) => {
                if impact_speed.is_nan() || impact_speed <= 0.0 || impact_speed.is_infinite() {
                    return Err(ModelError(
                        "contact.restitution with damping = \"viscoelastic\" needs a first impact speed > 0"
                            .into(),
                    ));
                }
                let t = (mass / stiffness).powf(0.4) * impact_speed.powf(-0.2);
                // A contact that never ends (creeping back under heavy
                // damping) counts as e = 0: the damping is too strong.
                let e_of = |ln_delta: f64| {
                    viscoelastic_restitution(
                        stiffness,
                        ln_delta.exp() * t,
                        mass,
                        impact_speed,
                        attractive,
                    )
                    .unwrap_or(0.0)
                };
                // e decreases with δ: e(1e−9) ≈ 1, e(30) ≈ 0.
                let (mut lo, mut hi) = ((1e-9_f64).ln(), (30.0_f64).ln());
                if e_of(lo) < e || e_of(hi) > e {
                    return Err(ModelError(format!(
                        "contact.restitution = {e} is out of reach of the viscoelastic law (0 < δ ≤ 30)"
                    )));
                }
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if e_of(mid) > e {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                    if hi - lo < 1e-13 {
                        break;
                    }
                }
                (0.5 * (lo + hi)).exp() * t
            }
        };
        Ok(Self { stiffness, a })
    }
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
