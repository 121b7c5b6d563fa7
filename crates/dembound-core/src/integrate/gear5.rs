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

use super::{DenseOutput, Integrator, Kinematics};

/// 5th-order Gear predictor–corrector for second-order equations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear5 {
    /// Corrector coefficients c₀..c₅.
    pub(crate) corrector: [f64; 6],
    /// Σ c_k and Σ k c_k (see [`Gear5State`]).
    pub(crate) corrector_sums: [f64; 2],
}

const fn gear5(c0: f64) -> Gear5 {
    let c = [c0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0];
    Gear5 {
        corrector: c,
        corrector_sums: [
            c[0] + c[1] + c[2] + c[3] + c[4] + c[5],
            c[1] + 2.0 * c[2] + 3.0 * c[3] + 4.0 * c[4] + 5.0 * c[5],
        ],
    }
}

impl Gear5 {
    /// For forces that depend on position only (c₀ = 3/16).
    pub const POSITION_DEPENDENT: Gear5 = gear5(3.0 / 16.0);
    /// For forces that also depend on velocity (c₀ = 3/20).
    pub const VELOCITY_DEPENDENT: Gear5 = gear5(3.0 / 20.0);

    /// The right coefficients for a force that does or does not depend on velocity.
    pub fn for_force(depends_on_velocity: bool) -> Self {
        if depends_on_velocity {
            Self::VELOCITY_DEPENDENT
        } else {
            Self::POSITION_DEPENDENT
        }
    }
}

/// Scaled Nordsieck vector and the step it is scaled for.
///
/// Besides r₀..r₅ the state carries the *next* predicted position and
/// velocity. After a correction r_k = r_kᵖ + c_k Δ, the next prediction is
/// Σ_k r_k = Σ_k r_kᵖ + (Σ_k c_k) Δ; the first sum is known before the force
/// is evaluated, so only one multiply–add separates Δ from the next force
/// evaluation (instead of a chain of five additions). Same scheme, shorter
/// latency chain; the rounding differs from the naive sum by a few ulps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear5State {
    /// r_k = Δt^k x⁽ᵏ⁾/k!.
    pub r: [f64; 6],
    /// Δt, s.
    pub dt: f64,
    /// Δt²/2 and 1/Δt, cached.
    pub(crate) half_dt2: f64,
    pub(crate) inv_dt: f64,
    /// Σ r_kᵖ and Σ k r_kᵖ of the current prediction (x and Δt·ẋ before correction).
    pub(crate) predicted_sums: [f64; 2],
    /// x and Δt·ẋ that the next prediction will give.
    pub(crate) next: [f64; 2],
}

impl Gear5State {
    fn new(r: [f64; 6], dt: f64) -> Self {
        let mut s = Gear5State {
            r,
            dt,
            half_dt2: 0.5 * dt * dt,
            inv_dt: 1.0 / dt,
            predicted_sums: [0.0; 2],
            next: [0.0; 2],
        };
        s.next = pascal_sums(&s.r);
        s
    }
}

/// x and Δt·ẋ of the Taylor prediction from `r`: Σ r_k and Σ k r_k.
#[inline(always)]
pub(crate) fn pascal_sums(r: &[f64; 6]) -> [f64; 2] {
    [
        ((r[0] + r[1]) + (r[2] + r[3])) + (r[4] + r[5]),
        (r[1] + 2.0 * r[2]) + (3.0 * r[3] + 4.0 * r[4]) + 5.0 * r[5],
    ]
}

const FACTORIAL: [f64; 6] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0];

impl Integrator for Gear5 {
    type State = Gear5State;
    type Dense = Gear5Dense;

    fn name(&self) -> &'static str {
        "gear5"
    }

    fn start(&self, derivatives: [f64; 6], dt: f64) -> Gear5State {
        let mut r = [0.0; 6];
        let mut power = 1.0;
        for k in 0..6 {
            r[k] = derivatives[k] * power / FACTORIAL[k];
            power *= dt;
        }
        Gear5State::new(r, dt)
    }

    fn set_step(&self, state: &mut Gear5State, dt: f64) {
        let ratio = dt / state.dt;
        let mut power = ratio;
        for k in 1..6 {
            state.r[k] *= power;
            power *= ratio;
        }
        *state = Gear5State::new(state.r, dt);
    }

    fn step_size(&self, state: &Gear5State) -> f64 {
        state.dt
    }

    #[inline(always)]
    fn predict(&self, s: &mut Gear5State) -> (f64, f64) {
        let [_, _, r2, r3, r4, r5] = s.r;
        let [x, v_dt] = s.next;
        s.r = [
            x,
            v_dt,
            r2 + 3.0 * r3 + 6.0 * r4 + 10.0 * r5,
            r3 + 4.0 * r4 + 10.0 * r5,
            r4 + 5.0 * r5,
            r5,
        ];
        // Off the critical path: the force evaluation runs meanwhile.
        s.predicted_sums = pascal_sums(&s.r);
        (x, v_dt * s.inv_dt)
    }

    #[inline(always)]
    fn correct(&self, s: &mut Gear5State, acceleration: f64) {
        let delta = acceleration * s.half_dt2 - s.r[2];
        for k in 0..6 {
            s.r[k] += self.corrector[k] * delta;
        }
        s.next = [
            s.predicted_sums[0] + self.corrector_sums[0] * delta,
            s.predicted_sums[1] + self.corrector_sums[1] * delta,
        ];
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
