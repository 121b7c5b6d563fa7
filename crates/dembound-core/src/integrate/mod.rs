//! Time integrators behind one trait.
//!
//! A step is split in two phases, `predict` and `correct`, with the force
//! evaluated in between at the predicted position and velocity. A
//! many-body driver predicts every body, evaluates every pair force, then
//! corrects every body; the single bouncing particle does the same with one
//! body. Integrators never see the force law, gravity or events.
//!
//! Each integrator also provides dense output on the last step (its own
//! interpolating polynomial) so that events are located inside the step.

mod free_fall;
mod gear5;
mod verlet;

pub use free_fall::{FreeFall, Gear5FreeFall, Stepwise, VerletFreeFall};
pub use gear5::pascal;
pub use gear5::{Gear5, Gear5State};
pub use verlet::{Verlet, VerletState};

use serde::{Deserialize, Serialize};

/// Position, velocity and acceleration of one degree of freedom.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Kinematics {
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

/// A one-step integrator for ẍ = f(x, ẋ).
pub trait Integrator: Copy + Send + Sync + std::fmt::Debug {
    /// The integrator's per-degree-of-freedom state, including its step size.
    type State: Copy + std::fmt::Debug;
    /// Its interpolating polynomial over one step.
    type Dense: DenseOutput;
    /// Its free flight at a fixed step ([`Self::free_fall`]).
    type FreeFall: FreeFall<Self::State>;

    fn name(&self) -> &'static str;

    /// A state at a point where the derivatives are known:
    /// `derivatives` = [x, ẋ, ẍ, x⁽³⁾, x⁽⁴⁾, x⁽⁵⁾]; schemes that keep fewer
    /// use the leading ones.
    fn start(&self, derivatives: [f64; 6], dt: f64) -> Self::State;

    /// Changes the step size of `state` for the steps that follow.
    fn set_step(&self, state: &mut Self::State, dt: f64);

    /// The step size `state` is set up for, s.
    fn step_size(&self, state: &Self::State) -> f64;

    /// Phase 1: advance to t + Δt with the prediction; returns the position
    /// and velocity at which the force must be evaluated.
    fn predict(&self, state: &mut Self::State) -> (f64, f64);

    /// Phase 2: finish the step with the acceleration evaluated at the
    /// predicted point.
    fn correct(&self, state: &mut Self::State, acceleration: f64);

    /// Position, velocity and acceleration held by `state`.
    fn kinematics(&self, state: &Self::State) -> Kinematics;

    /// Interpolant over the step from `before` to `after` (θ = 0 at `before`,
    /// θ = 1 at `after`).
    fn dense(&self, before: &Self::State, after: &Self::State) -> Self::Dense;

    /// One whole step for a single body with acceleration `f(x, v)`.
    #[inline(always)]
    fn step(&self, state: &mut Self::State, f: impl Fn(f64, f64) -> f64) {
        let (x, v) = self.predict(state);
        self.correct(state, f(x, v));
    }

    /// One whole step for a single body with acceleration `f(x, v) + c`,
    /// `c` constant (−g): the same step as `step` with `|x, v| f(x, v) + c`,
    /// but a scheme may reassociate it to take `c` off the latency chain
    /// from one force to the next (Gear5 does; the rounding then differs
    /// by a few ulps).
    #[inline(always)]
    fn step_split(&self, state: &mut Self::State, c: f64, f: impl Fn(f64, f64) -> f64) {
        self.step(state, |x, v| f(x, v) + c);
    }

    /// Free flight from `state` under the constant `acceleration`: the
    /// states of repeated [`Self::step`] with `|_, _| acceleration`, bit for
    /// bit, at less cost where the scheme allows ([`free_fall`]).
    fn free_fall(&self, state: Self::State, acceleration: f64) -> Self::FreeFall;

    /// The factor G by which [`Self::step_scaled`] wants its force
    /// multiplied; it depends on the step size only. 1 by default.
    fn force_gain(&self, _state: &Self::State) -> f64 {
        1.0
    }

    /// `step_split` with `f` returning G × the acceleration, G =
    /// [`Self::force_gain`]: a caller that folds G into the law's constants
    /// (`NormalContactLaw::scaled`) once per step size saves the scheme a
    /// multiplication on the latency chain. Schemes whose G is not 1
    /// override it.
    #[inline(always)]
    fn step_scaled(&self, state: &mut Self::State, c: f64, f: impl Fn(f64, f64) -> f64) {
        self.step_split(state, c, f);
    }
}

/// `x`, opaque to the optimiser: keeps LLVM's SLP vectoriser from packing
/// the next predicted position into one vector addition with a value
/// that waits for the force (Gear5: the next predicted velocity, which
/// waits for Δ), which would put the corrector on the latency chain from
/// one force to the next (measured with `benches/steps.rs`: 12.1 → 7.8 ns/step for Hertz).
/// No instruction is emitted.
#[inline(always)]
pub(crate) fn keep_scalar(x: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        let mut x = x;
        // SAFETY: an empty template; it reads and writes one register and
        // touches no memory.
        unsafe {
            std::arch::asm!("/* {0} */", inout(xmm_reg) x, options(pure, nomem, nostack, preserves_flags));
        }
        x
    }
    #[cfg(not(target_arch = "x86_64"))]
    x
}

/// A polynomial over one step in the step fraction θ ∈ [0, 1].
pub trait DenseOutput {
    /// x(θ), ẋ(θ), ẍ(θ).
    fn at(&self, theta: f64) -> Kinematics;
    /// Length of the step, s.
    fn step_size(&self) -> f64;
}

/// Which integrator a scenario uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    /// 5th-order Gear predictor–corrector, the paper's scheme (eqs 18–19).
    Gear5,
    /// Velocity Verlet, the scheme of LAMMPS and LIGGGHTS.
    Verlet,
}

impl Scheme {
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::Gear5 => "gear5",
            Scheme::Verlet => "verlet",
        }
    }
}
