//! The frictionless force loop of a decomposed run split around the halo
//! exchange (`comm::distributed`): the pairs that need no fresh halo state
//! while the exchange is in flight, the rest once it has arrived, every
//! body's force summed with the same additions in the same order as the
//! engine's sequential loop, so the same bits.
//!
//! The order to keep. A decomposed run's loop
//! ([`PairList::sequential`], `contacts::run_blocks_then`) takes the rows
//! i = 0, 1, … in order; row i adds each touching pair's force f to its
//! partner j as it goes and its own sum (−Σ f from zero, in entry order)
//! to i at the row's end. Rows list only partners j > i, so body y's force
//! is its per-body force (gravity, walls) plus, in order, the pairs of the
//! rows before y that list y, then y's own row's sum.
//!
//! The split. *Stale* bodies are the halo copies whose owners send their
//! state every step (free bodies of another rank); *late* bodies are the
//! stale ones and every body listed with one; the others are *early*.
//! - While the exchange is in flight ([`HaloSplit::early`]): every row in
//!   order; a pair of two fresh bodies is computed (its history updated)
//!   and its force added to an early body as the loop adds it, and stored
//!   for a late one; a pair with a stale body is left. An early body has
//!   no stale partner, so all its additions are made, in the loop's
//!   order, and its block's follow-up (the fused Verlet half,
//!   `contacts::FollowUp`) runs on it as in the engine; a late body's
//!   force and position are not touched.
//! - Once the exchange has arrived ([`HaloSplit::late`]): the pairs with a
//!   stale body are computed and stored; each late body's force is summed
//!   from its stored pairs in the loop's order (the rows before it that
//!   list it, then its own row from zero), then its follow-up runs.
//!
//! Every pair is computed once (one history update), from the same
//! positions and velocities as the engine's loop reads (a body's follow-up
//! moves it only after every row reading it), and every body gets the same
//! additions in the same order: the split changes no bit. Rows without a
//! late body run the engine's own row code ([`Rows::rows_avx2`], else
//! [`Rows::row`]); the others test their pairs four at a time as well
//! (`quad`), without stored histories on AVX2. The order of the first
//! part's rows, runs and follow-ups is planned at the list build
//! ([`Early`]).

use dembound_physics::contact::ContactHistory;

use super::contacts::{add, contact_force, sub, touching_lazy, FollowUp, Rows, NO_HISTORY};
use crate::geometry::neighbour::PairList;

#[cfg(target_arch = "x86_64")]
mod quad;

/// [`HaloSplit::slot_of`] of a pair of two early bodies (not stored).
const NOT_STORED: u32 = u32::MAX;

/// A stored pair: its force on j (N), valid when `stamp` is this step's
/// (the pair touches). Side by side, 32 bytes a pair: two a cache
/// line, none straddling one.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(32))]
struct Stored {
    force: [f64; 3],
    stamp: u32,
}

/// One item of the first part's plan, in the loop's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Early {
    /// Plain rows lo..hi (neither body nor partner late): the engine's
    /// row code.
    Rows(u32, u32),
    /// A row that is not plain, of a fresh body, with pairs.
    Row(u32),
    /// The follow-up of the early bodies lo..hi (their forces complete).
    Follow(u32, u32),
    /// A block's end: the exchange may progress.
    Progress,
}

/// Which pairs of a list wait for the halo, and the pair forces stored
/// for the late bodies. Built at each list build (the list and the stale
/// bodies fix it).
#[derive(Debug, Clone, Default)]
pub struct HaloSplit {
    /// Body → its state arrives with the exchange.
    stale: Vec<bool>,
    /// Body → stale or listed with a stale body.
    late: Vec<bool>,
    /// The first part, in order.
    plan: Vec<Early>,
    /// Rows whose body and partners are all early.
    plain_rows: usize,
    /// Row i's first stored pair (the pairs with a late body, numbered in
    /// list order); n + 1 entries.
    slot_start: Vec<u32>,
    /// The pairs with a stale body: (entry, row, stored pair).
    deferred: Vec<(u32, u32, u32)>,
    /// The rows holding a pair with a stale body, ascending.
    deferred_rows: Vec<u32>,
    /// Entry → its stored pair ([`NOT_STORED`] for a pair of two early
    /// bodies).
    slot_of: Vec<u32>,
    /// The late bodies, ascending.
    late_bodies: Vec<u32>,
    /// The runs of consecutive late bodies (their follow-ups).
    late_runs: Vec<(u32, u32)>,
    /// Each late body's stored pairs as the partner j, in row order:
    /// `incoming[incoming_start[p]..incoming_start[p + 1]]` for
    /// `late_bodies[p]`.
    incoming_start: Vec<u32>,
    incoming: Vec<u32>,
    /// Each stored pair's force on j and its step stamp ([`Stored`]).
    pairs: Vec<Stored>,
    stamp: u32,
    /// The list's bodies and entries.
    shape: (usize, usize),
}

impl HaloSplit {
    /// The split of `list` (rows in body order) when the bodies flagged
    /// in `stale` (one flag per body) get their state from the exchange.
    pub fn new(list: &PairList, stale: &[bool]) -> Self {
        let n = stale.len();
        let m = list.j.len();
        let mut late = stale.to_vec();
        for (i, k) in list.entries() {
            let j = list.j[k] as usize;
            if stale[i] {
                late[j] = true;
            }
            if stale[j] {
                late[i] = true;
            }
        }
        let mut plain = vec![true; n];
        let mut slot_start = Vec::with_capacity(n + 1);
        let mut deferred = Vec::new();
        let mut deferred_rows = Vec::new();
        let mut slot_of = vec![NOT_STORED; m];
        let mut slots = 0u32;
        // (late partner j, stored pair), in list order.
        let mut to_late: Vec<(u32, u32)> = Vec::new();
        for i in 0..n {
            slot_start.push(slots);
            let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
            for (k, slot_k) in slot_of.iter_mut().enumerate().take(e).skip(s) {
                let j = list.j[k] as usize;
                if !(late[i] || late[j]) {
                    continue;
                }
                plain[i] = false;
                if stale[i] || stale[j] {
                    if deferred_rows.last() != Some(&(i as u32)) {
                        deferred_rows.push(i as u32);
                    }
                    deferred.push((k as u32, i as u32, slots));
                }
                *slot_k = slots;
                if late[j] {
                    to_late.push((j as u32, slots));
                }
                slots += 1;
            }
            if late[i] {
                plain[i] = false;
            }
        }
        slot_start.push(slots);
        let late_bodies: Vec<u32> = (0..n as u32).filter(|&k| late[k as usize]).collect();
        // Counting sort by the partner's place among the late bodies (a
        // stable sort: each body's pairs stay in list order).
        let mut place = vec![0u32; n];
        for (p, &k) in late_bodies.iter().enumerate() {
            place[k as usize] = p as u32;
        }
        let mut incoming_start = vec![0u32; late_bodies.len() + 1];
        for &(j, _) in &to_late {
            incoming_start[place[j as usize] as usize + 1] += 1;
        }
        for p in 0..late_bodies.len() {
            incoming_start[p + 1] += incoming_start[p];
        }
        let mut fill = incoming_start.clone();
        let mut incoming = vec![0u32; to_late.len()];
        for &(j, slot) in &to_late {
            let p = place[j as usize] as usize;
            incoming[fill[p] as usize] = slot;
            fill[p] += 1;
        }
        HaloSplit {
            plan: plan(list, stale, &late, &plain),
            plain_rows: plain.iter().filter(|&&p| p).count(),
            late_runs: runs(&late_bodies),
            stale: stale.to_vec(),
            late,
            slot_start,
            deferred,
            deferred_rows,
            slot_of,
            late_bodies,
            incoming_start,
            incoming,
            pairs: vec![Stored::default(); slots as usize],
            stamp: 0,
            shape: (n, m),
        }
    }

    /// Built for this list (its bodies and entries).
    pub fn fits(&self, list: &PairList) -> bool {
        self.shape == (list.start.len().saturating_sub(1), list.j.len())
    }

    /// Rows computed whole before the exchange arrives (neither body nor
    /// partner late).
    pub fn plain_rows(&self) -> usize {
        self.plain_rows
    }

    /// Pairs computed after the exchange arrives (with a stale body).
    pub fn deferred_pairs(&self) -> usize {
        self.deferred.len()
    }

    /// Stored pair `slot` touches this step: its force is set.
    #[inline(always)]
    fn set(&mut self, slot: usize, fj: [f64; 3]) {
        debug_assert!(slot < self.pairs.len());
        let stamp = self.stamp;
        // SAFETY: as in `stored`: every slot the split holds is below the
        // stored pairs' count.
        *unsafe { self.pairs.get_unchecked_mut(slot) } = Stored { force: fj, stamp };
    }

    /// The force on j of stored pair `slot` if it touches this step.
    #[inline(always)]
    fn stored(&self, slot: usize) -> Option<[f64; 3]> {
        debug_assert!(slot < self.pairs.len());
        // SAFETY: every slot the split holds (`slot_of`, `deferred`,
        // `incoming`, `slot_start`'s ranges) was numbered below the
        // stored pairs' count when it was built (`HaloSplit::new`).
        let s = unsafe { self.pairs.get_unchecked(slot) };
        (s.stamp == self.stamp).then_some(s.force)
    }

    /// The first part (see the module): every row in order, the pairs of
    /// fresh bodies, early bodies' sums and follow-ups; `progress` between
    /// blocks (lets the exchange advance). Returns the follow-ups'
    /// maximum.
    ///
    /// # Safety
    /// As `contacts::add_pair_forces_then`'s, the list sequential (one
    /// thread) and this split built for it ([`Self::fits`]).
    pub(crate) unsafe fn early(
        &mut self,
        rows: &Rows,
        follow: FollowUp,
        progress: &mut dyn FnMut(),
    ) -> f64 {
        // A new step: every stored pair apart until set.
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.pairs.fill(Stored::default());
            self.stamp = 1;
        }
        // The rows' pairs four at a time as the engine's blocks test them
        // (`Rows::block_avx2`: no histories, AVX2), else pair by pair.
        #[cfg(target_arch = "x86_64")]
        let quad = rows.parts().3.is_none() && std::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let quad = false;
        let mut moved = 0.0f64;
        for p in 0..self.plan.len() {
            match self.plan[p] {
                Early::Rows(lo, hi) => {
                    #[cfg(target_arch = "x86_64")]
                    if quad {
                        // SAFETY: one thread; as the caller's; AVX2 and no
                        // histories just checked.
                        unsafe { rows.rows_avx2(lo as usize, hi as usize) };
                        continue;
                    }
                    for r in lo as usize..hi as usize {
                        // SAFETY: one thread; as the caller's.
                        unsafe { rows.row::<false>(r) };
                    }
                }
                Early::Row(i) => {
                    #[cfg(target_arch = "x86_64")]
                    if quad {
                        // SAFETY: as the caller's; AVX2 and no histories
                        // just checked.
                        unsafe { self.early_row_avx2(rows, i as usize) };
                        continue;
                    }
                    // SAFETY: as the caller's.
                    unsafe { self.early_row(rows, i as usize) };
                }
                Early::Follow(lo, hi) => {
                    moved = moved.max(follow(lo as usize, hi as usize));
                }
                Early::Progress => progress(),
            }
        }
        moved
    }

    /// Row i's pairs of two fresh bodies pair by pair (the first part of
    /// a row that is not plain, with histories or without AVX2): stored
    /// when either body is late, added to an early j as they come, an
    /// early i's sum at the row's end.
    ///
    /// # Safety
    /// As [`Self::early`]'s; row i is not stale.
    unsafe fn early_row(&mut self, rows: &Rows, i: usize) {
        let (bodies, laws, list, hist) = rows.parts();
        let (position, velocity, radius) = (&bodies.position, &bodies.velocity, &bodies.radius);
        let f_ptr = rows.forces();
        let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
        let late_i = self.late[i];
        let (xi, vi, ri) = (position[i], velocity[i], radius[i]);
        let mut fi = [0.0; 3];
        for k in s..e {
            let j = list.j[k] as usize;
            if self.stale[j] {
                continue;
            }
            let mut scratch = NO_HISTORY;
            let h = match hist {
                // SAFETY: entry k's history, this row's only.
                Some(h) => unsafe { &mut *h.0.add(k) },
                None => &mut scratch,
            };
            let Some(g) = touching_lazy(xi, vi, ri, position[j], || velocity[j], radius[j]) else {
                if hist.is_some() && *h != ContactHistory::default() {
                    *h = ContactHistory::default();
                }
                continue;
            };
            let fj = contact_force(&laws.pair(bodies, i, j), &g, h);
            let slot = self.slot_of[k];
            if slot != NOT_STORED {
                self.set(slot as usize, fj);
            }
            if !late_i {
                sub(&mut fi, fj);
            }
            if !self.late[j] {
                // SAFETY: one thread; j a body.
                unsafe { add(f_ptr.at(j), fj) };
            }
        }
        if !late_i {
            // SAFETY: as above.
            unsafe { add(f_ptr.at(i), fi) };
        }
    }

    /// The second part's pairs (see the module), once the stale bodies'
    /// state has arrived: the pairs with a stale body, stored.
    ///
    /// # Safety
    /// As [`Self::early`], which ran just before on the same state.
    pub(crate) unsafe fn late_pairs(&mut self, rows: &Rows) {
        let (bodies, laws, list, hist) = rows.parts();
        let js = &list.j[..];
        let (position, velocity, radius) = (&bodies.position, &bodies.velocity, &bodies.radius);
        // Four at a time as in the first part, else pair by pair.
        #[cfg(target_arch = "x86_64")]
        let quad = hist.is_none() && std::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let quad = false;
        if quad {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as the caller's; AVX2 and no histories just checked.
            unsafe {
                self.late_rows_avx2(rows)
            };
        } else {
            for d in 0..self.deferred.len() {
                let (k, i, slot) = self.deferred[d];
                let (k, i, slot) = (k as usize, i as usize, slot as usize);
                let j = js[k] as usize;
                let mut scratch = NO_HISTORY;
                let h = match hist {
                    // SAFETY: entry k's history; one thread.
                    Some(h) => unsafe { &mut *h.0.add(k) },
                    None => &mut scratch,
                };
                match touching_lazy(
                    position[i],
                    velocity[i],
                    radius[i],
                    position[j],
                    || velocity[j],
                    radius[j],
                ) {
                    Some(g) => {
                        let fj = contact_force(&laws.pair(bodies, i, j), &g, h);
                        self.set(slot, fj);
                    }
                    None => {
                        if hist.is_some() && *h != ContactHistory::default() {
                            *h = ContactHistory::default();
                        }
                    }
                }
            }
        }
    }

    /// The second part's sums (see the module), every stored pair set
    /// ([`Self::late_pairs`]): each late
    /// body's sum in the loop's order, its follow-up. Returns the
    /// follow-ups' maximum.
    ///
    /// # Safety
    /// As [`Self::early`], which ran on the same state.
    pub(crate) unsafe fn late_sums(&mut self, rows: &Rows, follow: FollowUp) -> f64 {
        let start = &rows.parts().2.start[..];
        let f_ptr = rows.forces();
        // Each late body's sum, in registers: the same additions in the
        // same order as adding to its force in place.
        for (p, &y) in self.late_bodies.iter().enumerate() {
            let y = y as usize;
            if self.stale[y] {
                // A halo copy: its follow-up sets its force to zero (it
                // is not integrated here), so no sum.
                continue;
            }
            // SAFETY: one thread; y a body.
            let f = unsafe { f_ptr.at(y) };
            let mut sum = *f;
            let (a, z) = (
                self.incoming_start[p] as usize,
                self.incoming_start[p + 1] as usize,
            );
            for &slot in &self.incoming[a..z] {
                if let Some(fj) = self.stored(slot as usize) {
                    add(&mut sum, fj);
                }
            }
            let (s, e) = (start[y] as usize, start[y + 1] as usize);
            if s != e {
                let first = self.slot_start[y] as usize;
                let mut fy = [0.0; 3];
                for pair in &self.pairs[first..first + (e - s)] {
                    if pair.stamp == self.stamp {
                        sub(&mut fy, pair.force);
                    }
                }
                add(&mut sum, fy);
            }
            *f = sum;
        }
        let mut moved = 0.0f64;
        for &(a, z) in &self.late_runs {
            moved = moved.max(follow(a as usize, z as usize));
        }
        moved
    }
}

/// The first part's order (see [`Early`]): block by block, its plain rows
/// in runs and its other rows of fresh bodies one by one, in row order,
/// then the follow-ups of its early bodies in runs, then a progress call.
fn plan(list: &PairList, stale: &[bool], late: &[bool], plain: &[bool]) -> Vec<Early> {
    let mut plan = Vec::new();
    for b in 0..list.blocks.len().saturating_sub(1) {
        let (lo, hi) = (list.blocks[b] as usize, list.blocks[b + 1] as usize);
        let mut i = lo;
        while i < hi {
            if plain[i] {
                let mut z = i + 1;
                while z < hi && plain[z] {
                    z += 1;
                }
                plan.push(Early::Rows(i as u32, z as u32));
                i = z;
                continue;
            }
            if !stale[i] && list.start[i] != list.start[i + 1] {
                plan.push(Early::Row(i as u32));
            }
            i += 1;
        }
        let mut a = lo;
        while a < hi {
            if late[a] {
                a += 1;
                continue;
            }
            let mut z = a;
            while z < hi && !late[z] {
                z += 1;
            }
            plan.push(Early::Follow(a as u32, z as u32));
            a = z;
        }
        plan.push(Early::Progress);
    }
    plan
}

/// The runs of consecutive values of an ascending list, as (first,
/// last + 1).
fn runs(sorted: &[u32]) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = Vec::new();
    for &k in sorted {
        match out.last_mut() {
            Some((_, z)) if *z == k => *z = k + 1,
            _ => out.push((k, k + 1)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A list of 6 bodies in rows: 0–{1, 2}, 1–{3}, 2–{4, 5}, 3–{5},
    /// body 4 stale: late are 4 and its partner 2; rows 2 and 4 are late,
    /// row 0 lists 2, rows 1, 3 and 5 are plain.
    #[test]
    fn late_bodies_are_the_stale_and_their_partners() {
        let list = PairList {
            start: vec![0, 2, 3, 5, 6, 6, 6],
            j: vec![1, 2, 3, 4, 5, 5],
            blocks: vec![0, 6],
            ..Default::default()
        };
        let stale = [false, false, false, false, true, false];
        let s = HaloSplit::new(&list, &stale);
        assert_eq!(s.late, [false, false, true, false, true, false]);
        // Rows 0 and 2 pair by pair, the plain ones in runs, row 4 (stale)
        // left to the late part; the early bodies' follow-ups in runs.
        use Early::*;
        assert_eq!(
            s.plan,
            [
                Row(0),
                Rows(1, 2),
                Row(2),
                Rows(3, 4),
                Rows(5, 6),
                Follow(0, 2),
                Follow(3, 4),
                Follow(5, 6),
                Progress
            ]
        );
        // Stored pairs: 0–2, 2–4, 2–5 (slots 0, 1, 2).
        assert_eq!(s.slot_start, [0, 1, 1, 3, 3, 3, 3]);
        assert_eq!(s.slot_of, [NOT_STORED, 0, NOT_STORED, 1, 2, NOT_STORED]);
        assert_eq!(s.deferred, [(3, 2, 1)]);
        assert_eq!(s.deferred_rows, [2]);
        assert_eq!(s.late_bodies, [2, 4]);
        assert_eq!(s.late_runs, [(2, 3), (4, 5)]);
        // Body 2 gets slot 0 (row 0) as j; body 4 slot 1 (row 2).
        assert_eq!(s.incoming_start, [0, 1, 2]);
        assert_eq!(s.incoming, [0, 1]);
        assert_eq!(s.plain_rows(), 3);
        assert_eq!(s.deferred_pairs(), 1);
        assert!(s.fits(&list));
    }
}
