//! [`events::locate`] on the Gear5 polynomial of several steps at once.
//!
//! The events of the lanes come in bursts (cases of similar length stay in
//! step), and one scalar location is a latency-bound chain of Newton
//! iterations with divisions; here a register's worth of them run as one
//! chain. Each lane performs exactly the scalar function's operations, in
//! the same order, on [`Gear5Dense::at`]'s polynomials; its branches
//! become per-lane masks (a lane that has finished keeps its values while
//! the others iterate), so every lane's result is the scalar one to the
//! bit (tested below against [`events::locate`]).
//!
//! [`events::locate`]: crate::bounce::events::locate
//! [`Gear5Dense::at`]: crate::integrate::Gear5Dense

use super::simd::{Simd, V};
use crate::bounce::events::Crossing;
use crate::integrate::Kinematics;

/// Most steps located at once.
pub(in crate::bounce) const MAX_STEPS: usize = 16;

/// Steps to locate an event in, one lane each (structure of arrays): the
/// corrected Nordsieck vector and size of each step (a
/// [`crate::integrate::Gear5State`]'s `r` and `dt`). Lanes from `n` to the
/// next multiple of 8 must hold a valid step too (a copy; see [`Steps::pad`]).
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(in crate::bounce) struct Steps {
    pub r: [[f64; MAX_STEPS]; 6],
    pub dt: [f64; MAX_STEPS],
    pub n: usize,
}

impl Steps {
    pub(in crate::bounce) fn new() -> Self {
        Steps {
            r: [[0.0; MAX_STEPS]; 6],
            dt: [1.0; MAX_STEPS],
            n: 0,
        }
    }

    pub(in crate::bounce) fn push(&mut self, r: [f64; 6], dt: f64) {
        for (k, x) in r.into_iter().enumerate() {
            self.r[k][self.n] = x;
        }
        self.dt[self.n] = dt;
        self.n += 1;
    }

    /// Copies the last step into the lanes up to the next multiple of 8.
    pub(in crate::bounce) fn pad(&mut self) {
        let Some(last) = self.n.checked_sub(1) else {
            return;
        };
        for i in self.n..self.n.next_multiple_of(8).min(MAX_STEPS) {
            for k in 0..6 {
                self.r[k][i] = self.r[k][last];
            }
            self.dt[i] = self.dt[last];
        }
    }
}

/// Where the events are: the step fraction θ and the kinematics there.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(in crate::bounce) struct Located {
    pub theta: [f64; MAX_STEPS],
    pub position: [f64; MAX_STEPS],
    pub velocity: [f64; MAX_STEPS],
    pub acceleration: [f64; MAX_STEPS],
}

impl Located {
    pub(in crate::bounce) fn new() -> Self {
        let z = [0.0; MAX_STEPS];
        Located {
            theta: z,
            position: z,
            velocity: z,
            acceleration: z,
        }
    }

    /// Step i's θ and kinematics.
    pub(in crate::bounce) fn get(&self, i: usize) -> (f64, Kinematics) {
        (
            self.theta[i],
            Kinematics {
                position: self.position[i],
                velocity: self.velocity[i],
                acceleration: self.acceleration[i],
            },
        )
    }
}

/// `locate(&gear.dense(state, state), crossing)` for every step.
#[inline(always)]
pub(in crate::bounce) fn locate_steps<S: Simd>(
    s: S,
    crossing: Crossing,
    steps: &Steps,
    out: &mut Located,
) {
    let mut i = 0;
    while i < steps.n {
        locate_register(s, crossing, steps, i, out);
        i += S::W;
    }
}

/// `Gear5Dense::at`: (x, v, a) at θ (no closures here or below: a
/// closure is compiled without the caller's instruction set).
#[inline(always)]
fn at<S: Simd>(s: S, r: &[V<S, 1>; 6], dt: V<S, 1>, dt2: V<S, 1>, theta: V<S, 1>) -> [V<S, 1>; 3] {
    let t = theta - V::splat(s, 1.0);
    let x = r[0] + t * (r[1] + t * (r[2] + t * (r[3] + t * (r[4] + t * r[5]))));
    let v =
        r[1] + t * (2.0 * r[2] + t * (3.0 * r[3] + t * (4.0 * r[4] + t * V::splat(s, 5.0) * r[5])));
    let a = 2.0 * r[2] + t * (6.0 * r[3] + t * (12.0 * r[4] + t * V::splat(s, 20.0) * r[5]));
    [x, v / dt, a / dt2]
}

/// `events::value`: the quantity and its derivative times Δt, at θ.
#[inline(always)]
fn value<S: Simd>(
    s: S,
    crossing: Crossing,
    r: &[V<S, 1>; 6],
    dt: V<S, 1>,
    dt2: V<S, 1>,
    theta: V<S, 1>,
) -> (V<S, 1>, V<S, 1>) {
    let [x, v, a] = at(s, r, dt, dt2, theta);
    match crossing {
        Crossing::Position => (x, v * dt),
        Crossing::Velocity => (v, a * dt),
    }
}

/// The register of steps from lane `i`.
#[inline(always)]
fn locate_register<S: Simd>(s: S, crossing: Crossing, steps: &Steps, i: usize, out: &mut Located) {
    let r = [
        V::<S, 1>::load(s, &steps.r[0][i..]),
        V::load(s, &steps.r[1][i..]),
        V::load(s, &steps.r[2][i..]),
        V::load(s, &steps.r[3][i..]),
        V::load(s, &steps.r[4][i..]),
        V::load(s, &steps.r[5][i..]),
    ];
    let dt = V::load(s, &steps.dt[i..]);
    let dt2 = dt * dt;
    let (zero, one) = (V::splat(s, 0.0), V::splat(s, 1.0));
    let mut hi = one;
    let mut lo = zero;
    let y0 = value(s, crossing, &r, dt, dt2, zero).0;
    let extended = y0.ge(zero);
    lo = extended.select(V::splat(s, -1.0), lo);
    let y_back = value(s, crossing, &r, dt, dt2, V::splat(s, -1.0)).0;
    // No sign change on the polynomial: the step end.
    let degenerate = extended.and(y_back.ge(zero));
    let mut theta = 0.5 * (lo + hi);
    let f_lo = extended.select(y_back, y0);
    let f_hi = value(s, crossing, &r, dt, dt2, hi).0;
    theta = f_hi
        .gt(f_lo)
        .select(lo - f_lo * (hi - lo) / (f_hi - f_lo), theta);
    let mut active = zero.eq(zero).and_not(degenerate);
    let (floor, tolerance) = (V::splat(s, 1e-300), V::splat(s, 4.0 * f64::EPSILON));
    let epsilon = V::splat(s, f64::EPSILON);
    for _ in 0..100 {
        if !active.any() {
            break;
        }
        let (y, dy) = value(s, crossing, &r, dt, dt2, theta);
        // y == 0: done, θ as it is.
        let live = active.and(y.ne(zero));
        let below = y.lt(zero);
        lo = live.and(below).select(theta, lo);
        hi = live.and_not(below).select(theta, hi);
        let newton = theta - y / dy;
        let inside = dy.gt(zero).and(newton.gt(lo)).and(newton.lt(hi));
        let next = inside.select(newton, 0.5 * (lo + hi));
        // |θ|.max(1e-300)
        let size = theta.abs();
        let scale = size.gt(floor).select(size, floor);
        let converged = (next - theta).abs().le(tolerance * scale) | (hi - lo).le(epsilon);
        theta = live.select(next, theta);
        active = live.and_not(converged);
    }
    theta = degenerate.select(one, theta);
    let [x, v, a] = at(s, &r, dt, dt2, theta);
    theta.store(&mut out.theta[i..]);
    x.store(&mut out.position[i..]);
    v.store(&mut out.velocity[i..]);
    a.store(&mut out.acceleration[i..]);
}

#[cfg(test)]
mod tests {
    use super::super::Isa;
    use super::*;
    use crate::bounce::events::locate;
    use crate::integrate::{Gear5, Gear5State, Integrator};

    /// xorshift64*.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A step: its Nordsieck vector and size.
    struct Step {
        r: [f64; 6],
        dt: f64,
    }

    /// Steps of a Hertz-like contact near its maximum overlap and its
    /// rebound, and odd ones (no sign change, a root at the step start).
    fn steps(n: usize) -> Vec<Step> {
        let mut rng = Rng(0x10ca7e);
        let gear = Gear5::POSITION_DEPENDENT;
        (0..n)
            .map(|i| {
                let dt = 1e-8 * (0.1 + rng.next());
                let w = 1e4 * (0.5 + rng.next());
                // x = −A sin(w τ) near τ where the chosen quantity crosses.
                let amp = 1e-7 * (0.5 + rng.next());
                let tau = match i % 4 {
                    0 => std::f64::consts::FRAC_PI_2 / w + dt * (rng.next() - 0.2),
                    1 => std::f64::consts::PI / w + dt * (rng.next() - 0.2),
                    2 => std::f64::consts::PI / w + dt * 5.0,
                    _ => std::f64::consts::PI / w + dt * (rng.next() - 1.0),
                };
                let d = [
                    -amp * (w * tau).sin(),
                    -amp * w * (w * tau).cos(),
                    amp * w * w * (w * tau).sin(),
                    amp * w.powi(3) * (w * tau).cos(),
                    -amp * w.powi(4) * (w * tau).sin(),
                    -amp * w.powi(5) * (w * tau).cos(),
                ];
                let state: Gear5State = gear.start(d, dt);
                Step { r: state.r, dt }
            })
            .collect()
    }

    fn check<S: Simd>(s: S) {
        let gear = Gear5::POSITION_DEPENDENT;
        let all = steps(203);
        for crossing in [Crossing::Position, Crossing::Velocity] {
            for (c, chunk) in all.chunks(MAX_STEPS - 3).enumerate() {
                let mut steps = Steps::new();
                for st in chunk {
                    steps.push(st.r, st.dt);
                }
                steps.pad();
                let mut out = Located::new();
                s.locate(crossing, &steps, &mut out);
                for (i, st) in chunk.iter().enumerate() {
                    let state = gear.start([0.0; 6], st.dt);
                    let state = Gear5State { r: st.r, ..state };
                    let want = locate(&gear.dense(&state, &state), crossing);
                    let bits = |(t, k): (f64, Kinematics)| {
                        [t, k.position, k.velocity, k.acceleration].map(f64::to_bits)
                    };
                    assert_eq!(
                        bits(out.get(i)),
                        bits(want),
                        "{crossing:?} chunk {c} step {i}"
                    );
                }
            }
        }
    }

    #[test]
    fn lanes_locate_as_the_scalar_function_does() {
        #[cfg(target_arch = "x86_64")]
        {
            use super::super::simd::{Avx2, Avx512, Sse2};
            if let Some(s) = Avx512::detect() {
                check(s);
            }
            if let Some(s) = Avx2::detect() {
                check(s);
            }
            if let Some(s) = Sse2::detect() {
                check(s);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        if let Some(s) = super::super::simd::Scalar::detect() {
            check(s);
        }
        let _ = Isa::detect();
    }
}
