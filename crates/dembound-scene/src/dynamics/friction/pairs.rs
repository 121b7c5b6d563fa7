//! The pair force loop with friction: each touching pair is the
//! composer's contact (`ContactLaw::calculate_forces`, or its stages in
//! the batched pass of `pair_batch.rs`), over the frictionless loop's
//! blocks and order.

use dembound_physics::contact::tangential::SpringRotation;
use dembound_physics::contact::{ContactHistory, ContactState, Side};

use super::pair_batch::{Batch, BATCH};
use super::row_laws::{ClassTable, HertzMindlin, OneLaw, RowLaws};
use super::{add, sub, FrictionLaw, FrictionTable, PairShear};
use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::contacts::{
    extended, run_blocks_then, touching, touching_lazy, FollowUp, LawTable, PairGeometry,
    PairHistories, NO_HISTORY,
};
use crate::dynamics::entry_tally::{EntryTally, EntryTerms};
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::{SharedMut, Workers};

/// Forces on j and torques on i and j of one touching pair with friction
/// (`ContactLaw::calculate_forces`); updates both histories and the
/// springs. The force on i is minus the returned one. `roll`: the rolling
/// spring, `None` when no surface of the scene rolls (its torque is then
/// zero and nothing is evaluated).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn contact(
    stores_force: bool,
    fl: &FrictionLaw,
    g: &PairGeometry,
    history: &mut ContactHistory,
    shear: &mut [f64; 3],
    roll: Option<&mut [f64; 3]>,
    a: Side,
    b: Side,
    dt: f64,
) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let n = g.normal;
    let c = fl.calculate_forces_known(
        stores_force,
        g,
        &a,
        &b,
        ContactState {
            history,
            tangential: shear,
            rolling: roll,
        },
        dt,
    );
    (c.on_body2(n), c.torque1(), c.torque2())
}

/// Body i as a side of its contacts.
#[inline(always)]
fn side(bodies: &Bodies, i: usize) -> Side {
    Side {
        velocity: bodies.velocity[i],
        spin: bodies.angular_velocity[i],
        arm: bodies.radius[i],
        inverse_inertia: bodies.inverse_inertia[i],
    }
}

/// What the friction force loop reads and writes.
pub struct PairForceInput<'a> {
    pub bodies: &'a Bodies,
    pub ghosts: &'a Ghosts,
    pub list: &'a PairList,
    pub laws: &'a LawTable,
    pub friction: &'a FrictionTable,
    /// Time since the last evaluation, s (0: do not move the springs).
    pub dt: f64,
}

/// Adds every pair force and torque (the frictionless loop's blocks and
/// order: deterministic for any thread count).
pub fn add_pair_forces(
    input: &PairForceInput,
    histories: &mut PairHistories,
    shear: &mut PairShear,
    force: &mut [[f64; 3]],
    torque: &mut [[f64; 3]],
    workers: &Workers,
) {
    let n = input.bodies.len();
    assert!(force.len() == n && torque.len() == n);
    // SAFETY: one force and one torque per body (asserted), borrowed
    // mutably here.
    unsafe {
        add_pair_forces_then(
            input,
            histories,
            shear,
            (SharedMut::new(force), SharedMut::new(torque)),
            workers,
            None,
            None,
            EntryTerms::NONE,
        )
    };
}

/// [`add_pair_forces`], and each body's [`PairTally`] of its listed pairs
/// at this state into `tally` (one per body): what
/// `friction_observables` would count and sum over them, with the same
/// bits; with `entries`, each main entry's elastic and springs' energy
/// too ([`EntryTally`]). `false` (nothing written) when the tally does not
/// apply: extra pairs, no class table, or histories or rolling springs
/// not those the observation reads.
#[allow(clippy::too_many_arguments)]
pub fn add_pair_forces_tallied(
    input: &PairForceInput,
    histories: &mut PairHistories,
    shear: &mut PairShear,
    force: &mut [[f64; 3]],
    torque: &mut [[f64; 3]],
    workers: &Workers,
    tally: &mut Vec<PairTally>,
    entries: Option<&mut EntryTally>,
) -> bool {
    let n = input.bodies.len();
    assert!(force.len() == n && torque.len() == n);
    let applies = tally_applies(input, histories, shear);
    if applies {
        tally.resize(n, [0.0; 4]);
    }
    let terms = match entries {
        Some(e) if applies => e.prepare(input.list.j.len(), true),
        _ => EntryTerms::NONE,
    };
    // SAFETY: one force and one torque per body (asserted), one tally
    // (resized) and one term per main entry (prepared), borrowed mutably
    // here.
    unsafe {
        add_pair_forces_then(
            input,
            histories,
            shear,
            (SharedMut::new(force), SharedMut::new(torque)),
            workers,
            None,
            applies.then(|| SharedMut::new(tally)),
            terms,
        )
    };
    applies
}

/// What a body's listed pairs add to the observables
/// (`friction_observables`): touching pairs with neither in a
/// boundary-particle wall, touching pairs with one in such a wall, their
/// normal elastic energy (J) and their springs' energy (J), each summed
/// over the body's entries in list order.
pub type PairTally = [f64; 4];

/// Whether the force loop can tally the observables: every pair in the
/// main list (its rows one per body), laws from the class table, the
/// histories the loop updates those the observation reads (none kept:
/// none stored), the rolling springs the loop moves those it reads.
fn tally_applies(input: &PairForceInput, histories: &PairHistories, shear: &PairShear) -> bool {
    let n = input.bodies.len();
    input.list.extra.is_empty()
        && input.list.start.len() == n + 1
        && crate::dynamics::contacts::covers(input.list, n)
        && input.friction.classes > 0
        && (input.laws.history || histories.main.is_empty())
        && shear.rolling == input.friction.rolling
        && input.bodies.group.len() == n
}

/// [`add_pair_forces`] with a follow-up on each block's bodies once their
/// forces and torques are complete (as `contacts::add_pair_forces_then`:
/// no extra pairs). Returns the follow-ups' maximum.
///
/// # Safety
/// As `contacts::add_pair_forces_then`, for the forces and the torques
/// (and the spins, which `follow` may write like the velocities).
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn add_pair_forces_then(
    input: &PairForceInput,
    histories: &mut PairHistories,
    shear: &mut PairShear,
    (force, torque): (SharedMut<[f64; 3]>, SharedMut<[f64; 3]>),
    workers: &Workers,
    follow: Option<FollowUp>,
    tally: Option<SharedMut<PairTally>>,
    entries: EntryTerms,
) -> f64 {
    let PairForceInput {
        bodies,
        ghosts,
        list,
        laws,
        friction,
        dt,
    } = *input;
    let n = bodies.len();
    let keep = laws.history;
    let rolling = friction.rolling;
    assert!(list.start.len() == n + 1);
    assert!(follow.is_none() || list.extra.is_empty());
    assert!(!keep || histories.main.len() == list.j.len());
    assert!(shear.main.len() == list.j.len() && shear.extra.len() == list.extra.len());
    assert!(
        !rolling
            || (shear.roll_main.len() == list.j.len()
                && shear.roll_extra.len() == list.extra.len())
    );
    assert!(
        bodies.position.len() == n
            && bodies.velocity.len() == n
            && bodies.radius.len() == n
            && bodies.angular_velocity.len() == n
            && bodies.inverse_inertia.len() == n
            && bodies.class.len() == n
    );
    // Rows lie within j (start is nondecreasing, the list's construction).
    assert!(list.start[n] as usize <= list.j.len());
    let (spin, inverse_inertia) = (&bodies.angular_velocity[..], &bodies.inverse_inertia[..]);
    let main = MainPairs {
        bodies,
        laws,
        friction,
        list,
        position: &bodies.position,
        velocity: &bodies.velocity,
        radius: &bodies.radius,
        spin,
        inverse_inertia,
        class: &bodies.class,
        start: &list.start,
        js: &list.j,
        table: &friction.pairs,
        classes: friction.classes,
        force,
        torque,
        history: SharedMut(histories.main.as_mut_ptr()),
        shear: SharedMut(shear.main.as_mut_ptr()),
        roll: SharedMut(shear.roll_main.as_mut_ptr()),
        dt,
        tally: tally.unwrap_or(SharedMut(std::ptr::null_mut())),
        entries,
    };
    // One loop per setting, so that the per-contact code has no branch on
    // them (the compiler does not unswitch the loop by itself).
    let table = friction.classes > 0;
    // The tally needs the class table (`tally_applies`): four more loops.
    let tallied = tally.is_some() && table;
    // One body class whose law is Hertz–Mindlin (no history kept): four
    // loops without the per-contact dispatch on the law's variants
    // (`row_laws`).
    let one = match (friction.classes, keep) {
        (1, false) if !row_by_row() => OneLaw::<HertzMindlin>::new(&friction.pairs[0]),
        _ => None,
    };
    // The scene's kind of tangential spring (`contact.tangential`, one
    // for every pair): the class table's kernels instantiated for it.
    let stores_force = friction.setup.model.tangential.stores_force();
    let value = match (rolling, tallied, one) {
        (false, false, Some(one)) => {
            main.run::<false, false, true, false, _>(workers, follow, &one)
        }
        (false, true, Some(one)) => main.run::<false, false, true, true, _>(workers, follow, &one),
        (true, false, Some(one)) => main.run::<false, true, true, false, _>(workers, follow, &one),
        (true, true, Some(one)) => main.run::<false, true, true, true, _>(workers, follow, &one),
        (_, _, None) if stores_force => {
            run_class_table::<true>(&main, workers, follow, (keep, rolling, table, tallied))
        }
        (_, _, None) => {
            run_class_table::<false>(&main, workers, follow, (keep, rolling, table, tallied))
        }
    };
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        let (i, j) = (i as usize, j as usize);
        let (xj, vj, owner) = extended(bodies, ghosts, j);
        let mut scratch = NO_HISTORY;
        let hist = if keep {
            &mut histories.extra[k]
        } else {
            &mut scratch
        };
        let sh = &mut shear.extra[k];
        let roll = shear.roll_extra.get_mut(k);
        match touching(
            bodies.position[i],
            bodies.velocity[i],
            bodies.radius[i],
            xj,
            vj,
            bodies.radius[owner],
        ) {
            Some(g) => {
                let mut computed = None;
                let fl = friction.pair(laws, bodies, i, owner, &mut computed);
                let (fj, tqi, tqj) = contact(
                    stores_force,
                    fl,
                    &g,
                    hist,
                    sh,
                    roll,
                    side(bodies, i),
                    Side {
                        velocity: vj,
                        ..side(bodies, owner)
                    },
                    dt,
                );
                // SAFETY: i and owner are bodies; the blocks are done.
                unsafe {
                    sub(force.at(i), fj);
                    add(force.at(owner), fj);
                    add(torque.at(i), tqi);
                    add(torque.at(owner), tqj);
                }
            }
            None => {
                *hist = ContactHistory::default();
                *sh = [0.0; 3];
                if let Some(r) = roll {
                    *r = [0.0; 3];
                }
            }
        }
    }
    value
}

/// What the loop over the list's main pairs reads and writes (slices, so
/// that the compiler does not reload the vectors' headers after the raw
/// writes, as in the frictionless loop).
pub(super) struct MainPairs<'a> {
    pub(super) bodies: &'a Bodies,
    pub(super) laws: &'a LawTable,
    pub(super) friction: &'a FrictionTable,
    pub(super) list: &'a PairList,
    pub(super) position: &'a [[f64; 3]],
    pub(super) velocity: &'a [[f64; 3]],
    pub(super) radius: &'a [f64],
    pub(super) spin: &'a [[f64; 3]],
    pub(super) inverse_inertia: &'a [f64],
    pub(super) class: &'a [u16],
    pub(super) start: &'a [u32],
    pub(super) js: &'a [u32],
    /// The class table (one row per class pair) when there is one.
    pub(super) table: &'a [FrictionLaw],
    pub(super) classes: usize,
    pub(super) force: SharedMut<[f64; 3]>,
    pub(super) torque: SharedMut<[f64; 3]>,
    pub(super) history: SharedMut<ContactHistory>,
    pub(super) shear: SharedMut<[f64; 3]>,
    pub(super) roll: SharedMut<[f64; 3]>,
    pub(super) dt: f64,
    /// Each body's [`PairTally`] is written here by the loops with
    /// `TALLY` (a body's row is visited by one block only); null without.
    pub(super) tally: SharedMut<PairTally>,
    /// Each touching entry's terms, written by the loops with `TALLY`
    /// when asked.
    pub(super) entries: EntryTerms,
}

impl MainPairs<'_> {
    /// Every block of main pairs. `KEEP`: the normal law keeps histories;
    /// `ROLL`: rolling springs are kept; `TABLE`: laws come from the class
    /// table, the batches' through `rows`. The caller has checked the
    /// lengths (`add_pair_forces`).
    fn run<const KEEP: bool, const ROLL: bool, const TABLE: bool, const TALLY: bool, R: RowLaws>(
        &self,
        workers: &Workers,
        follow: Option<FollowUp>,
        rows: &R,
    ) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (just checked).
            return run_blocks_then(
                workers,
                self.list,
                |b| unsafe { self.block_avx2::<KEEP, ROLL, TABLE, TALLY, R>(b, rows) },
                follow,
            );
        }
        run_blocks_then(
            workers,
            self.list,
            |b| self.block::<KEEP, ROLL, TABLE, TALLY, false, R>(b, rows),
            follow,
        )
    }

    /// [`Self::block`] compiled for AVX2: three-operand (VEX) arithmetic,
    /// about a fifth fewer instructions than the baseline's SSE2 copies.
    /// The same operations in the same order, and no fused multiply–add
    /// (Rust does not contract a·b + c): the same bits as the baseline.
    ///
    /// # Safety
    /// The processor must have AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    unsafe fn block_avx2<
        const KEEP: bool,
        const ROLL: bool,
        const TABLE: bool,
        const TALLY: bool,
        R: RowLaws,
    >(
        &self,
        b: usize,
        rows: &R,
    ) {
        self.block::<KEEP, ROLL, TABLE, TALLY, true, R>(b, rows)
    }

    /// Block `b`'s rows, in batches of consecutive rows with at most
    /// [`BATCH`] entries between them: a first pass over a batch finds the
    /// touching entries and their geometry without a branch on whether
    /// they touch (in the settled lattice drop 2/3 of the listed pairs
    /// touch, 30,446 of 45,157: a branch the processor cannot predict),
    /// so that the square roots and divisions of several
    /// pairs overlap instead of heading each contact's chain of dependent
    /// operations; the second pass computes the contacts found. Same
    /// operations on the same values in the same order as [`Self::row`]
    /// (the springs of untouched entries set to exactly +0): the same bits.
    /// `AVX2`: called from [`Self::block_avx2`] (the batches' springs
    /// turned four at a time, [`super::turn_four`]).
    #[inline(always)]
    fn block<
        const KEEP: bool,
        const ROLL: bool,
        const TABLE: bool,
        const TALLY: bool,
        const AVX2: bool,
        R: RowLaws,
    >(
        &self,
        b: usize,
        rows: &R,
    ) {
        let start = self.start;
        let lo = self.list.blocks[b] as usize;
        let hi = self.list.blocks[b + 1] as usize;
        // SAFETY: this thread's scratch, used by this call alone (a block
        // runs no other block inside it).
        let scratch = unsafe { &mut *BATCH_SCRATCH.with(|s| s.get()) };
        // The batches turn the springs by the rescale alone (their pass 1b
        // and `turn_four`): under `contact.spring_rotation = "project"`
        // every row runs entry by entry (`FrictionPair::rotate_spring`).
        let project = self.friction.setup.spring_rotation == SpringRotation::Project;
        let mut i = lo;
        while i < hi {
            // The batch: rows i..end, as many as fit in BATCH rows and
            // BATCH entries. The rows that fit are a prefix of
            // i + 1..=min(hi, i + BATCH) (row ends are nondecreasing),
            // found by bisection (six steps) rather than row by row.
            let first = start[i] as usize;
            let last = hi.min(i + BATCH);
            let end = i + start[i + 1..=last].partition_point(|&e| e as usize - first <= BATCH);
            if end == i || !TABLE || project || row_by_row() {
                // A row longer than a batch (a large body's), laws
                // computed per pair (no class table), or springs projected.
                self.row::<KEEP, ROLL, TABLE, TALLY>(i, R::STORES_FORCE);
                i += 1;
            } else {
                self.batch::<KEEP, ROLL, TABLE, TALLY, AVX2, R>(i, end, scratch, rows);
                i = end;
            }
        }
    }

    /// Row i entry by entry (rows longer than a batch). `stores_force`:
    /// the scene's [`RowLaws::STORES_FORCE`] (a constant where inlined).
    #[inline(always)]
    fn row<const KEEP: bool, const ROLL: bool, const TABLE: bool, const TALLY: bool>(
        &self,
        i: usize,
        stores_force: bool,
    ) {
        let (position, velocity, radius, spin, inverse_inertia, class) = (
            self.position,
            self.velocity,
            self.radius,
            self.spin,
            self.inverse_inertia,
            self.class,
        );
        let (start, js, table, classes) = (self.start, self.js, self.table, self.classes);
        let (s, e) = (start[i] as usize, start[i + 1] as usize);
        if s == e {
            if TALLY {
                // SAFETY: i is in this block (one per body, the caller's).
                unsafe { *self.tally.at(i) = [0.0; 4] };
            }
            return;
        }
        let (xi, vi, ri) = (position[i], velocity[i], radius[i]);
        let a = Side {
            velocity: vi,
            spin: spin[i],
            arm: ri,
            inverse_inertia: inverse_inertia[i],
        };
        let ci = if TABLE { class[i] as usize } else { 0 };
        let mut fi = [0.0; 3];
        let mut ti = [0.0; 3];
        let mut sums: PairTally = [0.0; 4];
        for k in s..e {
            // SAFETY (the unchecked reads): k < js.len() (rows lie
            // within j, asserted via start[n]), and every j < n (the
            // list's construction); body arrays of length n asserted
            // by the caller.
            let j = unsafe { *js.get_unchecked(k) } as usize;
            let (xj, rj) = unsafe { (*position.get_unchecked(j), *radius.get_unchecked(j)) };
            // SAFETY (every pointer below): entry k belongs to row i,
            // which only this block visits; j lies in this block or the
            // next, and blocks of one parity are two apart (the
            // frictionless loop's argument, `contacts::add_pair_forces`).
            let sh = unsafe { &mut *self.shear.0.add(k) };
            // The velocity is read only for touching pairs.
            let vj = || unsafe { *velocity.get_unchecked(j) };
            if let Some(g) = touching_lazy(xi, vi, ri, xj, vj, rj) {
                let mut scratch = NO_HISTORY;
                let hist = if KEEP {
                    unsafe { &mut *self.history.0.add(k) }
                } else {
                    &mut scratch
                };
                let b = unsafe {
                    Side {
                        velocity: *velocity.get_unchecked(j),
                        spin: *spin.get_unchecked(j),
                        arm: rj,
                        inverse_inertia: *inverse_inertia.get_unchecked(j),
                    }
                };
                let mut computed = None;
                let fl = if TABLE {
                    // SAFETY: classes are < `classes` when the table
                    // exists (`FrictionTable::new`), so the row is in
                    // the table of classes² rows.
                    unsafe { table.get_unchecked(ci * classes + *class.get_unchecked(j) as usize) }
                } else {
                    self.friction
                        .pair(self.laws, self.bodies, i, j, &mut computed)
                };
                let roll = if ROLL {
                    Some(unsafe { &mut *self.roll.0.add(k) })
                } else {
                    None
                };
                let (fj, tqi, tqj) = contact(stores_force, fl, &g, hist, sh, roll, a, b, self.dt);
                if TALLY {
                    let roll = if ROLL {
                        // SAFETY: as the spring above.
                        Some(unsafe { &*self.roll.0.add(k) })
                    } else {
                        None
                    };
                    let walled =
                        self.bodies.group[i] != NO_GROUP || self.bodies.group[j] != NO_GROUP;
                    let hist = if KEEP {
                        // SAFETY: as the history above.
                        unsafe { &*self.history.0.add(k) }
                    } else {
                        &NO_HISTORY
                    };
                    let sh = unsafe { &*self.shear.0.add(k) };
                    let (energy, spring) = tally_entry(
                        stores_force,
                        &mut sums,
                        fl,
                        g.overlap,
                        walled,
                        hist,
                        sh,
                        roll,
                    );
                    // SAFETY: entry k belongs to row i, which only this
                    // block visits.
                    unsafe { self.entries.energy_and_spring(k, energy, spring) };
                }
                sub(&mut fi, fj);
                add(&mut ti, tqi);
                unsafe {
                    add(&mut *self.force.0.add(j), fj);
                    add(&mut *self.torque.0.add(j), tqj);
                }
            } else {
                // An untouched pair: relax its springs to +0 (a read and a
                // compare when they are relaxed already). Compared by
                // bits: a −0 spring (a contact's with no slip along an
                // axis) is set to +0 as the batched pass's mask sets it.
                if KEEP {
                    let hist = unsafe { &mut *self.history.0.add(k) };
                    if *hist != ContactHistory::default() {
                        *hist = ContactHistory::default();
                    }
                }
                if sh.map(f64::to_bits) != [0; 3] {
                    *sh = [0.0; 3];
                }
                if ROLL {
                    let r = unsafe { &mut *self.roll.0.add(k) };
                    if r.map(f64::to_bits) != [0; 3] {
                        *r = [0.0; 3];
                    }
                }
            }
        }
        // SAFETY: i is in this block.
        unsafe {
            add(&mut *self.force.0.add(i), fi);
            add(&mut *self.torque.0.add(i), ti);
            if TALLY {
                *self.tally.at(i) = sums;
            }
        }
    }
}

/// The class table's loops of [`add_pair_forces_then`] (one per setting:
/// `keep`, `rolling`, `table`, `tallied`), for the kind of tangential
/// spring `STORES_FORCE` ([`RowLaws::STORES_FORCE`]): the laws from
/// `main`'s class table.
fn run_class_table<const STORES_FORCE: bool>(
    main: &MainPairs,
    workers: &Workers,
    follow: Option<FollowUp>,
    (keep, rolling, table, tallied): (bool, bool, bool, bool),
) -> f64 {
    let rows = &ClassTable::<STORES_FORCE> {
        table: main.table,
        class: main.class,
        classes: main.classes,
    };
    match (keep, rolling, table, tallied) {
        (false, false, true, true) => {
            main.run::<false, false, true, true, _>(workers, follow, rows)
        }
        (false, true, true, true) => main.run::<false, true, true, true, _>(workers, follow, rows),
        (true, false, true, true) => main.run::<true, false, true, true, _>(workers, follow, rows),
        (true, true, true, true) => main.run::<true, true, true, true, _>(workers, follow, rows),
        (false, false, true, _) => main.run::<false, false, true, false, _>(workers, follow, rows),
        (false, false, false, _) => {
            main.run::<false, false, false, false, _>(workers, follow, rows)
        }
        (false, true, true, _) => main.run::<false, true, true, false, _>(workers, follow, rows),
        (false, true, false, _) => main.run::<false, true, false, false, _>(workers, follow, rows),
        (true, false, true, _) => main.run::<true, false, true, false, _>(workers, follow, rows),
        (true, false, false, _) => main.run::<true, false, false, false, _>(workers, follow, rows),
        (true, true, true, _) => main.run::<true, true, true, false, _>(workers, follow, rows),
        (true, true, false, _) => main.run::<true, true, false, false, _>(workers, follow, rows),
    }
}

/// Adds one touching entry to its body's [`PairTally`], as
/// `friction_observables` does (the same operations in the same order on
/// the same values: the overlap, the history and springs after the force
/// stage moved them). `roll`: the rolling spring, `None` when none are
/// kept (zero). Returns the entry's elastic energy and its springs'
/// energy (0 where they are relaxed and not added), J.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn tally_entry(
    stores_force: bool,
    sums: &mut PairTally,
    fl: &FrictionLaw,
    overlap: f64,
    walled: bool,
    history: &ContactHistory,
    shear: &[f64; 3],
    roll: Option<&[f64; 3]>,
) -> (f64, f64) {
    if walled {
        sums[1] += 1.0;
    } else {
        sums[0] += 1.0;
    }
    let energy = fl.law.elastic_energy(overlap, history);
    sums[2] += energy;
    let r = roll.copied().unwrap_or([0.0; 3]);
    let mut spring = 0.0;
    if *shear != [0.0; 3] || r != [0.0; 3] {
        spring = fl.spring_energy_known(stores_force, overlap, shear, &r);
        sums[3] += spring;
    }
    (energy, spring)
}

thread_local! {
    /// Each thread's scratch for [`MainPairs::batch`], kept across blocks
    /// and steps rather than made (and zeroed) per block: a batch writes
    /// every entry it reads before reading it (its first pass fills the
    /// entries of its pairs, the stages read those).
    static BATCH_SCRATCH: std::cell::UnsafeCell<Batch> =
        const { std::cell::UnsafeCell::new(Batch::EMPTY) };
}

/// Tests: run [`MainPairs::row`] for every row, through the class
/// table's loops (the reference of the batched path, and of the one-law
/// loops with their settings).
#[cfg(test)]
static ROW_BY_ROW: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

#[cfg(test)]
fn row_by_row() -> bool {
    ROW_BY_ROW.load(std::sync::atomic::Ordering::Relaxed)
}

#[cfg(not(test))]
#[inline(always)]
fn row_by_row() -> bool {
    false
}

#[cfg(test)]
#[path = "pairs_tests.rs"]
mod tests;
