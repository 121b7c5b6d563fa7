//! The integration of the friction body pass (`verlet_chunk_friction_body`)
//! four bodies at a time, with AVX2: the pending closing half kick, the
//! half kick and the drift of position, velocity and spin (Verlet as
//! LAMMPS `nve/sphere`: v ← v + (Δt/2/m) F, ω ← ω + (Δt/2 · 1/I) τ,
//! x ← x + Δt v), each body's squared displacement since the list build,
//! its weight m g as its force and a zero torque.
//!
//! Four bodies' 3-vectors lie in 12 consecutive doubles, three 4-lane
//! registers; a per-body factor (Δt/2/m, Δt/2 · 1/I, m) is spread over
//! them as [a a a b] [b b c c] [c d d d]. Each lane does the scalar loop's
//! operation on the scalar loop's operands (IEEE multiply, add, subtract
//! and divide per lane, no fused multiply–add): the same bits.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_div_pd, _mm256_loadu_pd, _mm256_mul_pd,
    _mm256_permute4x64_pd, _mm256_permute_pd, _mm256_set1_pd, _mm256_setr_pd, _mm256_setzero_pd,
    _mm256_storeu_pd, _mm256_sub_pd,
};

/// Where four consecutive bodies' state lies: each pointer at the first
/// body's first component (position, velocity, spin, force and torque:
/// 12 doubles each; the reference positions of the list build, 12; mass
/// and 1/I, 4).
pub(super) struct Four {
    pub(super) x: *mut f64,
    pub(super) v: *mut f64,
    pub(super) w: *mut f64,
    pub(super) f: *mut f64,
    pub(super) t: *mut f64,
    pub(super) reference: *const f64,
    pub(super) mass: *const f64,
    pub(super) inverse_inertia: *const f64,
}

/// Spreads one factor per body over the three registers of four bodies'
/// 3-vectors: [a a a b], [b b c c], [c d d d].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
#[inline]
fn spread(s: __m256d) -> [__m256d; 3] {
    [
        _mm256_permute4x64_pd::<0b01_00_00_00>(s),
        _mm256_permute4x64_pd::<0b10_10_01_01>(s),
        _mm256_permute4x64_pd::<0b11_11_11_10>(s),
    ]
}

/// Advances four free bodies (`verlet_chunk_friction_body`'s first loop
/// for each, in the same operations): kicks (two when `pending`) and
/// drift, step `dt` (s); force m g (N), torque 0. Returns their squared
/// displacements from the reference positions, m², body k in lane k:
/// (dx² + dy²) + dz² as `integrate::displacement2`, the three registers'
/// squares transposed in registers (a store of them read back as single
/// doubles would wait for the store: the halves of a vector store do not
/// forward to narrower loads at other offsets).
///
/// # Safety
/// The processor has AVX2; the pointers of `four` are valid for four
/// bodies and no other thread touches those bodies.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
#[inline]
pub(super) unsafe fn advance(four: &Four, dt: f64, pending: bool, gravity: [f64; 3]) -> __m256d {
    let half_dt = 0.5 * dt;
    // SAFETY (every load and store): within the four bodies' state (the
    // caller's).
    unsafe {
        let mass = _mm256_loadu_pd(four.mass);
        let dtfm = spread(_mm256_div_pd(_mm256_set1_pd(half_dt), mass));
        let dtfi = spread(_mm256_mul_pd(
            _mm256_set1_pd(half_dt),
            _mm256_loadu_pd(four.inverse_inertia),
        ));
        let mass = spread(mass);
        let [g0, g1, g2] = gravity;
        let weight = [
            _mm256_setr_pd(g0, g1, g2, g0),
            _mm256_setr_pd(g1, g2, g0, g1),
            _mm256_setr_pd(g2, g0, g1, g2),
        ];
        let step = _mm256_set1_pd(dt);
        let mut squares = [_mm256_setzero_pd(); 3];
        for k in 0..3 {
            let at = 4 * k;
            let kick_v = _mm256_mul_pd(_mm256_loadu_pd(four.f.add(at)), dtfm[k]);
            let kick_w = _mm256_mul_pd(_mm256_loadu_pd(four.t.add(at)), dtfi[k]);
            let (mut v, mut w) = (
                _mm256_loadu_pd(four.v.add(at)),
                _mm256_loadu_pd(four.w.add(at)),
            );
            if pending {
                v = _mm256_add_pd(v, kick_v);
                w = _mm256_add_pd(w, kick_w);
            }
            v = _mm256_add_pd(v, kick_v);
            w = _mm256_add_pd(w, kick_w);
            let x = _mm256_add_pd(_mm256_loadu_pd(four.x.add(at)), _mm256_mul_pd(v, step));
            _mm256_storeu_pd(four.x.add(at), x);
            _mm256_storeu_pd(four.v.add(at), v);
            _mm256_storeu_pd(four.w.add(at), w);
            let d = _mm256_sub_pd(x, _mm256_loadu_pd(four.reference.add(at)));
            squares[k] = _mm256_mul_pd(d, d);
            _mm256_storeu_pd(four.f.add(at), _mm256_mul_pd(mass[k], weight[k]));
            _mm256_storeu_pd(four.t.add(at), _mm256_setzero_pd());
        }
        // [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3] -> the x, y and z
        // squares of bodies 0-3 (as `verlet::advance_bodies_quad`).
        let [dx, dy, dz] = lanes_to_xyz!(squares);
        _mm256_add_pd(_mm256_add_pd(dx, dy), dz)
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::{advance, Four};
    use crate::dynamics::integrate;

    /// Four bodies' kicks, drift, displacements and weights equal the
    /// scalar loop's operations (`integrate::half_kick`, `drift`,
    /// `displacement2`, m g) bit for bit, with and without the pending
    /// kick, on values of unlike magnitudes and signs (each lane must take
    /// its own body's factor: a factor spread to the wrong lane changes
    /// the bits).
    #[test]
    fn four_bodies_equal_the_scalar_loop_bit_for_bit() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        // Deterministic values of unlike magnitudes (a small LCG).
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut value = |scale: f64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            scale * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.3)
        };
        let vec3 = |value: &mut dyn FnMut(f64) -> f64, s: f64| [value(s), value(s), value(s)];
        let (dt, gravity) = (2.0e-6, [0.3, -1.7, -9.81]);
        for pending in [false, true] {
            for round in 0..20 {
                let s = 10f64.powi(round % 7 - 3);
                let mut x: Vec<[f64; 3]> = (0..4).map(|_| vec3(&mut value, 1e-2 * s)).collect();
                let mut v: Vec<[f64; 3]> = (0..4).map(|_| vec3(&mut value, s)).collect();
                let mut w: Vec<[f64; 3]> = (0..4).map(|_| vec3(&mut value, 1e3 * s)).collect();
                let mut f: Vec<[f64; 3]> = (0..4).map(|_| vec3(&mut value, 1e-3 * s)).collect();
                let mut t: Vec<[f64; 3]> = (0..4).map(|_| vec3(&mut value, 1e-9 * s)).collect();
                let reference: Vec<[f64; 3]> =
                    x.iter().map(|p| p.map(|c| c + value(1e-4 * s))).collect();
                let mass: Vec<f64> = (0..4).map(|_| 1e-6 * (1.5 + value(1.0))).collect();
                let inverse_inertia: Vec<f64> = (0..4).map(|_| 1e10 * (1.5 + value(1.0))).collect();
                // The scalar loop's operations, body by body.
                let half_dt = 0.5 * dt;
                let mut expected = Vec::new();
                for i in 0..4 {
                    let (mut xi, mut vi, mut wi) = (x[i], v[i], w[i]);
                    let (dtfm, dtfi) = (half_dt / mass[i], half_dt * inverse_inertia[i]);
                    if pending {
                        integrate::half_kick(&mut vi, f[i], dtfm);
                        integrate::half_kick(&mut wi, t[i], dtfi);
                    }
                    integrate::half_kick(&mut vi, f[i], dtfm);
                    integrate::half_kick(&mut wi, t[i], dtfi);
                    integrate::drift(&mut xi, vi, dt);
                    let d2 = integrate::displacement2(xi, reference[i]);
                    let weight = gravity.map(|g| mass[i] * g);
                    expected.push((xi, vi, wi, weight, d2));
                }
                let four = Four {
                    x: x.as_mut_ptr().cast(),
                    v: v.as_mut_ptr().cast(),
                    w: w.as_mut_ptr().cast(),
                    f: f.as_mut_ptr().cast(),
                    t: t.as_mut_ptr().cast(),
                    reference: reference.as_ptr().cast(),
                    mass: mass.as_ptr(),
                    inverse_inertia: inverse_inertia.as_ptr(),
                };
                let mut moved2 = [0.0f64; 4];
                // SAFETY: AVX2 (checked); four bodies' state each.
                unsafe {
                    std::arch::x86_64::_mm256_storeu_pd(
                        moved2.as_mut_ptr(),
                        advance(&four, dt, pending, gravity),
                    )
                };
                let bits = |a: [f64; 3]| a.map(f64::to_bits);
                for i in 0..4 {
                    let (xi, vi, wi, weight, d2) = expected[i];
                    let at = format!("round {round}, body {i}, pending {pending}");
                    assert_eq!(bits(x[i]), bits(xi), "position, {at}");
                    assert_eq!(bits(v[i]), bits(vi), "velocity, {at}");
                    assert_eq!(bits(w[i]), bits(wi), "spin, {at}");
                    assert_eq!(bits(f[i]), bits(weight), "force, {at}");
                    assert_eq!(bits(t[i]), bits([0.0; 3]), "torque, {at}");
                    assert_eq!(moved2[i].to_bits(), d2.to_bits(), "displacement², {at}");
                }
            }
        }
    }
}
