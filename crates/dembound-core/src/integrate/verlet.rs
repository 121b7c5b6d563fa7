//! Velocity Verlet, the baseline scheme of LAMMPS and LIGGGHTS:
//! x ← x + v Δt + a Δt²/2, v ← v + a Δt/2, a ← f(x, v), v ← v + a Δt/2.
//! The force is evaluated with the half-step velocity, as LAMMPS does for
//! velocity-dependent (damped) contacts. Dense output is the cubic Hermite
//! polynomial through (x, v) at both ends of the step.
//!
//! Written for latency: the state carries the next position, so that
//! x_{n+2} = (x_{n+1} + Δt v_{n+1/2} + Δt² c) + Δt² a_{n+1}: a multiply and
//! an add after the force (the textbook order has +c, ×Δt/2, +v, ×Δt, +x).

use super::{keep_scalar, DenseOutput, Integrator, Kinematics, VerletFreeFall};

/// Velocity Verlet (second order, symplectic).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Verlet;

/// Position, velocity and acceleration, and the step size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerletState {
    pub x: f64,
    pub v: f64,
    pub a: f64,
    pub dt: f64,
    /// Δt².
    pub(crate) gain: f64,
    /// x + Δt (v + a Δt/2): the next step's position.
    pub(crate) next_x: f64,
}

impl VerletState {
    fn new(x: f64, v: f64, a: f64, dt: f64) -> Self {
        VerletState {
            x,
            v,
            a,
            dt,
            gain: dt * dt,
            next_x: x + dt * (v + 0.5 * dt * a),
        }
    }
}

impl Integrator for Verlet {
    type State = VerletState;
    type Dense = HermiteDense;
    type FreeFall = VerletFreeFall;

    fn name(&self) -> &'static str {
        "verlet"
    }

    fn free_fall(&self, state: VerletState, acceleration: f64) -> VerletFreeFall {
        VerletFreeFall::new(state, acceleration)
    }

    fn start(&self, d: [f64; 6], dt: f64) -> VerletState {
        VerletState::new(d[0], d[1], d[2], dt)
    }

    fn set_step(&self, state: &mut VerletState, dt: f64) {
        *state = VerletState::new(state.x, state.v, state.a, dt);
    }

    fn step_size(&self, state: &VerletState) -> f64 {
        state.dt
    }

    #[inline(always)]
    fn predict(&self, s: &mut VerletState) -> (f64, f64) {
        s.x = s.next_x;
        s.v += 0.5 * s.dt * s.a;
        (s.x, s.v)
    }

    #[inline(always)]
    fn correct(&self, s: &mut VerletState, acceleration: f64) {
        s.a = acceleration;
        s.v += 0.5 * s.dt * acceleration;
        s.next_x = s.x + s.dt * (s.v + 0.5 * s.dt * acceleration);
    }

    /// x_{n+2} = (x_{n+1} + Δt v_{n+1/2} + Δt² c) + Δt² a_{n+1} (see the
    /// module doc); the same step as `predict` then `correct`, the rounding
    /// differs by a few ulps. (The gain Δt² is not folded into the law:
    /// that saves one multiplication on the chain but costs a division per
    /// step-size change, and the graded mesh changes it nearly every step.)
    #[inline(always)]
    fn step_split(&self, s: &mut VerletState, c: f64, f: impl Fn(f64, f64) -> f64) {
        let x = s.next_x;
        let v_half = s.v + 0.5 * s.dt * s.a;
        let next_x_base = (x + s.dt * v_half) + s.gain * c;
        let contact = f(x, v_half);
        let a = contact + c;
        s.x = x;
        s.a = a;
        s.v = v_half + 0.5 * s.dt * a;
        s.next_x = keep_scalar(next_x_base + s.gain * contact);
    }

    #[inline(always)]
    fn step(&self, s: &mut VerletState, f: impl Fn(f64, f64) -> f64) {
        self.step_split(s, 0.0, f);
    }

    fn kinematics(&self, s: &VerletState) -> Kinematics {
        Kinematics {
            position: s.x,
            velocity: s.v,
            acceleration: s.a,
        }
    }

    fn dense(&self, before: &VerletState, after: &VerletState) -> HermiteDense {
        HermiteDense {
            x0: before.x,
            v0: before.v,
            x1: after.x,
            v1: after.v,
            dt: after.dt,
        }
    }
}

/// Cubic Hermite interpolant through (x₀, v₀) and (x₁, v₁).
#[derive(Debug, Clone, Copy)]
pub struct HermiteDense {
    x0: f64,
    v0: f64,
    x1: f64,
    v1: f64,
    dt: f64,
}

impl DenseOutput for HermiteDense {
    fn at(&self, t: f64) -> Kinematics {
        let (h, m0, m1) = (self.dt, self.v0 * self.dt, self.v1 * self.dt);
        let (t2, t3) = (t * t, t * t * t);
        let x = (2.0 * t3 - 3.0 * t2 + 1.0) * self.x0
            + (t3 - 2.0 * t2 + t) * m0
            + (-2.0 * t3 + 3.0 * t2) * self.x1
            + (t3 - t2) * m1;
        let dx = (6.0 * t2 - 6.0 * t) * self.x0
            + (3.0 * t2 - 4.0 * t + 1.0) * m0
            + (-6.0 * t2 + 6.0 * t) * self.x1
            + (3.0 * t2 - 2.0 * t) * m1;
        let ddx = (12.0 * t - 6.0) * self.x0
            + (6.0 * t - 4.0) * m0
            + (-12.0 * t + 6.0) * self.x1
            + (6.0 * t - 2.0) * m1;
        Kinematics {
            position: x,
            velocity: dx / h,
            acceleration: ddx / (h * h),
        }
    }

    fn step_size(&self) -> f64 {
        self.dt
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_oscillator_is_second_order() {
        // Global error of velocity Verlet on x'' = −x is ~ (ωΔt)²/24·t; halving Δt
        // must divide the error by ~4 (between 3.5 and 4.5 allows for rounding).
        let err = |n: usize| {
            let dt = std::f64::consts::PI / n as f64;
            let mut s = Verlet.start([0.0, 1.0, 0.0, 0.0, 0.0, 0.0], dt);
            for _ in 0..n {
                Verlet.step(&mut s, |x, _| -x);
            }
            (s.v + 1.0).abs() + s.x.abs()
        };
        let ratio = err(100) / err(200);
        assert!((3.5..4.5).contains(&ratio), "{ratio}");
    }

    #[test]
    fn hermite_reproduces_cubics() {
        // x(t) = t³ − t on [0, 2]: a cubic is reproduced exactly by the interpolant.
        let d = HermiteDense {
            x0: 0.0,
            v0: -1.0,
            x1: 6.0,
            v1: 11.0,
            dt: 2.0,
        };
        let k = d.at(0.25);
        assert!((k.position - (0.125 - 0.5)).abs() < 1e-14);
        assert!((k.velocity - (3.0 * 0.25 - 1.0)).abs() < 1e-14);
        assert!((k.acceleration - 3.0).abs() < 1e-14);
    }
}
