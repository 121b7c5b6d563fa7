//! Sphere–sphere contact forces through the physics crate's `PairLaw`, with
//! each pair's `ContactHistory` kept beside the neighbour list.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use crate::balance::share_order;
use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::entry_tally::{EntryTally, EntryTerms};
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::{SharedMut, Workers};
use dembound_physics::contact::model::overlap_rate;
use dembound_physics::contact::{ContactHistory, ContactModel, Geometry, PairLaw};
use dembound_physics::material::{Material, PairProperties};

use crate::walls::LawSlot;

mod both_ends;
mod one_law;
mod rows;
pub(crate) use rows::Rows;

/// At most this many body classes (material, radius, fixed) get a
/// precomputed table of pair laws; beyond, laws are computed per contact.
const MAX_CLASSES: usize = 64;
/// Class of a body when there is no table.
pub const NO_CLASS: u16 = u16::MAX;

/// The pair laws of a scene: a table over body classes when there are few
/// (monodisperse or a few sizes), else computed per contact.
#[derive(Debug, Clone)]
pub struct LawTable {
    pub model: ContactModel,
    /// The normal law keeps a per-contact history (hysteretic laws); when
    /// it does not, no history is stored at all.
    pub history: bool,
    pub materials: Vec<Material>,
    classes: usize,
    pairs: Vec<PairLaw>,
    planes: Vec<PairLaw>,
    /// The wall rows (`crate::walls::LawSlot`).
    pub slots: Vec<LawSlot>,
    /// The key of each class ([`Self::class_keys`]).
    keys: Option<Vec<ClassKey>>,
    /// The variants every row of `pairs` has, if a dispatch-free kernel
    /// has them (`one_law`): found once here, with the rows.
    row_variants: Option<one_law::RowVariants>,
}

/// What a body's pair laws are computed from: the bits of its radius (m)
/// and mass (kg), and its material.
pub type ClassKey = (u64, u64, u32);

/// Body `k`'s [`ClassKey`].
pub fn class_key(bodies: &Bodies, k: usize) -> ClassKey {
    (
        bodies.radius[k].to_bits(),
        bodies.mass[k].to_bits(),
        bodies.material[k],
    )
}

/// Radius (m), mass (kg) and material index of a [`ClassKey`].
pub fn class_info((r, m, mat): ClassKey) -> (f64, f64, usize) {
    (f64::from_bits(r), f64::from_bits(m), mat as usize)
}

impl LawTable {
    /// Assigns `bodies.class` and tabulates.
    pub fn new(
        model: ContactModel,
        materials: Vec<Material>,
        bodies: &mut Bodies,
        slots: Vec<LawSlot>,
    ) -> Self {
        let mut keys: Vec<ClassKey> = Vec::new();
        let mut class = Vec::with_capacity(bodies.len());
        for k in 0..bodies.len() {
            let key = class_key(bodies, k);
            let c = match keys.iter().position(|&q| q == key) {
                Some(c) => c,
                None => {
                    keys.push(key);
                    keys.len() - 1
                }
            };
            if keys.len() > MAX_CLASSES {
                break;
            }
            class.push(c as u16);
        }
        let table = Self::from_keys(model, materials, keys, slots);
        bodies.class = if table.keys.is_some() {
            class
        } else {
            vec![NO_CLASS; bodies.len()]
        };
        table
    }

    /// The tables of the classes `keys` (class c the c-th key), or none
    /// (laws per contact) beyond [`MAX_CLASSES`] keys.
    pub(crate) fn from_keys(
        model: ContactModel,
        materials: Vec<Material>,
        keys: Vec<ClassKey>,
        slots: Vec<LawSlot>,
    ) -> Self {
        let mut table = LawTable {
            model,
            history: model.normal.row().capabilities.history,
            materials,
            classes: 0,
            pairs: Vec::new(),
            planes: Vec::new(),
            slots,
            keys: None,
            row_variants: None,
        };
        if keys.len() > MAX_CLASSES {
            return table;
        }
        let c = keys.len();
        let info = |k: usize| class_info(keys[k]);
        for a in 0..c {
            for b in 0..c {
                let (ra, ma, mata) = info(a);
                let (rb, mb, matb) = info(b);
                table
                    .pairs
                    .push(table.compute_pair(ra, ma, mata, rb, mb, matb));
            }
        }
        for a in 0..c {
            for p in 0..table.slots.len() {
                let (ra, ma, mata) = info(a);
                table.planes.push(table.compute_plane(ra, ma, mata, p));
            }
        }
        table.classes = c;
        table.keys = Some(keys);
        table.row_variants = one_law::RowVariants::of(&table.pairs, table.history);
        table
    }

    /// The key of each class in class order; `None` when the laws are
    /// computed per contact (too many classes).
    pub(crate) fn class_keys(&self) -> Option<&[ClassKey]> {
        self.keys.as_deref()
    }

    fn compute_pair(
        &self,
        ra: f64,
        ma: f64,
        mata: usize,
        rb: f64,
        mb: f64,
        matb: usize,
    ) -> PairLaw {
        let props =
            PairProperties::spheres(ra, ma, &self.materials[mata], rb, mb, &self.materials[matb]);
        self.model.pair(&props)
    }

    fn compute_plane(&self, r: f64, m: f64, mat: usize, slot: usize) -> PairLaw {
        let row = &self.slots[slot];
        let wall = &self.materials[row.material as usize];
        let props = row.properties(r, m, &self.materials[mat], wall);
        self.model.pair(&props)
    }

    /// The law of bodies i and j.
    #[inline(always)]
    pub fn pair(&self, bodies: &Bodies, i: usize, j: usize) -> PairLaw {
        if self.classes > 0 {
            let (a, b) = (bodies.class[i] as usize, bodies.class[j] as usize);
            self.pairs[a * self.classes + b]
        } else {
            self.compute_pair(
                bodies.radius[i],
                bodies.mass[i],
                bodies.material[i] as usize,
                bodies.radius[j],
                bodies.mass[j],
                bodies.material[j] as usize,
            )
        }
    }

    /// The law of body i against wall row `plane` (`Wall::law_slot`).
    #[inline]
    pub fn wall(&self, bodies: &Bodies, i: usize, plane: usize) -> PairLaw {
        if self.classes > 0 {
            self.planes[bodies.class[i] as usize * self.slots.len() + plane]
        } else {
            self.compute_plane(
                bodies.radius[i],
                bodies.mass[i],
                bodies.material[i] as usize,
                plane,
            )
        }
    }

    /// Elastic energy (J) stored in a contact at overlap h (the normal
    /// law's, `PairLaw::elastic_energy`).
    #[inline]
    pub fn elastic_energy(&self, law: &PairLaw, overlap: f64, history: &ContactHistory) -> f64 {
        law.elastic_energy(overlap, history)
    }
}

/// Histories aligned with a [`PairList`]: `main[k]` for `list.j[k]`,
/// `extra[k]` for `list.extra[k]`; both empty when the law keeps none.
#[derive(Debug, Clone, Default)]
pub struct PairHistories {
    pub main: Vec<ContactHistory>,
    pub extra: Vec<ContactHistory>,
}

/// The history every contact of a history-free law reads.
pub const NO_HISTORY: ContactHistory = ContactHistory {
    max_overlap: 0.0,
    unloading: false,
};

impl PairHistories {
    /// History of main entry k (the default when none are kept).
    #[inline]
    pub fn main(&self, k: usize) -> &ContactHistory {
        self.main.get(k).unwrap_or(&NO_HISTORY)
    }

    /// History of extra entry k.
    #[inline]
    pub fn extra(&self, k: usize) -> &ContactHistory {
        self.extra.get(k).unwrap_or(&NO_HISTORY)
    }
}

/// The geometry of one pair at one instant: the contact composer's
/// (overlap R_i + R_j − |x_j − x_i| in m, negative apart; overlap rate in
/// m/s, positive while approaching; unit normal from i to j).
pub type PairGeometry = Geometry;

/// Overlap, rate and normal of spheres (x_i, v_i, R_i) and (x_j, v_j, R_j);
/// `None` when they do not touch.
#[inline(always)]
pub fn touching(
    xi: [f64; 3],
    vi: [f64; 3],
    ri: f64,
    xj: [f64; 3],
    vj: [f64; 3],
    rj: f64,
) -> Option<PairGeometry> {
    touching_lazy(xi, vi, ri, xj, || vj, rj)
}

/// [`touching`] with the partner's velocity read only in contact.
#[inline(always)]
pub fn touching_lazy(
    xi: [f64; 3],
    vi: [f64; 3],
    ri: f64,
    xj: [f64; 3],
    vj: impl Fn() -> [f64; 3],
    rj: f64,
) -> Option<PairGeometry> {
    let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let s = ri + rj;
    if r2 >= s * s {
        return None;
    }
    if r2 == 0.0 {
        // Coincident centres: no direction to push along.
        return None;
    }
    Some(geometry(d, r2, s, vi, vj()))
}

/// The pair's geometry whether or not it touches (collision log).
#[inline]
pub fn separation(
    xi: [f64; 3],
    vi: [f64; 3],
    ri: f64,
    xj: [f64; 3],
    vj: [f64; 3],
    rj: f64,
) -> PairGeometry {
    let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    geometry(d, r2, ri + rj, vi, vj)
}

#[inline(always)]
fn geometry(d: [f64; 3], r2: f64, s: f64, vi: [f64; 3], vj: [f64; 3]) -> PairGeometry {
    let r = r2.sqrt();
    geometry_at(d, r, 1.0 / r, s, vi, vj)
}

/// The geometry of a touching pair whose centre distance `r` = √r² and
/// its inverse `inv` = 1 / r are known (computed four pairs at a time by
/// `Rows`: the same correctly rounded operations, the same bits); `d` is
/// x_j − x_i and `s` the radii's sum.
#[inline(always)]
pub(crate) fn geometry_at(
    d: [f64; 3],
    r: f64,
    inv: f64,
    s: f64,
    vi: [f64; 3],
    vj: [f64; 3],
) -> PairGeometry {
    let n = [d[0] * inv, d[1] * inv, d[2] * inv];
    PairGeometry {
        overlap: s - r,
        overlap_rate: overlap_rate(vi, vj, n),
        normal: n,
    }
}

/// Force on j (N) of a touching frictionless pair, updating its history;
/// i gets minus it: the contact composer's normal stage alone
/// ([`PairLaw::normal_stage`]), F_n n.
#[inline(always)]
pub(crate) fn contact_force(
    law: &PairLaw,
    g: &PairGeometry,
    history: &mut ContactHistory,
) -> [f64; 3] {
    let f = law.normal_stage(g.overlap, g.overlap_rate, history);
    [f * g.normal[0], f * g.normal[1], f * g.normal[2]]
}

/// a ← a + b.
#[inline(always)]
pub(crate) fn add(a: &mut [f64; 3], b: [f64; 3]) {
    a[0] += b[0];
    a[1] += b[1];
    a[2] += b[2];
}

/// a ← a − b.
#[inline(always)]
pub(crate) fn sub(a: &mut [f64; 3], b: [f64; 3]) {
    a[0] -= b[0];
    a[1] -= b[1];
    a[2] -= b[2];
}

/// Adds every pair force to `force` (indexed like the bodies). Blocks of
/// the list run even ones first then odd ones, in parallel within a phase;
/// the extra pairs (large bodies, ghosts) follow serially. Deterministic
/// for any thread count.
pub fn add_pair_forces(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    histories: &mut PairHistories,
    laws: &LawTable,
    force: &mut [[f64; 3]],
    workers: &Workers,
) {
    assert!(force.len() == bodies.len());
    // SAFETY: one force per body (asserted), borrowed mutably here.
    unsafe {
        add_pair_forces_then(
            bodies,
            ghosts,
            list,
            histories,
            laws,
            SharedMut::new(force),
            workers,
            None,
            None,
            EntryTerms::NONE,
        )
    };
}

/// What a body's main-list pairs add to the observables
/// ([`pair_observables`]): touching pairs with neither in a
/// boundary-particle wall, touching pairs with one in such a wall, and
/// their normal elastic energy (J), each summed over the body's entries
/// in list order.
pub type PairTally = [f64; 3];

/// [`add_pair_forces`], and each body's [`PairTally`] at this state into
/// `tally` (one per body), the same bits as [`pair_observables`] sums;
/// with `entries`, each main entry's elastic energy too ([`EntryTally`]).
/// `false` (nothing written) when the tally does not apply: the list's
/// rows or blocks not one per body, or histories stored that the loop
/// does not update.
#[allow(clippy::too_many_arguments)]
pub fn add_pair_forces_tallied(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    histories: &mut PairHistories,
    laws: &LawTable,
    force: &mut [[f64; 3]],
    workers: &Workers,
    tally: &mut Vec<PairTally>,
    entries: Option<&mut EntryTally>,
) -> bool {
    let n = bodies.len();
    assert!(force.len() == n);
    let applies = list.start.len() == n + 1
        && covers(list, n)
        && (laws.history || histories.main.is_empty())
        && bodies.group.len() == n;
    if applies {
        tally.resize(n, [0.0; 3]);
    }
    let terms = match entries {
        Some(e) if applies => e.prepare(list.j.len(), false),
        _ => EntryTerms::NONE,
    };
    // SAFETY: one force per body (asserted), one tally (resized) and one
    // term per main entry (prepared), borrowed mutably here.
    unsafe {
        add_pair_forces_then(
            bodies,
            ghosts,
            list,
            histories,
            laws,
            SharedMut::new(force),
            workers,
            None,
            applies.then(|| SharedMut::new(tally)),
            terms,
        )
    };
    applies
}

/// The list's blocks are bodies 0..n, each once.
pub(crate) fn covers(list: &PairList, n: usize) -> bool {
    list.blocks.first() == Some(&0)
        && list.blocks.last() == Some(&(n as u32))
        && list.blocks.windows(2).all(|w| w[0] <= w[1])
}

/// [`add_pair_forces`] with a follow-up on each block's bodies once their
/// forces are complete (see [`run_blocks_then`]; the list must have no
/// extra pairs, which come after the blocks). Returns the follow-ups'
/// maximum.
///
/// # Safety
/// `force` points to one force per body, which nothing else reads or
/// writes meanwhile but `follow`, on the bodies it is given. `follow` may
/// write the positions and velocities of those bodies: the blocks that
/// read them are done, and no later block reads them (the force loop
/// reads them through `bodies`' slices, never after such a write).
/// `entries`, when asked, points to one term per main entry
/// (`EntryTally::prepare`), written only with `tally`.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn add_pair_forces_then(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    histories: &mut PairHistories,
    laws: &LawTable,
    f_ptr: SharedMut<[f64; 3]>,
    workers: &Workers,
    follow: Option<FollowUp>,
    tally: Option<SharedMut<PairTally>>,
    entries: EntryTerms,
) -> f64 {
    pair_forces_then(
        bodies, ghosts, list, histories, laws, f_ptr, workers, follow, tally, entries, true, true,
    )
}

/// [`add_pair_forces_then`]; `quad`: each row's pairs tested four at a
/// time where they can be ([`Rows::block_avx2`]), else pair by pair (the
/// unit tests' reference); `one_law`: a scene of one body class and law
/// through the kernel instantiated for it (`one_law`), else every law read
/// from the table (the unit tests' reference).
///
/// # Safety
/// As [`add_pair_forces_then`].
#[allow(clippy::too_many_arguments)]
unsafe fn pair_forces_then(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    histories: &mut PairHistories,
    laws: &LawTable,
    f_ptr: SharedMut<[f64; 3]>,
    workers: &Workers,
    follow: Option<FollowUp>,
    tally: Option<SharedMut<PairTally>>,
    entries: EntryTerms,
    quad: bool,
    one_law: bool,
) -> f64 {
    let n = bodies.len();
    let keep = laws.history;
    assert!(follow.is_none() || list.extra.is_empty());
    let rows = Rows::new(bodies, list, histories, laws, f_ptr, tally, entries);
    let rows = if one_law {
        rows
    } else {
        rows.table_laws_only()
    };
    // The pairs four at a time where they can be: no histories (a pair
    // apart does nothing) and AVX2.
    #[cfg(target_arch = "x86_64")]
    let quad = quad && !keep && std::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let _ = quad;
    // One loop with the tally and one without, so that the force loop
    // has no per-row test of it.
    #[cfg(target_arch = "x86_64")]
    let value = match (quad, tally.is_some()) {
        // SAFETY: as the caller's; one tally per body when asked; AVX2
        // and no histories just checked.
        (true, true) => run_blocks_then(
            workers,
            list,
            |b| unsafe { rows.block_avx2::<true>(b) },
            follow,
        ),
        (true, false) => run_blocks_then(
            workers,
            list,
            |b| unsafe { rows.block_avx2::<false>(b) },
            follow,
        ),
        // SAFETY: as the caller's, and one tally per body.
        (false, true) => {
            run_blocks_then(workers, list, |b| unsafe { rows.block::<true>(b) }, follow)
        }
        (false, false) => {
            run_blocks_then(workers, list, |b| unsafe { rows.block::<false>(b) }, follow)
        }
    };
    #[cfg(not(target_arch = "x86_64"))]
    let value = if tally.is_some() {
        // SAFETY: as the caller's, and one tally per body.
        run_blocks_then(workers, list, |b| unsafe { rows.block::<true>(b) }, follow)
    } else {
        run_blocks_then(workers, list, |b| unsafe { rows.block::<false>(b) }, follow)
    };
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        let (i, j) = (i as usize, j as usize);
        let (xj, vj, owner) = if j < n {
            (bodies.position[j], bodies.velocity[j], j)
        } else {
            let g = j - n;
            (
                ghosts.position[g],
                ghosts.velocity[g],
                ghosts.owner[g] as usize,
            )
        };
        let mut scratch = NO_HISTORY;
        let hist = if keep {
            &mut histories.extra[k]
        } else {
            &mut scratch
        };
        match touching(
            bodies.position[i],
            bodies.velocity[i],
            bodies.radius[i],
            xj,
            vj,
            bodies.radius[owner],
        ) {
            Some(g) => {
                let law = laws.pair(bodies, i, owner);
                let fj = contact_force(&law, &g, hist);
                // SAFETY: i and owner are bodies; the blocks are done.
                unsafe {
                    sub(f_ptr.at(i), fj);
                    add(f_ptr.at(owner), fj);
                }
            }
            None => *hist = ContactHistory::default(),
        }
    }
    value
}

/// What a worker does with the bodies `lo..hi` of a block once their
/// forces are complete: Verlet's closing and opening half kicks and drift
/// (the next step's first stage, fused into this one: one hand-off between
/// the workers per step). Returns a value whose maximum over the blocks
/// [`run_blocks_then`] returns (the squared displacement).
pub(crate) type FollowUp<'a> = &'a (dyn Fn(usize, usize) -> f64 + Sync);

/// Runs `run_block(b)` for every block of `list` on the workers: even
/// blocks then odd blocks, without a barrier between the phases. Odd block
/// b starts when even blocks b − 1 and b + 1 are done, which is all the two
/// phases ordered (a block writes forces of its own bodies and of the next
/// block's): each body's additions come in the same order as with the
/// barrier, the same bits for any thread count.
///
/// Worker t runs the blocks of its share ([`PairList::shares`]), the same
/// bodies it advanced: their data stay in its core's cache; each block's
/// time goes to the shares' balance. The blocks a neighbouring share waits
/// for run first ([`share_order`]), so waits across workers are short.
/// Two workers instead take the blocks from both ends of the list until
/// they meet ([`both_ends::run`]): no share to balance by measurement.
///
/// A list marked [`PairList::sequential`] runs its blocks in order on the
/// calling thread.
///
/// With `follow`, also runs it on each block's bodies as soon as its
/// forces are complete: block b's pairs and block b − 1's are done (no
/// other block writes b's forces or reads b's positions and velocities, so
/// `follow` may change them). Returns the maximum of `follow`'s values (0
/// without it).
pub(crate) fn run_blocks_then(
    workers: &Workers,
    list: &PairList,
    run_block: impl Fn(usize) + Sync + Send,
    follow: Option<FollowUp>,
) -> f64 {
    let blocks = list.blocks.len().saturating_sub(1);
    let done: Vec<AtomicBool> = (0..blocks).map(|_| AtomicBool::new(false)).collect();
    let threads = workers.threads();
    let shared = !list.sequential && list.shares.blocks(0, threads).is_some();
    // Two workers need no measurements (`both_ends`).
    let measured = shared && !list.shares.both_ends();
    let timed = |b: usize, f: &dyn Fn() -> f64| -> f64 {
        if measured {
            // The block's own time, waits excluded.
            let started = Instant::now();
            let value = f();
            list.shares
                .record_block(b, started.elapsed().as_nanos() as u64);
            value
        } else {
            f()
        }
    };
    let run = |b: usize| {
        if b % 2 == 1 && !list.sequential {
            wait_for(&done[b - 1]);
            if let Some(d) = done.get(b + 1) {
                wait_for(d);
            }
        }
        timed(b, &|| {
            run_block(b);
            0.0
        });
        done[b].store(true, Ordering::Release);
    };
    let bodies = |b: usize| (list.blocks[b] as usize, list.blocks[b + 1] as usize);
    let complete = |b: usize| {
        done[b].load(Ordering::Acquire) && (b == 0 || done[b - 1].load(Ordering::Acquire))
    };
    // One worker's run over blocks `first..end` in `order`, following up
    // each of them as soon as it is complete, the rest at the end.
    let work = |first: usize, end: usize, order: Vec<usize>| -> f64 {
        let mut value = 0.0f64;
        let mut followed = vec![false; end - first];
        for b in order {
            run(b);
            if let Some(f) = follow {
                for c in [b, b + 1] {
                    if (first..end).contains(&c) && !followed[c - first] && complete(c) {
                        followed[c - first] = true;
                        let (lo, hi) = bodies(c);
                        value = value.max(timed(c, &|| f(lo, hi)));
                    }
                }
            }
        }
        if let Some(f) = follow {
            for c in first..end {
                if !followed[c - first] {
                    if c > 0 {
                        wait_for(&done[c - 1]);
                    }
                    wait_for(&done[c]);
                    let (lo, hi) = bodies(c);
                    value = value.max(timed(c, &|| f(lo, hi)));
                }
            }
        }
        value
    };
    if list.sequential {
        // A decomposed run: the rows in body order, so each body gets the
        // forces of its partners in their order (rows before it, then its
        // own row's sum), whatever the blocks of this rank's list.
        return work(0, blocks, (0..blocks).collect());
    }
    if shared && threads == 2 && blocks >= 2 {
        return both_ends::run(workers, list, &run, &complete, &|c| {
            follow.map_or(0.0, |f| {
                let (lo, hi) = bodies(c);
                f(lo, hi)
            })
        });
    }
    if shared {
        return workers
            .broadcast(|t| {
                list.shares.blocks(t, threads).map_or(0.0, |(first, end)| {
                    if crate::parallel::trace::on() {
                        let (a, b) = (list.blocks[first] as usize, list.blocks[end] as usize);
                        crate::parallel::trace::add_units(u64::from(list.start[b] - list.start[a]));
                    }
                    work(first, end, share_order(first, end, blocks))
                })
            })
            .into_iter()
            .fold(0.0, f64::max);
    }
    if threads == 1 {
        return work(0, blocks, block_order(blocks));
    }
    // No shares: the blocks are taken in `order` by whichever worker is
    // free; a block waits only for blocks earlier in it, which a running
    // worker has taken: no deadlock. The follow-ups come after all.
    let order = block_order(blocks);
    let next = AtomicUsize::new(0);
    workers.run(threads, |_| loop {
        let t = next.fetch_add(1, Ordering::Relaxed);
        let Some(&b) = order.get(t) else { break };
        run(b);
    });
    let mut value = 0.0f64;
    if let Some(f) = follow {
        for c in 0..blocks {
            let (lo, hi) = bodies(c);
            value = value.max(f(lo, hi));
        }
    }
    value
}

/// The force blocks in the order they are taken: 0, 2, 1, 4, 3, 6, 5, …
/// (each odd block right after the even block it waits for last).
fn block_order(blocks: usize) -> Vec<usize> {
    let mut order = Vec::with_capacity(blocks);
    for e in (0..blocks).step_by(2) {
        order.push(e);
        if e >= 2 {
            order.push(e - 1);
        }
    }
    if blocks.is_multiple_of(2) && blocks > 0 {
        order.push(blocks - 1);
    }
    order
}

/// Waits until another worker has set `flag`.
fn wait_for(flag: &AtomicBool) {
    wait_until(|| flag.load(Ordering::Acquire));
}

/// Waits until `ready()` (spinning, then yielding the core: a step is
/// short, but the machine may be shared and the other worker off its core).
fn wait_until(ready: impl Fn() -> bool) {
    if ready() {
        return;
    }
    let traced = crate::parallel::trace::on().then(Instant::now);
    let mut backoff = crate::parallel::Backoff::new();
    while !ready() {
        backoff.snooze();
    }
    if let Some(t) = traced {
        crate::parallel::trace::add_wait(t.elapsed().as_nanos() as u64);
    }
}

/// Position and velocity of extended index j (a body or a ghost) and its
/// owner body.
#[inline]
pub fn extended(bodies: &Bodies, ghosts: &Ghosts, j: usize) -> ([f64; 3], [f64; 3], usize) {
    let n = bodies.len();
    if j < n {
        (bodies.position[j], bodies.velocity[j], j)
    } else {
        let g = j - n;
        (
            ghosts.position[g],
            ghosts.velocity[g],
            ghosts.owner[g] as usize,
        )
    }
}

/// Contacts between particles, contacts with a boundary-particle wall (a
/// body with a group), and elastic energy (J) of the listed pairs at the
/// bodies' current state.
pub fn pair_observables(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    histories: &PairHistories,
    laws: &LawTable,
    workers: &Workers,
    tally: Option<&[PairTally]>,
) -> (usize, usize, f64) {
    let n = bodies.len();
    if list.start.len() != n + 1 {
        return (0, 0, 0.0);
    }
    let walled = |i: usize, j: usize| bodies.group[i] != NO_GROUP || bodies.group[j] != NO_GROUP;
    let sums = match tally.filter(|t| t.len() == n) {
        // The same sums, made by the force pass
        // ([`add_pair_forces_tallied`]), in the same chunks and order.
        Some(t) => sum_tallies(t, workers),
        None => pair_sums(bodies, list, histories, laws, workers),
    };
    let [count, wall_count, energy] = sums;
    let mut count = count as usize;
    let mut wall_count = wall_count as usize;
    let mut energy = energy;
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        let (i, j) = (i as usize, j as usize);
        let (xj, vj, owner) = extended(bodies, ghosts, j);
        if let Some(g) = touching(
            bodies.position[i],
            bodies.velocity[i],
            bodies.radius[i],
            xj,
            vj,
            bodies.radius[owner],
        ) {
            if walled(i, owner) {
                wall_count += 1;
            } else {
                count += 1;
            }
            energy +=
                laws.elastic_energy(&laws.pair(bodies, i, owner), g.overlap, histories.extra(k));
        }
    }
    (count, wall_count, energy)
}

/// Σ `tally` element-wise, as `Workers::sum` sums one value per body: in
/// chunks of `BODY_CHUNK` bodies, the chunks in order (the same bits),
/// over the slice without an index test per body; with AVX2 a body's
/// three values in one 4-lane addition ([`sum_rows_avx2`]).
fn sum_tallies(tally: &[PairTally], workers: &Workers) -> PairTally {
    use crate::parallel::BODY_CHUNK;
    let n = tally.len();
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::is_x86_feature_detected!("avx2");
    let partial = workers.map_bodies(n, BODY_CHUNK, |c| {
        let (lo, hi) = (c * BODY_CHUNK, ((c + 1) * BODY_CHUNK).min(n));
        #[cfg(target_arch = "x86_64")]
        if avx2 {
            // SAFETY: lo ≤ hi ≤ n; AVX2 checked.
            return unsafe { sum_rows_avx2(tally, lo, hi) };
        }
        sum_rows(&tally[lo..hi], [0.0; 3])
    });
    let mut s = [0.0; 3];
    for p in partial {
        s[0] += p[0];
        s[1] += p[1];
        s[2] += p[2];
    }
    s
}

/// `s` plus Σ `rows` element-wise, the rows in order.
#[inline(always)]
fn sum_rows(rows: &[PairTally], mut s: PairTally) -> PairTally {
    for t in rows {
        s[0] += t[0];
        s[1] += t[1];
        s[2] += t[2];
    }
    s
}

/// [`sum_rows`] of rows lo..hi of `tally` from zero, with AVX2: row k's
/// three values and the next row's first are one 4-lane load added to one
/// register, so lanes 0–2 take the three sums with the scalar loop's
/// additions in its order (IEEE per lane; lane 3's sum is not used); the
/// last row of `tally`, whose load would pass its end, is added as the
/// scalar loop adds it.
///
/// # Safety
/// lo ≤ hi ≤ `tally.len()`; the processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
unsafe fn sum_rows_avx2(tally: &[PairTally], lo: usize, hi: usize) -> PairTally {
    use std::arch::x86_64::*;
    // Rows whose four-double load stays within `tally`: all but its last.
    let wide = hi.min(tally.len().saturating_sub(1)).max(lo);
    let p = tally.as_ptr() as *const f64;
    let mut acc = _mm256_setzero_pd();
    let mut k = lo;
    // SAFETY (every load): row k + 1 < tally.len() exists, so doubles
    // 3k..3k + 4 lie within `tally`.
    while k + 4 <= wide {
        acc = _mm256_add_pd(acc, _mm256_loadu_pd(p.add(3 * k)));
        acc = _mm256_add_pd(acc, _mm256_loadu_pd(p.add(3 * k + 3)));
        acc = _mm256_add_pd(acc, _mm256_loadu_pd(p.add(3 * k + 6)));
        acc = _mm256_add_pd(acc, _mm256_loadu_pd(p.add(3 * k + 9)));
        k += 4;
    }
    while k < wide {
        acc = _mm256_add_pd(acc, _mm256_loadu_pd(p.add(3 * k)));
        k += 1;
    }
    let mut lanes = [0.0f64; 4];
    _mm256_storeu_pd(lanes.as_mut_ptr(), acc);
    sum_rows(&tally[wide..hi], [lanes[0], lanes[1], lanes[2]])
}

/// [`pair_observables`]' sums over the main list's rows, pair by pair:
/// touching pairs with neither in a boundary-particle wall, with one in
/// one, and their elastic energy (J).
fn pair_sums(
    bodies: &Bodies,
    list: &PairList,
    histories: &PairHistories,
    laws: &LawTable,
    workers: &Workers,
) -> PairTally {
    let n = bodies.len();
    let walled = |i: usize, j: usize| bodies.group[i] != NO_GROUP || bodies.group[j] != NO_GROUP;
    workers.sum(n, |i| {
        let mut c = 0.0;
        let mut w = 0.0;
        let mut e = 0.0;
        for k in list.start[i] as usize..list.start[i + 1] as usize {
            let j = list.j[k] as usize;
            if let Some(g) = touching(
                bodies.position[i],
                bodies.velocity[i],
                bodies.radius[i],
                bodies.position[j],
                bodies.velocity[j],
                bodies.radius[j],
            ) {
                if walled(i, j) {
                    w += 1.0;
                } else {
                    c += 1.0;
                }
                e += laws.elastic_energy(&laws.pair(bodies, i, j), g.overlap, histories.main(k));
            }
        }
        [c, w, e]
    })
}

/// The in-contact state of a pair for the checkpoint: (input id a, input id
/// b, history), a < b.
pub fn active_histories(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    histories: &PairHistories,
) -> Vec<(u32, u32, ContactHistory)> {
    let mut out = Vec::new();
    let n = bodies.len();
    if list.start.len() != n + 1
        || histories.main.len() != list.j.len()
        || histories.extra.len() != list.extra.len()
    {
        // No list yet.
        return out;
    }
    for i in 0..n {
        for k in list.start[i] as usize..list.start[i + 1] as usize {
            if histories.main[k] != ContactHistory::default() {
                let (a, b) = (bodies.id[i], bodies.id[list.j[k] as usize]);
                out.push((a.min(b), a.max(b), histories.main[k]));
            }
        }
    }
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        if histories.extra[k] != ContactHistory::default() {
            let (_, _, owner) = extended(bodies, ghosts, j as usize);
            let (a, b) = (bodies.id[i as usize], bodies.id[owner]);
            out.push((a.min(b), a.max(b), histories.extra[k]));
        }
    }
    out.sort_by_key(|x| (x.0, x.1));
    out
}

#[cfg(test)]
mod tests {
    use super::{block_order, one_law, pair_forces_then, PairTally};
    use crate::dynamics::friction_observables::tests::scene;
    use crate::parallel::SharedMut;
    use crate::Simulation;
    use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};

    /// The pairs tested four at a time (AVX2) give every force and every
    /// row's tally bit for bit as the pair-by-pair loop (the reference: it
    /// tests and forces every listed pair), with and without the tally, on
    /// 1 and 2 threads, along a frictionless run of mixed radii with walls
    /// and contacts made and broken; rows of 4 or more pairs (the four-lane
    /// test) and of 1–3 (pair by pair) both there.
    #[test]
    fn pairs_four_at_a_time_equal_the_pair_loop_bit_for_bit() {
        for threads in [1, 2] {
            let mut setup = scene();
            setup.friction = None;
            let mut sim = Simulation::new(setup, threads).unwrap();
            assert!(
                !sim.world.laws.history,
                "the scene must take the four-lane path"
            );
            let mut touching = 0.0;
            let (mut long, mut short) = (0, 0);
            for _ in 0..25 {
                sim.step(11);
                let w = &mut sim.world;
                let n = w.bodies.len();
                for i in 0..n {
                    let len = w.list.start[i + 1] - w.list.start[i];
                    if len >= 4 {
                        long += 1;
                    } else if len > 0 {
                        short += 1;
                    }
                }
                for tally in [false, true] {
                    let mut out = Vec::new();
                    for quad in [false, true] {
                        let (f, t) = list_forces(w, &sim.workers, quad, tally);
                        let bits: Vec<u64> =
                            f.iter().chain(&t).flatten().map(|x| x.to_bits()).collect();
                        out.push((bits, t));
                    }
                    assert!(out[0].0 == out[1].0, "{threads} threads, tally {tally}");
                    touching += out[1].1.iter().map(|t| t[0]).sum::<f64>();
                }
            }
            // Contacts were there to force, in rows of both kinds.
            assert!(touching > 100.0, "{touching}");
            assert!(long > 100 && short > 100, "{long} {short}");
        }
    }

    /// The pair forces of `w`'s list, four lanes at a time (`quad`, where
    /// the processor has AVX2) or pair by pair, with the rows' tallies
    /// (`tally`; zeros without).
    fn list_forces(
        w: &crate::pipeline::World,
        workers: &crate::parallel::Workers,
        quad: bool,
        tally: bool,
    ) -> (Vec<[f64; 3]>, Vec<PairTally>) {
        list_forces_with(w, workers, quad, tally, true)
    }

    /// [`list_forces`]; `one_law`: a scene of one body class and law
    /// through the kernel instantiated for it, else every law read from
    /// the class table.
    fn list_forces_with(
        w: &crate::pipeline::World,
        workers: &crate::parallel::Workers,
        quad: bool,
        tally: bool,
        one_law: bool,
    ) -> (Vec<[f64; 3]>, Vec<PairTally>) {
        let n = w.bodies.len();
        let mut f = vec![[0.0f64; 3]; n];
        let mut t: Vec<PairTally> = vec![[0.0; 3]; n];
        let mut histories = w.histories.clone();
        // SAFETY: one force and one tally per body, borrowed here; no
        // follow-up.
        unsafe {
            pair_forces_then(
                &w.bodies,
                &w.ghosts,
                &w.list,
                &mut histories,
                &w.laws,
                SharedMut::new(&mut f),
                workers,
                None,
                tally.then(|| SharedMut::new(&mut t)),
                crate::dynamics::entry_tally::EntryTerms::NONE,
                quad,
                one_law,
            )
        };
        (f, t)
    }

    /// The kernels without the per-contact dispatch on the law (Hertz,
    /// undamped or with Tsuji's damping; one body class and its one row,
    /// or two classes and their table: `one_law`) give the class table's
    /// forces and tallies bit for bit (the reference: every contact's law
    /// read from the table and dispatched on its variants), four lanes at
    /// a time and pair by pair, on 1 and 2 threads, along frictionless
    /// runs with contacts made and broken.
    #[test]
    fn known_law_kernels_equal_the_class_table_bit_for_bit() {
        use one_law::KnownLaw;
        let tsuji = ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
        );
        for threads in [1, 2] {
            for model in [ContactModel::elastic(NormalLaw::Hertz), tsuji] {
                for one_class in [true, false] {
                    let mut setup = scene();
                    setup.friction = None;
                    if one_class {
                        for s in &mut setup.spheres {
                            s.radius = 0.5e-3;
                        }
                    }
                    setup.contact = model;
                    // A step well inside the Hertz contact time of these
                    // impacts (~0.1 ms at 5 cm/s).
                    setup.integration.time_step = crate::setup::TimeStep::Fixed(5.0e-6);
                    let mut sim = Simulation::new(setup, threads).unwrap();
                    let w = &sim.world;
                    let kernel = KnownLaw::of(&w.laws, &w.bodies);
                    let label = format!("{threads} threads, {model:?}, one class {one_class}");
                    assert!(
                        matches!(
                            (&kernel, model.damping.kind(), one_class),
                            (Some(KnownLaw::OneHertzUndamped(_)), DampingKind::None, true)
                                | (Some(KnownLaw::OneHertzTsuji(_)), DampingKind::Tsuji, true)
                                | (Some(KnownLaw::HertzUndamped(_)), DampingKind::None, false)
                                | (Some(KnownLaw::HertzTsuji(_)), DampingKind::Tsuji, false)
                        ),
                        "{label}: the scene must take its law's kernel"
                    );
                    let mut touching = 0.0;
                    for _ in 0..25 {
                        sim.step(100);
                        let w = &sim.world;
                        let bits = |(f, t): (Vec<[f64; 3]>, Vec<PairTally>)| -> Vec<u64> {
                            f.iter().chain(&t).flatten().map(|x| x.to_bits()).collect()
                        };
                        for quad in [false, true] {
                            for tally in [false, true] {
                                let table = list_forces_with(w, &sim.workers, quad, tally, false);
                                touching += table.1.iter().map(|t| t[0]).sum::<f64>();
                                let known = list_forces_with(w, &sim.workers, quad, tally, true);
                                assert!(
                                    bits(known) == bits(table),
                                    "{label}, quad {quad}, tally {tally}"
                                );
                            }
                        }
                    }
                    // Contacts were there to force.
                    assert!(touching > 100.0, "{label}: {touching}");
                }
            }
        }
    }

    /// The list's pair forces, four lanes at a time and pair by pair,
    /// against every pair of bodies (i < j) tested and forced on its own
    /// (`touching`, `contact_force`): no list, no rows, no four-lane test
    /// (so a row's pair left out or taken twice, in the four-lane part or
    /// the last 1–3 pairs that both paths share, shows), along the
    /// frictionless run of `pairs_four_at_a_time_equal_the_pair_loop_bit_for_bit`.
    /// Each pair's force has the same bits either way (i and j swapped
    /// negate d and n exactly); only the order of each body's sum
    /// differs, so the tolerance is 1e-14 of the sum of its terms'
    /// magnitudes (≤ 12 terms a body: round-off ≤ 12 × 1.1e-16 of it).
    #[test]
    fn list_forces_equal_every_pair_forced_alone() {
        let mut setup = scene();
        setup.friction = None;
        let mut sim = Simulation::new(setup, 1).unwrap();
        assert!(!sim.world.laws.history);
        let (mut compared, mut in_tails) = (0usize, 0usize);
        for _ in 0..25 {
            sim.step(11);
            let w = &sim.world;
            let b = &w.bodies;
            let n = b.len();
            assert!(w.list.extra.is_empty() && w.ghosts.position.is_empty());
            let touching = |i: usize, j: usize| {
                super::touching(
                    b.position[i],
                    b.velocity[i],
                    b.radius[i],
                    b.position[j],
                    b.velocity[j],
                    b.radius[j],
                )
            };
            let mut expected = vec![[0.0f64; 3]; n];
            let mut magnitude = vec![0.0f64; n];
            for i in 0..n {
                for j in i + 1..n {
                    let Some(g) = touching(i, j) else {
                        continue;
                    };
                    let mut history = super::NO_HISTORY;
                    let fj = super::contact_force(&w.laws.pair(b, i, j), &g, &mut history);
                    super::sub(&mut expected[i], fj);
                    super::add(&mut expected[j], fj);
                    let m = fj.iter().map(|x| x.abs()).sum::<f64>();
                    magnitude[i] += m;
                    magnitude[j] += m;
                    compared += 1;
                }
            }
            // Touching pairs among a row's last 1–3 entries (pair by pair
            // on either path).
            for i in 0..n {
                let (s, e) = (w.list.start[i] as usize, w.list.start[i + 1] as usize);
                let tail = s + (e - s) / 4 * 4;
                in_tails += (tail..e)
                    .filter(|&k| touching(i, w.list.j[k] as usize).is_some())
                    .count();
            }
            for quad in [false, true] {
                let (f, _) = list_forces(w, &sim.workers, quad, true);
                for (i, (got, want)) in f.iter().zip(&expected).enumerate() {
                    assert!(
                        got.iter()
                            .zip(want)
                            .all(|(g, e)| (g - e).abs() <= 1e-14 * magnitude[i]),
                        "quad {quad}, body {i}: {got:?} against {want:?}"
                    );
                }
            }
        }
        // Contacts compared, some of them among the rows' last pairs (497
        // and 174 when written).
        assert!(compared > 300 && in_tails > 100, "{compared} {in_tails}");
    }

    /// The frictionless scene after 11 steps (its list built, spheres in
    /// contact), for the four-lane tests below.
    fn frictionless_after_11_steps() -> Simulation {
        let mut setup = scene();
        setup.friction = None;
        let mut sim = Simulation::new(setup, 1).unwrap();
        sim.step(11);
        sim
    }

    /// The list's forces and tallies four lanes at a time, asserted equal
    /// bit for bit to pair by pair; returns the four-lane ones.
    fn four_lanes_as_pair_by_pair(
        w: &crate::pipeline::World,
        workers: &crate::parallel::Workers,
    ) -> (Vec<[f64; 3]>, Vec<PairTally>) {
        let (one, tally_one) = list_forces(w, workers, false, true);
        let (four, tally_four) = list_forces(w, workers, true, true);
        let bits = |f: &[[f64; 3]], t: &[PairTally]| -> Vec<u64> {
            f.iter().chain(t).flatten().map(|x| x.to_bits()).collect()
        };
        assert!(bits(&one, &tally_one) == bits(&four, &tally_four));
        (four, tally_four)
    }

    /// A pair with coincident centres (r = 0: no direction to push along)
    /// in one of a row's four-lane groups: the four-lane path's r = √0 = 0
    /// and 1/r = ∞ must give what the pair-by-pair test gives (no force: it
    /// is not touching there), bit for bit and finite, forces and tallies.
    /// Partners are put on their row's body, at the first and
    /// the last lane of the row's first group of four, and (where the row
    /// has one) at its last entry, among the pairs left over.
    #[test]
    fn coincident_centres_in_a_lane_of_four_give_no_force() {
        let mut sim = frictionless_after_11_steps();
        let w = &mut sim.world;
        let n = w.bodies.len();
        let (mut lanes, mut moved) = (0, vec![false; n]);
        for i in 0..n {
            let (s, e) = (w.list.start[i] as usize, w.list.start[i + 1] as usize);
            if e - s < 4 || moved[i] {
                continue;
            }
            let mut entries = vec![s, s + 3];
            if (e - s) % 4 != 0 {
                entries.push(e - 1);
            }
            for k in entries {
                let j = w.list.j[k] as usize;
                if !moved[j] {
                    w.bodies.position[j] = w.bodies.position[i];
                    moved[j] = true;
                    moved[i] = true;
                    lanes += 1;
                }
            }
        }
        assert!(lanes > 10, "{lanes}");
        let (four, tally) = four_lanes_as_pair_by_pair(w, &sim.workers);
        assert!(four.iter().chain(&tally).flatten().all(|x| x.is_finite()));
    }

    /// A partner whose centre is NaN (a run gone unstable) in a lane of
    /// four counts as touching there as pair by pair (`touching_lazy`'s
    /// `r² ≥ (R_i + R_j)²` is false for NaN: the NaN reaches the forces,
    /// where the step's guard sees it): the same bits, with NaN in the
    /// forces of the row's body and of the partner.
    #[test]
    fn a_nan_centre_in_a_lane_of_four_is_forced_as_pair_by_pair() {
        let mut sim = frictionless_after_11_steps();
        let w = &mut sim.world;
        let n = w.bodies.len();
        let i = (0..n)
            .find(|&i| w.list.start[i + 1] - w.list.start[i] >= 4)
            .expect("a row of four");
        let j = w.list.j[w.list.start[i] as usize + 1] as usize;
        w.bodies.position[j][2] = f64::NAN;
        let (four, _) = four_lanes_as_pair_by_pair(w, &sim.workers);
        assert!(
            four[i].iter().chain(&four[j]).all(|x| x.is_nan()),
            "{:?}",
            four[i]
        );
    }

    /// The tallies summed four lanes at a time (`sum_rows_avx2`) against
    /// the scalar loop (`sum_rows`, the reference: the same additions one
    /// value at a time), bit for bit, over every range lo..hi of 23 rows
    /// (so the last row, whose four-double load would pass the end, and
    /// every remainder of the four-row steps): values of magnitudes
    /// 1e-3..1e16 whose sums depend on the order, and an infinite and a NaN
    /// value in later rounds.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn tallies_summed_four_lanes_equal_the_scalar_loop_bit_for_bit() {
        if !std::is_x86_feature_detected!("avx2") {
            return;
        }
        let n = 23;
        let mut tally: Vec<PairTally> = (0..n)
            .map(|k| {
                [0, 1, 2].map(|a| {
                    let t = (k * 5 + a * 11) as f64;
                    (t * 0.71).sin() * 10f64.powi(((k * 7 + a * 3) % 20) as i32 - 3)
                })
            })
            .collect();
        // The order matters for these values: summed backwards, a sum differs.
        let forward = super::sum_rows(&tally, [0.0; 3]);
        let mut reversed = tally.clone();
        reversed.reverse();
        assert_ne!(forward, super::sum_rows(&reversed, [0.0; 3]));
        for spoil in 0..3 {
            match spoil {
                1 => tally[9][1] = f64::INFINITY,
                2 => tally[17][2] = f64::NAN,
                _ => {}
            }
            for lo in 0..=n {
                for hi in lo..=n {
                    // SAFETY: lo ≤ hi ≤ n; AVX2 checked above.
                    let four = unsafe { super::sum_rows_avx2(&tally, lo, hi) };
                    let one = super::sum_rows(&tally[lo..hi], [0.0; 3]);
                    assert_eq!(
                        four.map(f64::to_bits),
                        one.map(f64::to_bits),
                        "{spoil} {lo}..{hi}"
                    );
                }
            }
        }
    }

    /// Every block once; each odd block after both even neighbours (the
    /// order the two-phase loop gave every body's additions).
    #[test]
    fn block_order_takes_each_block_once_after_its_even_neighbours() {
        for blocks in 0..20 {
            let order = block_order(blocks);
            let mut seen = order.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..blocks).collect::<Vec<_>>(), "{blocks} blocks");
            let at = |b: usize| order.iter().position(|&x| x == b);
            for b in (1..blocks).step_by(2) {
                assert!(at(b - 1) < at(b), "{blocks} blocks: {b} before {}", b - 1);
                if b + 1 < blocks {
                    assert!(at(b + 1) < at(b), "{blocks} blocks: {b} before {}", b + 1);
                }
            }
        }
    }
}
