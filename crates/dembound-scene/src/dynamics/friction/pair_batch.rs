//! The batched pass of the pair loop ([`MainPairs::batch`]): the
//! composer's stages over a batch of contacts, one stage at a time, with
//! the row-by-row loop's bits.

use dembound_physics::contact::model::{assemble, overlap_rate, slip_velocity};
use dembound_physics::contact::tangential::{FrictionPair, MovedSpring};
use dembound_physics::contact::Side;

use super::pairs::{tally_entry, MainPairs, PairTally};
use super::row_laws::RowLaws;
use super::{add, sub, FrictionLaw};
use crate::bodies::NO_GROUP;
use crate::dynamics::contacts::NO_HISTORY;

impl MainPairs<'_> {
    /// Rows `lo..hi`, at most [`BATCH`] of them with at most [`BATCH`]
    /// entries in all (see [`Self::block`]), each contact's law from
    /// `rows`. `AVX2`: inlined into [`Self::block_avx2`] (the processor
    /// has AVX2), the springs turned four at a time.
    #[inline(always)]
    pub(super) fn batch<
        const KEEP: bool,
        const ROLL: bool,
        const TABLE: bool,
        const TALLY: bool,
        const AVX2: bool,
        R: RowLaws,
    >(
        &self,
        lo: usize,
        hi: usize,
        scratch: &mut Batch,
        rows: &R,
    ) {
        let (position, velocity, radius, spin, inverse_inertia) = (
            self.position,
            self.velocity,
            self.radius,
            self.spin,
            self.inverse_inertia,
        );
        let (start, js) = (self.start, self.js);
        // Pass 1: every entry's geometry ([`touching_lazy`]'s operations
        // without its branches): the partners gathered, then the roots and
        // divisions of all entries in one loop over arrays (vectorised:
        // IEEE square root and division per lane, the same bits), then the
        // touching entries listed in `found` and the others' springs
        // relaxed by masking their bits.
        // Once per batch, so that the rows' reads below need no check of
        // their own: rows lo..hi are bodies with a row end each, and index
        // `ends` ([`Self::block`] builds batches of at most BATCH rows).
        assert!(hi < start.len() && hi <= position.len() && hi <= radius.len() && hi - lo <= BATCH);
        let first = start[lo] as usize;
        let count = start[hi] as usize - first;
        let g = &mut *scratch;
        for i in lo..hi {
            let (s, e) = (start[i] as usize, start[i + 1] as usize);
            let (xi, ri) = (position[i], radius[i]);
            for k in s..e {
                // SAFETY: as in [`Self::row`] for k and j; k − first <
                // count ≤ BATCH (the batch's construction).
                unsafe {
                    let q = k - first;
                    let j = *js.get_unchecked(k);
                    let xj = *position.get_unchecked(j as usize);
                    *g.partner.get_unchecked_mut(q) = j;
                    *g.dx.get_unchecked_mut(q) = xj[0] - xi[0];
                    *g.dy.get_unchecked_mut(q) = xj[1] - xi[1];
                    *g.dz.get_unchecked_mut(q) = xj[2] - xi[2];
                    *g.sum.get_unchecked_mut(q) = ri + *radius.get_unchecked(j as usize);
                }
            }
        }
        let count = count.min(BATCH);
        for q in 0..count {
            let (x, y, z, sum) = (g.dx[q], g.dy[q], g.dz[q], g.sum[q]);
            let r2 = x * x + y * y + z * z;
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            let touches = !(r2 >= sum * sum) && r2 != 0.0;
            g.touches[q] = touches as u64;
            let r = r2.sqrt();
            let inv = 1.0 / r;
            g.overlap[q] = sum - r;
            g.nx[q] = x * inv;
            g.ny[q] = y * inv;
            g.nz[q] = z * inv;
        }
        // The springs four entries at a time: each touching entry's
        // turned into its tangent plane (pass 1b below), each other
        // entry's set to +0 (the mask below), the same bits.
        #[cfg(target_arch = "x86_64")]
        if AVX2 {
            // SAFETY: AVX2 (`AVX2` is set by `block_avx2` alone); entries
            // first..first + count are this batch's, their springs
            // consecutive and borrowed by nothing else here; the arrays
            // hold BATCH ≥ count values.
            unsafe {
                super::turn_four::turn_or_clear(
                    self.shear.0.add(first),
                    &g.nx,
                    &g.ny,
                    &g.nz,
                    &g.touches,
                    count,
                )
            };
        }
        let vector = AVX2 && cfg!(target_arch = "x86_64");
        let mut m = 0usize;
        for i in lo..hi {
            let (s, e) = (start[i] as usize, start[i + 1] as usize);
            for k in s..e {
                let q = k - first;
                // SAFETY: q < count ≤ BATCH; m ≤ q.
                let touches = unsafe { *g.touches.get_unchecked(q) };
                unsafe { *g.found.get_unchecked_mut(m) = q as u8 };
                m += touches as usize;
                // All ones when touching: the springs kept bit for bit;
                // else exactly +0.
                let keep = touches.wrapping_neg();
                let mask = |v: &mut [f64; 3]| {
                    *v = v.map(|x| f64::from_bits(x.to_bits() & keep));
                };
                // SAFETY: entry k belongs to row i of this block (as in
                // [`Self::row`]).
                unsafe {
                    if !vector {
                        mask(&mut *self.shear.0.add(k));
                    }
                    if KEEP {
                        let hist = &mut *self.history.0.add(k);
                        hist.max_overlap = f64::from_bits(hist.max_overlap.to_bits() & keep);
                        hist.unloading &= touches != 0;
                    }
                    if ROLL {
                        mask(&mut *self.roll.0.add(k));
                    }
                }
            }
            g.ends[i - lo] = m as u8;
        }
        let found = m.min(BATCH);
        // Pass 1b: the springs of the contacts found turned into their
        // tangent planes (`FrictionPair::turn_spring`, the first part of the
        // tangential force): it needs only the stored spring and the
        // normal, both known now, so its chain of dependent operations (the
        // dot products and the division by |δ|²) runs here, contacts
        // overlapping one another, instead of heading each contact's stages
        // below, which take the rest (`tangential_force_turned`).
        // (The four-lane pass above, when it ran, turned them already.)
        // Batches run under the default rotation only (`Self::block`).
        debug_assert_eq!(
            self.friction.setup.spring_rotation,
            dembound_physics::contact::tangential::SpringRotation::Rescale
        );
        if !vector {
            for t in 0..found {
                let q = g.entry(t);
                let n = [g.nx[q], g.ny[q], g.nz[q]];
                // SAFETY: entry first + q belongs to a row of this batch (pass 1).
                let sh = unsafe { &mut *self.shear.0.add(first + q) };
                FrictionPair::turn_spring(sh, n);
            }
        }
        // Pass 2 over the contacts found. The
        // same operations on the same values as [`contact`]: the same bits.
        // Batches run only with the class table ([`Self::block`]); i and
        // j are bodies (pass 1).
        debug_assert!(TABLE);
        let row_law = |i: usize, j: usize| -> &FrictionLaw { rows.law(i, j) };
        // The sides of a contact (a body's velocity, spin, lever arm and
        // inverse inertia; a stage reads the fields it needs).
        let side = |i: usize| -> Side {
            // SAFETY: i is a body (pass 1).
            unsafe {
                Side {
                    velocity: *velocity.get_unchecked(i),
                    spin: *spin.get_unchecked(i),
                    arm: *radius.get_unchecked(i),
                    inverse_inertia: *inverse_inertia.get_unchecked(i),
                }
            }
        };
        // Row by row (body i's side read once per row, not per contact),
        // in [`Self::row`]'s order, in three passes over the contacts
        // found: 2a each contact's overlap rate and tangential slip
        // velocity, normal force (history updated) and, for a
        // displacement spring, the spring moved (`FrictionPair::
        // move_spring`); 2b the Coulomb tests and cut factors of all of
        // them (`MovedSpring::cut`: a root and a division each, of
        // independent contacts, which overlap here instead of ending each
        // contact's chain of dependent operations); 2c the tangential
        // forces (spring cut; a force-storing spring's whole step here),
        // rolling torques, and the forces and torques summed. Each
        // contact's operations are those of [`contact`], in its order:
        // the same bits. The Hertz force and the Mindlin stiffness share
        // the root of the overlap (taken once).
        let mut from = 0usize;
        for i in lo..hi {
            let (s, e) = (start[i] as usize, start[i + 1] as usize);
            if s == e {
                continue;
            }
            let to = (g.ends[i - lo] as usize).min(found);
            let a = side(i);
            for t in from..to {
                let q = g.entry(t);
                let (j, k) = (g.partner[q] as usize, first + q);
                let b = side(j);
                let fl = row_law(i, j);
                let overlap = g.overlap[q];
                let n = [g.nx[q], g.ny[q], g.nz[q]];
                let rate = overlap_rate(a.velocity, b.velocity, n);
                let (slip_a, slip_b) = fl.torque_arm.slip_sides(overlap, &a, &b);
                let slip = slip_velocity(&slip_a, &slip_b, n);
                let mut scratch = NO_HISTORY;
                // SAFETY: entry k belongs to row i of this block.
                let hist = if KEEP {
                    unsafe { &mut *self.history.0.add(k) }
                } else {
                    &mut scratch
                };
                let force = fl.law.normal_stage(overlap, rate, hist);
                // SAFETY: t < found ≤ BATCH.
                unsafe {
                    *g.force.get_unchecked_mut(t) = force;
                    *g.slip.get_unchecked_mut(t) = slip;
                }
                if !R::STORES_FORCE {
                    // SAFETY: entry k belongs to row i of this block; the
                    // spring was turned in pass 1b.
                    let sh = unsafe { &mut *self.shear.0.add(k) };
                    let moved = fl.friction.move_spring(overlap, force, slip, self.dt, sh);
                    // SAFETY: t < found ≤ BATCH.
                    unsafe { *g.moved.get_unchecked_mut(t) = moved };
                }
            }
            from = to;
        }
        if !R::STORES_FORCE {
            for t in 0..found {
                let (sliding, s) = g.moved[t].cut();
                g.sliding[t] = sliding;
                g.cut[t] = s;
            }
        }
        let mut from = 0usize;
        for i in lo..hi {
            let (s, e) = (start[i] as usize, start[i + 1] as usize);
            if s == e {
                continue;
            }
            let to = (g.ends[i - lo] as usize).min(found);
            let a = side(i);
            let mut fi = [0.0; 3];
            let mut ti = [0.0; 3];
            for t in from..to {
                let q = g.entry(t);
                let (j, k) = (g.partner[q] as usize, first + q);
                let fl = row_law(i, j);
                let overlap = g.overlap[q];
                let n = [g.nx[q], g.ny[q], g.nz[q]];
                // SAFETY: t < found ≤ BATCH.
                let (force, slip) =
                    unsafe { (*g.force.get_unchecked(t), *g.slip.get_unchecked(t)) };
                // SAFETY: entry k belongs to row i of this block.
                let sh = unsafe { &mut *self.shear.0.add(k) };
                let tangential = if R::STORES_FORCE {
                    // The spring was turned in pass 1b.
                    fl.friction
                        .tangential_force_turned_known(true, overlap, force, slip, self.dt, sh)
                } else {
                    // SAFETY: t < found ≤ BATCH.
                    let (moved, sliding, cut) = unsafe {
                        (
                            g.moved.get_unchecked(t),
                            *g.sliding.get_unchecked(t),
                            *g.cut.get_unchecked(t),
                        )
                    };
                    fl.friction
                        .cut_spring_force(moved, sliding, cut, overlap, slip, sh)
                };
                let arm_j = if ROLL {
                    let b = side(j);
                    // SAFETY: as the spring.
                    let roll = unsafe { &mut *self.roll.0.add(k) };
                    (
                        Some(fl.rolling_stage(overlap, force, n, &a, &b, self.dt, roll)),
                        b.arm,
                    )
                } else {
                    // SAFETY: j is a body (pass 1).
                    (None, unsafe { *radius.get_unchecked(j) })
                };
                let (rolling, arm_j) = arm_j;
                let (arm_i, arm_j) = fl.torque_arm.arms(overlap, a.arm, arm_j);
                let c = assemble(force, tangential, rolling, n, arm_i, arm_j);
                let (fj, tqj) = (c.on_body2(n), c.torque2());
                sub(&mut fi, fj);
                add(&mut ti, c.torque1());
                // SAFETY: j lies in this block or the next (the list's
                // blocks, as in [`Self::row`]).
                unsafe {
                    add(&mut *self.force.0.add(j), fj);
                    add(&mut *self.torque.0.add(j), tqj);
                }
            }
            from = to;
            // SAFETY: i is in this block.
            unsafe {
                add(&mut *self.force.0.add(i), fi);
                add(&mut *self.torque.0.add(i), ti);
            }
        }
        // The rows' tallies of the observables, when asked: the contacts
        // found, row by row in list order, with the histories and springs
        // as the stages left them.
        if TALLY {
            // Each entry's terms recorded only where a rank asks for them:
            // the one-process loop is the same code as without the record.
            if self.entries.asked() {
                self.tally_rows::<KEEP, ROLL, true, R>(lo, hi, first, found, g, rows);
            } else {
                self.tally_rows::<KEEP, ROLL, false, R>(lo, hi, first, found, g, rows);
            }
        }
    }

    /// The rows' tallies of the observables of rows `lo..hi` (a batch whose
    /// first entry is `first`, with `found` contacts in `g`): the contacts
    /// found, row by row in list order, with the histories and springs as
    /// the stages left them; with `RECORD`, each entry's terms into
    /// `self.entries` too.
    #[inline(always)]
    fn tally_rows<const KEEP: bool, const ROLL: bool, const RECORD: bool, R: RowLaws>(
        &self,
        lo: usize,
        hi: usize,
        first: usize,
        found: usize,
        g: &Batch,
        rows: &R,
    ) {
        let row_law = |i: usize, j: usize| -> &FrictionLaw { rows.law(i, j) };
        let tally = self.tally;
        let group = &self.bodies.group[..];
        let mut from = 0usize;
        for i in lo..hi {
            let to = (g.ends[i - lo] as usize).min(found);
            let walled_i = group[i] != NO_GROUP;
            let mut sums: PairTally = [0.0; 4];
            for t in from..to {
                let q = g.entry(t);
                let (j, k) = (g.partner[q] as usize, first + q);
                // SAFETY: entry k belongs to row i of this block (as
                // in the stages above).
                let (hist, sh, roll) = unsafe {
                    (
                        if KEEP {
                            &*self.history.0.add(k)
                        } else {
                            &NO_HISTORY
                        },
                        &*self.shear.0.add(k),
                        if ROLL {
                            Some(&*self.roll.0.add(k))
                        } else {
                            None
                        },
                    )
                };
                let walled = walled_i || group[j] != NO_GROUP;
                let (energy, spring) = tally_entry(
                    R::STORES_FORCE,
                    &mut sums,
                    row_law(i, j),
                    g.overlap[q],
                    walled,
                    hist,
                    sh,
                    roll,
                );
                if RECORD {
                    // SAFETY: entry k belongs to row i of this block.
                    unsafe { self.entries.energy_and_spring(k, energy, spring) };
                }
            }
            from = to;
            // SAFETY: i is in this block (one tally per body).
            unsafe { *tally.at(i) = sums };
        }
    }
}

/// Entries per batch of [`MainPairs::block`] (≤ 256: indices are `u8`).
pub(super) const BATCH: usize = 64;

/// The first pass's results for one batch of [`MainPairs::batch`], by
/// entry (its index in the list minus the batch's first): the partner,
/// the difference of centres (m) and sum of radii (m), whether it
/// touches, the overlap (m) and unit normal; `found`: the touching
/// entries in order; `ends`: where each row's end in `found`. Then by
/// contact found (its index in `found`), the second pass's stages: the
/// normal force (N), the slip velocity (m/s), the moved displacement
/// spring, whether it slides and its cut factor.
pub(super) struct Batch {
    partner: [u32; BATCH],
    dx: [f64; BATCH],
    dy: [f64; BATCH],
    dz: [f64; BATCH],
    sum: [f64; BATCH],
    touches: [u64; BATCH],
    overlap: [f64; BATCH],
    nx: [f64; BATCH],
    ny: [f64; BATCH],
    nz: [f64; BATCH],
    found: [u8; BATCH],
    ends: [u8; BATCH],
    force: [f64; BATCH],
    slip: [[f64; 3]; BATCH],
    moved: [MovedSpring; BATCH],
    sliding: [bool; BATCH],
    cut: [f64; BATCH],
}

impl Batch {
    /// The entry of the t-th contact found (its index into the first
    /// pass's arrays), known to be < [`BATCH`]: the stages index those
    /// arrays without a check per contact.
    #[inline(always)]
    fn entry(&self, t: usize) -> usize {
        let q = self.found[t] as usize;
        // SAFETY: every value written to `found` is an entry q < count ≤
        // BATCH (pass 1), and those of [`Batch::EMPTY`] are 0.
        unsafe { std::hint::assert_unchecked(q < BATCH) };
        q
    }
}

impl Batch {
    /// Zeros: every index an entry (< [`BATCH`]).
    pub(super) const EMPTY: Batch = Batch {
        partner: [0; BATCH],
        dx: [0.0; BATCH],
        dy: [0.0; BATCH],
        dz: [0.0; BATCH],
        sum: [0.0; BATCH],
        touches: [0; BATCH],
        overlap: [0.0; BATCH],
        nx: [0.0; BATCH],
        ny: [0.0; BATCH],
        nz: [0.0; BATCH],
        found: [0; BATCH],
        ends: [0; BATCH],
        force: [0.0; BATCH],
        slip: [[0.0; 3]; BATCH],
        moved: [MovedSpring {
            stiffness: 0.0,
            limit: 0.0,
            stretch: 0.0,
        }; BATCH],
        sliding: [false; BATCH],
        cut: [0.0; BATCH],
    };
}
