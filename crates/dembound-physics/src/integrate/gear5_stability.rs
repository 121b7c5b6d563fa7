//! Where Gear5 is stable on a damped contact: a closed-form bound on the
//! step from the contact's stiffness and damping rate.
//!
//! On the linearised contact ẍ = −ω² x − β ẋ (ω² = (∂F/∂h)/m, β =
//! (∂F/∂ḣ)/m) one Gear5 step maps the Nordsieck vector r to A r with
//! A = (I + c dᵀ) P: P the Pascal predictor, c the corrector
//! ([`Gear5::corrector`]) and dᵀ r = (Δt²/2) a(r₀, r₁/Δt) − r₂, i.e.
//! d = (−(ωΔt)²/2, −βΔt/2, −1, 0, 0, 0). Two of A's six eigenvalues follow
//! exp(λΔt) (λ = −β/2 ± √(β²/4 − ω²)); the four others are parasitic. As
//! Δt grows, one parasitic eigenvalue runs along the negative real axis
//! and leaves the unit circle through z = −1, for every damping ratio
//! ξ = β/(2ω) from 0 to ∞ (found by computing A's eigenvalues over
//! ξ = 0–5 with numpy; the other parasitic ones stay below 0.45 in
//! modulus there). The boundary is therefore det(I + A) = 0, and as P is
//! unit upper triangular and c dᵀ has rank one,
//!
//!   det(I + A) = det(I + P) (1 + dᵀ u),  u = P (I + P)⁻¹ c,
//!
//! which is linear in (ωΔt)² and βΔt: the step is stable for
//!
//!   (ωΔt)² u₀/2 + βΔt u₁/2 ≤ 1 − u₂,  i.e.  (ωΔt/W)² + βΔt/B ≤ 1.
//!
//! With c₀ = 3/20 (a rate-dependent force) u = (17/96, 551/720, 15/16):
//! W = √(12/17) = 0.8402 (the undamped oscillator) and B = 90/551 =
//! 0.1633 (pure damping: the corrector's interval on the negative real
//! axis, as [`super::gear5::FIRST_ORDER_CORRECTOR`]'s 0.17). With c₀ =
//! 3/16, W = √(30/47) = 0.7989 and the same B. For a strong damping the
//! bound is βΔt ≤ 0.163 whatever the stiffness: the contact's damping
//! rate, not its period, limits the step.
//!
//! Past the boundary the parasitic mode grows by |z| per step: the bounce
//! study's spring–dashpot with e = 0.01 (ξ = 0.83, attraction allowed)
//! rebounds with e = 0.0215 at η = 0.05 (|z| = 1.46) and 0.245 at η = 0.1
//! (|z| = 2.38), with exit 0 before this bound was applied (session 36;
//! the measured grid is in `dembound-core`'s `scenario::limits`).

use super::gear5::{pascal, Gear5};
use crate::contact::peak::Linearization;

/// Gear5's stability bound on ẍ = −ω² x − β ẋ: stable for
/// (ωΔt/W)² + βΔt/B ≤ 1 (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedStability {
    /// W: the largest ωΔt without damping.
    pub omega_step: f64,
    /// B: the largest βΔt without stiffness.
    pub rate_step: f64,
}

impl Gear5 {
    /// The stability bound of this corrector on a linear damped contact,
    /// from det(I + A) = 0 (module doc).
    pub fn damped_stability(&self) -> DampedStability {
        // (I + P) y = c by back substitution (I + P is upper triangular,
        // 2 on the diagonal), then u = P y.
        let c = self.corrector;
        let mut y = [0.0; 6];
        for i in (0..6).rev() {
            // Row i of I + P: 2 at i, C(j, i) at j > i.
            let mut s = c[i];
            for (j, yj) in y.iter().enumerate().skip(i + 1) {
                s -= binomial(j, i) * yj;
            }
            y[i] = s / 2.0;
        }
        let u = pascal(&y);
        let room = 1.0 - u[2];
        DampedStability {
            omega_step: (2.0 * room / u[0]).sqrt(),
            rate_step: 2.0 * room / u[1],
        }
    }
}

/// C(n, k) for n ≤ 5.
fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

impl DampedStability {
    /// (ωΔt/W)² + βΔt/B: ≤ 1 where the step is stable.
    pub fn index(&self, omega_dt: f64, rate_dt: f64) -> f64 {
        let w = omega_dt / self.omega_step;
        w * w + rate_dt / self.rate_step
    }

    /// The largest Δt (s) with [`Self::index`] ≤ 1 for angular frequency
    /// `omega` (rad/s) and damping rate `rate` (1/s): the positive root of
    /// (ω/W)² Δt² + (β/B) Δt = 1, written without cancellation. Infinite
    /// when both are 0.
    pub fn max_step(&self, omega: f64, rate: f64) -> f64 {
        let a = (omega / self.omega_step).powi(2);
        let b = rate / self.rate_step;
        // Δt = 2/(b + √(b² + 4a)).
        2.0 / (b + (b * b + 4.0 * a).sqrt())
    }
}

/// A step past a [`DampedStability`] bound on a contact linearised at
/// its largest overlap ([`DampedStability::check`]): what a refusal states.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnstableStep {
    /// The contact at its largest overlap.
    pub peak: Linearization,
    /// The scheme's bound.
    pub stability: DampedStability,
    /// The step, s.
    pub dt: f64,
    /// The largest stable step, s.
    pub dt_max: f64,
}

impl DampedStability {
    /// `Err` when `dt` (s) is past the bound on the contact `peak`. A NaN
    /// step passes: refusing it is the step rule's business.
    pub fn check(self, peak: Linearization, dt: f64) -> Result<(), UnstableStep> {
        let dt_max = self.max_step(peak.omega, peak.rate);
        if dt <= dt_max || dt.is_nan() {
            return Ok(());
        }
        Err(UnstableStep {
            peak,
            stability: self,
            dt,
            dt_max,
        })
    }
}

impl UnstableStep {
    /// (ωΔt/W)² + βΔt/B at the step (> 1).
    pub fn index(&self) -> f64 {
        let p = &self.peak;
        self.stability.index(p.omega * self.dt, p.rate * self.dt)
    }

    /// "at its largest overlap h = … m the contact's frequency ω = … rad/s
    /// and damping rate β = … 1/s (`damping`) give (ωΔt/W)² + βΔt/B = … > 1
    /// at Δt = … s, where the predictor–corrector is unstable and the
    /// rebound would be wrong": the refusal's reason, `damping` naming the
    /// setting that gives β.
    pub fn describe(&self, damping: &str) -> String {
        format!(
            "at its largest overlap h = {h:.4e} m the contact's frequency ω = {omega:.4e} rad/s \
             and damping rate β = {rate:.4e} 1/s ({damping}) give (ωΔt/{w:.4})² + βΔt/{b:.4} = \
             {index:.3} > 1 at Δt = {dt:.4e} s, where the predictor–corrector is unstable and \
             the rebound would be wrong",
            h = self.peak.overlap,
            omega = self.peak.omega,
            rate = self.peak.rate,
            w = self.stability.omega_step,
            b = self.stability.rate_step,
            index = self.index(),
            dt = self.dt,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Integrator, Kinematics};
    use super::*;

    #[test]
    fn bounds_are_the_closed_fractions() {
        // u = (17/96, 551/720, 15/16) for c₀ = 3/20 and (47/240, 551/720,
        // 15/16) for 3/16, solved by hand with exact fractions (Python's
        // `fractions`): W² = 2(1 − u₂)/u₀, B = 2(1 − u₂)/u₁. Only rounding
        // separates them (1e-14).
        let v = Gear5::VELOCITY_DEPENDENT.damped_stability();
        assert!(
            (v.omega_step / (12.0f64 / 17.0).sqrt() - 1.0).abs() < 1e-14,
            "{v:?}"
        );
        assert!((v.rate_step / (90.0 / 551.0) - 1.0).abs() < 1e-14, "{v:?}");
        let p = Gear5::POSITION_DEPENDENT.damped_stability();
        assert!(
            (p.omega_step / (30.0f64 / 47.0).sqrt() - 1.0).abs() < 1e-14,
            "{p:?}"
        );
        assert!((p.rate_step / (90.0 / 551.0) - 1.0).abs() < 1e-14, "{p:?}");
    }

    /// |x| + |ẋ|Δt after `n` steps of ẍ = −ω² x − β ẋ from x = 1.
    fn after(omega_dt: f64, rate_dt: f64, n: usize) -> f64 {
        let (omega, rate) = (omega_dt, rate_dt); // Δt = 1
        let gear = Gear5::VELOCITY_DEPENDENT;
        let mut s = gear.start([1.0, 0.0, -omega * omega, 0.0, 0.0, 0.0], 1.0);
        for _ in 0..n {
            gear.step(&mut s, |x, v| -omega * omega * x - rate * v);
        }
        let Kinematics {
            position, velocity, ..
        } = gear.kinematics(&s);
        position.abs() + velocity.abs()
    }

    #[test]
    fn iterating_the_scheme_decays_inside_the_bound_and_grows_outside() {
        // The scheme itself on the linear damped oscillator, for damping
        // ratios from light to overdamped, against the closed-form bound:
        // at 0.97 of the largest stable step the spectral radius of A is
        // 0.978–0.9984 (numpy's eigenvalues of the same matrix), so 20000
        // steps leave < e^(−32); at 1.03 the parasitic root passes −1.015
        // or beyond, > e^(300) over 20000 steps. A bound off by 3 % either
        // way fails one of the two.
        let stab = Gear5::VELOCITY_DEPENDENT.damped_stability();
        for xi in [0.1, 0.3, 0.5, 0.83, 1.0, 2.0, 5.0] {
            let dt = stab.max_step(1.0, 2.0 * xi);
            let (inside, outside) = (0.97 * dt, 1.03 * dt);
            let a = after(inside, 2.0 * xi * inside, 20_000);
            let b = after(outside, 2.0 * xi * outside, 20_000);
            assert!(a < 1e-6, "ξ = {xi}: {a} at 0.97 of Δt_max = {dt}");
            assert!(b > 1e6, "ξ = {xi}: {b} at 1.03 of Δt_max = {dt}");
        }
    }

    #[test]
    fn check_refuses_past_the_largest_step_only() {
        let stab = Gear5::VELOCITY_DEPENDENT.damped_stability();
        let peak = Linearization {
            overlap: 1e-6,
            omega: 1e6,
            rate: 2e6,
        };
        let dt_max = stab.max_step(peak.omega, peak.rate);
        assert_eq!(stab.check(peak, dt_max), Ok(()));
        assert_eq!(stab.check(peak, f64::NAN), Ok(()));
        let past = stab.check(peak, 1.01 * dt_max).expect_err("past the bound");
        assert_eq!(past.dt_max, dt_max);
        // Both terms grow with Δt: 1.01 Δt_max gives an index in (1.01, 1.0201).
        assert!(past.index() > 1.01 && past.index() < 1.0201, "{past:?}");
        let why = past.describe("contact.restitution = 0.01");
        assert!(
            why.contains("(contact.restitution = 0.01)") && why.contains("> 1"),
            "{why}"
        );
    }

    #[test]
    fn max_step_solves_the_index() {
        let stab = Gear5::VELOCITY_DEPENDENT.damped_stability();
        for (omega, rate) in [(1.0, 0.0), (0.0, 1.0), (3.0, 0.7), (2e6, 5e7)] {
            let dt = stab.max_step(omega, rate);
            let index = stab.index(omega * dt, rate * dt);
            assert!((index - 1.0).abs() < 1e-14, "{omega} {rate}: {index}");
        }
        assert_eq!(stab.max_step(0.0, 0.0), f64::INFINITY);
    }
}
