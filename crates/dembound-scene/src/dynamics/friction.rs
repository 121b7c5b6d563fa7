//! Friction and rotation (issue 13): the tangential spring with Coulomb
//! limit and the rolling resistance of the physics crate
//! (`contact::tangential`, `contact::rolling`) for sphere pairs and plane
//! walls, each contact's tangential displacement (a 3-vector) kept beside
//! the neighbour list and carried across rebuilds, reordering and
//! checkpoints by input ids.
//!
//! Geometry (LAMMPS `GranularModel`, LIGGGHTS `surface_model_default`): for
//! bodies i, j with unit normal n from i to j, the contact point lies at
//! R_i n from i and −R_j n from j (the undeformed radii as lever arms, so
//! that in gross sliding the spin change is exactly (5/2) μ J_n/(m R)); the
//! slip velocity is v_c = v_i − v_j + (R_i ω_i + R_j ω_j) × n, its
//! tangential part v_t drives the spring; the tangential force F_t acts on
//! i (−F_t on j), with torques R_i n × F_t on i and R_j n × F_t on j. A
//! plane is a body of infinite radius and mass with n the plane's inward
//! normal reversed.
//!
//! Kept apart from the frictionless force loop (`contacts.rs`), which stays
//! as it was: a scene without friction runs the same instructions.

use std::collections::HashMap;

use dembound_physics::contact::model::{assemble, overlap_rate, slip_velocity};
use dembound_physics::contact::tangential::{effective_shear_modulus, mix_friction};
use dembound_physics::contact::{ContactHistory, ContactLaw, ContactState, Side};
use dembound_physics::material::{Material, PairProperties};
use serde::{Deserialize, Serialize};

use super::contacts::{
    extended, run_blocks_then, touching, touching_lazy, FollowUp, LawTable, PairGeometry,
    PairHistories, NO_CLASS, NO_HISTORY,
};
use crate::bodies::Bodies;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::{SharedMut, Workers};
use crate::setup::FrictionSetup;
use crate::walls::{Surface, WallContacts, WallContactsMut};

#[inline(always)]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn add(a: &mut [f64; 3], b: [f64; 3]) {
    a[0] += b[0];
    a[1] += b[1];
    a[2] += b[2];
}

#[inline(always)]
fn sub(a: &mut [f64; 3], b: [f64; 3]) {
    a[0] -= b[0];
    a[1] -= b[1];
    a[2] -= b[2];
}

/// The tangential part of `v` for unit normal `n`.
#[inline(always)]
pub fn tangential(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let a = dot(v, n);
    [v[0] - a * n[0], v[1] - a * n[1], v[2] - a * n[2]]
}

/// The friction laws of a scene, tabulated over the body classes of the
/// [`LawTable`] when it has them.
#[derive(Debug, Clone)]
pub struct FrictionTable {
    pub setup: FrictionSetup,
    materials: Vec<Material>,
    /// The wall rows of the law table (material, wall, curvature).
    plane_surfaces: Vec<crate::walls::LawSlot>,
    /// Body classes of the tables (0: no tables).
    pub(crate) classes: usize,
    /// Per class pair (a · classes + b): the normal law beside its
    /// friction, so that the force loops read both by reference from one
    /// row (no per-contact copies).
    pub(crate) pairs: Vec<FrictionLaw>,
    /// Per class and plane (a · planes + p).
    pub(crate) planes: Vec<FrictionLaw>,
    /// Some surface has rolling friction (μ_r > 0): the rolling springs
    /// are stored and evaluated; else they are skipped entirely.
    rolling: bool,
}

/// The normal law and the friction of one class pair or class–plane: the
/// physics crate's contact composer.
pub type FrictionLaw = ContactLaw;

impl FrictionTable {
    pub fn new(setup: FrictionSetup, laws: &LawTable, bodies: &Bodies) -> Self {
        let plane_surfaces = laws.slots.clone();
        let rolling = setup.model.rolling_friction != 0.0
            || setup.materials.iter().flatten().any(|&(_, r)| r != 0.0)
            || setup.walls.iter().flatten().any(|&(_, r)| r != 0.0);
        let mut table = FrictionTable {
            setup,
            materials: laws.materials.clone(),
            plane_surfaces,
            classes: 0,
            pairs: Vec::new(),
            planes: Vec::new(),
            rolling,
        };
        if bodies.class.contains(&NO_CLASS) {
            return table;
        }
        let classes = bodies
            .class
            .iter()
            .map(|&c| c as usize + 1)
            .max()
            .unwrap_or(0);
        let mut first = vec![usize::MAX; classes];
        for (k, &c) in bodies.class.iter().enumerate() {
            if first[c as usize] == usize::MAX {
                first[c as usize] = k;
            }
        }
        let info = |c: usize| {
            let k = first[c];
            (
                bodies.radius[k],
                bodies.mass[k],
                bodies.material[k] as usize,
            )
        };
        for a in 0..classes {
            for b in 0..classes {
                let (ra, ma, mata) = info(a);
                let (rb, mb, matb) = info(b);
                let p = table.compute_pair(laws, ra, ma, mata, rb, mb, matb);
                table.pairs.push(p);
            }
        }
        for a in 0..classes {
            for p in 0..table.plane_surfaces.len() {
                let (ra, ma, mata) = info(a);
                let f = table.compute_plane(laws, ra, ma, mata, p);
                table.planes.push(f);
            }
        }
        table.classes = classes;
        table
    }

    #[allow(clippy::too_many_arguments)]
    fn compute_pair(
        &self,
        laws: &LawTable,
        ra: f64,
        ma: f64,
        mata: usize,
        rb: f64,
        mb: f64,
        matb: usize,
    ) -> FrictionLaw {
        let (a, b) = (&self.materials[mata], &self.materials[matb]);
        let props = PairProperties::spheres(ra, ma, a, rb, mb, b);
        let law = laws.model.pair(&props);
        let (mu_a, roll_a) = self.setup.of_material(mata);
        let (mu_b, roll_b) = self.setup.of_material(matb);
        let friction = self.setup.model.pair(
            &law,
            &props,
            effective_shear_modulus(a, b),
            mix_friction(mu_a, mu_b),
            mix_friction(roll_a, roll_b),
        );
        FrictionLaw { law, friction }
    }

    fn compute_plane(
        &self,
        laws: &LawTable,
        r: f64,
        m: f64,
        mat: usize,
        plane: usize,
    ) -> FrictionLaw {
        let row = self.plane_surfaces[plane];
        let (wall_material, wall) = (row.material, row.wall);
        let (a, w) = (
            &self.materials[mat],
            &self.materials[wall_material as usize],
        );
        let props = row.properties(r, m, a, w);
        let law = laws.model.pair(&props);
        let (mu_a, roll_a) = self.setup.of_material(mat);
        let (mu_w, roll_w) = self.setup.of_wall(wall, wall_material as usize);
        let friction = self.setup.model.pair(
            &law,
            &props,
            effective_shear_modulus(a, w),
            mix_friction(mu_a, mu_w),
            mix_friction(roll_a, roll_w),
        );
        FrictionLaw { law, friction }
    }

    /// Whether any surface has rolling friction.
    pub fn rolling(&self) -> bool {
        self.rolling
    }

    /// The law and friction of bodies i and j: a reference into the table,
    /// or computed into `scratch` when there is no table (too many
    /// classes).
    #[inline(always)]
    pub fn pair<'s>(
        &'s self,
        laws: &LawTable,
        bodies: &Bodies,
        i: usize,
        j: usize,
        scratch: &'s mut Option<FrictionLaw>,
    ) -> &'s FrictionLaw {
        if self.classes > 0 {
            let (a, b) = (bodies.class[i] as usize, bodies.class[j] as usize);
            &self.pairs[a * self.classes + b]
        } else {
            scratch.insert(self.compute_pair(
                laws,
                bodies.radius[i],
                bodies.mass[i],
                bodies.material[i] as usize,
                bodies.radius[j],
                bodies.mass[j],
                bodies.material[j] as usize,
            ))
        }
    }

    /// The law and friction of body i against plane `plane` (as
    /// [`Self::pair`]).
    #[inline(always)]
    pub fn plane<'s>(
        &'s self,
        laws: &LawTable,
        bodies: &Bodies,
        i: usize,
        plane: usize,
        scratch: &'s mut Option<FrictionLaw>,
    ) -> &'s FrictionLaw {
        if self.classes > 0 {
            &self.planes[bodies.class[i] as usize * self.plane_surfaces.len() + plane]
        } else {
            scratch.insert(self.compute_plane(
                laws,
                bodies.radius[i],
                bodies.mass[i],
                bodies.material[i] as usize,
                plane,
            ))
        }
    }
}

/// The springs of one contact as saved in checkpoints and carried across
/// rebuilds: the tangential displacement of body 1's contact point
/// relative to body 2's (m, components 0..3) and the rolling spring's
/// torque on body 1 (N m, components 3..6). Seen from body 2 both change
/// sign.
pub type Springs = [f64; 6];

fn negate(s: Springs) -> Springs {
    s.map(|x| -x)
}

fn split(s: &mut Springs) -> (&mut [f64; 3], &mut [f64; 3]) {
    let (a, b) = s.split_at_mut(3);
    // Infallible: 6 = 3 + 3.
    (
        a.try_into().unwrap_or_else(|_| unreachable!()),
        b.try_into().unwrap_or_else(|_| unreachable!()),
    )
}

/// Contact springs aligned with a [`PairList`] (like [`PairHistories`]),
/// seen from the row body i: the tangential displacements (`main`,
/// `extra`) and, only when some surface rolls, the rolling spring torques
/// (`roll_main`, `roll_extra`; empty otherwise, so that a scene without
/// rolling friction stores and touches 3 doubles per listed pair, not 6).
#[derive(Debug, Clone, Default)]
pub struct PairShear {
    pub main: Vec<[f64; 3]>,
    pub extra: Vec<[f64; 3]>,
    pub roll_main: Vec<[f64; 3]>,
    pub roll_extra: Vec<[f64; 3]>,
    /// The rolling springs are kept.
    pub rolling: bool,
}

impl PairShear {
    /// Appends an extra pair with relaxed springs.
    pub fn push_extra(&mut self) {
        self.extra.push([0.0; 3]);
        if self.rolling {
            self.roll_extra.push([0.0; 3]);
        }
    }

    fn springs(shear: [f64; 3], roll: Option<&[f64; 3]>) -> Springs {
        let r = roll.copied().unwrap_or([0.0; 3]);
        [shear[0], shear[1], shear[2], r[0], r[1], r[2]]
    }
}

/// A sphere–plane contact's springs with the values they had before the
/// step `stamp` moved them: evaluating the same step's forces twice (the
/// per-body pass again after a list rebuild) starts again from `before`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WallShear {
    pub shear: Springs,
    pub before: Springs,
    pub stamp: u64,
}

/// The springs of the pairs in contact, by input ids (a < b), seen from a.
pub fn active_shear(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    shear: &PairShear,
) -> Vec<(u32, u32, Springs)> {
    let mut out = Vec::new();
    let n = bodies.len();
    if list.start.len() != n + 1
        || shear.main.len() != list.j.len()
        || shear.extra.len() != list.extra.len()
    {
        return out;
    }
    let mut push = |i: usize, owner: usize, s: Springs| {
        if s != [0.0; 6] {
            let (a, b) = (bodies.id[i], bodies.id[owner]);
            if a < b {
                out.push((a, b, s));
            } else {
                out.push((b, a, negate(s)));
            }
        }
    };
    for i in 0..n {
        for k in list.start[i] as usize..list.start[i + 1] as usize {
            let s = PairShear::springs(shear.main[k], shear.roll_main.get(k));
            push(i, list.j[k] as usize, s);
        }
    }
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        let (_, _, owner) = extended(bodies, ghosts, j as usize);
        let s = PairShear::springs(shear.extra[k], shear.roll_extra.get(k));
        push(i as usize, owner, s);
    }
    out.sort_by_key(|x| (x.0, x.1));
    out
}

/// Displacements for a new list from `saved` (by input ids, as
/// [`active_shear`] gives them); `rolling`: keep the rolling springs
/// ([`FrictionTable::rolling`]).
pub fn restore_shear(
    bodies: &Bodies,
    ghosts: &Ghosts,
    list: &PairList,
    saved: &HashMap<(u32, u32), Springs>,
    rolling: bool,
) -> PairShear {
    let mut main = vec![[0.0; 3]; list.j.len()];
    let mut extra = vec![[0.0; 3]; list.extra.len()];
    let (mut roll_main, mut roll_extra) = if rolling {
        (
            vec![[0.0; 3]; list.j.len()],
            vec![[0.0; 3]; list.extra.len()],
        )
    } else {
        (Vec::new(), Vec::new())
    };
    if !saved.is_empty() {
        let get = |i: usize, j_ext: usize| -> Option<Springs> {
            let (_, _, owner) = extended(bodies, ghosts, j_ext);
            let (a, b) = (bodies.id[i], bodies.id[owner]);
            if a < b {
                saved.get(&(a, b)).copied()
            } else {
                saved.get(&(b, a)).map(|s| negate(*s))
            }
        };
        let put = |s: Springs, shear: &mut [f64; 3], roll: Option<&mut [f64; 3]>| {
            *shear = [s[0], s[1], s[2]];
            if let Some(r) = roll {
                *r = [s[3], s[4], s[5]];
            }
        };
        for (i, k) in list.entries() {
            if let Some(s) = get(i, list.j[k] as usize) {
                put(s, &mut main[k], roll_main.get_mut(k));
            }
        }
        for (k, &(i, j)) in list.extra.iter().enumerate() {
            if let Some(s) = get(i as usize, j as usize) {
                put(s, &mut extra[k], roll_extra.get_mut(k));
            }
        }
    }
    PairShear {
        main,
        extra,
        roll_main,
        roll_extra,
        rolling,
    }
}

/// Forces on j and torques on i and j of one touching pair with friction
/// ([`ContactLaw::calculate_forces`]); updates both histories and the
/// springs. The force on i is minus the returned one. `roll`: the rolling
/// spring, `None` when no surface of the scene rolls (its torque is then
/// zero and nothing is evaluated).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn contact(
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
    let c = fl.calculate_forces(
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
        )
    };
}

/// [`add_pair_forces`] with a follow-up on each block's bodies once their
/// forces and torques are complete (as `contacts::add_pair_forces_then`:
/// no extra pairs). Returns the follow-ups' maximum.
///
/// # Safety
/// As `contacts::add_pair_forces_then`, for the forces and the torques
/// (and the spins, which `follow` may write like the velocities).
pub(crate) unsafe fn add_pair_forces_then(
    input: &PairForceInput,
    histories: &mut PairHistories,
    shear: &mut PairShear,
    (force, torque): (SharedMut<[f64; 3]>, SharedMut<[f64; 3]>),
    workers: &Workers,
    follow: Option<FollowUp>,
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
    };
    // One loop per setting, so that the per-contact code has no branch on
    // them (the compiler does not unswitch the loop by itself).
    let table = friction.classes > 0;
    let value = match (keep, rolling, table) {
        (false, false, true) => main.run::<false, false, true>(workers, follow),
        (false, false, false) => main.run::<false, false, false>(workers, follow),
        (false, true, true) => main.run::<false, true, true>(workers, follow),
        (false, true, false) => main.run::<false, true, false>(workers, follow),
        (true, false, true) => main.run::<true, false, true>(workers, follow),
        (true, false, false) => main.run::<true, false, false>(workers, follow),
        (true, true, true) => main.run::<true, true, true>(workers, follow),
        (true, true, false) => main.run::<true, true, false>(workers, follow),
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
struct MainPairs<'a> {
    bodies: &'a Bodies,
    laws: &'a LawTable,
    friction: &'a FrictionTable,
    list: &'a PairList,
    position: &'a [[f64; 3]],
    velocity: &'a [[f64; 3]],
    radius: &'a [f64],
    spin: &'a [[f64; 3]],
    inverse_inertia: &'a [f64],
    class: &'a [u16],
    start: &'a [u32],
    js: &'a [u32],
    /// The class table (one row per class pair) when there is one.
    table: &'a [FrictionLaw],
    classes: usize,
    force: SharedMut<[f64; 3]>,
    torque: SharedMut<[f64; 3]>,
    history: SharedMut<ContactHistory>,
    shear: SharedMut<[f64; 3]>,
    roll: SharedMut<[f64; 3]>,
    dt: f64,
}

impl MainPairs<'_> {
    /// Every block of main pairs. `KEEP`: the normal law keeps histories;
    /// `ROLL`: rolling springs are kept; `TABLE`: laws come from the class
    /// table. The caller has checked the lengths (`add_pair_forces`).
    fn run<const KEEP: bool, const ROLL: bool, const TABLE: bool>(
        &self,
        workers: &Workers,
        follow: Option<FollowUp>,
    ) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (just checked).
            return run_blocks_then(
                workers,
                self.list,
                |b| unsafe { self.block_avx2::<KEEP, ROLL, TABLE>(b) },
                follow,
            );
        }
        run_blocks_then(
            workers,
            self.list,
            |b| self.block::<KEEP, ROLL, TABLE>(b),
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
    unsafe fn block_avx2<const KEEP: bool, const ROLL: bool, const TABLE: bool>(&self, b: usize) {
        self.block::<KEEP, ROLL, TABLE>(b)
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
    #[inline(always)]
    fn block<const KEEP: bool, const ROLL: bool, const TABLE: bool>(&self, b: usize) {
        let start = self.start;
        let lo = self.list.blocks[b] as usize;
        let hi = self.list.blocks[b + 1] as usize;
        let mut scratch = Batch::default();
        let mut i = lo;
        while i < hi {
            let first = start[i] as usize;
            let mut end = i;
            while end < hi && end - i < BATCH && start[end + 1] as usize - first <= BATCH {
                end += 1;
            }
            if end == i || !TABLE || row_by_row() {
                // A row longer than a batch (a large body's), or laws
                // computed per pair (no class table).
                self.row::<KEEP, ROLL, TABLE>(i);
                i += 1;
            } else {
                self.batch::<KEEP, ROLL, TABLE>(i, end, &mut scratch);
                i = end;
            }
        }
    }

    /// Rows `lo..hi`, at most [`BATCH`] of them with at most [`BATCH`]
    /// entries in all (see [`Self::block`]).
    #[inline(always)]
    fn batch<const KEEP: bool, const ROLL: bool, const TABLE: bool>(
        &self,
        lo: usize,
        hi: usize,
        scratch: &mut Batch,
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
        // Pass 1: every entry's geometry ([`touching_lazy`]'s operations
        // without its branches): the partners gathered, then the roots and
        // divisions of all entries in one loop over arrays (vectorised:
        // IEEE square root and division per lane, the same bits), then the
        // touching entries listed in `found` and the others' springs
        // relaxed by masking their bits.
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
        let mut m = 0usize;
        for i in lo..hi {
            let (s, e) = (start[i] as usize, start[i + 1] as usize);
            for k in s..e {
                let q = k - first;
                // SAFETY: q < count ≤ BATCH; m ≤ q.
                let touches = unsafe { *g.touches.get_unchecked(q) };
                unsafe {
                    *g.found.get_unchecked_mut(m) = q as u8;
                    *g.row.get_unchecked_mut(m) = (i - lo) as u8;
                }
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
                    mask(&mut *self.shear.0.add(k));
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
        // Pass 2, in stages over the contacts found, each a short loop
        // whose iterations are independent, so that the processor overlaps
        // the chains of dependent operations of several contacts (one
        // contact's chain, root to Coulomb test, is longer than its
        // window); the forces summed last, in [`Self::row`]'s order. The
        // same operations on the same values as [`contact`]: the same bits.
        let found = m.min(BATCH);
        // Batches run only with the class table ([`Self::block`]).
        debug_assert!(TABLE && table.len() == classes * classes);
        let row_law = |i: usize, j: usize| -> &FrictionLaw {
            // SAFETY: classes are < `classes` when the table exists
            // (`FrictionTable::new`), so the row is in the table of
            // classes² rows; i and j are bodies (pass 1).
            unsafe {
                table.get_unchecked(
                    *class.get_unchecked(i) as usize * classes + *class.get_unchecked(j) as usize,
                )
            }
        };
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
        // 2a: overlap rates and tangential slip velocities.
        for t in 0..found {
            let q = g.found[t] as usize;
            let (i, j) = (lo + g.row[t] as usize, g.partner[q] as usize);
            let (a, b) = (side(i), side(j));
            let n = [g.nx[q], g.ny[q], g.nz[q]];
            g.rate[t] = overlap_rate(a.velocity, b.velocity, n);
            g.slip[t] = slip_velocity(&a, &b, n);
        }
        // 2b: normal forces (histories updated).
        for t in 0..found {
            let q = g.found[t] as usize;
            let (i, j, k) = (lo + g.row[t] as usize, g.partner[q] as usize, first + q);
            let law = &row_law(i, j).law;
            let mut scratch = NO_HISTORY;
            // SAFETY: entry k belongs to row i of this block.
            let hist = if KEEP {
                unsafe { &mut *self.history.0.add(k) }
            } else {
                &mut scratch
            };
            g.force[t] = law.normal_stage(g.overlap[q], g.rate[t], hist);
        }
        // 2c: tangential forces (springs moved) and rolling torques.
        for t in 0..found {
            let q = g.found[t] as usize;
            let (i, j, k) = (lo + g.row[t] as usize, g.partner[q] as usize, first + q);
            let fl = row_law(i, j);
            let n = [g.nx[q], g.ny[q], g.nz[q]];
            // SAFETY: entry k belongs to row i of this block.
            let sh = unsafe { &mut *self.shear.0.add(k) };
            g.tangential[t] =
                fl.tangential_stage(g.overlap[q], g.force[t], n, g.slip[t], self.dt, sh);
            if ROLL {
                // SAFETY: as the spring.
                let roll = unsafe { &mut *self.roll.0.add(k) };
                g.rolling[t] = fl.rolling_stage(
                    g.overlap[q],
                    g.force[t],
                    n,
                    &side(i),
                    &side(j),
                    self.dt,
                    roll,
                );
            }
        }
        // 2d: forces and torques summed row by row.
        let mut from = 0usize;
        for i in lo..hi {
            let (s, e) = (start[i] as usize, start[i + 1] as usize);
            if s == e {
                continue;
            }
            let to = (g.ends[i - lo] as usize).min(found);
            let ri = radius[i];
            let mut fi = [0.0; 3];
            let mut ti = [0.0; 3];
            for t in from..to {
                let q = g.found[t] as usize;
                let j = g.partner[q] as usize;
                // SAFETY: j is a body (pass 1).
                let rj = unsafe { *radius.get_unchecked(j) };
                let n = [g.nx[q], g.ny[q], g.nz[q]];
                let rolling = if ROLL { Some(g.rolling[t]) } else { None };
                let c = assemble(g.force[t], g.tangential[t], rolling, n, ri, rj);
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
    }

    /// Row i entry by entry (rows longer than a batch).
    #[inline(always)]
    fn row<const KEEP: bool, const ROLL: bool, const TABLE: bool>(&self, i: usize) {
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
                let (fj, tqi, tqj) = contact(fl, &g, hist, sh, roll, a, b, self.dt);
                sub(&mut fi, fj);
                add(&mut ti, tqi);
                unsafe {
                    add(&mut *self.force.0.add(j), fj);
                    add(&mut *self.torque.0.add(j), tqj);
                }
            } else {
                // An untouched pair: relax its springs (a read and a
                // compare when they are relaxed already).
                if KEEP {
                    let hist = unsafe { &mut *self.history.0.add(k) };
                    if *hist != ContactHistory::default() {
                        *hist = ContactHistory::default();
                    }
                }
                if *sh != [0.0; 3] {
                    *sh = [0.0; 3];
                }
                if ROLL {
                    let r = unsafe { &mut *self.roll.0.add(k) };
                    if *r != [0.0; 3] {
                        *r = [0.0; 3];
                    }
                }
            }
        }
        // SAFETY: i is in this block.
        unsafe {
            add(&mut *self.force.0.add(i), fi);
            add(&mut *self.torque.0.add(i), ti);
        }
    }
}

/// Tests: run [`MainPairs::row`] for every row (the reference of the
/// batched path).
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

/// Entries per batch of [`MainPairs::block`] (≤ 256: indices are `u8`).
const BATCH: usize = 64;

/// The first pass's results for one batch of [`MainPairs::batch`], by
/// entry (its index in the list minus the batch's first): the partner,
/// the difference of centres (m) and sum of radii (m), whether it
/// touches, the overlap (m) and unit normal; `found`: the touching
/// entries in order; `ends`: where each row's end in `found`.
struct Batch {
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
    /// By contact found (index into `found`): its row (minus the
    /// batch's first), overlap rate (m/s), tangential slip velocity
    /// (m/s), normal force (N), tangential force (N) and rolling torque
    /// (N m).
    row: [u8; BATCH],
    rate: [f64; BATCH],
    slip: [[f64; 3]; BATCH],
    force: [f64; BATCH],
    tangential: [[f64; 3]; BATCH],
    rolling: [[f64; 3]; BATCH],
}

impl Default for Batch {
    fn default() -> Self {
        Self {
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
            row: [0; BATCH],
            rate: [0.0; BATCH],
            slip: [[0.0; 3]; BATCH],
            force: [0.0; BATCH],
            tangential: [[0.0; 3]; BATCH],
            rolling: [[0.0; 3]; BATCH],
        }
    }
}

/// What the per-body friction pass reads.
#[derive(Clone, Copy)]
pub struct BodyForceInput<'a> {
    pub bodies: &'a Bodies,
    pub surfaces: &'a [Surface],
    pub laws: &'a LawTable,
    pub friction: &'a FrictionTable,
    pub gravity: [f64; 3],
    /// The step whose forces these are (see [`WallShear`]).
    pub step: u64,
    /// Time since the last evaluation, s (0: do not move the springs).
    pub dt: f64,
}

/// Gravity and plane-wall forces (with friction) and the plane-wall
/// torques of body i at position `x`, velocity `v` and spin `w`: the
/// frictionless `walls::body_force` with the tangential force, its torque
/// and the rolling torque added.
///
/// # Safety
/// Body i's entries of `walls` and `shear` are touched by no other thread.
#[inline(always)]
pub unsafe fn body_force(
    c: &BodyForceInput,
    i: usize,
    (x, v, w): ([f64; 3], [f64; 3], [f64; 3]),
    walls: &WallContactsMut,
) -> ([f64; 3], [f64; 3]) {
    let bodies = c.bodies;
    if bodies.fixed[i] {
        return ([0.0; 3], [0.0; 3]);
    }
    let mut acc = gravity_force(c, i);
    let mut torque = [0.0; 3];
    add_plane_forces(c, i, (x, v, w), walls, &mut acc, &mut torque);
    (acc, torque)
}

/// Body i's weight m g, N.
#[inline(always)]
pub fn gravity_force(c: &BodyForceInput, i: usize) -> [f64; 3] {
    let m = c.bodies.mass[i];
    let g = c.gravity;
    [m * g[0], m * g[1], m * g[2]]
}

/// Adds the walls' forces (with friction) onto `acc` and their torques
/// onto `torque`, for free body i at (x, v, w) ([`body_force`] without
/// the weight), over its near entries.
///
/// # Safety
/// As [`body_force`].
#[inline(always)]
pub unsafe fn add_plane_forces(
    c: &BodyForceInput,
    i: usize,
    (x, v, w): ([f64; 3], [f64; 3], [f64; 3]),
    walls: &WallContactsMut,
    acc: &mut [f64; 3],
    torque: &mut [f64; 3],
) {
    let bodies = c.bodies;
    let (s, e) = walls.range(i);
    let r = bodies.radius[i];
    for k in s..e {
        let key = *walls.key.at(k);
        let surface = c.surfaces.get_unchecked(key.wall as usize);
        let p = surface.contact(key.element, x, v, r);
        let h = p.overlap;
        let touching = walls.touching.at(k);
        let mut scratch = NO_HISTORY;
        let hist = if walls.keep {
            walls.history.at(k)
        } else {
            &mut scratch
        };
        let sh = walls.shear.at(k);
        if h > 0.0 {
            let mut computed = None;
            let slot = surface.law_slot(key.element);
            let fl = c.friction.plane(c.laws, bodies, i, slot, &mut computed);
            *touching = true;
            if sh.stamp != c.step {
                sh.before = sh.shear;
                sh.stamp = c.step;
            }
            let mut d = sh.before;
            let (ds, dr) = split(&mut d);
            // The sphere is body 1, the wall body 2 (n from the sphere to
            // the wall): the composer's whole contact.
            let g = p.geometry();
            let sphere = Side {
                velocity: v,
                spin: w,
                arm: r,
                inverse_inertia: bodies.inverse_inertia[i],
            };
            let f = fl.calculate_forces(
                &g,
                &sphere,
                &surface.side(key.element, &p, x, r),
                ContactState {
                    history: hist,
                    tangential: ds,
                    rolling: c.friction.rolling.then_some(dr),
                },
                c.dt,
            );
            sh.shear = d;
            // −F_n n + F_t = F_n (wall normal) + F_t, and the two torque
            // parts added one after the other.
            add(acc, f.on_body1(g.normal));
            add(torque, f.tangential_torque1);
            if let Some(rolling) = f.rolling {
                add(torque, rolling);
            }
        } else if *touching {
            *hist = ContactHistory::default();
            *sh = WallShear::default();
            *touching = false;
        }
    }
}

/// Asks the processor to fetch body i's wall springs (and histories), so
/// that [`body_force`] a few bodies later finds them in cache: only the
/// few bodies near a wall read theirs, too sparse a pattern for the
/// hardware prefetcher. A hint only: nothing is read or written.
///
/// # Safety
/// i < the body count of `walls`.
#[inline(always)]
pub unsafe fn prefetch_wall_springs(i: usize, walls: &WallContactsMut) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let (s, e) = walls.range(i);
        for k in s..e {
            let at = walls.shear.0.add(k) as *const i8;
            // Its first and last byte: the lines it spans (≤ 3 of 64 B).
            _mm_prefetch::<_MM_HINT_T0>(at);
            _mm_prefetch::<_MM_HINT_T0>(at.add(64));
            _mm_prefetch::<_MM_HINT_T0>(at.add(std::mem::size_of::<WallShear>() - 1));
            if walls.keep {
                _mm_prefetch::<_MM_HINT_T0>(walls.history.0.add(k) as *const i8);
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (i, walls);
}

/// The tangential force (N) each wall (surface index) takes from the
/// spheres touching it at their current state, from the stored
/// displacements (not moved): added to the wall forces of the
/// observables.
pub fn plane_tangential_forces(
    bodies: &Bodies,
    surfaces: &[Surface],
    laws: &LawTable,
    friction: &FrictionTable,
    walls: &WallContacts,
) -> Vec<[f64; 3]> {
    let np = surfaces.len();
    let n = bodies.len();
    let mut out = vec![[0.0; 3]; np];
    if np == 0 || walls.bodies() != n || walls.shear.len() != walls.key.len() {
        return out;
    }
    for i in 0..n {
        if bodies.fixed[i] {
            continue;
        }
        // Only the entries the force pass looks at: a body touches no
        // other (the list is rebuilt before it could), so the sum is the
        // same.
        let (x, v, w, r) = (
            bodies.position[i],
            bodies.velocity[i],
            bodies.angular_velocity[i],
            bodies.radius[i],
        );
        for k in walls.range(i) {
            let key = walls.key[k];
            let surface = &surfaces[key.wall as usize];
            let c = surface.contact(key.element, x, v, r);
            let h = c.overlap;
            if h <= 0.0 {
                continue;
            }
            let mut computed = None;
            let slot = surface.law_slot(key.element);
            let fl = friction.plane(laws, bodies, i, slot, &mut computed);
            let hist = walls.history.get(k).unwrap_or(&NO_HISTORY);
            let sphere = Side {
                velocity: v,
                spin: w,
                arm: r,
                inverse_inertia: bodies.inverse_inertia[i],
            };
            let d = walls.shear[k].shear;
            let ft = fl
                .observe(
                    &c.geometry(),
                    &sphere,
                    &surface.side(key.element, &c, x, r),
                    hist,
                    [d[0], d[1], d[2]],
                    None,
                )
                .tangential;
            sub(&mut out[key.wall as usize], ft);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::Ordering;

    use dembound_physics::contact::{ContactModel, NormalLaw};

    use super::{add_pair_forces, PairForceInput, ROW_BY_ROW};
    use crate::dynamics::friction_observables::tests::scene;
    use crate::setup::TimeStep;
    use crate::Simulation;

    /// The batched pair loop (two passes, stages) gives the row-by-row
    /// loop's forces, torques, springs and histories bit for bit (the
    /// row-by-row loop is the reference: each contact evaluated whole, in
    /// list order), along a run of impacts, sliding and sticking, with
    /// rolling springs, with and without contact histories.
    #[test]
    fn batched_pairs_equal_row_by_row_bit_for_bit() {
        for history in [false, true] {
            let mut setup = scene();
            if history {
                // Walton–Braun's linear spring is soft: a step well inside
                // its contact time (~50 µs).
                setup.contact = ContactModel::elastic(NormalLaw::WaltonBraun { restitution: 0.5 });
                setup.integration.time_step = TimeStep::Fixed(2.0e-6);
            }
            let mut sim = Simulation::new(setup, 1).unwrap();
            let mut touching = 0;
            for _ in 0..30 {
                sim.step(100);
                let w = &sim.world;
                let n = w.bodies.len();
                let input = PairForceInput {
                    bodies: &w.bodies,
                    ghosts: &w.ghosts,
                    list: &w.list,
                    laws: &w.laws,
                    friction: w.friction.as_ref().unwrap(),
                    dt: sim.dt(),
                };
                let run = |rows: bool| {
                    let (mut histories, mut shear) = (w.histories.clone(), w.shear.clone());
                    let (mut force, mut torque) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
                    ROW_BY_ROW.store(rows, Ordering::Relaxed);
                    add_pair_forces(
                        &input,
                        &mut histories,
                        &mut shear,
                        &mut force,
                        &mut torque,
                        &sim.workers,
                    );
                    ROW_BY_ROW.store(false, Ordering::Relaxed);
                    let bits = |v: &[[f64; 3]]| -> Vec<u64> {
                        v.iter().flatten().map(|x| x.to_bits()).collect()
                    };
                    (
                        bits(&force),
                        bits(&torque),
                        bits(&shear.main),
                        bits(&shear.roll_main),
                        histories.main,
                    )
                };
                let (batched, rows) = (run(false), run(true));
                assert!(batched == rows, "history {history}");
                touching += batched.2.iter().filter(|&&x| x != 0).count();
            }
            // Loaded springs were compared: the settling bed has hundreds
            // of loaded components per check by the end (Walton–Braun's
            // shorter run, tens; 833 in all when written).
            assert!(touching > 500, "{touching}");
        }
    }
}
