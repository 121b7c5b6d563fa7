//! Verlet's closing half kick of a series row's step, with the bodies'
//! energies and the state's soundness in the same pass
//! ([`kick_then_energies`]): the row's per-body work, four bodies at a time
//! where AVX2 is available.

use crate::dynamics::integrate;
use crate::parallel::{SharedMut, Workers, BODY_CHUNK};

#[cfg(doc)]
use super::observe::body_energies;
use super::World;

/// What [`kick_then_energies`] found at the kicked state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct KickedState {
    /// [`body_energies`], J.
    pub energies: (f64, f64),
    /// Every position, velocity and spin is finite, and (with `bounds`)
    /// every centre lies within its radius of the box: what
    /// `Simulation::check_finite` passes without a second look.
    pub sound: bool,
}

/// Verlet's last half kick of the velocities (and spins, with friction),
/// and in the same pass [`body_energies`] at the kicked state, J: the same
/// kicks as `integrate::verlet_kick` and `verlet::friction_spin_kick`
/// (per body), the same sums in the same chunks and order as
/// [`body_energies`], so the same bits as the kick and the pass after it.
/// Also whether the state is sound ([`KickedState::sound`]; `bounds`: the
/// box of `domain.outside = "error"`, tested as `Simulation::check_finite`
/// tests it).
pub(crate) fn kick_then_energies(
    world: &mut World,
    workers: &Workers,
    bounds: Option<([f64; 3], [f64; 3])>,
) -> KickedState {
    let spin = world.friction.is_some();
    let b = &mut world.bodies;
    let n = b.len();
    assert!(
        b.force.len() == n
            && b.mass.len() == n
            && b.fixed.len() == n
            && b.position.len() == n
            && b.velocity.len() == n
            && b.radius.len() == n
            && (!spin
                || (b.torque.len() == n
                    && b.angular_velocity.len() == n
                    && b.inverse_inertia.len() == n))
    );
    // Spins are tested only where they are kept per body.
    let spins = b.angular_velocity.len() == n;
    let kick = Kick {
        v: SharedMut::new(&mut b.velocity),
        w: SharedMut::new(&mut b.angular_velocity),
        force: &b.force,
        torque: &b.torque,
        mass: &b.mass,
        inverse_inertia: &b.inverse_inertia,
        fixed: &b.fixed,
        position: &b.position,
        radius: &b.radius,
        dt: world.dt,
        gravity: world.gravity,
        bounds: bounds.unwrap_or(([f64::NEG_INFINITY; 3], [f64::INFINITY; 3])),
    };
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::is_x86_feature_detected!("avx2");
    let partial = workers.map_bodies(n, BODY_CHUNK, |c| {
        let (lo, hi) = (c * BODY_CHUNK, ((c + 1) * BODY_CHUNK).min(n));
        // One copy per setting: no per-body test of them.
        // SAFETY (all): lengths asserted; chunks are disjoint ranges of
        // bodies, each kicked once; AVX2 checked.
        // Four bodies at a time with AVX2.
        macro_rules! run {
            ($spin:literal, $spins:literal, $within:literal) => {{
                #[cfg(target_arch = "x86_64")]
                if avx2 {
                    return unsafe { kick.chunk_four_avx2::<$spin, $spins, $within>(lo, hi) };
                }
                unsafe { kick.chunk::<$spin, $spins, $within>(lo, hi) }
            }};
        }
        match (spin, spins, bounds.is_some()) {
            (true, _, false) => run!(true, true, false),
            (true, _, true) => run!(true, true, true),
            (false, true, false) => run!(false, true, false),
            (false, true, true) => run!(false, true, true),
            (false, false, false) => run!(false, false, false),
            (false, false, true) => run!(false, false, true),
        }
    });
    let mut s = [0.0; 2];
    let mut sound = true;
    for (p, ok) in partial {
        s[0] += p[0];
        s[1] += p[1];
        sound &= ok;
    }
    KickedState {
        energies: (s[0], s[1]),
        sound,
    }
}

/// What [`kick_then_energies`] reads and writes (lengths asserted there).
#[derive(Clone, Copy)]
struct Kick<'a> {
    v: SharedMut<[f64; 3]>,
    w: SharedMut<[f64; 3]>,
    force: &'a [[f64; 3]],
    torque: &'a [[f64; 3]],
    mass: &'a [f64],
    inverse_inertia: &'a [f64],
    fixed: &'a [bool],
    position: &'a [[f64; 3]],
    radius: &'a [f64],
    /// s.
    dt: f64,
    /// m/s².
    gravity: [f64; 3],
    /// The check's box (lower, upper), m.
    bounds: ([f64; 3], [f64; 3]),
}

impl Kick<'_> {
    /// Bodies lo..hi: kicked (`SPIN`: the spins too), their energies
    /// summed as [`body_energies`] sums them, and whether every position,
    /// velocity and (`SPINS`) spin is finite and (`WITHIN`) every centre
    /// within its radius of the box, as `Simulation::check_finite` tests
    /// ([`KickSums::result`]).
    ///
    /// # Safety
    /// Bodies lo..hi exist and no other thread touches their velocities
    /// and spins.
    #[inline(always)]
    unsafe fn chunk<const SPIN: bool, const SPINS: bool, const WITHIN: bool>(
        &self,
        lo: usize,
        hi: usize,
    ) -> ([f64; 2], bool) {
        let mut sums = KickSums::new();
        self.bodies::<SPIN, SPINS, WITHIN>(lo, hi, &mut sums);
        sums.result::<WITHIN>(self.bounds)
    }

    /// Bodies lo..hi, one at a time, added to `sums`: kicked (`SPIN`: the
    /// spins too), their two energy terms added to the sums in body order,
    /// their values tested and their centres' extremes taken
    /// ([`KickSums`]).
    ///
    /// # Safety
    /// As [`Self::chunk`].
    #[inline(always)]
    // x − x is meant: +0 for a finite x, NaN otherwise.
    #[allow(clippy::eq_op)]
    unsafe fn bodies<const SPIN: bool, const SPINS: bool, const WITHIN: bool>(
        &self,
        lo: usize,
        hi: usize,
        sums: &mut KickSums,
    ) {
        let (g, dt) = (self.gravity, self.dt);
        // SAFETY (every `get_unchecked`): every slice of `Kick` holds a
        // value per body (asserted in `kick_then_energies`; torque and
        // 1/I read with `SPIN` only, where they are asserted), k < hi ≤ n.
        for k in lo..hi {
            let x = *self.position.get_unchecked(k);
            let mass = *self.mass.get_unchecked(k);
            let e = if *self.fixed.get_unchecked(k) {
                let v = *self.v.0.add(k);
                for a in 0..3 {
                    sums.not_finite += (x[a] - x[a]) + (v[a] - v[a]);
                }
                if SPINS {
                    let w = *self.w.0.add(k);
                    sums.not_finite += (w[0] - w[0]) + (w[1] - w[1]) + (w[2] - w[2]);
                }
                [0.0, 0.0]
            } else {
                // `integrate::verlet_kick`'s kick.
                let vk = &mut *self.v.0.add(k);
                integrate::half_kick(vk, *self.force.get_unchecked(k), 0.5 * dt / mass);
                let v = *vk;
                let mut e = 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                if SPIN {
                    // `verlet::friction_spin_kick`'s kick.
                    let inv = *self.inverse_inertia.get_unchecked(k);
                    let wk = &mut *self.w.0.add(k);
                    integrate::half_kick(wk, *self.torque.get_unchecked(k), 0.5 * dt * inv);
                    let w = *wk;
                    e += 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / inv;
                } else if SPINS {
                    let w = *self.w.0.add(k);
                    sums.not_finite += (w[0] - w[0]) + (w[1] - w[1]) + (w[2] - w[2]);
                }
                [e, -mass * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])]
            };
            sums.s[0] += e[0];
            sums.s[1] += e[1];
            if WITHIN {
                let r = *self.radius.get_unchecked(k);
                sums.r_min = if r < sums.r_min { r } else { sums.r_min };
                for ((&c, least), most) in x.iter().zip(&mut sums.least).zip(&mut sums.most) {
                    *least = if c < *least { c } else { *least };
                    *most = if c > *most { c } else { *most };
                }
            }
        }
    }

    /// [`Self::chunk`] four free bodies at a time (a group of four with a
    /// fixed body, and the last bodies short of four, go one at a time:
    /// [`Self::bodies`]). Four bodies' 3-vectors lie in 12 consecutive
    /// doubles, three 4-lane registers [x0 y0 z0 x1] [y1 z1 x2 y2]
    /// [z2 x3 y3 z3]; the kick is done in that layout with Δt/2/m (`SPIN`:
    /// and Δt/2 · 1/I for the spins) spread over the lanes (as
    /// `verlet_four`), the squared velocities (and spins) and the
    /// positions transposed to one register per component, so that each
    /// lane computes body k's ½ m v² (`SPIN`: plus ½ ω² / (1/I)) and
    /// −m g·x with the scalar loop's operations on its operands (IEEE per
    /// lane, no fused multiply–add: the same bits), then the four bodies'
    /// terms are added to the two sums in body order, as the scalar loop
    /// adds them. The tests as the scalar loop's: x − x of the spins
    /// summed per lane (+0 or NaN, in any order), the centres' extremes
    /// per lane with `min_pd(x, m)` = `if x < m { x } else { m }` (and
    /// `max_pd` likewise), folded into the scalar ones at the end.
    ///
    /// # Safety
    /// As [`Self::chunk`]; the processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    // x − x is meant: +0 for a finite x, NaN otherwise.
    #[allow(clippy::eq_op)]
    unsafe fn chunk_four_avx2<const SPIN: bool, const SPINS: bool, const WITHIN: bool>(
        &self,
        lo: usize,
        hi: usize,
    ) -> ([f64; 2], bool) {
        use std::arch::x86_64::*;
        let mut sums = KickSums::new();
        let g = self.gravity;
        let half_dt = _mm256_set1_pd(0.5 * self.dt);
        let half = _mm256_set1_pd(0.5);
        let sign = _mm256_set1_pd(-0.0);
        let (gx, gy, gz) = (
            _mm256_set1_pd(g[0]),
            _mm256_set1_pd(g[1]),
            _mm256_set1_pd(g[2]),
        );
        let x = self.position.as_ptr() as *const f64;
        let f = self.force.as_ptr() as *const f64;
        let v = self.v.0 as *mut f64;
        let w = self.w.0 as *mut f64;
        let torque = self.torque.as_ptr() as *const f64;
        let (mass, radius) = (self.mass.as_ptr(), self.radius.as_ptr());
        let inverse_inertia = self.inverse_inertia.as_ptr();
        let fixed = self.fixed.as_ptr();
        // Per lane: Σ (w − w), the extremes of the centres' coordinates in
        // the three registers' lane layout, the smallest radius.
        let mut not_finite = _mm256_setzero_pd();
        let mut least = [_mm256_set1_pd(f64::INFINITY); 3];
        let mut most = [_mm256_set1_pd(f64::NEG_INFINITY); 3];
        let mut r_min = _mm256_set1_pd(f64::INFINITY);
        // Lane 0, 1, 2, 3 of a register added to `s` in that order.
        macro_rules! add_lanes {
            ($s:expr, $r:expr) => {{
                let r = $r;
                let (low, high) = (_mm256_castpd256_pd128(r), _mm256_extractf128_pd::<1>(r));
                $s += _mm_cvtsd_f64(low);
                $s += _mm_cvtsd_f64(_mm_unpackhi_pd(low, low));
                $s += _mm_cvtsd_f64(high);
                $s += _mm_cvtsd_f64(_mm_unpackhi_pd(high, high));
            }};
        }
        let mut i = lo;
        // SAFETY (every load and store): bodies i..i + 4 < hi ≤ n, each
        // slice holding a value (3 doubles for a vector) per body (torque
        // and 1/I read with `SPIN` only, where they are asserted).
        while i + 4 <= hi {
            // The four fixed flags (bools: one byte each, 0 or 1).
            if (fixed.add(i) as *const u32).read_unaligned() != 0 {
                self.bodies::<SPIN, SPINS, WITHIN>(i, i + 4, &mut sums);
                i += 4;
                continue;
            }
            let m = _mm256_loadu_pd(mass.add(i));
            // `integrate::verlet_kick`'s kick: v + F (Δt/2/m).
            let dtfm = spread_lanes!(_mm256_div_pd(half_dt, m));
            // `verlet::friction_spin_kick`'s kick: ω + τ (Δt/2 · 1/I).
            let inverse = if SPIN {
                _mm256_loadu_pd(inverse_inertia.add(i))
            } else {
                _mm256_setzero_pd()
            };
            let dtfi = spread_lanes!(_mm256_mul_pd(half_dt, inverse));
            let mut squares = [_mm256_setzero_pd(); 3];
            let mut spin_squares = [_mm256_setzero_pd(); 3];
            let mut centres = [_mm256_setzero_pd(); 3];
            for q in 0..3 {
                // Lanes 4q..4q + 4 of the four bodies' 12 values.
                let at = 3 * i + 4 * q;
                let vq = _mm256_add_pd(
                    _mm256_loadu_pd(v.add(at)),
                    _mm256_mul_pd(_mm256_loadu_pd(f.add(at)), dtfm[q]),
                );
                _mm256_storeu_pd(v.add(at), vq);
                squares[q] = _mm256_mul_pd(vq, vq);
                let xq = _mm256_loadu_pd(x.add(at));
                centres[q] = xq;
                if SPIN {
                    let wq = _mm256_add_pd(
                        _mm256_loadu_pd(w.add(at)),
                        _mm256_mul_pd(_mm256_loadu_pd(torque.add(at)), dtfi[q]),
                    );
                    _mm256_storeu_pd(w.add(at), wq);
                    spin_squares[q] = _mm256_mul_pd(wq, wq);
                } else if SPINS {
                    let wq = _mm256_loadu_pd(w.add(at));
                    not_finite = _mm256_add_pd(not_finite, _mm256_sub_pd(wq, wq));
                }
                if WITHIN {
                    least[q] = _mm256_min_pd(xq, least[q]);
                    most[q] = _mm256_max_pd(xq, most[q]);
                }
            }
            if WITHIN {
                r_min = _mm256_min_pd(_mm256_loadu_pd(radius.add(i)), r_min);
            }
            // ½ m ((vx² + vy²) + vz²).
            let [qx, qy, qz] = lanes_to_xyz!(squares);
            let mut kinetic = _mm256_mul_pd(
                _mm256_mul_pd(half, m),
                _mm256_add_pd(_mm256_add_pd(qx, qy), qz),
            );
            if SPIN {
                // + ½ ((ωx² + ωy²) + ωz²) / (1/I).
                let [wx, wy, wz] = lanes_to_xyz!(spin_squares);
                kinetic = _mm256_add_pd(
                    kinetic,
                    _mm256_div_pd(
                        _mm256_mul_pd(half, _mm256_add_pd(_mm256_add_pd(wx, wy), wz)),
                        inverse,
                    ),
                );
            }
            // −m ((gx x + gy y) + gz z).
            let [px, py, pz] = lanes_to_xyz!(centres);
            let gravity = _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(gx, px), _mm256_mul_pd(gy, py)),
                _mm256_mul_pd(gz, pz),
            );
            let potential = _mm256_mul_pd(_mm256_xor_pd(m, sign), gravity);
            // The terms of bodies i..i + 4 in body order, as the scalar
            // loop adds them (the two sums are independent).
            add_lanes!(sums.s[0], kinetic);
            add_lanes!(sums.s[1], potential);
            i += 4;
        }
        self.bodies::<SPIN, SPINS, WITHIN>(i, hi, &mut sums);
        // The lanes folded into the scalar tests.
        let mut lanes = [0.0f64; 4];
        _mm256_storeu_pd(lanes.as_mut_ptr(), not_finite);
        for l in lanes {
            sums.not_finite += l;
        }
        if WITHIN {
            // Register q's lane l holds component (4q + l) mod 3.
            for q in 0..3 {
                let (mut low, mut high) = ([0.0f64; 4], [0.0f64; 4]);
                _mm256_storeu_pd(low.as_mut_ptr(), least[q]);
                _mm256_storeu_pd(high.as_mut_ptr(), most[q]);
                for l in 0..4 {
                    let a = (4 * q + l) % 3;
                    sums.least[a] = if low[l] < sums.least[a] {
                        low[l]
                    } else {
                        sums.least[a]
                    };
                    sums.most[a] = if high[l] > sums.most[a] {
                        high[l]
                    } else {
                        sums.most[a]
                    };
                }
            }
            _mm256_storeu_pd(lanes.as_mut_ptr(), r_min);
            for r in lanes {
                sums.r_min = if r < sums.r_min { r } else { sums.r_min };
            }
        }
        sums.result::<WITHIN>(self.bounds)
    }
}

/// What [`Kick::bodies`] has summed and seen of a chunk so far.
struct KickSums {
    /// The kinetic and potential energy terms, summed in body order, J.
    s: [f64; 2],
    /// Σ (x − x) over the values tested one by one: +0 while every one
    /// is finite, NaN from the first that is not.
    not_finite: f64,
    /// The extreme centre coordinates (a NaN coordinate is not taken: the
    /// finite tests catch it), m.
    least: [f64; 3],
    most: [f64; 3],
    /// The smallest radius, m.
    r_min: f64,
}

impl KickSums {
    fn new() -> Self {
        Self {
            s: [0.0; 2],
            not_finite: 0.0,
            least: [f64::INFINITY; 3],
            most: [f64::NEG_INFINITY; 3],
            r_min: f64::INFINITY,
        }
    }

    /// The two sums, and whether the chunk passed the tests, without a
    /// test per value: a free body's position, velocity and (with spin
    /// kicks) spin enter its energies (½ m v², ½ I ω², −m g·x: a value not
    /// finite makes its term not finite, 0 · ∞ being NaN), and a sum with a
    /// term not finite is not finite, so the chunk's two sums are finite
    /// only if those are (a finite overflow of a sum fails the test too:
    /// the full check then decides). The other values (fixed bodies, spins
    /// without spin kicks) are tested as `x − x`: +0 when finite, NaN
    /// otherwise. The box (`WITHIN`; lower, upper): the chunk's smallest
    /// and largest centre coordinates against the box grown by the chunk's
    /// smallest radius: x ≥ min ≥ lower − r_min ≥ lower − r for every body
    /// (IEEE subtraction is monotone), so passing implies `check_finite`'s
    /// test of each body (failing sends the state to the full check).
    fn result<const WITHIN: bool>(&self, bounds: ([f64; 3], [f64; 3])) -> ([f64; 2], bool) {
        let (lower, upper) = bounds;
        let mut within = true;
        if WITHIN {
            for a in 0..3 {
                within &= (self.least[a] >= lower[a] - self.r_min)
                    & (self.most[a] <= upper[a] + self.r_min);
            }
        }
        let finite = self.not_finite == 0.0 && self.s[0].is_finite() && self.s[1].is_finite();
        (self.s, finite && within)
    }
}

#[cfg(test)]
mod tests {
    use crate::dynamics::friction_observables::tests::scene;
    use crate::Simulation;

    /// A velocity that is not finite fails the kick's state test, and the
    /// state check then finds it (the check's own error).
    #[test]
    fn a_state_not_finite_is_not_passed_by_the_kick() {
        let mut sim = Simulation::new(scene(), 1).unwrap();
        sim.world.bodies.velocity[7] = [f64::NAN, 0.0, 0.0];
        sim.will_observe();
        sim.step(1);
        assert!(!sim.pipeline.sound(&sim.world));
        assert!(matches!(
            sim.check_finite(),
            Err(crate::error::SceneError::Unstable { .. })
        ));
    }

    /// The kick's box test: every centre within its radius of the box
    /// passes; a box whose upper x face lies more than a radius below one
    /// centre (so `check_finite`'s per-body test fails it) does not, with
    /// and without friction, and the full check then runs.
    #[test]
    fn a_centre_outside_the_box_is_not_passed_by_the_kick() {
        for friction in [true, false] {
            let mut setup = scene();
            if !friction {
                setup.friction = None;
            }
            let mut sim = Simulation::new(setup, 1).unwrap();
            sim.step(20);
            let b = &sim.world.bodies;
            let (mut lower, mut upper) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for x in &b.position {
                for a in 0..3 {
                    lower[a] = lower[a].min(x[a]);
                    upper[a] = upper[a].max(x[a]);
                }
            }
            // Every centre inside: passed (the box the kick tests is the
            // state check's, `Simulation::outside_box`).
            sim.outside_box = Some((lower, upper));
            sim.will_observe();
            sim.step(1);
            let b = &sim.world.bodies;
            let inside = b
                .position
                .iter()
                .zip(&b.radius)
                .all(|(x, &r)| (0..3).all(|a| x[a] >= lower[a] - r && x[a] <= upper[a] + r));
            assert!(inside);
            assert!(sim.pipeline.sound(&sim.world), "friction {friction}");
            // The largest x centre beyond the upper face by 1.5 radii.
            let (k, _) = b
                .position
                .iter()
                .enumerate()
                .max_by(|p, q| p.1[0].total_cmp(&q.1[0]))
                .unwrap();
            let mut cut = upper;
            cut[0] = b.position[k][0] - 1.5 * b.radius[k];
            sim.outside_box = Some((lower, cut));
            sim.will_observe();
            sim.step(1);
            assert!(!sim.pipeline.sound(&sim.world), "friction {friction}");
        }
    }

    /// The kick four bodies at a time (`Kick::chunk_four_avx2`) against the
    /// same kick one body at a time (`Kick::chunk`, the scalar loop, an
    /// independent computation of the same operations): the velocities,
    /// the spins, both sums and the state test bit for bit, over chunks of
    /// 0–23 bodies starting anywhere (groups of four with a fixed body, and
    /// remainders, go body by body), with spin kicks (friction), without
    /// them with and without the spins' test, each with and without the
    /// box; a NaN spin, a NaN velocity, an infinite torque and a centre
    /// outside the box fail the test in both.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_kick_four_bodies_at_a_time_equals_the_scalar_loop_bit_for_bit() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        let n = 23;
        // Deterministic values of mixed signs and magnitudes.
        let value = |k: usize, a: usize, scale: f64| {
            let t = (k * 7 + a * 3) as f64;
            scale * ((t * 0.37).sin() + 0.1 * (t * 1.91).cos())
        };
        let vec3 = |scale: f64| -> Vec<[f64; 3]> {
            (0..n)
                .map(|k| [0, 1, 2].map(|a| value(k, a, scale)))
                .collect()
        };
        let position = vec3(0.01);
        let force = vec3(1e-3);
        let mass: Vec<f64> = (0..n)
            .map(|k| 1e-6 * (1.0 + 0.3 * value(k, 0, 1.0)))
            .collect();
        let radius: Vec<f64> = (0..n)
            .map(|k| 5e-4 * (1.0 + 0.1 * value(k, 1, 1.0)))
            .collect();
        // 1/I of a solid sphere, 1 / (2/5 m r²), 1/(kg m²).
        let inverse_inertia: Vec<f64> = (0..n)
            .map(|k| 2.5 / (mass[k] * radius[k] * radius[k]))
            .collect();
        let fixed: Vec<bool> = (0..n).map(|k| k == 5 || k == 14).collect();
        let inside = ([-0.02; 3], [0.02; 3]);
        // The box's upper x face below body 9's centre by 1.5 radii.
        let mut cut = inside;
        cut.1[0] = position[9][0] - 1.5 * radius[9];
        #[allow(clippy::too_many_arguments)]
        let run = |four: bool,
                   kicks: bool,
                   spins: bool,
                   bounds: Option<([f64; 3], [f64; 3])>,
                   velocity: &mut Vec<[f64; 3]>,
                   spin: &mut Vec<[f64; 3]>,
                   torque: &[[f64; 3]],
                   lo: usize,
                   hi: usize| {
            let kick = super::Kick {
                v: crate::parallel::SharedMut::new(velocity),
                w: crate::parallel::SharedMut::new(spin),
                force: &force,
                torque,
                mass: &mass,
                inverse_inertia: if kicks { &inverse_inertia } else { &[] },
                fixed: &fixed,
                position: &position,
                radius: &radius,
                dt: 2e-6,
                gravity: [0.3, -0.2, -9.81],
                bounds: bounds.unwrap_or(([f64::NEG_INFINITY; 3], [f64::INFINITY; 3])),
            };
            macro_rules! call {
                ($spin:literal, $spins:literal, $within:literal) => {
                    if four {
                        kick.chunk_four_avx2::<$spin, $spins, $within>(lo, hi)
                    } else {
                        kick.chunk::<$spin, $spins, $within>(lo, hi)
                    }
                };
            }
            // SAFETY: every slice holds n values (torque and 1/I with spin
            // kicks), lo ≤ hi ≤ n, one thread; AVX2 checked above.
            unsafe {
                match (kicks, spins, bounds.is_some()) {
                    (true, _, true) => call!(true, true, true),
                    (true, _, false) => call!(true, true, false),
                    (false, true, true) => call!(false, true, true),
                    (false, true, false) => call!(false, true, false),
                    (false, false, true) => call!(false, false, true),
                    (false, false, false) => call!(false, false, false),
                }
            }
        };
        let mut failed = 0;
        for spoil in 0..5 {
            // Spin kicks (and so the spins' test), the spins' test alone, neither.
            for (kicks, spins) in [(true, true), (false, true), (false, false)] {
                for bounds in [None, Some(inside), Some(cut)] {
                    for lo in 0..n {
                        for hi in lo..=n {
                            let mut results = Vec::new();
                            for four in [true, false] {
                                let mut velocity = vec3(0.05);
                                let mut spin = if spins { vec3(10.0) } else { Vec::new() };
                                let mut torque = if kicks { vec3(1e-9) } else { Vec::new() };
                                match spoil {
                                    1 if spins => spin[11][2] = f64::NAN,
                                    2 => velocity[12][1] = f64::NAN,
                                    3 => velocity[5][0] = f64::INFINITY,
                                    4 if kicks => torque[2][1] = f64::INFINITY,
                                    _ => {}
                                }
                                let (sums, sound) = run(
                                    four,
                                    kicks,
                                    spins,
                                    bounds,
                                    &mut velocity,
                                    &mut spin,
                                    &torque,
                                    lo,
                                    hi,
                                );
                                let bits: Vec<u64> = velocity
                                    .iter()
                                    .chain(&spin)
                                    .flatten()
                                    .map(|x| x.to_bits())
                                    .collect();
                                results.push((sums.map(f64::to_bits), sound, bits));
                            }
                            assert_eq!(
                                results[0], results[1],
                                "{spoil} {kicks} {spins} {bounds:?} {lo}..{hi}"
                            );
                            // A sound chunk has a free body or sums of +0.
                            if !results[0].1 {
                                failed += 1;
                            }
                            if lo == 0 && hi == n && bounds != Some(cut) {
                                // The whole range: sound unless spoiled
                                // (body 5 is fixed: its velocity tested, not kicked).
                                let spoiled = spoil == 2
                                    || spoil == 3
                                    || (spoil == 1 && spins)
                                    || (spoil == 4 && kicks);
                                assert_eq!(
                                    results[0].1, !spoiled,
                                    "{spoil} {kicks} {spins} {bounds:?}"
                                );
                            }
                            if lo == 0 && hi == n && bounds == Some(cut) {
                                assert!(!results[0].1);
                            }
                        }
                    }
                }
            }
        }
        assert!(failed > 0);
    }
}
