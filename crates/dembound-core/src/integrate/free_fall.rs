//! Free flight, ẍ = a constant, stepped at a fixed Δt: the states that
//! repeated [`Integrator::step`] with `|_, _| a` gives, bit for bit, at
//! less cost where the scheme allows.
//!
//! Fixed stepping integrates the whole 5 mm fall and the flights between
//! the contacts at the contact's Δt (2.3·10⁸ steps for the linear law at
//! η = 1/2000), so this loop is most of `dembound paper`'s run time.
//!
//! **Gear5.** The predicted components r₂…r₅ and the corrector's Δ depend
//! on r₂…r₅ alone (Pascal's triangle is upper triangular, and with a
//! constant force Δ = G a/(Σc) − r₂ᵖ), so once one step leaves them
//! unchanged, bit for bit, they stay so for every later step. In free
//! flight that happens on the first step for most Δt (Δ rounds to 0 and
//! r₃…r₅ stay 0); where Δ does not round to 0 the full step goes on. From then on a step is the
//! same floating-point additions on x and ẋ with the same constants (the
//! sums of r₂…r₅ that Pascal's triangle adds, in its order), 9 additions
//! instead of ~45 operations. An addend that is +0 and followed by one
//! that is not −0 is left off as well ((y + 0) + b = y + b for every y
//! unless b = −0): where Δ rounds to 0 and r₃…r₅ are 0 that leaves 4
//! additions on the latency chain of x (5 before) and 2 on that of ẋ.
//!
//! **Velocity Verlet.** Its step adds Δt² c = +0 (c = 0: the constant is
//! the force here) to the position before the force's Δt² a; (y + 0) + K
//! is y + K for every y unless K = −0 (g = 0), so the free flight leaves
//! that addition off the position's latency chain (3 additions a step
//! there, 2 now) and takes the full step where K = −0.

use super::gear5::Gear5State;
use super::verlet::VerletState;
use super::{keep_scalar, Gear5, Integrator, Kinematics, Verlet};

/// A free flight in progress: [`Integrator::free_fall`].
pub trait FreeFall<S> {
    /// One step of Δt.
    fn step(&mut self);
    /// Position, velocity and acceleration now (as
    /// [`Integrator::kinematics`] of [`Self::state`]).
    fn kinematics(&self) -> Kinematics;
    /// The integrator's state now.
    fn state(&self) -> S;
}

/// The general free flight: [`Integrator::step`] with a constant force.
#[derive(Debug, Clone, Copy)]
pub struct Stepwise<I: Integrator> {
    integrator: I,
    state: I::State,
    acceleration: f64,
}

impl<I: Integrator> Stepwise<I> {
    pub fn new(integrator: I, state: I::State, acceleration: f64) -> Self {
        Stepwise {
            integrator,
            state,
            acceleration,
        }
    }
}

impl<I: Integrator> FreeFall<I::State> for Stepwise<I> {
    #[inline(always)]
    fn step(&mut self) {
        let a = self.acceleration;
        self.integrator.step(&mut self.state, |_, _| a);
    }

    #[inline(always)]
    fn kinematics(&self) -> Kinematics {
        self.integrator.kinematics(&self.state)
    }

    fn state(&self) -> I::State {
        self.state
    }
}

/// Gear5's free flight (see the module doc).
#[derive(Debug, Clone, Copy)]
pub struct Gear5FreeFall {
    integrator: Gear5,
    state: Gear5State,
    acceleration: f64,
    /// The constant addends once r₂…r₅ have settled, and whether the
    /// short form applies ([`Addends::short`]).
    settled: Option<(Addends, bool)>,
}

/// What a settled step adds to the predicted x and ẋ, each the value the
/// full step computes from the settled r₂ᵖ…r₅ᵖ and Δ.
#[derive(Debug, Clone, Copy)]
struct Addends {
    /// Predicted x: ((x + ẋ) + (r₂ + r₃)) + (r₄ + r₅), then + (P c)₀ D,
    /// then + G a (D = −r₂ᵖ, [`Gear5State`]).
    x: [f64; 4],
    /// Predicted ẋ: ((ẋ + 2 r₂) + (3 r₃ + 4 r₄)) + 5 r₅, then + (P c)₁ Δ.
    v: [f64; 4],
    /// The corrector's c₀ Δ and c₁ Δ (corrected x and ẋ from predicted).
    correct: [f64; 2],
}

impl Gear5FreeFall {
    pub fn new(integrator: Gear5, state: Gear5State, acceleration: f64) -> Self {
        Gear5FreeFall {
            integrator,
            state,
            acceleration,
            settled: None,
        }
    }

    /// The addends of a step from the predicted vector `p`, whose r₂…r₅
    /// are settled, with `Gear5::step_scaled`'s operations.
    fn addends(&self, p: &[f64; 6]) -> Addends {
        let (it, s) = (&self.integrator, &self.state);
        let pc = &it.predicted_corrector;
        let base = 0.0 * s.half_dt2 - p[2];
        let scaled = s.gain * self.acceleration;
        let delta = scaled * it.inverse_sum + base;
        Addends {
            x: [p[2] + p[3], p[4] + p[5], pc[0] * base, scaled],
            v: [
                2.0 * p[2],
                3.0 * p[3] + 4.0 * p[4],
                5.0 * p[5],
                pc[1] * delta,
            ],
            correct: [it.corrector[0] * delta, it.corrector[1] * delta],
        }
    }
}

impl Addends {
    /// The +0 addends of x and ẋ can be left off: r₃…r₅ are 0 and Δ is +0
    /// (x: r₄ + r₅ = +0 before (P c)₀ D ≠ −0; ẋ: 3 r₃ + 4 r₄ = 5 r₅ = +0
    /// before (P c)₁ Δ ≠ −0).
    fn short(&self) -> bool {
        let plus_zero = |a: f64| a.to_bits() == 0.0f64.to_bits();
        let minus_zero = |a: f64| a.to_bits() == (-0.0f64).to_bits();
        plus_zero(self.x[1])
            && !minus_zero(self.x[2])
            && plus_zero(self.v[1])
            && plus_zero(self.v[2])
            && !minus_zero(self.v[3])
    }
}

impl FreeFall<Gear5State> for Gear5FreeFall {
    #[inline(always)]
    fn step(&mut self) {
        let s = &mut self.state;
        if let Some((add, short)) = &self.settled {
            let [x, v] = [s.next[0], s.next[1]];
            s.r[0] = x + add.correct[0];
            s.r[1] = v + add.correct[1];
            if *short {
                s.next[0] = keep_scalar(((x + v) + add.x[0]) + add.x[2]) + add.x[3];
                s.next[1] = (v + add.v[0]) + add.v[3];
            } else {
                s.next[0] = keep_scalar((((x + v) + add.x[0]) + add.x[1]) + add.x[2]) + add.x[3];
                s.next[1] = (((v + add.v[0]) + add.v[1]) + add.v[2]) + add.v[3];
            }
            return;
        }
        let before = s.next;
        let a = self.acceleration;
        self.integrator.step(s, |_, _| a);
        let same = |k: usize| s.next[k].to_bits() == before[k].to_bits();
        if (2..6).all(same) {
            let next = s.next;
            let add = self.addends(&next);
            self.settled = Some((add, add.short()));
        }
    }

    #[inline(always)]
    fn kinematics(&self) -> Kinematics {
        self.integrator.kinematics(&self.state)
    }

    fn state(&self) -> Gear5State {
        self.state
    }
}

/// Velocity Verlet's free flight (see the module doc).
#[derive(Debug, Clone, Copy)]
pub struct VerletFreeFall {
    state: VerletState,
    acceleration: f64,
    /// Δt² a is not −0: the step's + Δt² c (= +0) can be left off.
    short: bool,
}

impl VerletFreeFall {
    pub fn new(state: VerletState, acceleration: f64) -> Self {
        let k = state.gain * acceleration;
        VerletFreeFall {
            state,
            acceleration,
            short: k.to_bits() != (-0.0f64).to_bits(),
        }
    }
}

impl FreeFall<VerletState> for VerletFreeFall {
    /// `Verlet::step_split` with c = 0 and the constant force, less the
    /// + Δt² c.
    #[inline(always)]
    fn step(&mut self) {
        let s = &mut self.state;
        let force = self.acceleration;
        if !self.short {
            Verlet.step(s, |_, _| force);
            return;
        }
        let x = s.next_x;
        let v_half = s.v + 0.5 * s.dt * s.a;
        let next_x_base = x + s.dt * v_half;
        let a = force + 0.0;
        s.x = x;
        s.a = a;
        s.v = v_half + 0.5 * s.dt * a;
        s.next_x = keep_scalar(next_x_base + s.gain * force);
    }

    #[inline(always)]
    fn kinematics(&self) -> Kinematics {
        Verlet.kinematics(&self.state)
    }

    fn state(&self) -> VerletState {
        self.state
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The free flight's state after every step against `Gear5::step` with
    /// the constant force, compared bit for bit; once settled, the full
    /// form of the settled step too (`long`).
    fn same_as_stepwise(dt: f64, steps: usize) -> bool {
        let it = Gear5::POSITION_DEPENDENT;
        let g = 9.81;
        let start = it.start([5e-3, 0.0, -g, 0.0, 0.0, 0.0], dt);
        let mut reference = Stepwise::new(it, start, -g);
        let mut fast = it.free_fall(start, -g);
        let mut long = fast;
        let bits = |s: &Gear5State| {
            let mut v: Vec<u64> = s.r.iter().chain(&s.next).map(|x| x.to_bits()).collect();
            v.extend([s.dt, s.half_dt2, s.inv_dt, s.gain].map(f64::to_bits));
            v
        };
        for _ in 0..steps {
            reference.step();
            fast.step();
            long.step();
            if let Some((_, short)) = &mut long.settled {
                *short = false;
            }
            let a = bits(&reference.state());
            if a != bits(&fast.state()) || a != bits(&long.state()) {
                return false;
            }
        }
        true
    }

    #[test]
    fn gear5_free_fall_is_the_stepwise_flight_bit_for_bit() {
        // Δt of the paper's runs (T_c ≈ 4.9 µs, η from 1/5 to 1/2000),
        // which settle on the first step, and 9.8e-7 s, where Δ does not
        // round to 0 and r₃…r₅ keep changing (no repeat in 3·10⁶ steps,
        // found by iterating the scheme): the full step throughout.
        for dt in [2.4e-9, 4.896e-6 / 2000.0, 4.896e-6 / 50.0, 1e-6, 9.8e-7] {
            assert!(same_as_stepwise(dt, 20_000), "dt = {dt:e}");
        }
    }

    #[test]
    fn verlet_free_fall_is_the_stepwise_flight_bit_for_bit() {
        // Dropped from 5 mm, thrown up from the surface (x = 0, the start
        // after a rebound) and, with g = 0, the full step (Δt² a = −0).
        let bits = |s: &VerletState| [s.x, s.v, s.a, s.dt, s.gain, s.next_x].map(f64::to_bits);
        for (x, v, g) in [(5e-3, 0.0, 9.81), (0.0, 0.3, 9.81), (-0.0, -0.0, 0.0)] {
            for dt in [2.4e-9, 4.896e-6 / 50.0, 1e-6, 9.8e-7] {
                let start = Verlet.start([x, v, -g, 0.0, 0.0, 0.0], dt);
                let mut reference = Stepwise::new(Verlet, start, -g);
                let mut fast = Verlet.free_fall(start, -g);
                assert_eq!(fast.short, g != 0.0);
                for _ in 0..20_000 {
                    reference.step();
                    fast.step();
                    assert_eq!(bits(&reference.state()), bits(&fast.state()), "dt = {dt:e}");
                }
            }
        }
    }

    #[test]
    fn gear5_free_fall_settles() {
        // The fast path must be taken (or the test above proves nothing
        // about it): at Δt = 1e-6 s, Δ rounds to 0 on the first step.
        let it = Gear5::POSITION_DEPENDENT;
        let mut f = it.free_fall(it.start([5e-3, 0.0, -9.81, 0.0, 0.0, 0.0], 1e-6), -9.81);
        f.step();
        f.step();
        assert!(matches!(f.settled, Some((_, true))), "{:?}", f.settled);
    }
}
