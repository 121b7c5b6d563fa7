//! Verlet's first half (the pending closing half kick, kick, drift) and
//! the per-body forces in one pass over the bodies, alone or fused into
//! the force stage block by block; the spins' closing half kick.

use std::time::Instant;

use super::{verlet_four, Pipeline, World};
use crate::bodies::Bodies;
use crate::dynamics::contacts::{self, LawTable};
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
    // Two passes, as `verlet_chunk_friction_body`: the integration and the
    // weights of all bodies, then the wall forces of the few near a wall
    // (`walls::body_force` split: the same operations in the same order,
    // the same bits). In one pass, a wall type whose contact is a call (a
    // triangle mesh's) made every body spill its registers around it:
    // +2.7 % instructions on the lattice drop of planes.
    for i in lo..hi {
        let (s, e) = c.walls.range(i);
        if *fixed.get_unchecked(i) || s == e {
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
    }
    m
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
    let mut i = lo;
    while i < hi {
        #[cfg(target_arch = "x86_64")]
        if FOUR
            && i + 4 <= hi
            && !(b.fixed[i] || b.fixed[i + 1] || b.fixed[i + 2] || b.fixed[i + 3])
        {
            for k in i..i + 4 {
                // SAFETY: bodies of this chunk (read in the second pass).
                friction::prefetch_wall_springs(k, &c.walls);
            }
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
            for d in moved2 {
                m = m.max(d);
            }
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
    for i in lo..hi {
        let (s, e) = c.walls.range(i);
        if b.fixed[i] || s == e {
            continue;
        }
        let (fi, ti) = (c.f.at(i), c.torque.at(i));
        let (mut f, mut t) = (*fi, *ti);
        let state = (*c.x.at(i), *c.v.at(i), *c.spin.at(i));
        friction::add_plane_forces(&input, i, state, &c.walls, &mut f, &mut t);
        (*fi, *ti) = (f, t);
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
            )
        }
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
            // any order: the same bits).
            let list = &world.list;
            workers.broadcast(|t| {
                let started = Instant::now();
                let moved2 = list
                    .share(t, threads)
                    .map_or(0.0, |(lo, hi)| advance(lo, hi));
                list.shares
                    .record_advance(t, started.elapsed().as_nanos() as u64);
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
