//! The 5th-order Gear predictor–corrector (paper eqs 18–19; Allen &
//! Tildesley, *Computer Simulation of Liquids*, §3.2) in Nordsieck form:
//! the state is rₖ = Δtᵏ x⁽ᵏ⁾/k!, k = 0…5. The predictor is the Pascal
//! matrix (a Taylor step); the corrector adds cₖ Δ with
//! Δ = (Δt²/2) a(x_p, v_p) − r₂ᵖ.
//!
//! Corrector coefficients (Gear 1971): c = (3/16, 251/360, 1, 11/18, 1/6,
//! 1/60) for forces that depend on the position only, c₀ = 3/20 when they
//! depend on the velocity too.

use super::{Integrator, Kinematics, State};
use std::ops::{Add, Mul};

/// The Gear5 coefficients of one force type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear5 {
    /// Corrector coefficients cₖ.
    pub corrector: [f64; 6],
    /// The corrector carried through the next prediction, P c (so that a
    /// fused step can form the next predicted vector as P rᵖ + (P c) Δ).
    pub predicted_corrector: [f64; 6],
    /// 1/(P c)₀.
    pub inverse_sum: f64,
}

/// Gear5 with corrector coefficient c₀ (the others are fixed).
pub const fn gear5(c0: f64) -> Gear5 {
    let c = [c0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0];
    let pc = [
        ((c[0] + c[1]) + (c[2] + c[3])) + (c[4] + c[5]),
        ((c[1] + 2.0 * c[2]) + (3.0 * c[3] + 4.0 * c[4])) + 5.0 * c[5],
        (c[2] + 3.0 * c[3]) + (6.0 * c[4] + 10.0 * c[5]),
        (c[3] + 4.0 * c[4]) + 10.0 * c[5],
        c[4] + 5.0 * c[5],
        c[5],
    ];
    Gear5 {
        corrector: c,
        predicted_corrector: pc,
        inverse_sum: 1.0 / pc[0],
    }
}

impl Gear5 {
    /// c₀ = 3/16: forces of the position only.
    pub const POSITION_DEPENDENT: Gear5 = gear5(3.0 / 16.0);
    /// c₀ = 3/20: forces that depend on the velocity too.
    pub const VELOCITY_DEPENDENT: Gear5 = gear5(3.0 / 20.0);

    /// The coefficients for a force that does or does not depend on the velocity.
    pub fn for_force(depends_on_velocity: bool) -> Self {
        if depends_on_velocity {
            Self::VELOCITY_DEPENDENT
        } else {
            Self::POSITION_DEPENDENT
        }
    }
}

/// Gear's corrector coefficients for a first-order equation ẏ = f(y) with
/// five values, the Nordsieck vector rₖ = Δtᵏ y⁽ᵏ⁾/k!, k = 0…4 (Gear 1971;
/// Allen & Tildesley, *Computer Simulation of Liquids*, 1987, appendix E,
/// table E.1): c = (251/720, 1, 11/12, 1/3, 1/24), applied as rₖ += cₖ Δ
/// with Δ = Δt f(yᵖ) − r₁ᵖ after the same Pascal predictor. They are the
/// velocity part of the second-order corrector above (c₁…c₅ = 251/360,
/// 1, 11/18, 1/6, 1/60 in the velocity's own scaling): a quantity
/// integrated with them behaves as Gear5's velocities do, with the same
/// stability for ẏ = λy (|λΔt| < 0.17 on the negative real axis, 0.23 on
/// the imaginary axis; the six-value set (95/288, 1, 25/24, 35/72, 5/48,
/// 1/120) of the same table: 0.09 and 0.12, found by iterating the
/// scheme on ẏ = λy). The scene engine integrates the spins with them
/// (dω/dt = τ/I), so that a sphere's spin and its centre's velocity are
/// advanced alike.
pub const FIRST_ORDER_CORRECTOR: [f64; 5] =
    [251.0 / 720.0, 1.0, 11.0 / 12.0, 1.0 / 3.0, 1.0 / 24.0];

/// The Pascal-matrix predictor P r (a Taylor step of the Nordsieck
/// vector), summed pairwise: the same bits for every state type, scalar or
/// SIMD lanes (the bounce's batch uses it on lane vectors).
#[inline(always)]
pub fn pascal<T>(r: &[T; 6]) -> [T; 6]
where
    T: Copy + Add<Output = T>,
    f64: Mul<T, Output = T>,
{
    [
        ((r[0] + r[1]) + (r[2] + r[3])) + (r[4] + r[5]),
        ((r[1] + 2.0 * r[2]) + (3.0 * r[3] + 4.0 * r[4])) + 5.0 * r[5],
        (r[2] + 3.0 * r[3]) + (6.0 * r[4] + 10.0 * r[5]),
        (r[3] + 4.0 * r[4]) + 10.0 * r[5],
        r[4] + 5.0 * r[5],
        r[5],
    ]
}

/// k! for k = 0…5.
const FACTORIAL: [f64; 6] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0];

/// Gear5's state: the Nordsieck vector, the next prediction and the step
/// size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear5Step<S> {
    /// rₖ = Δtᵏ x⁽ᵏ⁾/k!.
    pub r: [S; 6],
    /// The next predicted vector P r, kept up to date by the corrector as
    /// P rᵖ + (P c) Δ (the prediction then costs no Pascal sums on the
    /// critical path; the bounce's scalar loop relies on the same bits).
    next: [S; 6],
    /// Step size, s.
    pub dt: f64,
    /// Δt²/2.
    half_dt2: f64,
    /// 1/Δt.
    inv_dt: f64,
}

impl<S: State> Integrator<S> for Gear5
where
    f64: Mul<S, Output = S>,
{
    type Step = Gear5Step<S>;

    fn start(&self, derivatives: [S; 6], dt: f64) -> Gear5Step<S> {
        let mut power = 1.0;
        let r = std::array::from_fn(|k| {
            let rk = derivatives[k] * power / FACTORIAL[k];
            power *= dt;
            rk
        });
        Gear5Step {
            r,
            next: pascal(&r),
            dt,
            half_dt2: half_square(dt),
            inv_dt: 1.0 / dt,
        }
    }

    /// rₖ scaled by (Δt'/Δt)ᵏ.
    fn set_step(&self, s: &mut Gear5Step<S>, dt: f64) {
        let ratio = dt / s.dt;
        let mut power = ratio;
        for k in 1..6 {
            s.r[k] = s.r[k] * power;
            power *= ratio;
        }
        s.dt = dt;
        s.half_dt2 = half_square(dt);
        s.inv_dt = 1.0 / dt;
        s.next = pascal(&s.r);
    }

    #[inline(always)]
    fn predict(&self, s: &mut Gear5Step<S>) -> (S, S) {
        s.r = s.next;
        s.next = pascal(&s.r);
        (s.r[0], s.r[1] * s.inv_dt)
    }

    #[inline(always)]
    fn correct(&self, s: &mut Gear5Step<S>, acceleration: S) {
        let delta = acceleration * s.half_dt2 - s.r[2];
        for k in 0..6 {
            s.r[k] = s.r[k] + self.corrector[k] * delta;
            s.next[k] = s.next[k] + self.predicted_corrector[k] * delta;
        }
    }

    fn kinematics(&self, s: &Gear5Step<S>) -> Kinematics<S> {
        Kinematics {
            position: s.r[0],
            velocity: s.r[1] * s.inv_dt,
            acceleration: s.r[2] / s.half_dt2,
        }
    }
}

/// Δt²/2 (outside the generic impl, where `f64 * f64` would be read
/// through its `f64: Mul<S>` bound).
fn half_square(dt: f64) -> f64 {
    0.5 * dt * dt
}
