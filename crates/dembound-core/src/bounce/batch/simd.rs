//! The vector operations of the batched kernel, written with explicit
//! instructions for each instruction set (left to itself, the compiler
//! vectorised the kernel's element-wise array code across the wrong
//! dimension or kept the lanes in memory).
//!
//! Every operation is the IEEE operation of the scalar path in each lane:
//! add, subtract, multiply, divide and square root correctly rounded,
//! absolute value and negation on the sign bit, comparisons with the
//! scalar operators' semantics for NaN (`!=` true, `<` and `>=` false). No
//! fused multiply–add.
//!
//! A type implementing [`Simd`] is a token: it is built only where the CPU
//! has its instructions ([`Simd::detect`]), so the safe methods that use
//! them are sound.

use super::locate::{Located, Steps};
use crate::bounce::events::Crossing;
use std::ops::{Add, BitOr, Div, Mul, Neg, Sub};

/// An instruction set's vector of f64 and its operations.
pub(super) trait Simd: Copy + Send + Sync + 'static {
    /// A register of [`Self::W`] f64.
    type F: Copy;
    /// A lane mask of one register.
    type M: Copy;
    /// Lanes per register.
    const W: usize;
    /// The token, if this CPU has the instructions.
    fn detect() -> Option<Self>;
    fn splat(self, x: f64) -> Self::F;
    /// The first W values of `p` (which must hold at least W).
    fn load(self, p: &[f64]) -> Self::F;
    /// Into the first W values of `p` (which must hold at least W).
    fn store(self, p: &mut [f64], v: Self::F);
    fn add(self, a: Self::F, b: Self::F) -> Self::F;
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;
    fn div(self, a: Self::F, b: Self::F) -> Self::F;
    fn sqrt(self, a: Self::F) -> Self::F;
    fn abs(self, a: Self::F) -> Self::F;
    fn neg(self, a: Self::F) -> Self::F;
    /// a != b (true for NaN).
    fn ne(self, a: Self::F, b: Self::F) -> Self::M;
    /// a < b (false for NaN).
    fn lt(self, a: Self::F, b: Self::F) -> Self::M;
    /// a >= b (false for NaN).
    fn ge(self, a: Self::F, b: Self::F) -> Self::M;
    /// a == b, a > b, a <= b (false for NaN).
    fn eq(self, a: Self::F, b: Self::F) -> Self::M;
    fn gt(self, a: Self::F, b: Self::F) -> Self::M;
    fn le(self, a: Self::F, b: Self::F) -> Self::M;
    fn or(self, a: Self::M, b: Self::M) -> Self::M;
    fn and(self, a: Self::M, b: Self::M) -> Self::M;
    /// a and not b.
    fn and_not(self, a: Self::M, b: Self::M) -> Self::M;
    /// a where the mask is set, b elsewhere.
    fn select(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F;
    /// The mask as bits, lane l in bit l.
    fn bits(self, m: Self::M) -> u32;
    /// [`super::locate::locate_steps`] compiled for this instruction set.
    fn locate(self, crossing: Crossing, steps: &Steps, out: &mut Located);
}

#[cfg(target_arch = "x86_64")]
pub(super) use x86::{Avx2, Avx512, Sse2};

// The AVX-512 intrinsics and the `avx512*` target features are stable since
// Rust 1.89, the workspace's `rust-version`.
#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::super::locate::{locate_steps, Located, Steps};
    use super::Simd;
    use crate::bounce::events::Crossing;
    use std::arch::x86_64::*;

    #[target_feature(enable = "avx512f,avx512dq,avx512vl,avx2,fma")]
    unsafe fn locate_avx512(s: Avx512, crossing: Crossing, steps: &Steps, out: &mut Located) {
        locate_steps(s, crossing, steps, out)
    }

    #[target_feature(enable = "avx2,fma")]
    unsafe fn locate_avx2(s: Avx2, crossing: Crossing, steps: &Steps, out: &mut Located) {
        locate_steps(s, crossing, steps, out)
    }

    /// AVX-512F/DQ/VL: 8 lanes per register.
    #[derive(Debug, Clone, Copy)]
    pub(in super::super) struct Avx512(());

    /// AVX2: 4 lanes per register.
    #[derive(Debug, Clone, Copy)]
    pub(in super::super) struct Avx2(());

    /// SSE2 (x86-64's baseline): 2 lanes per register.
    #[derive(Debug, Clone, Copy)]
    pub(in super::super) struct Sse2(());

    // SAFETY (all `unsafe` blocks below): the token exists only if the CPU
    // has the instruction set (`detect`); loads and stores check the
    // slice's length first.

    impl Simd for Avx512 {
        type F = __m512d;
        type M = __mmask8;
        const W: usize = 8;
        fn detect() -> Option<Self> {
            super::super::Isa::Avx512.available().then_some(Avx512(()))
        }
        #[inline(always)]
        fn splat(self, x: f64) -> __m512d {
            unsafe { _mm512_set1_pd(x) }
        }
        #[inline(always)]
        fn load(self, p: &[f64]) -> __m512d {
            assert!(p.len() >= Self::W);
            unsafe { _mm512_loadu_pd(p.as_ptr()) }
        }
        #[inline(always)]
        fn store(self, p: &mut [f64], v: __m512d) {
            assert!(p.len() >= Self::W);
            unsafe { _mm512_storeu_pd(p.as_mut_ptr(), v) }
        }
        #[inline(always)]
        fn add(self, a: __m512d, b: __m512d) -> __m512d {
            unsafe { _mm512_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: __m512d, b: __m512d) -> __m512d {
            unsafe { _mm512_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: __m512d, b: __m512d) -> __m512d {
            unsafe { _mm512_mul_pd(a, b) }
        }
        #[inline(always)]
        fn div(self, a: __m512d, b: __m512d) -> __m512d {
            unsafe { _mm512_div_pd(a, b) }
        }
        #[inline(always)]
        fn sqrt(self, a: __m512d) -> __m512d {
            unsafe { _mm512_sqrt_pd(a) }
        }
        #[inline(always)]
        fn abs(self, a: __m512d) -> __m512d {
            unsafe { _mm512_andnot_pd(_mm512_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn neg(self, a: __m512d) -> __m512d {
            unsafe { _mm512_xor_pd(_mm512_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn ne(self, a: __m512d, b: __m512d) -> __mmask8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_NEQ_UQ>(a, b) }
        }
        #[inline(always)]
        fn lt(self, a: __m512d, b: __m512d) -> __mmask8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a, b) }
        }
        #[inline(always)]
        fn ge(self, a: __m512d, b: __m512d) -> __mmask8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_GE_OQ>(a, b) }
        }
        #[inline(always)]
        fn eq(self, a: __m512d, b: __m512d) -> __mmask8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(a, b) }
        }
        #[inline(always)]
        fn gt(self, a: __m512d, b: __m512d) -> __mmask8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(a, b) }
        }
        #[inline(always)]
        fn le(self, a: __m512d, b: __m512d) -> __mmask8 {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a, b) }
        }
        #[inline(always)]
        fn or(self, a: __mmask8, b: __mmask8) -> __mmask8 {
            a | b
        }
        #[inline(always)]
        fn and(self, a: __mmask8, b: __mmask8) -> __mmask8 {
            a & b
        }
        #[inline(always)]
        fn and_not(self, a: __mmask8, b: __mmask8) -> __mmask8 {
            a & !b
        }
        fn locate(self, crossing: Crossing, steps: &Steps, out: &mut Located) {
            unsafe { locate_avx512(self, crossing, steps, out) }
        }
        #[inline(always)]
        fn select(self, m: __mmask8, a: __m512d, b: __m512d) -> __m512d {
            unsafe { _mm512_mask_blend_pd(m, b, a) }
        }
        #[inline(always)]
        fn bits(self, m: __mmask8) -> u32 {
            u32::from(m)
        }
    }

    impl Simd for Avx2 {
        type F = __m256d;
        type M = __m256d;
        const W: usize = 4;
        fn detect() -> Option<Self> {
            super::super::Isa::Avx2.available().then_some(Avx2(()))
        }
        #[inline(always)]
        fn splat(self, x: f64) -> __m256d {
            unsafe { _mm256_set1_pd(x) }
        }
        #[inline(always)]
        fn load(self, p: &[f64]) -> __m256d {
            assert!(p.len() >= Self::W);
            unsafe { _mm256_loadu_pd(p.as_ptr()) }
        }
        #[inline(always)]
        fn store(self, p: &mut [f64], v: __m256d) {
            assert!(p.len() >= Self::W);
            unsafe { _mm256_storeu_pd(p.as_mut_ptr(), v) }
        }
        #[inline(always)]
        fn add(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_mul_pd(a, b) }
        }
        #[inline(always)]
        fn div(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_div_pd(a, b) }
        }
        #[inline(always)]
        fn sqrt(self, a: __m256d) -> __m256d {
            unsafe { _mm256_sqrt_pd(a) }
        }
        #[inline(always)]
        fn abs(self, a: __m256d) -> __m256d {
            unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn neg(self, a: __m256d) -> __m256d {
            unsafe { _mm256_xor_pd(_mm256_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn ne(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_cmp_pd::<_CMP_NEQ_UQ>(a, b) }
        }
        #[inline(always)]
        fn lt(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(a, b) }
        }
        #[inline(always)]
        fn ge(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_cmp_pd::<_CMP_GE_OQ>(a, b) }
        }
        #[inline(always)]
        fn eq(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(a, b) }
        }
        #[inline(always)]
        fn gt(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(a, b) }
        }
        #[inline(always)]
        fn le(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(a, b) }
        }
        #[inline(always)]
        fn or(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_or_pd(a, b) }
        }
        #[inline(always)]
        fn and(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_and_pd(a, b) }
        }
        #[inline(always)]
        fn and_not(self, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_andnot_pd(b, a) }
        }
        fn locate(self, crossing: Crossing, steps: &Steps, out: &mut Located) {
            unsafe { locate_avx2(self, crossing, steps, out) }
        }
        #[inline(always)]
        fn select(self, m: __m256d, a: __m256d, b: __m256d) -> __m256d {
            unsafe { _mm256_blendv_pd(b, a, m) }
        }
        #[inline(always)]
        fn bits(self, m: __m256d) -> u32 {
            unsafe { _mm256_movemask_pd(m) as u32 }
        }
    }

    impl Simd for Sse2 {
        type F = __m128d;
        type M = __m128d;
        const W: usize = 2;
        fn detect() -> Option<Self> {
            // The baseline of the x86-64 target.
            Some(Sse2(()))
        }
        #[inline(always)]
        fn splat(self, x: f64) -> __m128d {
            unsafe { _mm_set1_pd(x) }
        }
        #[inline(always)]
        fn load(self, p: &[f64]) -> __m128d {
            assert!(p.len() >= Self::W);
            unsafe { _mm_loadu_pd(p.as_ptr()) }
        }
        #[inline(always)]
        fn store(self, p: &mut [f64], v: __m128d) {
            assert!(p.len() >= Self::W);
            unsafe { _mm_storeu_pd(p.as_mut_ptr(), v) }
        }
        #[inline(always)]
        fn add(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_mul_pd(a, b) }
        }
        #[inline(always)]
        fn div(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_div_pd(a, b) }
        }
        #[inline(always)]
        fn sqrt(self, a: __m128d) -> __m128d {
            unsafe { _mm_sqrt_pd(a) }
        }
        #[inline(always)]
        fn abs(self, a: __m128d) -> __m128d {
            unsafe { _mm_andnot_pd(_mm_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn neg(self, a: __m128d) -> __m128d {
            unsafe { _mm_xor_pd(_mm_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn ne(self, a: __m128d, b: __m128d) -> __m128d {
            // cmpneqpd: not equal or unordered.
            unsafe { _mm_cmpneq_pd(a, b) }
        }
        #[inline(always)]
        fn lt(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_cmplt_pd(a, b) }
        }
        #[inline(always)]
        fn ge(self, a: __m128d, b: __m128d) -> __m128d {
            // b <= a: false when unordered.
            unsafe { _mm_cmple_pd(b, a) }
        }
        #[inline(always)]
        fn eq(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_cmpeq_pd(a, b) }
        }
        #[inline(always)]
        fn gt(self, a: __m128d, b: __m128d) -> __m128d {
            // b < a: false when unordered.
            unsafe { _mm_cmplt_pd(b, a) }
        }
        #[inline(always)]
        fn le(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_cmple_pd(a, b) }
        }
        #[inline(always)]
        fn or(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_or_pd(a, b) }
        }
        #[inline(always)]
        fn and(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_and_pd(a, b) }
        }
        #[inline(always)]
        fn and_not(self, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_andnot_pd(b, a) }
        }
        fn locate(self, crossing: Crossing, steps: &Steps, out: &mut Located) {
            locate_steps(self, crossing, steps, out)
        }
        #[inline(always)]
        fn select(self, m: __m128d, a: __m128d, b: __m128d) -> __m128d {
            unsafe { _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b)) }
        }
        #[inline(always)]
        fn bits(self, m: __m128d) -> u32 {
            unsafe { _mm_movemask_pd(m) as u32 }
        }
    }
}

/// One lane per "register": the portable fallback for other targets.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Debug, Clone, Copy)]
pub(super) struct Scalar(());

#[cfg(not(target_arch = "x86_64"))]
impl Simd for Scalar {
    type F = f64;
    type M = bool;
    const W: usize = 1;
    fn detect() -> Option<Self> {
        Some(Scalar(()))
    }
    #[inline(always)]
    fn splat(self, x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn load(self, p: &[f64]) -> f64 {
        p[0]
    }
    #[inline(always)]
    fn store(self, p: &mut [f64], v: f64) {
        p[0] = v;
    }
    #[inline(always)]
    fn add(self, a: f64, b: f64) -> f64 {
        a + b
    }
    #[inline(always)]
    fn sub(self, a: f64, b: f64) -> f64 {
        a - b
    }
    #[inline(always)]
    fn mul(self, a: f64, b: f64) -> f64 {
        a * b
    }
    #[inline(always)]
    fn div(self, a: f64, b: f64) -> f64 {
        a / b
    }
    #[inline(always)]
    fn sqrt(self, a: f64) -> f64 {
        a.sqrt()
    }
    #[inline(always)]
    fn abs(self, a: f64) -> f64 {
        a.abs()
    }
    #[inline(always)]
    fn neg(self, a: f64) -> f64 {
        -a
    }
    #[inline(always)]
    fn ne(self, a: f64, b: f64) -> bool {
        a != b
    }
    #[inline(always)]
    fn lt(self, a: f64, b: f64) -> bool {
        a < b
    }
    #[inline(always)]
    fn ge(self, a: f64, b: f64) -> bool {
        a >= b
    }
    #[inline(always)]
    fn eq(self, a: f64, b: f64) -> bool {
        a == b
    }
    #[inline(always)]
    fn gt(self, a: f64, b: f64) -> bool {
        a > b
    }
    #[inline(always)]
    fn le(self, a: f64, b: f64) -> bool {
        a <= b
    }
    #[inline(always)]
    fn or(self, a: bool, b: bool) -> bool {
        a | b
    }
    #[inline(always)]
    fn and(self, a: bool, b: bool) -> bool {
        a & b
    }
    #[inline(always)]
    fn and_not(self, a: bool, b: bool) -> bool {
        a & !b
    }
    fn locate(self, crossing: Crossing, steps: &Steps, out: &mut Located) {
        super::locate::locate_steps(self, crossing, steps, out)
    }
    #[inline(always)]
    fn select(self, m: bool, a: f64, b: f64) -> f64 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn bits(self, m: bool) -> u32 {
        u32::from(m)
    }
}

/// G registers of lanes: `S::W * G` lanes.
#[derive(Clone, Copy)]
pub(super) struct V<S: Simd, const G: usize> {
    s: S,
    v: [S::F; G],
}

/// A lane mask of G registers.
#[derive(Clone, Copy)]
pub(super) struct Mask<S: Simd, const G: usize> {
    s: S,
    m: [S::M; G],
}

impl<S: Simd, const G: usize> V<S, G> {
    #[inline(always)]
    fn from_fn(s: S, f: impl Fn(usize) -> S::F) -> Self {
        // An explicit loop over G (≤ 4) registers, unrolled.
        let mut v = [s.splat(0.0); G];
        for (g, x) in v.iter_mut().enumerate() {
            *x = f(g);
        }
        V { s, v }
    }

    #[inline(always)]
    pub(super) fn splat(s: S, x: f64) -> Self {
        V {
            s,
            v: [s.splat(x); G],
        }
    }

    /// The first `LANES` values of `p`.
    #[inline(always)]
    pub(super) fn load(s: S, p: &[f64]) -> Self {
        Self::from_fn(s, |g| s.load(&p[g * S::W..]))
    }

    /// Into the first `LANES` values of `p`.
    #[inline(always)]
    pub(super) fn store(self, p: &mut [f64]) {
        for (g, x) in self.v.iter().enumerate() {
            self.s.store(&mut p[g * S::W..], *x);
        }
    }

    #[inline(always)]
    fn zip(self, b: Self, f: impl Fn(S, S::F, S::F) -> S::F) -> Self {
        let s = self.s;
        Self::from_fn(s, |g| f(s, self.v[g], b.v[g]))
    }

    #[inline(always)]
    fn cmp(self, b: Self, f: impl Fn(S, S::F, S::F) -> S::M) -> Mask<S, G> {
        let s = self.s;
        let mut m = [f(s, self.v[0], b.v[0]); G];
        for (g, x) in m.iter_mut().enumerate().skip(1) {
            *x = f(s, self.v[g], b.v[g]);
        }
        Mask { s, m }
    }

    #[inline(always)]
    pub(super) fn sqrt(self) -> Self {
        let s = self.s;
        Self::from_fn(s, |g| s.sqrt(self.v[g]))
    }

    #[inline(always)]
    pub(super) fn abs(self) -> Self {
        let s = self.s;
        Self::from_fn(s, |g| s.abs(self.v[g]))
    }

    #[inline(always)]
    pub(super) fn ne(self, b: Self) -> Mask<S, G> {
        self.cmp(b, S::ne)
    }

    #[inline(always)]
    pub(super) fn lt(self, b: Self) -> Mask<S, G> {
        self.cmp(b, S::lt)
    }

    #[inline(always)]
    pub(super) fn ge(self, b: Self) -> Mask<S, G> {
        self.cmp(b, S::ge)
    }

    #[inline(always)]
    pub(super) fn eq(self, b: Self) -> Mask<S, G> {
        self.cmp(b, S::eq)
    }

    #[inline(always)]
    pub(super) fn gt(self, b: Self) -> Mask<S, G> {
        self.cmp(b, S::gt)
    }

    #[inline(always)]
    pub(super) fn le(self, b: Self) -> Mask<S, G> {
        self.cmp(b, S::le)
    }
}

impl<S: Simd, const G: usize> Mask<S, G> {
    /// a where the mask is set, b elsewhere.
    #[inline(always)]
    pub(super) fn select(self, a: V<S, G>, b: V<S, G>) -> V<S, G> {
        let s = self.s;
        V::from_fn(s, |g| s.select(self.m[g], a.v[g], b.v[g]))
    }

    #[inline(always)]
    fn zip(self, b: Self, f: impl Fn(S, S::M, S::M) -> S::M) -> Self {
        let mut m = self.m;
        for (x, y) in m.iter_mut().zip(b.m) {
            *x = f(self.s, *x, y);
        }
        Mask { s: self.s, m }
    }

    #[inline(always)]
    pub(super) fn and(self, b: Self) -> Self {
        self.zip(b, S::and)
    }

    /// self and not b.
    #[inline(always)]
    pub(super) fn and_not(self, b: Self) -> Self {
        self.zip(b, S::and_not)
    }

    #[inline(always)]
    pub(super) fn any(self) -> bool {
        self.bits() != 0
    }

    /// Lane l in bit l.
    #[inline(always)]
    pub(super) fn bits(self) -> u32 {
        let mut bits = 0;
        for (g, m) in self.m.iter().enumerate() {
            bits |= self.s.bits(*m) << (g * S::W);
        }
        bits
    }
}

impl<S: Simd, const G: usize> BitOr for Mask<S, G> {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, b: Self) -> Self {
        self.zip(b, S::or)
    }
}

macro_rules! binop {
    ($tr:ident, $f:ident) => {
        impl<S: Simd, const G: usize> $tr for V<S, G> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, b: Self) -> Self {
                self.zip(b, S::$f)
            }
        }
        impl<S: Simd, const G: usize> $tr<V<S, G>> for f64 {
            type Output = V<S, G>;
            #[inline(always)]
            fn $f(self, b: V<S, G>) -> V<S, G> {
                V::splat(b.s, self).zip(b, S::$f)
            }
        }
    };
}
binop!(Add, add);
binop!(Sub, sub);
binop!(Mul, mul);
binop!(Div, div);

impl<S: Simd, const G: usize> Neg for V<S, G> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let s = self.s;
        Self::from_fn(s, |g| s.neg(self.v[g]))
    }
}
