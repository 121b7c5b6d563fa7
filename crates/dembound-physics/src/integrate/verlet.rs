//! Velocity Verlet (Swope et al. 1982), the scheme of LAMMPS and LIGGGHTS:
//! x₁ = x₀ + Δt (v₀ + Δt a₀/2), v_½ = v₀ + Δt a₀/2, a₁ = f(x₁, v_½),
//! v₁ = v_½ + Δt a₁/2. Second order; the force sees the half-step velocity.

use super::{Integrator, Kinematics, State};

/// Velocity Verlet.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Verlet;

/// Verlet's half kick v + `scale` · `rate`: (Δt/2) a, or (Δt/2m) F in a
/// many-body loop that keeps forces (LAMMPS `nve` scales the force by
/// dtf/m, one rounding fewer than forming a first). Any state: the bounce's
/// scalar, a body's 3-vector ([`super::Vec3`]: the scene engine's kicks).
#[inline(always)]
pub fn half_kick<S: State>(v: S, rate: S, scale: f64) -> S {
    v + rate * scale
}

/// Verlet's drift x + Δt v (v the half-step velocity).
#[inline(always)]
pub fn drift<S: State>(x: S, v: S, dt: f64) -> S {
    x + v * dt
}

/// Verlet's state: x, v, a and the step size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VerletStep<S> {
    /// Position.
    pub x: S,
    /// Velocity (after `predict`: the half-step velocity).
    pub v: S,
    /// Acceleration.
    pub a: S,
    /// Step size, s.
    pub dt: f64,
}

impl<S: State> Integrator<S> for Verlet {
    type Step = VerletStep<S>;

    fn start(&self, d: [S; 6], dt: f64) -> VerletStep<S> {
        VerletStep {
            x: d[0],
            v: d[1],
            a: d[2],
            dt,
        }
    }

    fn set_step(&self, step: &mut VerletStep<S>, dt: f64) {
        step.dt = dt;
    }

    /// x₁ = x₀ + Δt (v₀ + (Δt/2) a₀), v_½ = v₀ + (Δt/2) a₀.
    #[inline(always)]
    fn predict(&self, s: &mut VerletStep<S>) -> (S, S) {
        s.v = half_kick(s.v, s.a, 0.5 * s.dt);
        s.x = drift(s.x, s.v, s.dt);
        (s.x, s.v)
    }

    /// v₁ = v_½ + (Δt/2) a₁.
    #[inline(always)]
    fn correct(&self, s: &mut VerletStep<S>, acceleration: S) {
        s.a = acceleration;
        s.v = half_kick(s.v, acceleration, 0.5 * s.dt);
    }

    fn kinematics(&self, s: &VerletStep<S>) -> Kinematics<S> {
        Kinematics {
            position: s.x,
            velocity: s.v,
            acceleration: s.a,
        }
    }
}
