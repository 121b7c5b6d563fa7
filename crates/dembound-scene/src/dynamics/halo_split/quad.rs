//! The split's rows near the cut with their pairs tested four at a time,
//! as the engine's rows are ([`Rows::near4`], `Rows::block_avx2`): only
//! the pairs found near go through the pair code, in list order, so each
//! body gets the same additions in the same order as pair by pair (the
//! test is `touching_lazy`'s first comparison, lane by lane, and the pair
//! code decides again). Without stored histories only: a pair apart then
//! changes nothing (a stored pair not set this step counts as apart).

use std::arch::x86_64::_mm256_set1_pd;

use super::{HaloSplit, NOT_STORED};
use crate::dynamics::contacts::{add, contact_force, sub, touching_lazy, Rows, NO_HISTORY};

impl HaloSplit {
    /// Row i's pairs of two fresh bodies ([`HaloSplit::early`]'s part of a
    /// row that is not plain): a pair's force is stored when it has a late
    /// body, added to an early j as it comes, and an early i gets its
    /// row's sum at the end. A stale row is left whole to
    /// [`Self::late_rows_avx2`].
    ///
    /// # Safety
    /// As [`HaloSplit::early`]'s; the processor has AVX2 and no histories
    /// are kept.
    #[target_feature(enable = "avx,avx2")]
    pub(super) unsafe fn early_row_avx2(&mut self, rows: &Rows, i: usize) {
        let (bodies, _, list, _) = rows.parts();
        let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
        if s == e || self.stale[i] {
            return;
        }
        let (xi, ri) = (bodies.position[i], bodies.radius[i]);
        let centre = [
            _mm256_set1_pd(xi[0]),
            _mm256_set1_pd(xi[1]),
            _mm256_set1_pd(xi[2]),
            _mm256_set1_pd(ri),
        ];
        let mut fi = [0.0; 3];
        let mut k = s;
        while k + 4 <= e {
            // SAFETY: k..k + 4 within row i; AVX2 as the caller's.
            let mut near = unsafe { rows.near4(centre, k) };
            while near != 0 {
                let lane = near.trailing_zeros() as usize;
                near &= near - 1;
                // SAFETY: entry k + lane of row i.
                unsafe { self.early_pair(rows, i, k + lane, &mut fi) };
            }
            k += 4;
        }
        while k < e {
            // SAFETY: entry k of row i.
            unsafe { self.early_pair(rows, i, k, &mut fi) };
            k += 1;
        }
        if !self.late[i] {
            // SAFETY: one thread; i a body.
            unsafe { add(rows.forces().at(i), fi) };
        }
    }

    /// Entry k of row i, when its partner is fresh and the pair touches:
    /// stored if either body is late, subtracted from `fi` for an early
    /// i, added to an early j.
    ///
    /// # Safety
    /// As [`Self::early_row_avx2`]; k an entry of row i.
    #[inline(always)]
    unsafe fn early_pair(&mut self, rows: &Rows, i: usize, k: usize, fi: &mut [f64; 3]) {
        // SAFETY: as this function's.
        let Some((j, fj)) = (unsafe { self.pair_force(rows, i, k, |stale_j| !stale_j) }) else {
            return;
        };
        let slot = self.slot_of[k];
        if slot != NOT_STORED {
            self.set(slot as usize, fj);
        }
        if !self.late[i] {
            sub(fi, fj);
        }
        if !self.late[j] {
            // SAFETY: one thread; j a body.
            unsafe { add(rows.forces().at(j), fj) };
        }
    }

    /// The pairs with a stale body ([`HaloSplit::late`]'s first part),
    /// row by row, stored.
    ///
    /// # Safety
    /// As [`HaloSplit::late`]'s; the processor has AVX2 and no histories
    /// are kept.
    #[target_feature(enable = "avx,avx2")]
    pub(super) unsafe fn late_rows_avx2(&mut self, rows: &Rows) {
        let (bodies, _, list, _) = rows.parts();
        for r in 0..self.deferred_rows.len() {
            let i = self.deferred_rows[r] as usize;
            let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
            let stale_i = self.stale[i];
            let (xi, ri) = (bodies.position[i], bodies.radius[i]);
            let centre = [
                _mm256_set1_pd(xi[0]),
                _mm256_set1_pd(xi[1]),
                _mm256_set1_pd(xi[2]),
                _mm256_set1_pd(ri),
            ];
            let mut k = s;
            while k + 4 <= e {
                // SAFETY: k..k + 4 within row i; AVX2 as the caller's.
                let mut near = unsafe { rows.near4(centre, k) };
                while near != 0 {
                    let lane = near.trailing_zeros() as usize;
                    near &= near - 1;
                    // SAFETY: entry k + lane of row i.
                    unsafe { self.late_pair(rows, i, k + lane, stale_i) };
                }
                k += 4;
            }
            while k < e {
                // SAFETY: entry k of row i.
                unsafe { self.late_pair(rows, i, k, stale_i) };
                k += 1;
            }
        }
    }

    /// Entry k of row i, when the pair has a stale body and touches:
    /// stored.
    ///
    /// # Safety
    /// As [`Self::late_rows_avx2`]; k an entry of row i.
    #[inline(always)]
    unsafe fn late_pair(&mut self, rows: &Rows, i: usize, k: usize, stale_i: bool) {
        // SAFETY: as this function's.
        let Some((_, fj)) = (unsafe { self.pair_force(rows, i, k, |stale_j| stale_i || stale_j) })
        else {
            return;
        };
        // A pair with a stale body is stored (its late body).
        self.set(self.slot_of[k] as usize, fj);
    }

    /// Entry k of row i: its partner j and the force on j (N) when
    /// `wanted(j is stale)` and the pair touches — the one pair code of
    /// both parts ([`Self::early_pair`]: fresh partners; [`Self::late_pair`]:
    /// pairs with a stale body).
    ///
    /// # Safety
    /// k an entry of row i of `rows`' list.
    #[inline(always)]
    unsafe fn pair_force(
        &self,
        rows: &Rows,
        i: usize,
        k: usize,
        wanted: impl Fn(bool) -> bool,
    ) -> Option<(usize, [f64; 3])> {
        let (bodies, laws, list, _) = rows.parts();
        // SAFETY: k < the list's length; every listed j is a body.
        let j = unsafe { *list.j.get_unchecked(k) } as usize;
        if !wanted(self.stale[j]) {
            return None;
        }
        let (position, velocity, radius) = (&bodies.position, &bodies.velocity, &bodies.radius);
        let g = touching_lazy(
            position[i],
            velocity[i],
            radius[i],
            // SAFETY: j is a body.
            unsafe { *position.get_unchecked(j) },
            || unsafe { *velocity.get_unchecked(j) },
            unsafe { *radius.get_unchecked(j) },
        )?;
        let mut scratch = NO_HISTORY;
        Some((j, contact_force(&laws.pair(bodies, i, j), &g, &mut scratch)))
    }
}
