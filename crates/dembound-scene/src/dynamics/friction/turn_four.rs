//! A batch's stored springs, four entries at a time (AVX2): each touching
//! entry's spring turned into its tangent plane
//! ([`FrictionPair::turn_spring`]), each other entry's spring set to +0.
//! Every lane takes the scalar function's IEEE operations in its order
//! (no fused multiply–add), so the springs are the same bits as the
//! scalar pass's; a group of four in which a touching spring takes the
//! large-turn branch (a root, rare: a contact's normal turned by more
//! than ~10⁻⁴ rad in one step) runs the scalar function instead.

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m256d, __m256i, _mm256_add_pd, _mm256_and_pd, _mm256_andnot_pd, _mm256_blend_pd,
    _mm256_blendv_pd, _mm256_castsi256_pd, _mm256_cmp_pd, _mm256_div_pd, _mm256_loadu_pd,
    _mm256_loadu_si256, _mm256_movemask_pd, _mm256_mul_pd, _mm256_permute4x64_pd,
    _mm256_permute_pd, _mm256_set1_pd, _mm256_setzero_pd, _mm256_setzero_si256, _mm256_storeu_pd,
    _mm256_sub_epi64, _mm256_sub_pd, _CMP_GE_OQ, _CMP_LT_OQ, _CMP_NEQ_UQ,
};

use dembound_physics::contact::tangential::FrictionPair;

/// One entry: its spring turned into the plane of the unit normal `n`
/// when it touches (`touches` 1), else set to exactly +0 (`touches` 0):
/// what the batch's masking and turning passes do to it.
#[inline(always)]
pub(super) fn turn_or_clear_one(shear: &mut [f64; 3], n: [f64; 3], touches: u64) {
    if touches != 0 {
        FrictionPair::turn_spring(shear, n);
    } else {
        *shear = [0.0; 3];
    }
}

/// [`turn_or_clear_one`] on entries `0..count`: `shear` their springs
/// (consecutive), `nx`, `ny`, `nz` their unit normals' components and
/// `touches` 1 or 0 per entry. Four at a time, the rest one by one.
///
/// # Safety
/// The processor must have AVX2; `shear` must be valid for reads and
/// writes of `count` springs, none of them borrowed elsewhere; the four
/// arrays must hold at least `count` values each.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
#[inline]
pub(super) unsafe fn turn_or_clear(
    shear: *mut [f64; 3],
    nx: &[f64],
    ny: &[f64],
    nz: &[f64],
    touches: &[u64],
    count: usize,
) {
    debug_assert!(nx.len() >= count && ny.len() >= count && nz.len() >= count);
    debug_assert!(touches.len() >= count);
    let zero = _mm256_setzero_pd();
    let one = _mm256_set1_pd(1.0);
    let half = _mm256_set1_pd(0.5);
    let tiny = _mm256_set1_pd(1.0e-8);
    let normal_min = _mm256_set1_pd(f64::MIN_POSITIVE);
    let mut q = 0;
    while q + 4 <= count {
        // SAFETY: entries q..q + 4 are < count (the loop's test).
        unsafe {
            let at = shear.add(q) as *mut f64;
            // [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3] -> x, y, z of
            // entries q..q + 4 (the transpose of `verlet_four::advance`).
            let [x, y, z] = lanes_to_xyz!([
                _mm256_loadu_pd(at),
                _mm256_loadu_pd(at.add(4)),
                _mm256_loadu_pd(at.add(8)),
            ]);
            let (n0, n1, n2) = (
                _mm256_loadu_pd(nx.as_ptr().add(q)),
                _mm256_loadu_pd(ny.as_ptr().add(q)),
                _mm256_loadu_pd(nz.as_ptr().add(q)),
            );
            // All ones where the entry touches, else 0.
            let t = _mm256_loadu_si256(touches.as_ptr().add(q) as *const __m256i);
            let keep = _mm256_castsi256_pd(_mm256_sub_epi64(_mm256_setzero_si256(), t));
            // `turn_spring`, lane by lane: along = δ·n, before = δ·δ
            // (`dot`'s order), p = δ − along n, along² < 1e-8 before: the
            // small turn's scale 1 + ½ (along² · (1/before)).
            let along = dot(x, y, z, n0, n1, n2);
            let before = dot(x, y, z, x, y, z);
            let px = _mm256_sub_pd(x, _mm256_mul_pd(along, n0));
            let py = _mm256_sub_pd(y, _mm256_mul_pd(along, n1));
            let pz = _mm256_sub_pd(z, _mm256_mul_pd(along, n2));
            let along2 = _mm256_mul_pd(along, along);
            // The small turn's test, and |δ|² normal (`turn_spring`: a
            // subnormal |δ|² takes the root, in the scalar function).
            let small = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_LT_OQ>(along2, _mm256_mul_pd(tiny, before)),
                _mm256_cmp_pd::<_CMP_GE_OQ>(before, normal_min),
            );
            let turned = _mm256_cmp_pd::<_CMP_NEQ_UQ>(along, zero);
            // A touching spring that turns by the large-turn branch: the
            // scalar function for these four.
            let large = _mm256_and_pd(_mm256_andnot_pd(small, turned), keep);
            if _mm256_movemask_pd(large) != 0 {
                for e in q..q + 4 {
                    let n = [nx[e], ny[e], nz[e]];
                    turn_or_clear_one(&mut *shear.add(e), n, touches[e]);
                }
                q += 4;
                continue;
            }
            let scale = _mm256_add_pd(
                one,
                _mm256_mul_pd(half, _mm256_mul_pd(along2, _mm256_div_pd(one, before))),
            );
            // Unturned (along = 0): the spring as it was; untouched: +0.
            let pick = |p: __m256d, s: __m256d| {
                _mm256_and_pd(_mm256_blendv_pd(s, _mm256_mul_pd(p, scale), turned), keep)
            };
            let (x, y, z) = (pick(px, x), pick(py, y), pick(pz, z));
            // Back: x, y, z -> [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3].
            let [s0, s1, s2] = xyz_to_lanes!(x, y, z);
            _mm256_storeu_pd(at, s0);
            _mm256_storeu_pd(at.add(4), s1);
            _mm256_storeu_pd(at.add(8), s2);
        }
        q += 4;
    }
    for e in q..count {
        // SAFETY: e < count.
        let sh = unsafe { &mut *shear.add(e) };
        turn_or_clear_one(sh, [nx[e], ny[e], nz[e]], touches[e]);
    }
}

/// a·b lane by lane, as the physics crate's `dot`: (a₀b₀ + a₁b₁) + a₂b₂.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
#[inline]
fn dot(a0: __m256d, a1: __m256d, a2: __m256d, b0: __m256d, b1: __m256d, b2: __m256d) -> __m256d {
    _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(a0, b0), _mm256_mul_pd(a1, b1)),
        _mm256_mul_pd(a2, b2),
    )
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::{turn_or_clear, turn_or_clear_one};

    /// Four at a time equals the scalar function entry by entry, bit for
    /// bit (the expected springs from `FrictionPair::turn_spring` itself
    /// and +0), over groups that exercise every case of a lane: small
    /// turns of unlike magnitudes and signs, an unturned spring (δ·n = 0
    /// exactly), a zero spring, untouched entries (any spring, NaN
    /// included), a large turn (the scalar fallback) beside small ones,
    /// and counts that leave 0–3 entries for the scalar tail. A component
    /// taken from the wrong lane or entry, or an operation reordered,
    /// changes the bits.
    #[test]
    fn four_at_a_time_equals_the_scalar_function_bit_for_bit() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        // A deterministic spread of values (xorshift): springs ~1e-6 m,
        // normals unit vectors, the spring nearly in the tangent plane
        // (δ·n ~ 1e-9 |δ|: the small turn) unless stated.
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let count = 43;
        let mut shear = Vec::new();
        let (mut nx, mut ny, mut nz, mut touches) = (vec![], vec![], vec![], vec![]);
        for e in 0..count {
            let raw = [uniform(), uniform(), uniform() + 2.0];
            let len = (raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2]).sqrt();
            let n = raw.map(|c| c / len);
            // A tangent vector t ⟂ n, then δ = a t + b n.
            let t = {
                let c = [n[1], -n[0], 0.0];
                let l = (c[0] * c[0] + c[1] * c[1]).sqrt();
                [c[0] / l, c[1] / l, 0.0]
            };
            let a = 1.0e-6 * (1.0 + uniform()) * if e % 2 == 0 { 1.0 } else { -3.7e3 };
            let b = match e % 11 {
                3 => 0.0,     // δ·n may round to 0 or not: both fine
                7 => 0.3 * a, // a large turn: the fallback
                _ => 1.0e-9 * a * uniform(),
            };
            let mut d = [0.0; 3];
            for c in 0..3 {
                d[c] = a * t[c] + b * n[c];
            }
            if e % 13 == 5 {
                d = [0.0; 3];
            }
            if e % 17 == 9 {
                d = [1.0e-6, 0.0, 0.0];
                // exactly in the plane of n = z: δ·n = 0
                nx.push(0.0);
                ny.push(0.0);
                nz.push(1.0);
            } else {
                nx.push(n[0]);
                ny.push(n[1]);
                nz.push(n[2]);
            }
            if e % 19 == 2 {
                d = [f64::NAN, 1.0, -2.0];
            }
            if e % 23 == 12 {
                // |δ|² subnormal, a small turn (δ·n ~ 1e-5 |δ|): the
                // scalar function's root (1/|δ|² would be ∞).
                for c in 0..3 {
                    d[c] = 1.0e-155 * t[c] + 1.0e-160 * n[c];
                }
            }
            shear.push(d);
            touches.push(u64::from(e % 5 != 1 && e % 19 != 2));
        }
        for n in [43, 42, 41, 40, 4, 3, 0] {
            let mut expected = shear.clone();
            for (e, sh) in expected.iter_mut().enumerate().take(n) {
                turn_or_clear_one(sh, [nx[e], ny[e], nz[e]], touches[e]);
            }
            let mut got = shear.clone();
            // SAFETY: AVX2 checked; `got` holds `count` ≥ n springs.
            unsafe { turn_or_clear(got.as_mut_ptr(), &nx, &ny, &nz, &touches, n) };
            for e in (12..n).step_by(23) {
                assert!(
                    got[e].iter().all(|x| x.is_finite()),
                    "entry {e}: {:?}",
                    got[e]
                );
            }
            for e in 0..count {
                assert_eq!(
                    got[e].map(f64::to_bits),
                    expected[e].map(f64::to_bits),
                    "entry {e} of {n}: {:?} against {:?}",
                    got[e],
                    expected[e]
                );
            }
            // The cases were there: small turns changed springs, a large
            // turn and untouched entries occurred among the first n.
            if n == 43 {
                assert!((0..n).any(|e| touches[e] == 1 && expected[e] != shear[e]));
                assert!((0..n).any(|e| touches[e] == 0 && !shear[e].iter().all(|&c| c == 0.0)));
            }
        }
    }
}
