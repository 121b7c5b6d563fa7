//! Verlet's first half (the pending closing half kick, kick, drift) and
//! the per-body forces in one pass over the bodies, alone or fused into
//! the force stage block by block; the spins' closing half kick.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use super::{verlet_four, Pipeline, StepHooks, World};
use crate::bodies::Bodies;
use crate::dynamics::contacts::{self, LawTable, Rows};
use crate::dynamics::entry_tally::EntryTerms;
use crate::dynamics::friction::{self, FrictionTable};
use crate::dynamics::integrate;
use crate::dynamics::walls;
use crate::parallel::{SharedMut, Workers, STEP_CHUNK};
use crate::walls::{Surface, WallContactsMut};

/// What [`verlet_chunk`] needs. `bodies` is read only for radius, mass,
/// fixed flag and class; positions, velocities and forces go through the
/// raw pointers.
struct AdvanceContext<'a> {
    x: SharedMut<[f64; 3]>,
    v: SharedMut<[f64; 3]>,
    f: SharedMut<[f64; 3]>,
    walls: WallContactsMut,
    bodies: &'a Bodies,
    surfaces: &'a [Surface],
    laws: &'a LawTable,
    gravity: [f64; 3],
    reference: &'a [[f64; 3]],
    dt: f64,
    pending: bool,
    spin: SharedMut<[f64; 3]>,
    torque: SharedMut<[f64; 3]>,
    friction: Option<&'a FrictionTable>,
    /// The step being made (its forces' stamp).
    step: u64,
    /// Frictionless: each touching wall entry's elastic energy, for the
    /// series row (`walls::add_wall_forces_tallied`), when not null.
    wall_energy: SharedMut<f64>,
}

unsafe impl Sync for AdvanceContext<'_> {}

/// Verlet's first half (after a pending closing half kick) and the
/// per-body forces of bodies lo..hi. Returns their largest squared
/// displacement since the last list build, m².
///
/// `TALLY`: the wall entries' energies too (`AdvanceContext::wall_energy`).
///
/// # Safety
/// lo..hi within the bodies, and no other thread touches these bodies;
/// with `TALLY`, `wall_energy` holds one value per wall entry.
#[inline(never)]
unsafe fn verlet_chunk<const TALLY: bool>(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (just checked); the rest as ours.
        return verlet_chunk_avx2::<TALLY>(c, lo, hi);
    }
    let m = advance_bodies(c, lo, hi);
    add_wall_forces_of::<TALLY>(c, lo, hi);
    m
}

/// [`verlet_chunk`] with the bodies advanced four at a time
/// ([`advance_bodies_quad`]) and compiled for AVX2 (no fused
/// multiply–add: the same operations, the same bits).
///
/// # Safety
/// As [`verlet_chunk`], and the processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
unsafe fn verlet_chunk_avx2<const TALLY: bool>(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    let m = advance_bodies_quad(c, lo, hi);
    add_wall_forces_of::<TALLY>(c, lo, hi);
    m
}

/// [`verlet_chunk`]'s first pass, body by body: the pending closing half
/// kick, the half kick and the drift (LAMMPS `nve`: v ← v + (Δt/2m) F,
/// x ← x + Δt v), the squared displacement since the list build, and the
/// weight m g as the body's new force (a fixed body's force zero). Returns
/// the largest squared displacement, m².
///
/// # Safety
/// As [`verlet_chunk`].
#[inline(always)]
unsafe fn advance_bodies(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    let b = c.bodies;
    let half_dt = 0.5 * c.dt;
    let mut m = 0.0f64;
    // Local slices: their headers are not reloaded after the raw writes.
    let (fixed, mass, reference) = (&b.fixed[..], &b.mass[..], c.reference);
    for i in lo..hi {
        let fi = c.f.at(i);
        if *fixed.get_unchecked(i) {
            *fi = [0.0; 3];
            continue;
        }
        let (xi, vi) = (c.x.at(i), c.v.at(i));
        let dtfm = half_dt / *mass.get_unchecked(i);
        if c.pending {
            integrate::half_kick(vi, *fi, dtfm);
        }
        integrate::half_kick(vi, *fi, dtfm);
        integrate::drift(xi, *vi, c.dt);
        m = m.max(integrate::displacement2(*xi, *reference.get_unchecked(i)));
        let mi = *mass.get_unchecked(i);
        let g = c.gravity;
        *fi = [mi * g[0], mi * g[1], mi * g[2]];
    }
    m
}

/// [`advance_bodies`] four bodies at a time: their positions, velocities,
/// forces and reference positions are three 4-lane vectors each (12
/// consecutive f64), each body's Δt/2m and mass spread over its three
/// lanes, so every lane makes its component's operations of the body by
/// body loop in the same order (v + F·Δt/2m twice when pending,
/// x + v·Δt, m·g). The squared displacement is summed per body after a
/// transpose, (dx² + dy²) + dz² as [`integrate::displacement2`]; its
/// maximum ignores a NaN as `f64::max` does (`max_pd(d, m)` keeps m then).
/// A group with a fixed body, and the last bodies short of four, go body
/// by body.
///
/// # Safety
/// As [`verlet_chunk`]; the processor has AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn advance_bodies_quad(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    use std::arch::x86_64::*;
    let b = c.bodies;
    let half_dt = 0.5 * c.dt;
    let (fixed, mass) = (&b.fixed[..], &b.mass[..]);
    let (x, v, f) = (c.x.0 as *mut f64, c.v.0 as *mut f64, c.f.0 as *mut f64);
    let reference = c.reference.as_ptr() as *const f64;
    let g = c.gravity;
    // The weight's components in the lanes of the three vectors.
    let weight = [
        _mm256_setr_pd(g[0], g[1], g[2], g[0]),
        _mm256_setr_pd(g[1], g[2], g[0], g[1]),
        _mm256_setr_pd(g[2], g[0], g[1], g[2]),
    ];
    let (half, dt) = (_mm256_set1_pd(half_dt), _mm256_set1_pd(c.dt));
    let mut largest = _mm256_setzero_pd();
    let mut m = 0.0f64;
    let mut i = lo;
    while i + 4 <= hi {
        // The four fixed flags (bools: one byte each, 0 or 1).
        if (fixed.as_ptr().add(i) as *const u32).read_unaligned() != 0 {
            m = m.max(advance_bodies(c, i, i + 4));
            i += 4;
            continue;
        }
        let masses = _mm256_loadu_pd(mass.as_ptr().add(i));
        let dtfm = spread_lanes!(_mm256_div_pd(half, masses));
        let masses = spread_lanes!(masses);
        let mut d2 = [_mm256_setzero_pd(); 3];
        for q in 0..3 {
            // Lanes 4q..4q + 4 of the four bodies' 12 values.
            let at = 3 * i + 4 * q;
            let fq = _mm256_loadu_pd(f.add(at));
            let mut vq = _mm256_loadu_pd(v.add(at));
            if c.pending {
                vq = _mm256_add_pd(vq, _mm256_mul_pd(fq, dtfm[q]));
            }
            vq = _mm256_add_pd(vq, _mm256_mul_pd(fq, dtfm[q]));
            let xq = _mm256_add_pd(_mm256_loadu_pd(x.add(at)), _mm256_mul_pd(vq, dt));
            _mm256_storeu_pd(v.add(at), vq);
            _mm256_storeu_pd(x.add(at), xq);
            _mm256_storeu_pd(f.add(at), _mm256_mul_pd(masses[q], weight[q]));
            let d = _mm256_sub_pd(xq, _mm256_loadu_pd(reference.add(at)));
            d2[q] = _mm256_mul_pd(d, d);
        }
        // [x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3] -> x, y, z of bodies 0-3.
        let [dx, dy, dz] = lanes_to_xyz!(d2);
        let moved2 = _mm256_add_pd(_mm256_add_pd(dx, dy), dz);
        largest = _mm256_max_pd(moved2, largest);
        i += 4;
    }
    m = m.max(advance_bodies(c, i, hi));
    let mut lanes = [0.0f64; 4];
    _mm256_storeu_pd(lanes.as_mut_ptr(), largest);
    lanes.into_iter().fold(m, f64::max)
}

/// [`verlet_chunk`]'s second pass: the wall forces of the bodies lo..hi
/// with near wall entries, added to their weights. Two passes, as
/// `verlet_chunk_friction_body`: the integration and the weights of all
/// bodies, then the wall forces of the few near a wall (`walls::body_force`
/// split: the same operations in the same order, the same bits). In one
/// pass, a wall type whose contact is a call (a triangle mesh's) made every
/// body spill its registers around it: +2.7 % instructions on the lattice
/// drop of planes. Four bodies without entries are passed by one test.
///
/// # Safety
/// As [`verlet_chunk`].
#[inline(always)]
unsafe fn add_wall_forces_of<const TALLY: bool>(c: &AdvanceContext, lo: usize, hi: usize) {
    let b = c.bodies;
    let fixed = &b.fixed[..];
    let mut i = lo;
    while i < hi {
        if i + 4 <= hi && c.walls.range(i).0 == c.walls.range(i + 3).1 {
            i += 4;
            continue;
        }
        let (s, e) = c.walls.range(i);
        if *fixed.get_unchecked(i) || s == e {
            i += 1;
            continue;
        }
        let fi = c.f.at(i);
        let mut acc = *fi;
        let (x, v) = (*c.x.at(i), *c.v.at(i));
        if TALLY {
            walls::add_wall_forces_tallied(
                b,
                i,
                x,
                v,
                c.surfaces,
                &c.walls,
                c.laws,
                &mut acc,
                c.wall_energy,
            );
        } else {
            walls::add_wall_forces(b, i, x, v, c.surfaces, &c.walls, c.laws, &mut acc);
        }
        *fi = acc;
        i += 1;
    }
}

/// [`verlet_chunk`] with rotation: ω gets the same half kicks from the
/// torque (Δt/2 · τ/I, LAMMPS `nve/sphere`), and the per-body forces are
/// the friction pass's ([`friction::body_force`]).
///
/// # Safety
/// As [`verlet_chunk`].
#[inline(never)]
unsafe fn verlet_chunk_friction(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (just checked); the rest as ours.
        return verlet_chunk_friction_avx2(c, lo, hi);
    }
    verlet_chunk_friction_body::<false>(c, lo, hi)
}

/// [`verlet_chunk_friction`] compiled for AVX2, its integration four
/// bodies at a time (`verlet_four`; the same operations per body, no
/// fused multiply–add: the same bits).
///
/// # Safety
/// As [`verlet_chunk`], and the processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
unsafe fn verlet_chunk_friction_avx2(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    verlet_chunk_friction_body::<true>(c, lo, hi)
}

/// `FOUR`: four free bodies at a time where they are (`verlet_four`; only
/// in [`verlet_chunk_friction_avx2`]).
///
/// # Safety
/// As [`verlet_chunk`]; with `FOUR`, the processor must have AVX2.
#[inline(always)]
unsafe fn verlet_chunk_friction_body<const FOUR: bool>(
    c: &AdvanceContext,
    lo: usize,
    hi: usize,
) -> f64 {
    let b = c.bodies;
    let half_dt = 0.5 * c.dt;
    let mut m = 0.0f64;
    let Some(table) = c.friction else {
        return m;
    };
    let input = friction::BodyForceInput {
        bodies: b,
        surfaces: c.surfaces,
        laws: c.laws,
        friction: table,
        gravity: c.gravity,
        step: c.step,
        dt: c.dt,
    };
    // Two passes over the chunk: the integration and the weights of all
    // bodies, then the plane walls' forces of the few near a wall. One
    // pass spilled the wall code's registers on every body. Each body gets
    // the same operations in the same order: the same bits.
    // The four-body groups' largest squared displacements, lane by lane
    // (`_mm256_max_pd(d, largest)` keeps `largest` where d is NaN, as
    // `f64::max` ignores a NaN; squares are never −0), folded into `m` at
    // the end: the same maximum, without a chain of four scalar maxima per
    // group. Zeroed without an AVX instruction (the scalar instance never
    // touches it again).
    #[cfg(target_arch = "x86_64")]
    // SAFETY: all-zero bits are four +0.0 lanes.
    let mut largest: std::arch::x86_64::__m256d = unsafe { std::mem::zeroed() };
    let mut i = lo;
    while i < hi {
        #[cfg(target_arch = "x86_64")]
        if FOUR
            && i + 4 <= hi
            // The four fixed flags (bools: one byte each, 0 or 1), i + 4 ≤
            // hi ≤ the body count.
            && (b.fixed.as_ptr().add(i) as *const u32).read_unaligned() == 0
        {
            // SAFETY: bodies of this chunk (read in the second pass).
            friction::prefetch_wall_springs_of(i, i + 4, &c.walls);
            let four = verlet_four::Four {
                x: c.x.at(i).as_mut_ptr(),
                v: c.v.at(i).as_mut_ptr(),
                w: c.spin.at(i).as_mut_ptr(),
                f: c.f.at(i).as_mut_ptr(),
                t: c.torque.at(i).as_mut_ptr(),
                reference: c.reference[i..i + 4].as_ptr().cast(),
                mass: b.mass[i..i + 4].as_ptr(),
                inverse_inertia: b.inverse_inertia[i..i + 4].as_ptr(),
            };
            // SAFETY: AVX2 (`FOUR`); bodies i..i + 4 of this chunk, free,
            // touched by no other thread (the caller's).
            let moved2 = verlet_four::advance(&four, c.dt, c.pending, c.gravity);
            largest = std::arch::x86_64::_mm256_max_pd(moved2, largest);
            i += 4;
            continue;
        }
        // SAFETY: a body of this chunk; its springs are read in the
        // second pass.
        friction::prefetch_wall_springs(i, &c.walls);
        let fi = c.f.at(i);
        let ti = c.torque.at(i);
        if b.fixed[i] {
            *fi = [0.0; 3];
            *ti = [0.0; 3];
            i += 1;
            continue;
        }
        let (xi, vi, wi) = (c.x.at(i), c.v.at(i), c.spin.at(i));
        let dtfm = half_dt / b.mass[i];
        let dtfi = half_dt * b.inverse_inertia[i];
        // Kicks and drift on copies, stored once: written and read back
        // through memory, the halves of a vector store do not forward to
        // the next load and each body stalled on it. The same operations
        // in the same order.
        let (mut x, mut v, mut w, f0, t0) = (*xi, *vi, *wi, *fi, *ti);
        if c.pending {
            integrate::half_kick(&mut v, f0, dtfm);
            integrate::half_kick(&mut w, t0, dtfi);
        }
        integrate::half_kick(&mut v, f0, dtfm);
        integrate::half_kick(&mut w, t0, dtfi);
        integrate::drift(&mut x, v, c.dt);
        (*xi, *vi, *wi) = (x, v, w);
        m = m.max(integrate::displacement2(x, c.reference[i]));
        *fi = friction::gravity_force(&input, i);
        *ti = [0.0; 3];
        i += 1;
    }
    // Four bodies without wall entries are passed by one test (most are:
    // the entries' starts are equal across them), as `add_wall_forces_of`.
    // The lattice drop's plane laws are Hertz–Mindlin: the wall contacts
    // without the dispatch on the law's variants.
    let hertz_mindlin = friction::planes_are_hertz_mindlin(table);
    let mut i = lo;
    while i < hi {
        if i + 4 <= hi && c.walls.range(i).0 == c.walls.range(i + 3).1 {
            i += 4;
            continue;
        }
        let (s, e) = c.walls.range(i);
        if b.fixed[i] || s == e {
            i += 1;
            continue;
        }
        let (fi, ti) = (c.f.at(i), c.torque.at(i));
        let (mut f, mut t) = (*fi, *ti);
        let state = (*c.x.at(i), *c.v.at(i), *c.spin.at(i));
        if hertz_mindlin {
            // SAFETY: the table's plane laws checked above.
            friction::add_plane_forces::<true>(&input, i, state, &c.walls, &mut f, &mut t);
        } else {
            friction::add_plane_forces::<false>(&input, i, state, &c.walls, &mut f, &mut t);
        }
        (*fi, *ti) = (f, t);
        i += 1;
    }
    #[cfg(target_arch = "x86_64")]
    if FOUR {
        // SAFETY: an __m256d is four f64 lanes.
        let lanes: [f64; 4] = std::mem::transmute(largest);
        m = lanes.into_iter().fold(m, f64::max);
    }
    m
}

/// Verlet's last half kick of the spins: ω ← ω + Δt/2 · τ/I.
pub(super) fn friction_spin_kick(bodies: &mut Bodies, dt: f64, workers: &Workers) {
    let n = bodies.len();
    let w = SharedMut::new(&mut bodies.angular_velocity);
    let (torque, inv, fixed) = (&bodies.torque, &bodies.inverse_inertia, &bodies.fixed);
    workers.run_bodies(n, STEP_CHUNK, |c| {
        for i in c * STEP_CHUNK..((c + 1) * STEP_CHUNK).min(n) {
            if !fixed[i] {
                // SAFETY: one body per iteration.
                integrate::half_kick(unsafe { w.at(i) }, torque[i], 0.5 * dt * inv[i]);
            }
        }
    });
}

impl Pipeline {
    /// Where the frictionless body pass about to run writes its wall
    /// entries' energies (one per entry of `world.wall_contacts`), or null
    /// when it does not tally ([`Pipeline::wall_tallying`]); the last body
    /// pass decides whether the tally describes the state.
    pub(crate) fn wall_tally_target(&mut self, world: &World) -> SharedMut<f64> {
        let on = self.wall_tallying && world.friction.is_none();
        self.wall_tally_valid = on;
        if on {
            self.wall_energy.resize(world.wall_contacts.key.len(), 0.0);
            SharedMut::new(&mut self.wall_energy)
        } else {
            SharedMut(std::ptr::null_mut())
        }
    }

    /// The pair forces of this step and, fused, Verlet's first half of the
    /// next: each block's bodies are kicked, drifted and given their
    /// per-body forces as soon as their pair forces are complete
    /// (`contacts::run_blocks_then`), by the worker that forced them. One
    /// hand-off between the workers per step instead of two. Returns the
    /// largest squared displacement since the last list build, m².
    pub(crate) fn pair_forces_then_advance(&mut self, world: &mut World, workers: &Workers) -> f64 {
        let n = world.bodies.len();
        assert!(
            self.reference.len() == n
                && world.bodies.mass.len() == n
                && world.bodies.fixed.len() == n
                && world.bodies.force.len() == n
        );
        if world.friction.is_some() {
            world.bodies.torque.resize(n, [0.0; 3]);
        }
        let wall_energy = self.wall_tally_target(world);
        let tally = !wall_energy.0.is_null();
        let f = SharedMut::new(&mut world.bodies.force);
        let torque = SharedMut::new(&mut world.bodies.torque);
        let spin = SharedMut::new(&mut world.bodies.angular_velocity);
        let ctx = AdvanceContext {
            x: SharedMut::new(&mut world.bodies.position),
            v: SharedMut::new(&mut world.bodies.velocity),
            f,
            walls: world.wall_contacts.shared(),
            bodies: &world.bodies,
            surfaces: &world.surfaces,
            laws: &world.laws,
            gravity: world.gravity,
            reference: &self.reference,
            dt: world.dt,
            // This step's closing half kick, not applied yet.
            pending: true,
            spin,
            torque,
            friction: world.friction.as_ref(),
            // The next step's forces.
            step: world.steps_done + 2,
            wall_energy,
        };
        // SAFETY (the follow-ups): each block's bodies lo..hi are given
        // once, to one worker, when their forces (and torques) are complete
        // and no block still reads them (run_blocks_then); lengths asserted.
        let follow = |lo: usize, hi: usize| unsafe {
            if tally {
                verlet_chunk::<true>(&ctx, lo, hi)
            } else {
                verlet_chunk::<false>(&ctx, lo, hi)
            }
        };
        let follow_friction = |lo: usize, hi: usize| unsafe { verlet_chunk_friction(&ctx, lo, hi) };
        if let Some(table) = world.friction.as_ref() {
            // SAFETY: `f` and `torque` hold one entry per body; only the
            // force loop and the follow-up touch them, under the blocks'
            // rule.
            return unsafe {
                friction::add_pair_forces_then(
                    &friction::PairForceInput {
                        bodies: &world.bodies,
                        ghosts: &world.ghosts,
                        list: &world.list,
                        laws: &world.laws,
                        friction: table,
                        dt: world.dt,
                    },
                    &mut world.histories,
                    &mut world.shear,
                    (f, torque),
                    workers,
                    Some(&follow_friction),
                    None,
                    EntryTerms::NONE,
                )
            };
        }
        // SAFETY: as above, for the forces.
        unsafe {
            contacts::add_pair_forces_then(
                &world.bodies,
                &world.ghosts,
                &world.list,
                &mut world.histories,
                &world.laws,
                f,
                workers,
                Some(&follow),
                None,
                EntryTerms::NONE,
            )
        }
    }

    /// [`Self::pair_forces_then_advance`] with the halo exchange in flight
    /// during the pairs that need none of its state
    /// ([`StepHooks::halo_during`], `dynamics::halo_split`): the same
    /// additions in the same order, the same bits. Frictionless, the list
    /// sequential ([`Pipeline::halo_overlaps`]).
    pub(crate) fn pair_forces_around_halo_then_advance(
        &mut self,
        world: &mut World,
        workers: &Workers,
        hooks: &mut impl StepHooks,
    ) -> f64 {
        let Some(mut split) = self.halo_split.take() else {
            hooks.halo(world);
            self.ghosts(world);
            return self.pair_forces_then_advance(world, workers);
        };
        let wall_energy = self.wall_tally_target(world);
        let reference = &self.reference[..];
        let mut moved2 = 0.0f64;
        hooks.halo_during(world, &mut |world, progress| {
            // SAFETY: as `pair_forces_then_advance`'s: the split's first
            // part moves a body only once no row reads it.
            moved2 = with_fused(world, reference, wall_energy, |rows, follow| unsafe {
                split.early(rows, follow, progress)
            });
        });
        // SAFETY: as above; the early part ran on this state. The pairs
        // with a stale body, then the late bodies' sums.
        let late = with_fused(world, reference, wall_energy, |rows, follow| unsafe {
            split.late_pairs(rows);
            split.late_sums(rows, follow)
        });
        self.halo_split = Some(split);
        moved2.max(late)
    }

    /// Verlet: the pending half kick of the last step (if any), the half
    /// kick and drift of this one, and the body's gravity and wall forces
    /// at its new position. Returns the largest squared displacement since
    /// the last list build, m².
    pub(crate) fn verlet_advance(&mut self, world: &mut World, workers: &Workers) -> f64 {
        let n = world.bodies.len();
        let pending = self.pending_kick;
        self.pending_kick = false;
        let wall_energy = self.wall_tally_target(world);
        let tally = !wall_energy.0.is_null();
        let spin = SharedMut::new(&mut world.bodies.angular_velocity);
        let torque = SharedMut::new(&mut world.bodies.torque);
        let ctx = AdvanceContext {
            x: SharedMut::new(&mut world.bodies.position),
            v: SharedMut::new(&mut world.bodies.velocity),
            f: SharedMut::new(&mut world.bodies.force),
            walls: world.wall_contacts.shared(),
            bodies: &world.bodies,
            surfaces: &world.surfaces,
            laws: &world.laws,
            gravity: world.gravity,
            reference: &self.reference,
            dt: world.dt,
            pending,
            spin,
            torque,
            friction: world.friction.as_ref(),
            step: world.steps_done + 1,
            wall_energy,
        };
        assert!(
            self.reference.len() == n
                && world.bodies.mass.len() == n
                && world.bodies.fixed.len() == n
        );
        // SAFETY (both calls): the ranges are disjoint ranges of bodies;
        // lengths asserted.
        let advance = |lo: usize, hi: usize| unsafe {
            if ctx.friction.is_some() {
                verlet_chunk_friction(&ctx, lo, hi)
            } else if tally {
                verlet_chunk::<true>(&ctx, lo, hi)
            } else {
                verlet_chunk::<false>(&ctx, lo, hi)
            }
        };
        let threads = workers.threads();
        let partial = if world.list.share(threads - 1, threads).map(|s| s.1) == Some(n) {
            // Each worker advances the bodies of its share of the force
            // loop: they stay in its core's cache (a maximum is exact in
            // any order: the same bits). Each share is claimed: worker 0
            // then advances the shares of the workers that have not
            // started, and the stage ends without them.
            let list = &world.list;
            let claimed: Vec<AtomicBool> = (0..threads).map(|_| AtomicBool::new(false)).collect();
            let share = |u: usize| {
                if claimed[u].swap(true, Ordering::Relaxed) {
                    return 0.0;
                }
                let started = Instant::now();
                let moved2 = list
                    .share(u, threads)
                    .map_or(0.0, |(lo, hi)| advance(lo, hi));
                list.shares
                    .record_advance(u, started.elapsed().as_nanos() as u64);
                moved2
            };
            workers.broadcast_present(|t| {
                let mut moved2 = share(t);
                if t == 0 {
                    for u in 1..threads {
                        moved2 = moved2.max(share(u));
                    }
                }
                moved2
            })
        } else {
            workers.map(n.div_ceil(STEP_CHUNK), |c| {
                advance(c * STEP_CHUNK, ((c + 1) * STEP_CHUNK).min(n))
            })
        };
        partial.into_iter().fold(0.0, f64::max)
    }
}

/// Runs `run` with the frictionless force loop of `world`'s main pairs and
/// the fused follow-up (the closing half kick of this step, the next
/// step's first half and per-body forces: [`verlet_chunk`]), as
/// [`Pipeline::pair_forces_then_advance`] sets them up.
fn with_fused(
    world: &mut World,
    reference: &[[f64; 3]],
    wall_energy: SharedMut<f64>,
    run: impl FnOnce(&Rows, contacts::FollowUp) -> f64,
) -> f64 {
    let n = world.bodies.len();
    assert!(
        reference.len() == n
            && world.bodies.mass.len() == n
            && world.bodies.fixed.len() == n
            && world.bodies.force.len() == n
    );
    let tally = !wall_energy.0.is_null();
    let f = SharedMut::new(&mut world.bodies.force);
    let ctx = AdvanceContext {
        x: SharedMut::new(&mut world.bodies.position),
        v: SharedMut::new(&mut world.bodies.velocity),
        f,
        walls: world.wall_contacts.shared(),
        bodies: &world.bodies,
        surfaces: &world.surfaces,
        laws: &world.laws,
        gravity: world.gravity,
        reference,
        dt: world.dt,
        // This step's closing half kick, not applied yet.
        pending: true,
        spin: SharedMut(std::ptr::null_mut()),
        torque: SharedMut(std::ptr::null_mut()),
        friction: None,
        // The next step's forces.
        step: world.steps_done + 2,
        wall_energy,
    };
    // SAFETY: `run` gives each body to the follow-up once, when its forces
    // are complete and no pair still reads it (`halo_split`); lengths
    // asserted.
    let follow = |lo: usize, hi: usize| unsafe {
        if tally {
            verlet_chunk::<true>(&ctx, lo, hi)
        } else {
            verlet_chunk::<false>(&ctx, lo, hi)
        }
    };
    let rows = Rows::new(
        &world.bodies,
        &world.list,
        &mut world.histories,
        &world.laws,
        f,
        None,
        EntryTerms::NONE,
    );
    run(&rows, &follow)
}

#[cfg(test)]
mod tests {
    use super::{advance_bodies, verlet_chunk, verlet_chunk_friction, AdvanceContext};
    use crate::dynamics::friction_observables::tests::scene;
    use crate::dynamics::walls;
    use crate::parallel::SharedMut;
    use crate::Simulation;

    /// The reference: the body-by-body first pass, then every body with
    /// wall entries and not fixed given its wall forces, one at a time (the
    /// loops before the four-at-a-time pass).
    ///
    /// # Safety
    /// As `verlet_chunk`.
    unsafe fn body_by_body(c: &AdvanceContext, lo: usize, hi: usize, tally: bool) -> f64 {
        let m = advance_bodies(c, lo, hi);
        let b = c.bodies;
        for i in lo..hi {
            let (s, e) = c.walls.range(i);
            if b.fixed[i] || s == e {
                continue;
            }
            let mut acc = *c.f.at(i);
            let (x, v) = (*c.x.at(i), *c.v.at(i));
            if tally {
                walls::add_wall_forces_tallied(
                    b,
                    i,
                    x,
                    v,
                    c.surfaces,
                    &c.walls,
                    c.laws,
                    &mut acc,
                    c.wall_energy,
                );
            } else {
                walls::add_wall_forces(b, i, x, v, c.surfaces, &c.walls, c.laws, &mut acc);
            }
            *c.f.at(i) = acc;
        }
        m
    }

    /// `verlet_chunk` (on AVX2: the bodies four at a time, four bodies
    /// without wall entries passed by one test) gives every position,
    /// velocity and new force, the wall entries' energies and the largest
    /// squared displacement bit for bit as the body-by-body loops (the
    /// reference), with and without the pending half kick and the wall
    /// tally, over ranges of every length modulo 4 and starts off the
    /// groups of four, with fixed bodies among them, on a frictionless run
    /// of two radii (two masses) against plane walls, with gravity along
    /// −z and a skewed one, and a body whose position is not finite (its
    /// displacement NaN: the maximum ignores it in both).
    #[test]
    fn bodies_four_at_a_time_equal_the_body_loop_bit_for_bit() {
        let mut setup = scene();
        setup.friction = None;
        let mut sim = Simulation::new(setup, 1).unwrap();
        // The bottom layer on the floor by then.
        sim.step(200);
        let n = sim.world.bodies.len();
        assert!(n > 100, "{n}");
        for k in [5, 6, 41, 100] {
            sim.world.bodies.fixed[k] = true;
        }
        let (mut moved, mut walled) = (0, 0);
        let entries = sim.world.wall_contacts.key.len();
        for (gravity, nan) in [([0.0, 0.0, -9.81], false), ([0.3, -1.7, -9.81], true)] {
            let mut position = sim.world.bodies.position.clone();
            if nan {
                position[18][1] = f64::NAN;
            }
            let ranges = [
                (0, n),
                (1, n),
                (2, n - 1),
                (3, n - 2),
                (7, 8),
                (9, 21),
                (40, 44),
            ];
            for ((lo, hi), pending) in ranges.into_iter().flat_map(|r| [(r, false), (r, true)]) {
                for tally in [false, true] {
                    let mut out = Vec::new();
                    for reference in [true, false] {
                        let w = &mut sim.world;
                        let mut x = position.clone();
                        let mut v = w.bodies.velocity.clone();
                        let mut f = w.bodies.force.clone();
                        let mut energy = vec![0.0f64; entries];
                        let mut torque = w.bodies.torque.clone();
                        let mut spin = w.bodies.angular_velocity.clone();
                        let ctx = AdvanceContext {
                            x: SharedMut::new(&mut x),
                            v: SharedMut::new(&mut v),
                            f: SharedMut::new(&mut f),
                            walls: w.wall_contacts.shared(),
                            bodies: &w.bodies,
                            surfaces: &w.surfaces,
                            laws: &w.laws,
                            gravity,
                            reference: &sim.pipeline.reference,
                            dt: w.dt,
                            pending,
                            spin: SharedMut::new(&mut spin),
                            torque: SharedMut::new(&mut torque),
                            friction: None,
                            step: w.steps_done + 1,
                            wall_energy: if tally {
                                SharedMut::new(&mut energy)
                            } else {
                                SharedMut(std::ptr::null_mut())
                            },
                        };
                        // SAFETY: lo..hi within the bodies, whose arrays
                        // are this test's copies; one energy per entry.
                        let m = unsafe {
                            match (reference, tally) {
                                (true, _) => body_by_body(&ctx, lo, hi, tally),
                                (false, true) => verlet_chunk::<true>(&ctx, lo, hi),
                                (false, false) => verlet_chunk::<false>(&ctx, lo, hi),
                            }
                        };
                        let bits: Vec<u64> = [&x, &v, &f]
                            .iter()
                            .flat_map(|a| a.iter().flatten().map(|q| q.to_bits()))
                            .chain(energy.iter().map(|e| e.to_bits()))
                            .chain([m.to_bits()])
                            .collect();
                        let loaded = energy.iter().filter(|&&e| e > 0.0).count();
                        out.push((bits, m, loaded));
                    }
                    let what = format!("{lo}..{hi}, pending {pending}, tally {tally}");
                    assert!(out[0].0 == out[1].0, "{what}");
                    if out[0].1 > 0.0 {
                        moved += 1;
                    }
                    walled += out[0].2;
                }
            }
        }
        // The displacements and the wall contacts were there to compare.
        assert!(moved > 40, "{moved}");
        assert!(walled > 100, "{walled}");
    }

    /// The friction body pass (`verlet_chunk_friction`: on AVX2 the
    /// bodies four at a time with their largest squared displacement kept
    /// lane by lane, four bodies without wall entries passed by one test,
    /// and the plane laws without dispatch when they are Hertz–Mindlin)
    /// gives every position, velocity, spin, force, torque, wall spring
    /// and wall load and the largest squared displacement bit for bit as
    /// the reference: body by body, the scalar kicks and drift
    /// (`integrate`), then each free body with wall entries through
    /// `add_plane_forces::<false>` (the laws dispatched). With and without
    /// the pending kick, over ranges of every length modulo 4 and starts
    /// off the groups of four, fixed bodies among them, a body whose
    /// position is not finite; on the damped, rolling scene (dispatched)
    /// and on an undamped Hertz–Mindlin one without rolling (the laws
    /// stated).
    #[test]
    fn friction_body_pass_equals_the_body_loop_bit_for_bit() {
        use dembound_physics::contact::{ContactModel, NormalLaw};

        use crate::dynamics::{friction, integrate};
        for hertz_mindlin in [false, true] {
            let mut setup = scene();
            if hertz_mindlin {
                setup.contact = ContactModel::elastic(NormalLaw::Hertz);
                let f = setup.friction.as_mut().unwrap();
                f.model.rolling_friction = 0.0;
                f.walls = vec![Some((0.5, 0.0)); 6];
            }
            let mut sim = Simulation::new(setup, 1).unwrap();
            sim.step(200);
            let n = sim.world.bodies.len();
            assert!(n > 100, "{n}");
            for k in [5, 6, 41, 100] {
                sim.world.bodies.fixed[k] = true;
            }
            let table = sim.world.friction.clone().unwrap();
            assert_eq!(friction::planes_are_hertz_mindlin(&table), hertz_mindlin);
            let (mut moved, mut walled) = (0, 0);
            let mut position = sim.world.bodies.position.clone();
            position[18][1] = f64::NAN;
            let ranges = [
                (0, n),
                (1, n),
                (2, n - 1),
                (3, n - 2),
                (7, 8),
                (9, 21),
                (40, 44),
            ];
            for ((lo, hi), pending) in ranges.into_iter().flat_map(|r| [(r, false), (r, true)]) {
                let mut out = Vec::new();
                for reference in [true, false] {
                    let w = &sim.world;
                    let mut x = position.clone();
                    let mut v = w.bodies.velocity.clone();
                    let mut f = w.bodies.force.clone();
                    let mut torque = w.bodies.torque.clone();
                    let mut spin = w.bodies.angular_velocity.clone();
                    let mut walls = w.wall_contacts.clone();
                    let ctx = AdvanceContext {
                        x: SharedMut::new(&mut x),
                        v: SharedMut::new(&mut v),
                        f: SharedMut::new(&mut f),
                        walls: walls.shared(),
                        bodies: &w.bodies,
                        surfaces: &w.surfaces,
                        laws: &w.laws,
                        gravity: w.gravity,
                        reference: &sim.pipeline.reference,
                        dt: w.dt,
                        pending,
                        spin: SharedMut::new(&mut spin),
                        torque: SharedMut::new(&mut torque),
                        friction: Some(&table),
                        step: w.steps_done + 2,
                        wall_energy: SharedMut(std::ptr::null_mut()),
                    };
                    let b = &w.bodies;
                    // SAFETY: lo..hi within the bodies, whose arrays are
                    // this test's copies.
                    let m = unsafe {
                        if reference {
                            let input = friction::BodyForceInput {
                                bodies: b,
                                surfaces: ctx.surfaces,
                                laws: ctx.laws,
                                friction: &table,
                                gravity: ctx.gravity,
                                step: ctx.step,
                                dt: ctx.dt,
                            };
                            let half_dt = 0.5 * ctx.dt;
                            let mut m = 0.0f64;
                            for i in lo..hi {
                                if b.fixed[i] {
                                    *ctx.f.at(i) = [0.0; 3];
                                    *ctx.torque.at(i) = [0.0; 3];
                                    continue;
                                }
                                let (xi, vi, wi) = (ctx.x.at(i), ctx.v.at(i), ctx.spin.at(i));
                                let (fi, ti) = (*ctx.f.at(i), *ctx.torque.at(i));
                                let dtfm = half_dt / b.mass[i];
                                let dtfi = half_dt * b.inverse_inertia[i];
                                if pending {
                                    integrate::half_kick(vi, fi, dtfm);
                                    integrate::half_kick(wi, ti, dtfi);
                                }
                                integrate::half_kick(vi, fi, dtfm);
                                integrate::half_kick(wi, ti, dtfi);
                                integrate::drift(xi, *vi, ctx.dt);
                                m = m.max(integrate::displacement2(*xi, ctx.reference[i]));
                                *ctx.f.at(i) = friction::gravity_force(&input, i);
                                *ctx.torque.at(i) = [0.0; 3];
                            }
                            for i in lo..hi {
                                let (s, e) = ctx.walls.range(i);
                                if b.fixed[i] || s == e {
                                    continue;
                                }
                                let state = (*ctx.x.at(i), *ctx.v.at(i), *ctx.spin.at(i));
                                let (fi, ti) = (ctx.f.at(i), ctx.torque.at(i));
                                friction::add_plane_forces::<false>(
                                    &input, i, state, &ctx.walls, fi, ti,
                                );
                            }
                            m
                        } else {
                            verlet_chunk_friction(&ctx, lo, hi)
                        }
                    };
                    let touching = walls.touching.iter().filter(|&&t| t).count();
                    let bits: Vec<u64> =
                        [&x, &v, &spin, &f, &torque]
                            .iter()
                            .flat_map(|a| a.iter().flatten().map(|q| q.to_bits()))
                            .chain(walls.shear.iter().flat_map(|s| s.shear.map(f64::to_bits)))
                            .chain(walls.load.iter().flat_map(|l| {
                                l.force.into_iter().chain(l.torque).map(f64::to_bits)
                            }))
                            .chain([m.to_bits(), touching as u64])
                            .collect();
                    out.push((bits, m, touching));
                }
                let what = format!("{lo}..{hi}, pending {pending}, hertz_mindlin {hertz_mindlin}");
                assert!(out[0].0 == out[1].0, "{what}");
                if out[0].1 > 0.0 {
                    moved += 1;
                }
                walled += out[0].2;
            }
            // The displacements and the wall contacts were there to compare.
            assert!(moved > 10, "{moved}");
            assert!(walled > 100, "{walled}");
        }
    }
}
