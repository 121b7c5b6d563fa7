//! Time integrators generic over the state they advance: one degree of
//! freedom (`f64`, the bounce), a 3-vector ([`Vec3`], one body) or a fixed
//! array of either ([`Bodies`], many bodies), or any type with the
//! [`State`] arithmetic.
//!
//! A step is two phases, as in a many-body loop: `predict` moves every
//! degree of freedom to t + Δt and returns where the force is to be
//! evaluated; `correct` finishes the step with the acceleration found
//! there. The integrators never see the force law, gravity or events.
//!
//! - [`gear5`]: the paper's 5th-order Gear predictor–corrector (eqs 18–19)
//!   in Nordsieck form, with the Pascal-matrix predictor;
//! - [`gear5_stability`]: the largest step Gear5 keeps stable on a damped
//!   contact, in closed form;
//! - [`verlet`]: velocity Verlet (LAMMPS, LIGGGHTS).
//!
//! The bounce study (`dembound-core`) takes its Gear5 coefficients and
//! predictor from here and keeps, beside them, a scalar step fused for
//! latency (the force gain folded into the law, the next prediction carried
//! in the state): a trick that pays off only for one degree of freedom on
//! a dependency chain, so it stays with the bounce. The scalar generic
//! step here gives the same bits as the bounce's predict/correct (test in
//! `dembound-core/tests/generic_integrators.rs`).

pub mod gear5;
pub mod gear5_stability;
pub mod verlet;

use std::ops::{Add, Div, Mul, Sub};

/// What an integrator advances: a vector space over f64 (addition,
/// subtraction, scaling by a real on either side), `Copy`.
pub trait State:
    Copy
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// The zero state.
    fn zero() -> Self;
}

impl State for f64 {
    fn zero() -> Self {
        0.0
    }
}

/// A 3-vector (one body's position, velocity or acceleration), m, m/s, m/s².
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec3(pub [f64; 3]);

/// `N` states side by side (`N` bodies, or `N` degrees of freedom):
/// element-wise arithmetic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bodies<T, const N: usize>(pub [T; N]);

impl Add for Vec3 {
    type Output = Vec3;
    #[inline(always)]
    fn add(self, o: Vec3) -> Vec3 {
        Vec3([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}

impl Sub for Vec3 {
    type Output = Vec3;
    #[inline(always)]
    fn sub(self, o: Vec3) -> Vec3 {
        Vec3([self.0[0] - o.0[0], self.0[1] - o.0[1], self.0[2] - o.0[2]])
    }
}

impl Mul<f64> for Vec3 {
    type Output = Vec3;
    #[inline(always)]
    fn mul(self, k: f64) -> Vec3 {
        Vec3([self.0[0] * k, self.0[1] * k, self.0[2] * k])
    }
}

impl Div<f64> for Vec3 {
    type Output = Vec3;
    #[inline(always)]
    fn div(self, k: f64) -> Vec3 {
        Vec3([self.0[0] / k, self.0[1] / k, self.0[2] / k])
    }
}

impl Mul<Vec3> for f64 {
    type Output = Vec3;
    #[inline(always)]
    fn mul(self, v: Vec3) -> Vec3 {
        v * self
    }
}

impl State for Vec3 {
    fn zero() -> Self {
        Vec3([0.0; 3])
    }
}

impl<T: State, const N: usize> Add for Bodies<T, N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Bodies(std::array::from_fn(|i| self.0[i] + o.0[i]))
    }
}

impl<T: State, const N: usize> Sub for Bodies<T, N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Bodies(std::array::from_fn(|i| self.0[i] - o.0[i]))
    }
}

impl<T: State, const N: usize> Mul<f64> for Bodies<T, N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, k: f64) -> Self {
        Bodies(std::array::from_fn(|i| self.0[i] * k))
    }
}

impl<T: State, const N: usize> Div<f64> for Bodies<T, N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, k: f64) -> Self {
        Bodies(std::array::from_fn(|i| self.0[i] / k))
    }
}

impl<T: State, const N: usize> Mul<Bodies<T, N>> for f64 {
    type Output = Bodies<T, N>;
    #[inline(always)]
    fn mul(self, b: Bodies<T, N>) -> Bodies<T, N> {
        b * self
    }
}

impl<T: State, const N: usize> State for Bodies<T, N> {
    fn zero() -> Self {
        Bodies([T::zero(); N])
    }
}

/// Position, velocity and acceleration held by an integrator's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics<S> {
    /// x.
    pub position: S,
    /// ẋ.
    pub velocity: S,
    /// ẍ.
    pub acceleration: S,
}

/// A one-step integrator of ẍ = f(x, ẋ) over states `S`.
pub trait Integrator<S: State>: Copy + std::fmt::Debug {
    /// The scheme's own state (its history and step size).
    type Step: Copy + std::fmt::Debug;

    /// A state at a point where x, ẋ, ẍ and, for schemes that keep them,
    /// the higher derivatives x⁽³⁾, x⁽⁴⁾, x⁽⁵⁾ are known (`derivatives`, in
    /// that order), for steps of `dt` (s).
    fn start(&self, derivatives: [S; 6], dt: f64) -> Self::Step;

    /// Changes the step size for the steps that follow.
    fn set_step(&self, step: &mut Self::Step, dt: f64);

    /// Phase 1: to t + Δt by the prediction; the position and velocity at
    /// which the force is to be evaluated.
    fn predict(&self, step: &mut Self::Step) -> (S, S);

    /// Phase 2: finish the step with the acceleration at the predicted point.
    fn correct(&self, step: &mut Self::Step, acceleration: S);

    /// Position, velocity and acceleration now.
    fn kinematics(&self, step: &Self::Step) -> Kinematics<S>;

    /// One whole step with acceleration `f(x, v)`.
    #[inline(always)]
    fn step(&self, step: &mut Self::Step, f: impl Fn(S, S) -> S) {
        let (x, v) = self.predict(step);
        self.correct(step, f(x, v));
    }
}

#[cfg(test)]
mod tests;
