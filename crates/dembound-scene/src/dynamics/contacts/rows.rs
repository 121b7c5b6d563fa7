//! The frictionless loop over the main pairs: block by block, row by row,
//! each touching pair's force added to its partner as it goes and the
//! row's sum to its body at the row's end (the order that makes the sums
//! independent of the thread and rank counts); on AVX2 each row's pairs
//! are tested four at a time first.

use super::one_law::{KnownLaw, PairLaws};
use super::{
    add, contact_force, geometry_at, sub, touching_lazy, LawTable, PairGeometry, PairHistories,
    PairTally, NO_HISTORY,
};
use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::entry_tally::EntryTerms;
use crate::geometry::neighbour::PairList;
use crate::parallel::SharedMut;
use dembound_physics::contact::ContactHistory;

/// `$body` with `$laws` the loop's law source: the kernel of the scene's
/// one law when it has one ([`KnownLaw`]), else the table (one
/// instantiation of the loop each).
macro_rules! with_laws {
    ($rows:ident, $laws:ident => $body:expr) => {
        match &$rows.one {
            Some(KnownLaw::OneHertzUndamped($laws)) => $body,
            Some(KnownLaw::OneHertzTsuji($laws)) => $body,
            Some(KnownLaw::HertzUndamped($laws)) => $body,
            Some(KnownLaw::HertzTsuji($laws)) => $body,
            None => {
                let $laws = $rows.laws;
                $body
            }
        }
    };
}

/// What the frictionless loop over the main pairs reads and writes.
pub(crate) struct Rows<'a> {
    bodies: &'a Bodies,
    laws: &'a LawTable,
    list: &'a PairList,
    position: &'a [[f64; 3]],
    velocity: &'a [[f64; 3]],
    radius: &'a [f64],
    start: &'a [u32],
    js: &'a [u32],
    keep: bool,
    f_ptr: SharedMut<[f64; 3]>,
    h_ptr: SharedMut<ContactHistory>,
    /// One [`PairTally`] per body, written when `TALLY`.
    tally: SharedMut<PairTally>,
    /// Each touching entry's elastic energy, written when `TALLY` and
    /// asked.
    entries: EntryTerms,
    /// The scene's one law when it has one body class and a law a kernel
    /// without the per-contact dispatch has (`one_law`).
    one: Option<KnownLaw<'a>>,
}

impl<'a> Rows<'a> {
    /// The loop over `list`'s main pairs of `bodies`, adding to the forces
    /// at `f_ptr` (one per body) and updating `histories` (when the law
    /// keeps them: one per main entry, asserted); each row's
    /// [`PairTally`] into `tally` when given, and then each touching
    /// entry's elastic energy into `entries` when asked (one per main
    /// entry).
    pub(crate) fn new(
        bodies: &'a Bodies,
        list: &'a PairList,
        histories: &'a mut PairHistories,
        laws: &'a LawTable,
        f_ptr: SharedMut<[f64; 3]>,
        tally: Option<SharedMut<PairTally>>,
        entries: EntryTerms,
    ) -> Self {
        let n = bodies.len();
        let keep = laws.history;
        assert!(list.start.len() == n + 1);
        assert!(!keep || histories.main.len() == list.j.len());
        assert!(
            bodies.position.len() == n && bodies.velocity.len() == n && bodies.radius.len() == n
        );
        Rows {
            bodies,
            laws,
            list,
            // Local slices: the compiler cannot hoist loads of the vectors'
            // headers past the raw-pointer writes below.
            position: &bodies.position[..],
            velocity: &bodies.velocity[..],
            radius: &bodies.radius[..],
            start: &list.start[..],
            js: &list.j[..],
            keep,
            f_ptr,
            h_ptr: SharedMut(histories.main.as_mut_ptr()),
            tally: tally.unwrap_or(SharedMut(std::ptr::null_mut())),
            entries,
            one: KnownLaw::of(laws, bodies),
        }
    }

    /// The same loop with every contact's law read from the table and
    /// dispatched on (the one-law kernel's reference in the tests).
    pub(crate) fn table_laws_only(self) -> Self {
        Rows { one: None, ..self }
    }

    /// The laws, the list and the histories of the loop
    /// (`dynamics::halo_split` computes some pairs itself).
    pub(crate) fn parts(
        &self,
    ) -> (
        &'a Bodies,
        &'a LawTable,
        &'a PairList,
        Option<SharedMut<ContactHistory>>,
    ) {
        (
            self.bodies,
            self.laws,
            self.list,
            self.keep.then_some(self.h_ptr),
        )
    }

    /// Where the loop adds the forces (one per body).
    pub(crate) fn forces(&self) -> SharedMut<[f64; 3]> {
        self.f_ptr
    }

    /// Block `b`'s rows; `TALLY`: each row's [`PairTally`] too.
    ///
    /// # Safety
    /// As [`add_pair_forces_then`](super::add_pair_forces_then)'s; with
    /// `TALLY`, `tally` points to one per body.
    #[inline(always)]
    pub(super) unsafe fn block<const TALLY: bool>(&self, b: usize) {
        with_laws!(self, laws => self.block_with::<TALLY, false, _>(b, laws))
    }

    /// [`Self::block`] with each row's pairs tested four at a time for
    /// contact ([`Self::near4`]): only the pairs found touching go through
    /// the pair-by-pair code, in list order; a row's last 1–3 pairs go pair
    /// by pair. Without stored histories only (a pair apart then does
    /// nothing).
    ///
    /// # Safety
    /// As [`Self::block`]; the processor has AVX2 and no histories are
    /// kept.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    pub(super) unsafe fn block_avx2<const TALLY: bool>(&self, b: usize) {
        with_laws!(self, laws => self.block_with::<TALLY, true, _>(b, laws))
    }

    /// Rows `lo..hi` as [`Self::block_avx2`] runs a block's, each row's
    /// pairs tested four at a time (`dynamics::halo_split` runs its rows
    /// without a late body so).
    ///
    /// # Safety
    /// As [`Self::row`] for each of the rows; the processor has AVX2 and
    /// no histories are kept.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    pub(crate) unsafe fn rows_avx2(&self, lo: usize, hi: usize) {
        with_laws!(self, laws => self.rows_with::<true, _>(lo, hi, laws))
    }

    /// Rows `lo..hi`, no tally, the laws from `laws`.
    ///
    /// # Safety
    /// As [`Self::row`] for each of the rows; with `QUAD`, as
    /// [`Self::block_avx2`].
    #[inline(always)]
    unsafe fn rows_with<const QUAD: bool, L: PairLaws>(&self, lo: usize, hi: usize, laws: &L) {
        for i in lo..hi {
            // SAFETY: as the caller's.
            unsafe { self.row_with::<false, QUAD, L>(i, laws) };
        }
    }

    /// # Safety
    /// As [`Self::block`]; with `QUAD`, as [`Self::block_avx2`].
    #[inline(always)]
    unsafe fn block_with<const TALLY: bool, const QUAD: bool, L: PairLaws>(
        &self,
        b: usize,
        laws: &L,
    ) {
        let lo = self.list.blocks[b] as usize;
        let hi = self.list.blocks[b + 1] as usize;
        for i in lo..hi {
            // SAFETY: as the caller's.
            unsafe { self.row_with::<TALLY, QUAD, L>(i, laws) };
        }
    }

    /// Row `i`: each touching pair's force added to its j as it goes, the
    /// row's sum to i at its end; `TALLY`: the row's [`PairTally`] too.
    /// Pair by pair (`dynamics::halo_split` runs the rows it can alone).
    ///
    /// # Safety
    /// As [`add_pair_forces_then`](super::add_pair_forces_then)'s, and no
    /// other thread touches the forces of i and of its partners, nor the
    /// row's histories, meanwhile; with `TALLY`, `tally` points to one per
    /// body.
    #[inline(always)]
    pub(crate) unsafe fn row<const TALLY: bool>(&self, i: usize) {
        // SAFETY: as the caller's.
        unsafe { with_laws!(self, laws => self.row_with::<TALLY, false, _>(i, laws)) }
    }

    /// [`Self::row`]; with `QUAD`, the row's pairs tested four at a time
    /// ([`Self::block_avx2`]).
    ///
    /// # Safety
    /// As [`Self::row`]; with `QUAD`, as [`Self::block_avx2`].
    #[inline(always)]
    unsafe fn row_with<const TALLY: bool, const QUAD: bool, L: PairLaws>(
        &self,
        i: usize,
        laws: &L,
    ) {
        let Rows {
            position,
            velocity,
            radius,
            start,
            f_ptr,
            tally,
            ..
        } = *self;
        let (s, e) = (start[i] as usize, start[i + 1] as usize);
        if s == e {
            if TALLY {
                // SAFETY: i is in this block.
                unsafe { *tally.at(i) = [0.0; 3] };
            }
            return;
        }
        let xi = position[i];
        let vi = velocity[i];
        let ri = radius[i];
        let mut fi = [0.0; 3];
        // `pair_observables`'s sums of row i.
        let mut sums: PairTally = [0.0; 3];
        let mut k = s;
        #[cfg(target_arch = "x86_64")]
        if QUAD {
            use std::arch::x86_64::_mm256_set1_pd;
            let centre = [
                _mm256_set1_pd(xi[0]),
                _mm256_set1_pd(xi[1]),
                _mm256_set1_pd(xi[2]),
                _mm256_set1_pd(ri),
            ];
            while k + 4 <= e {
                // SAFETY: k..k + 4 within row i.
                let (mut near, r2) = unsafe { self.near4_distances(centre, k) };
                if near != 0 {
                    // The touching lanes' r = √r² and 1 / r, four at a
                    // time (`touching_lazy`'s scalar operations, correctly
                    // rounded either way: the same bits).
                    let (r, inv) = unsafe { distances_inverses(r2) };
                    while near != 0 {
                        let lane = near.trailing_zeros() as usize;
                        near &= near - 1;
                        // SAFETY: as the pair loop below; lane is one of
                        // near4's touching lanes.
                        unsafe {
                            self.pair_near::<TALLY, L>(
                                laws,
                                i,
                                k + lane,
                                (xi, vi, ri),
                                (r[lane], inv[lane]),
                                &mut fi,
                                &mut sums,
                            )
                        };
                    }
                }
                k += 4;
            }
        }
        while k < e {
            // SAFETY: k is an entry of row i, which only this block
            // visits.
            unsafe { self.pair::<TALLY, L>(laws, i, k, xi, vi, ri, &mut fi, &mut sums) };
            k += 1;
        }
        // SAFETY: i is in this block.
        unsafe {
            add(&mut *f_ptr.0.add(i), fi);
            if TALLY {
                *tally.at(i) = sums;
            }
        }
    }

    /// The lanes (bits 0–3) of entries k..k + 4 of row i whose pair
    /// touches as [`touching_lazy`] decides before its r² = 0 test: not
    /// |x_j − x_i|² ≥ (R_i + R_j)², each lane with `touching_lazy`'s
    /// operations in its order (no fused multiply–add: the same bits; a
    /// NaN distance counts as touching, as there). [`Self::pair`] decides
    /// again. `centre`: x_i, y_i, z_i and R_i in every lane. The partners'
    /// x and y come in 16-byte loads, z and R in 8-byte ones: with AVX2
    /// gathers instead (commit 922d37a) the test was slower than the pair
    /// loop on the processor measured (BENCHMARKS.md, "Why 922d37a's fewer
    /// instructions cost wall time"; `bench/pair_test_lanes.c`).
    ///
    /// # Safety
    /// k + 4 ≤ the list's length; every listed j < bodies; the processor
    /// has AVX2.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) unsafe fn near4(&self, centre: [std::arch::x86_64::__m256d; 4], k: usize) -> u32 {
        // SAFETY: as the caller's.
        unsafe { self.near4_distances(centre, k).0 }
    }

    /// [`Self::near4`]'s lanes and each lane's squared centre distance
    /// r² = |x_j − x_i|².
    ///
    /// # Safety
    /// As [`Self::near4`].
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) unsafe fn near4_distances(
        &self,
        centre: [std::arch::x86_64::__m256d; 4],
        k: usize,
    ) -> (u32, std::arch::x86_64::__m256d) {
        use std::arch::x86_64::*;
        let js = self.js.as_ptr().add(k);
        let p = self.position.as_ptr() as *const f64;
        let r = self.radius.as_ptr();
        let (j0, j1, j2, j3) = (
            *js as usize,
            *js.add(1) as usize,
            *js.add(2) as usize,
            *js.add(3) as usize,
        );
        // (Macros, not closures: a closure is compiled without AVX2
        // before it is inlined.)
        macro_rules! pair {
            ($lo:expr, $hi:expr) => {
                _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256($lo), $hi)
            };
        }
        macro_rules! two {
            ($u:expr, $v:expr) => {
                _mm_loadh_pd(_mm_load_sd($u), $v)
            };
        }
        // [x0 y0 x2 y2] and [x1 y1 x3 y3].
        let a = pair!(_mm_loadu_pd(p.add(3 * j0)), _mm_loadu_pd(p.add(3 * j2)));
        let b = pair!(_mm_loadu_pd(p.add(3 * j1)), _mm_loadu_pd(p.add(3 * j3)));
        let xj = _mm256_unpacklo_pd(a, b);
        let yj = _mm256_unpackhi_pd(a, b);
        let z = p.add(2);
        let zj = pair!(
            two!(z.add(3 * j0), z.add(3 * j1)),
            two!(z.add(3 * j2), z.add(3 * j3))
        );
        let rj = pair!(two!(r.add(j0), r.add(j1)), two!(r.add(j2), r.add(j3)));
        let d0 = _mm256_sub_pd(xj, centre[0]);
        let d1 = _mm256_sub_pd(yj, centre[1]);
        let d2 = _mm256_sub_pd(zj, centre[2]);
        let r2 = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(d0, d0), _mm256_mul_pd(d1, d1)),
            _mm256_mul_pd(d2, d2),
        );
        let s = _mm256_add_pd(centre[3], rj);
        let near = _mm256_cmp_pd::<_CMP_NGE_UQ>(r2, _mm256_mul_pd(s, s));
        (_mm256_movemask_pd(near) as u32, r2)
    }

    /// Entry k of row i: the pair's force if it touches (and its
    /// [`PairTally`] terms with `TALLY`), else its history reset.
    ///
    /// # Safety
    /// As [`Self::block`]; k is an entry of row i, which only this block
    /// visits.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    unsafe fn pair<const TALLY: bool, L: PairLaws>(
        &self,
        laws: &L,
        i: usize,
        k: usize,
        xi: [f64; 3],
        vi: [f64; 3],
        ri: f64,
        fi: &mut [f64; 3],
        sums: &mut PairTally,
    ) {
        let Rows {
            position,
            velocity,
            radius,
            js,
            keep,
            h_ptr,
            ..
        } = *self;
        // SAFETY (the unchecked reads): k < js.len() (rows lie within j),
        // and every j < n (the list's construction); lengths asserted in
        // `add_pair_forces_then`.
        let j = unsafe { *js.get_unchecked(k) } as usize;
        let (xj, rj) = unsafe { (*position.get_unchecked(j), *radius.get_unchecked(j)) };
        // The velocity is read only for touching pairs.
        let vj = || unsafe { *velocity.get_unchecked(j) };
        match touching_lazy(xi, vi, ri, xj, vj, rj) {
            // SAFETY: as the caller's.
            Some(g) => unsafe { self.touching_pair::<TALLY, L>(laws, i, k, j, &g, fi, sums) },
            None => {
                if keep {
                    // SAFETY: as above.
                    let hist = unsafe { &mut *h_ptr.0.add(k) };
                    if *hist != ContactHistory::default() {
                        *hist = ContactHistory::default();
                    }
                }
            }
        }
    }

    /// Entry k of row i, one of [`Self::near4`]'s touching lanes, whose
    /// centre distance r and its inverse are `(r, inv)`: as [`Self::pair`]
    /// (the same bits: `touching_lazy`'s second test, r² = 0, is r = 0).
    ///
    /// # Safety
    /// As [`Self::pair`]; no histories are kept (a pair apart does
    /// nothing).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    unsafe fn pair_near<const TALLY: bool, L: PairLaws>(
        &self,
        laws: &L,
        i: usize,
        k: usize,
        (xi, vi, ri): ([f64; 3], [f64; 3], f64),
        (r, inv): (f64, f64),
        fi: &mut [f64; 3],
        sums: &mut PairTally,
    ) {
        // Coincident centres: no direction to push along (`touching_lazy`).
        if r == 0.0 {
            return;
        }
        let Rows {
            position,
            velocity,
            radius,
            js,
            ..
        } = *self;
        // SAFETY: as in `Self::pair`.
        let j = unsafe { *js.get_unchecked(k) } as usize;
        let (xj, rj, vj) = unsafe {
            (
                *position.get_unchecked(j),
                *radius.get_unchecked(j),
                *velocity.get_unchecked(j),
            )
        };
        let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
        let g = geometry_at(d, r, inv, ri + rj, vi, vj);
        // SAFETY: as the caller's.
        unsafe { self.touching_pair::<TALLY, L>(laws, i, k, j, &g, fi, sums) };
    }

    /// The force of touching entry k (row i, partner j) with geometry `g`:
    /// subtracted from `fi`, added to j's force; with `TALLY`, its
    /// [`PairTally`] terms to `sums`.
    ///
    /// # Safety
    /// As [`Self::pair`].
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    unsafe fn touching_pair<const TALLY: bool, L: PairLaws>(
        &self,
        laws: &L,
        i: usize,
        k: usize,
        j: usize,
        g: &PairGeometry,
        fi: &mut [f64; 3],
        sums: &mut PairTally,
    ) {
        let Rows {
            bodies,
            keep,
            f_ptr,
            h_ptr,
            entries,
            ..
        } = *self;
        let mut scratch = NO_HISTORY;
        // SAFETY: history k belongs to row i, which only this block
        // visits.
        let hist = if keep {
            unsafe { &mut *h_ptr.0.add(k) }
        } else {
            &mut scratch
        };
        let law = laws.law(bodies, i, j);
        let fj = contact_force(&law, g, hist);
        if TALLY {
            // As `pair_observables`: the history as the force left it
            // (none kept: the default).
            if bodies.group[i] != NO_GROUP || bodies.group[j] != NO_GROUP {
                sums[1] += 1.0;
            } else {
                sums[0] += 1.0;
            }
            let hist = if keep { &*hist } else { &NO_HISTORY };
            let energy = law.elastic_energy(g.overlap, hist);
            sums[2] += energy;
            // SAFETY: entry k belongs to row i, which only this block
            // visits.
            unsafe { entries.energy(k, energy) };
        }
        sub(fi, fj);
        // SAFETY: j lies in this block or the next (the blocks'
        // construction); blocks of one parity are two apart, so no
        // other running block writes j.
        unsafe { add(&mut *f_ptr.0.add(j), fj) };
    }
}

/// √r² and 1 / √r² of each lane of `r2`, as arrays.
///
/// # Safety
/// The processor has AVX.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn distances_inverses(r2: std::arch::x86_64::__m256d) -> ([f64; 4], [f64; 4]) {
    use std::arch::x86_64::*;
    let r = _mm256_sqrt_pd(r2);
    let inv = _mm256_div_pd(_mm256_set1_pd(1.0), r);
    let (mut rs, mut invs) = ([0.0; 4], [0.0; 4]);
    _mm256_storeu_pd(rs.as_mut_ptr(), r);
    _mm256_storeu_pd(invs.as_mut_ptr(), inv);
    (rs, invs)
}
