//! The paper's 5th-order Gear predictor–corrector (eqs 18–19).
//!
//! State: the Nordsieck vector scaled by the step,
//! r_k = Δt^k x⁽ᵏ⁾/k!, k = 0..5 (x, v, a, b3, b4, b5 of the paper).
//! Predictor (eq 18): the Taylor series, i.e. multiplication by Pascal's
//! triangle. Corrector (eq 19): with Δ = Δt² a(x_p, v_p)/2 − r₂ᵖ,
//! r_k ← r_kᵖ + c_k Δ, where for second-order equations
//! c = (3/16, 251/360, 1, 11/18, 1/6, 1/60), and c₀ = 3/20 when the force
//! depends on the velocity (Allen & Tildesley, *Computer Simulation of
//! Liquids*, 1987, appendix E, table E.2; Gear 1966).
//!
//! Written by hand because the scheme is what the paper studies and its
//! per-step cost is the project's hot path.

use super::{keep_scalar, DenseOutput, Gear5FreeFall, Integrator, Kinematics};

pub use dembound_physics::integrate::gear5::{pascal, Gear5};

/// The bounce's scalar state built on the physics crate's [`Gear5`]
/// coefficients (one copy of them and of the Pascal predictor).
trait ScalarGear5 {
    fn state(&self, r: [f64; 6], dt: f64) -> Gear5State;
    fn apply(&self, r: &mut [f64; 6], next: &mut [f64; 6], delta: f64);
}

impl ScalarGear5 for Gear5 {
    fn state(&self, r: [f64; 6], dt: f64) -> Gear5State {
        let half_dt2 = 0.5 * dt * dt;
        Gear5State {
            r,
            dt,
            half_dt2,
            inv_dt: 1.0 / dt,
            gain: self.predicted_corrector[0] * half_dt2,
            next: pascal(&r),
        }
    }

    /// The corrector, r_k += c_k Δ, and its image in the next prediction,
    /// next_k += (P c)_k Δ for k ≥ 1 (the caller sets next₀).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // indices unroll; iterator chains did not (2× the instructions)
    fn apply(&self, r: &mut [f64; 6], next: &mut [f64; 6], delta: f64) {
        for k in 0..6 {
            r[k] += self.corrector[k] * delta;
        }
        for k in 1..6 {
            next[k] += self.predicted_corrector[k] * delta;
        }
    }
}

/// Scaled Nordsieck vector and the step it is scaled for.
///
/// Besides the corrected vector r the state carries the *next* predicted
/// vector, which is what keeps the latency chain from one force
/// evaluation to the next short. The predictor is linear: P(rᵖ + c Δ) =
/// P rᵖ + (P c) Δ, so P rᵖ is formed while the force is evaluated and
/// only one multiply–add per component follows Δ (instead of the corrector,
/// then Pascal's triangle, then the corrector's Δ for the next step). For
/// the position, with Δ = a Δt²/2 + D (D = c_g Δt²/2 − r₂ᵖ known before the
/// force), (P c)₀ Δ = (Σ c) D + G a with G = (Σ c) Δt²/2: a force already
/// multiplied by G ([`Integrator::step_scaled`]) is one addition away from
/// the next prediction. Same scheme as the textbook form; the rounding
/// differs from it by a few ulps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear5State {
    /// r_k = Δt^k x⁽ᵏ⁾/k!.
    pub r: [f64; 6],
    /// Δt, s.
    pub dt: f64,
    /// Δt²/2 and 1/Δt, cached.
    pub(crate) half_dt2: f64,
    pub(crate) inv_dt: f64,
    /// G = (Σ c_k) Δt²/2, the factor of [`Integrator::step_scaled`]'s force.
    pub(crate) gain: f64,
    /// The next predicted vector P r (between `predict` and `correct`: P rᵖ).
    pub(crate) next: [f64; 6],
}

const FACTORIAL: [f64; 6] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0];

impl Integrator for Gear5 {
    type State = Gear5State;
    type Dense = Gear5Dense;
    type FreeFall = Gear5FreeFall;

    fn name(&self) -> &'static str {
        "gear5"
    }

    fn free_fall(&self, state: Gear5State, acceleration: f64) -> Gear5FreeFall {
        Gear5FreeFall::new(*self, state, acceleration)
    }

    fn start(&self, derivatives: [f64; 6], dt: f64) -> Gear5State {
        let mut r = [0.0; 6];
        let mut power = 1.0;
        for k in 0..6 {
            r[k] = derivatives[k] * power / FACTORIAL[k];
            power *= dt;
        }
        self.state(r, dt)
    }

    /// Rescales r_k by (Δt'/Δt)^k in place (with the graded mesh this runs
    /// nearly every step of a contact's ends, so it avoids rebuilding and
    /// copying the whole state).
    #[inline(always)]
    fn set_step(&self, s: &mut Gear5State, dt: f64) {
        let ratio = dt / s.dt;
        let mut power = ratio;
        for k in 1..6 {
            s.r[k] *= power;
            power *= ratio;
        }
        s.dt = dt;
        s.half_dt2 = 0.5 * dt * dt;
        s.inv_dt = 1.0 / dt;
        s.gain = self.predicted_corrector[0] * s.half_dt2;
        s.next = pascal(&s.r);
    }

    fn step_size(&self, state: &Gear5State) -> f64 {
        state.dt
    }

    #[inline(always)]
    fn predict(&self, s: &mut Gear5State) -> (f64, f64) {
        s.r = s.next;
        // Off the critical path: the force evaluation runs meanwhile.
        s.next = pascal(&s.r);
        (s.r[0], s.r[1] * s.inv_dt)
    }

    #[inline(always)]
    fn correct(&self, s: &mut Gear5State, acceleration: f64) {
        let delta = acceleration * s.half_dt2 - s.r[2];
        self.apply(&mut s.r, &mut s.next, delta);
        s.next[0] += self.predicted_corrector[0] * delta;
    }

    fn force_gain(&self, s: &Gear5State) -> f64 {
        s.gain
    }

    /// See [`Gear5State`]: the next predicted x is (P rᵖ)₀ + (Σ c) D + f.
    /// (Written on local copies so that the state stays in registers.)
    #[inline(always)]
    fn step_scaled(&self, s: &mut Gear5State, c: f64, f: impl Fn(f64, f64) -> f64) {
        let mut r = s.next;
        let mut next = pascal(&r);
        // Known before the force: D = c Δt²/2 − r₂ᵖ.
        let base = c * s.half_dt2 - r[2];
        let next_x_base = next[0] + self.predicted_corrector[0] * base;
        let scaled = f(r[0], r[1] * s.inv_dt);
        let delta = scaled * self.inverse_sum + base;
        self.apply(&mut r, &mut next, delta);
        next[0] = keep_scalar(next_x_base + scaled);
        s.r = r;
        s.next = next;
    }

    /// `step_scaled` with the force multiplied by G here and c = 0 (the
    /// same step as `predict` then `correct`, on local copies).
    #[inline(always)]
    fn step(&self, s: &mut Gear5State, f: impl Fn(f64, f64) -> f64) {
        self.step_split(s, 0.0, f);
    }

    /// `step_scaled` with the force multiplied by G here.
    #[inline(always)]
    fn step_split(&self, s: &mut Gear5State, c: f64, f: impl Fn(f64, f64) -> f64) {
        let gain = s.gain;
        self.step_scaled(s, c, |x, v| gain * f(x, v));
    }

    fn kinematics(&self, s: &Gear5State) -> Kinematics {
        Kinematics {
            position: s.r[0],
            velocity: s.r[1] * s.inv_dt,
            acceleration: s.r[2] / s.half_dt2,
        }
    }

    /// The Nordsieck polynomial of the corrected end state, evaluated
    /// backwards over the step: exact at the end (where the event was
    /// detected) and of the scheme's own order inside the step.
    fn dense(&self, _before: &Gear5State, after: &Gear5State) -> Gear5Dense {
        Gear5Dense { end: *after }
    }
}

/// Nordsieck polynomial of the state at the end of a step.
#[derive(Debug, Clone, Copy)]
pub struct Gear5Dense {
    end: Gear5State,
}

impl DenseOutput for Gear5Dense {
    fn at(&self, theta: f64) -> Kinematics {
        let s = theta - 1.0;
        let r = &self.end.r;
        let x = r[0] + s * (r[1] + s * (r[2] + s * (r[3] + s * (r[4] + s * r[5]))));
        let v = r[1] + s * (2.0 * r[2] + s * (3.0 * r[3] + s * (4.0 * r[4] + s * 5.0 * r[5])));
        let a = 2.0 * r[2] + s * (6.0 * r[3] + s * (12.0 * r[4] + s * 20.0 * r[5]));
        let dt = self.end.dt;
        Kinematics {
            position: x,
            velocity: v / dt,
            acceleration: a / (dt * dt),
        }
    }

    fn step_size(&self) -> f64 {
        self.end.dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_oscillator_half_period_error_is_fifth_order_small() {
        // x'' = −x from x = 0, v = 1 with exact initial derivatives: after half a
        // period (50 steps) x = 0, v = −1 exactly. A Gear scheme with local
        // error O(Δt⁶) gives a global error ~ C (ω Δt)⁵ with C well below 1;
        // (π/50)⁵ ≈ 1e−6, so 1e−7 absolute would fail for a wrong coefficient
        // (those give O(Δt²) or worse, ~1e−3).
        let g = Gear5::POSITION_DEPENDENT;
        let n = 50;
        let dt = std::f64::consts::PI / n as f64;
        let mut s = g.start([0.0, 1.0, 0.0, -1.0, 0.0, 1.0], dt);
        for _ in 0..n {
            g.step(&mut s, |x, _| -x);
        }
        let k = g.kinematics(&s);
        assert!(k.position.abs() < 1e-7, "{k:?}");
        assert!((k.velocity + 1.0).abs() < 1e-7, "{k:?}");
    }

    #[test]
    fn constant_acceleration_is_integrated_exactly() {
        // Free flight: a polynomial of degree 2 lies in the scheme's exact space.
        let g = Gear5::POSITION_DEPENDENT;
        let dt = 1e-3;
        let mut s = g.start([5e-3, 0.0, -9.81, 0.0, 0.0, 0.0], dt);
        for _ in 0..10 {
            g.step(&mut s, |_, _| -9.81);
        }
        let t: f64 = 1e-2;
        let k = g.kinematics(&s);
        assert!((k.position - (5e-3 - 0.5 * 9.81 * t * t)).abs() < 1e-17);
        assert!((k.velocity + 9.81 * t).abs() < 1e-15);
    }

    #[test]
    fn rescaling_preserves_the_derivatives() {
        let g = Gear5::POSITION_DEPENDENT;
        let d = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let mut s = g.start(d, 0.1);
        g.set_step(&mut s, 0.03);
        let t = g.start(d, 0.03);
        for k in 0..6 {
            assert!((s.r[k] / t.r[k] - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn dense_output_matches_both_ends() {
        let g = Gear5::POSITION_DEPENDENT;
        let dt = 0.05;
        let mut s = g.start([0.0, 1.0, 0.0, -1.0, 0.0, 1.0], dt);
        let before = s;
        g.step(&mut s, |x, _| -x);
        let d = g.dense(&before, &s);
        assert_eq!(d.at(1.0).position, s.r[0]);
        // At θ = 0 the backward polynomial reproduces the start to the
        // scheme's local error, O(Δt⁶) ≈ 1e−8.
        assert!(d.at(0.0).position.abs() < 1e-9);
        assert!((d.at(0.0).velocity - 1.0).abs() < 1e-8);
        // Inside the step it follows sin t.
        assert!((d.at(0.5).position - (0.5 * dt).sin()).abs() < 1e-10);
    }
}
