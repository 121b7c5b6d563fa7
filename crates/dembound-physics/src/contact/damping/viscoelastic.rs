//! Viscoelastic Hertz damping (Kuwabara & Kono, Jpn. J. Appl. Phys. 26,
//! 1230 (1987); Brilliantov, Spahn, Hertzsch & Pöschel, Phys. Rev. E 53,
//! 5382 (1996)): F_d = (3/2) k A h^(1/2) ḣ, with the Hertz law
//! F = k (h^(3/2) + (3/2) A h^(1/2) ḣ), A in seconds.
//!
//! The restitution depends on the impact speed v: scaling h by v T and t
//! by T = (m/k)^(2/5) v^(−1/5) leaves u'' = −(u^(3/2) + (3/2) δ u^(1/2) u'),
//! so e is a function of δ = A (k/m)^(2/5) v^(1/5) alone, with no closed
//! form. This crate has no ODE solver, so a target restitution is mapped
//! by the published small-damping series only ([`Calibration::Formula`]):
//! e = 1 − C₁ δ' + (3/5) C₁² δ'² + O(δ'³), δ' = (3/2) δ,
//! C₁ = Γ(3/5)√π/(2^(1/5) 5^(2/5) Γ(21/10)) ≈ 1.15345 (Schwager & Pöschel,
//! Phys. Rev. E 57, 650 (1998); Ramírez et al., Phys. Rev. E 60, 4465
//! (1999); the 3/2 placement as checked in `dembound-core`'s
//! `reference::dissipative`), inverted in closed form at the model's
//! reference impact speed, for the unclamped law. It is accurate only near
//! e = 1 (see [`FORMULA_MIN_RESTITUTION`]); the exact calibration (the
//! bounce study's adaptive reference integration) stays in `dembound-core`.
//! Otherwise give A directly (`damping_coefficient`).

use super::{Calibration, DampingSetup, DampingSubModel, Dissipation};
use crate::contact::calibration::{heavy_damping_scale, power_law_free_contact};
use crate::error::PhysicsError;

/// The smallest target restitution the series calibration accepts. The
/// truncated series misses the law's true e by ≈ 0.3 x³, x = C₁ δ'
/// (measured for the unclamped law through a fine velocity-Verlet loop,
/// `contact::tests`): 5e−5 at e = 0.95, 4e−4 at 0.9, 4e−3 at 0.8, 1.7e−2
/// at 0.7 and 7e−2 at 0.6; 0.8 keeps it below 0.5 %.
pub const FORMULA_MIN_RESTITUTION: f64 = 0.8;

/// C₁ = Γ(3/5)√π/(2^(1/5) 5^(2/5) Γ(21/10)) ≈ 1.15345.
pub fn viscoelastic_c1() -> f64 {
    use std::f64::consts::PI;
    libm::tgamma(0.6) * PI.sqrt() / (2f64.powf(0.2) * 5f64.powf(0.4) * libm::tgamma(2.1))
}

/// δ = A (k/m)^(2/5) v^(1/5) for which the series
/// e = 1 − C₁ δ' + (3/5) C₁² δ'², δ' = (3/2) δ, gives `e` (the root on the
/// branch through δ = 0; NaN below e = 1 − 1/2.4, where it has none).
pub fn series_delta(e: f64) -> f64 {
    let x = (1.0 - (1.0 - 2.4 * (1.0 - e)).sqrt()) / 1.2;
    x / (1.5 * viscoelastic_c1())
}

/// F_d = (3/2) k A |h|^(1/2) ḣ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viscoelastic {
    /// A, s.
    pub coefficient: f64,
    /// (3/2) k A, N s/m^(3/2).
    rate_stiffness: f64,
    /// k, N/m^(3/2).
    stiffness: f64,
}

impl DampingSubModel for Viscoelastic {
    fn new(setup: &DampingSetup) -> Self {
        let (k, m) = (setup.stiffness, setup.mass);
        let coefficient = match setup.dissipation {
            Dissipation::Coefficient(a) => a,
            Dissipation::Restitution(e) if e >= 1.0 => 0.0,
            Dissipation::Restitution(e) => {
                let v = setup.reference_speed.unwrap_or(f64::NAN);
                series_delta(e) * (m / k).powf(0.4) * v.powf(-0.2)
            }
        };
        Self {
            coefficient,
            rate_stiffness: 1.5 * k * coefficient,
            stiffness: k,
        }
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64) -> f64 {
        self.rate_stiffness * overlap.abs().sqrt() * overlap_rate
    }

    /// (3/2) k A times `factor`; A, and the k of [`Self::time_factor`], unchanged.
    fn scaled(&self, factor: f64) -> Self {
        Self {
            rate_stiffness: self.rate_stiffness * factor,
            ..*self
        }
    }

    /// 1 up to an equivalent damping ratio ξ = 1/√2, 1/(√2 ξ) beyond
    /// ([`heavy_damping_scale`]); ξ is Tsuji's γ h^(1/4)/(√5 √(k m)) with
    /// the damping rate (3/2) k A h^(1/2)/m of this law at the elastic h_max:
    /// ξ = (3/2) A ω_h/√5, ω_h = √(k/m) h_max^(1/4) (as the bounce study).
    fn time_factor(&self, mass: f64, impact_speed: f64) -> f64 {
        let (h_max, _) = power_law_free_contact(self.stiffness, 1.5, mass, impact_speed);
        let omega_h = (self.stiffness / mass).sqrt() * h_max.powf(0.25);
        heavy_damping_scale(1.5 * self.coefficient * omega_h / 5f64.sqrt())
    }

    /// A target restitution needs the formula calibration, a reference
    /// impact speed and e ≥ [`FORMULA_MIN_RESTITUTION`].
    fn check(
        dissipation: Dissipation,
        calibration: Calibration,
        reference_speed: Option<f64>,
    ) -> Result<(), PhysicsError> {
        let Dissipation::Restitution(e) = dissipation else {
            return Ok(());
        };
        if calibration == Calibration::Exact {
            return Err(PhysicsError::new(
                "contact.calibration",
                "\"exact\"",
                "\"formula\" with damping = \"viscoelastic\" and contact.restitution \
                 (this crate has no exact viscoelastic calibration; or give \
                 contact.damping_coefficient A in s)",
            ));
        }
        match reference_speed {
            Some(v) if v.is_finite() && v > 0.0 => {}
            other => {
                return Err(PhysicsError::new(
                    "contact.reference_speed",
                    other.map_or("missing".to_string(), |v| format!("{v} m/s")),
                    "finite and > 0 m/s with damping = \"viscoelastic\" and contact.restitution \
                     (A is solved for at that impact speed)",
                ))
            }
        }
        if e < FORMULA_MIN_RESTITUTION {
            return Err(PhysicsError::new(
                "contact.restitution",
                e,
                format!(
                    "{FORMULA_MIN_RESTITUTION} ≤ e ≤ 1 with damping = \"viscoelastic\" \
                     (the series calibration's range; give contact.damping_coefficient A in s \
                     for stronger damping)"
                ),
            ));
        }
        Ok(())
    }
}
