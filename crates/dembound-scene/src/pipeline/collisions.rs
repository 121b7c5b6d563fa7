//! Stage "observe" for the collision log: the tracked couples (pairs
//! and sphere–wall) advanced at the end of the step, completed contacts
//! logged in a fixed order.
//!
//! A listed pair that neither touches at the step's end nor was in
//! contact is not visited: all the log would keep for it is its overlap,
//! rate and motion at that step (what a later onset, a list build or a
//! checkpoint reads), and those are computed when read, from the bodies'
//! state at that step kept in [`LoggedStep`]: the same formulas on the
//! same inputs, so the same bits as visiting every pair every step.

use super::{Pipeline, World};
use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::collisions::{Collision, Completed, Motion, Partner, Track};
use crate::dynamics::contacts::{self, extended, PairGeometry};
use crate::dynamics::friction;
use crate::geometry::ghosts::Ghosts;

/// A pair can touch only if r² < (Rᵢ + Rⱼ)² × this: the overlap
/// (Rᵢ + Rⱼ) − fl(√r²) > 0 needs fl(√r²) < Rᵢ + Rⱼ, hence √r² < Rᵢ + Rⱼ
/// (the rounded root is monotone and Rᵢ + Rⱼ a double); the factor
/// covers the two roundings of fl(fl(s·s)·c) (2⁻⁵² each) with room:
/// the test only spares pairs the exact overlap then sees apart.
const TOUCH_MARGIN: f64 = 1.0 + 1.0e-12;

/// The bodies' and ghosts' state at the end of the collision log's last
/// step, and which main entries were in contact after it.
#[derive(Debug, Clone, Default)]
pub(crate) struct LoggedStep {
    /// `World::steps_done` and `World::rebuilds` at that step.
    steps_done: u64,
    rebuilds: u64,
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    /// Empty without rotation.
    spin: Vec<[f64; 3]>,
    ghost_position: Vec<[f64; 3]>,
    ghost_velocity: Vec<[f64; 3]>,
    /// Main entry k's track was in contact after that step.
    open: Vec<bool>,
}

impl LoggedStep {
    /// This is the state of `world`'s bodies and lists at the end of step
    /// `steps_done` (no list build, no body added or removed since).
    pub(crate) fn current(&self, world: &World, steps_done: u64) -> bool {
        self.steps_done == steps_done
            && self.rebuilds == world.rebuilds
            && self.position.len() == world.bodies.len()
            && self.ghost_position.len() == world.ghosts.position.len()
            && self.open.len() == world.list.j.len()
    }

    /// Sets `track` (of main entry (i, j_ext), out of contact) to what the
    /// log left in it at that step: [`Track::advance_apart`] with the
    /// couple's overlap, rate and motion then.
    pub(crate) fn settle(
        &self,
        track: &mut Track,
        bodies: &Bodies,
        ghosts: &Ghosts,
        i: usize,
        j_ext: usize,
    ) {
        let (g, motion) = self.couple(bodies, ghosts, i, j_ext);
        track.advance_apart(g.overlap, g.overlap_rate, motion);
    }

    /// Sets the motion of `track` (of main entry (i, j_ext), in contact)
    /// to the couple's at that step: what the log stage leaves unstored
    /// while a contact goes on ([`Track::advance_listed`]).
    pub(crate) fn settle_motion(
        &self,
        track: &mut Track,
        bodies: &Bodies,
        ghosts: &Ghosts,
        i: usize,
        j_ext: usize,
    ) {
        track.set_last(self.couple(bodies, ghosts, i, j_ext).1);
    }

    /// The geometry and motion of main entry (i, j_ext) at that step.
    fn couple(
        &self,
        bodies: &Bodies,
        ghosts: &Ghosts,
        i: usize,
        j_ext: usize,
    ) -> (PairGeometry, Motion) {
        let n = self.position.len();
        let (xj, vj, owner) = if j_ext < n {
            (self.position[j_ext], self.velocity[j_ext], j_ext)
        } else {
            let g = j_ext - n;
            (
                self.ghost_position[g],
                self.ghost_velocity[g],
                ghosts.owner[g] as usize,
            )
        };
        let spin = |k: usize| self.spin.get(k).copied().unwrap_or([0.0; 3]);
        couple_state(
            (
                self.position[i],
                self.velocity[i],
                bodies.radius[i],
                spin(i),
            ),
            (xj, vj, bodies.radius[owner], spin(owner)),
        )
    }

    /// Keeps `world`'s state at the end of its current step.
    fn keep(&mut self, world: &World, open: Vec<bool>) {
        self.steps_done = world.steps_done;
        self.rebuilds = world.rebuilds;
        copy_rows(&mut self.position, &world.bodies.position);
        copy_rows(&mut self.velocity, &world.bodies.velocity);
        copy_rows(&mut self.spin, &world.bodies.angular_velocity);
        copy_rows(&mut self.ghost_position, &world.ghosts.position);
        copy_rows(&mut self.ghost_velocity, &world.ghosts.velocity);
        self.open = open;
    }
}

/// `dst` becomes a copy of `src`, 64 rows (1.5 kB) at a time: one large
/// copy would be a `rep movsb`, which instruction counts (callgrind)
/// count byte by byte; the short copies are vector loops.
fn copy_rows(dst: &mut Vec<[f64; 3]>, src: &[[f64; 3]]) {
    dst.resize(src.len(), [0.0; 3]);
    for (d, s) in dst.chunks_mut(64).zip(src.chunks(64)) {
        d.copy_from_slice(s);
    }
}

/// One side of a couple: centre (m), velocity (m/s), radius (m), spin
/// (rad/s).
type Side = ([f64; 3], [f64; 3], f64, [f64; 3]);

/// The geometry and tangential motion of a sphere pair.
#[inline(always)]
fn couple_state(a: Side, b: Side) -> (PairGeometry, Motion) {
    let (xi, vi, ri, wi) = a;
    let (xj, vj, rj, wj) = b;
    let g = contacts::separation(xi, vi, ri, xj, vj, rj);
    (g, couple_motion(vi, wi, vj, wj, g.normal))
}

/// The tangential motion of a sphere pair of velocities `vi`, `vj` (m/s)
/// and spins `wi`, `wj` (rad/s) at unit normal `normal`.
#[inline(always)]
fn couple_motion(
    vi: [f64; 3],
    wi: [f64; 3],
    vj: [f64; 3],
    wj: [f64; 3],
    normal: [f64; 3],
) -> Motion {
    Motion {
        tangential: friction::tangential([vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]], normal),
        spin_i: wi,
        spin_j: wj,
    }
}

pub(crate) fn partner_key(p: Partner) -> (u8, usize) {
    match p {
        Partner::Body(j) => (0, j),
        Partner::Wall(w) => (1, w),
        Partner::BoundaryParticle { body, .. } => (0, body),
    }
}

/// The two sides of a sphere–sphere collision, by input index a, b and
/// wall group: a boundary particle of a wall is named as the wall's
/// partner; two free (or two grouped) spheres in index order.
fn collision_pair(a: usize, group_a: u32, b: usize, group_b: u32) -> (usize, Partner) {
    match (group_a != NO_GROUP, group_b != NO_GROUP) {
        (false, true) => (
            a,
            Partner::BoundaryParticle {
                wall: group_b as usize,
                body: b,
            },
        ),
        (true, false) => (
            b,
            Partner::BoundaryParticle {
                wall: group_a as usize,
                body: a,
            },
        ),
        _ => (a.min(b), Partner::Body(a.max(b))),
    }
}

/// The log's row of a completed contact between body i and body `owner`
/// (extended index resolved), with the motion before and after it.
fn pair_collision(
    bodies: &Bodies,
    i: usize,
    owner: usize,
    c: Completed,
    before: Motion,
    after: Motion,
) -> Collision {
    let (a, b) = (bodies.id[i] as usize, bodies.id[owner] as usize);
    let (i, j) = collision_pair(a, bodies.group[i], b, bodies.group[owner]);
    // The log's sphere i is the engine's owner, not i: spins swap.
    let swap = i != a;
    let spins = |m: &Motion| match swap {
        false => [m.spin_i, m.spin_j],
        true => [m.spin_j, m.spin_i],
    };
    Collision::completed(i, j, &c, &before, &after, spins, None)
}

impl Pipeline {
    /// Stage "observe": the collision log at the end of the step.
    pub fn observe(&mut self, world: &mut World) {
        let t = world.time();
        if world.tracks.is_none() {
            return;
        }
        // The state of the last step, if it is that of these lists.
        let mut logged = world
            .tracks
            .as_mut()
            .and_then(|t| t.logged.take())
            .unwrap_or_default();
        let follows = world
            .steps_done
            .checked_sub(1)
            .is_some_and(|s| logged.current(world, s));
        let Some(tracks) = world.tracks.as_mut() else {
            return;
        };
        #[cfg(test)]
        let every_pair = tracks.every_pair;
        #[cfg(not(test))]
        let every_pair = false;
        let mut open = if follows {
            std::mem::take(&mut logged.open)
        } else {
            tracks.main.iter().map(Track::in_contact).collect()
        };
        let last = follows.then_some(&*logged);
        let dt = world.dt;
        let bodies = &world.bodies;
        let ghosts = &world.ghosts;
        let n = bodies.len();
        let laws = &world.laws;
        let histories = &world.histories;
        let spins = &bodies.angular_velocity[..];
        let spin = |k: usize| spins.get(k).copied().unwrap_or([0.0; 3]);
        let mut log = Vec::new();
        // Couple (i, j_ext) at the step's end: geometry, motion, j's body.
        let state = |i: usize, j_ext: usize| {
            let (xj, vj, owner) = extended(bodies, ghosts, j_ext);
            let (g, motion) = couple_state(
                (
                    bodies.position[i],
                    bodies.velocity[i],
                    bodies.radius[i],
                    spin(i),
                ),
                (xj, vj, bodies.radius[owner], spin(owner)),
            );
            (g, motion, owner)
        };
        // A couple not staying apart: the law, the interpolant, the row.
        let advance = |log: &mut Vec<Collision>,
                       i: usize,
                       owner: usize,
                       g: PairGeometry,
                       motion: Motion,
                       track: &mut Track,
                       history| {
            let law = laws.pair(bodies, i, owner);
            if let Some((c, before, after)) =
                track.advance_with_motion(t, dt, g.overlap, g.overlap_rate, motion, |h, r| {
                    law.force(h, r, history)
                })
            {
                log.push(pair_collision(bodies, i, owner, c, before, after));
            }
        };
        let list = &world.list;
        let (position, radius) = (&bodies.position[..n], &bodies.radius[..n]);
        for i in 0..n {
            let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
            let (xi, ri) = (position[i], radius[i]);
            let row = (s..e).zip(&list.j[s..e]).zip(&mut open[s..e]);
            for ((k, &j), open_k) in row {
                let j = j as usize;
                if !*open_k && !every_pair {
                    // Neither in contact nor touching: nothing to do now
                    // (its state at this step is `LoggedStep`'s).
                    let (xj, rj) = if j < n {
                        (position[j], radius[j])
                    } else {
                        let g = j - n;
                        (ghosts.position[g], radius[ghosts.owner[g] as usize])
                    };
                    let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
                    let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                    let reach = ri + rj;
                    // False for a NaN: apart, as the overlap would say.
                    let may_touch = r2 < reach * reach * TOUCH_MARGIN;
                    if !may_touch {
                        continue;
                    }
                }
                let (xj, vj, owner) = extended(bodies, ghosts, j);
                let vi = bodies.velocity[i];
                let g = contacts::separation(xi, vi, ri, xj, vj, radius[owner]);
                // The motion only where the track uses it (not while a
                // contact goes on: `Track::advance_listed`).
                let motion = || couple_motion(vi, spin(i), vj, spin(owner), g.normal);
                // Whether the track is in contact is `open`'s (the same
                // flag, dense): a couple staying apart is settled without
                // reading its track (`Track::stays_apart`).
                debug_assert!(every_pair || *open_k == tracks.main[k].in_contact());
                let in_contact = if every_pair {
                    tracks.main[k].in_contact()
                } else {
                    *open_k
                };
                let track = &mut tracks.main[k];
                if !in_contact && (g.overlap <= 0.0 || g.overlap.is_nan()) {
                    if every_pair {
                        track.advance_apart(g.overlap, g.overlap_rate, motion());
                    }
                    continue;
                }
                if every_pair {
                    advance(&mut log, i, owner, g, motion(), track, histories.main(k));
                } else {
                    if let (false, Some(last)) = (track.in_contact(), last) {
                        // An onset reads the state of the step before.
                        last.settle(track, bodies, ghosts, i, j);
                    }
                    let law = laws.pair(bodies, i, owner);
                    let history = histories.main(k);
                    if let Some((c, before, after)) =
                        track.advance_listed(t, dt, g.overlap, g.overlap_rate, motion, |h, r| {
                            law.force(h, r, history)
                        })
                    {
                        log.push(pair_collision(bodies, i, owner, c, before, after));
                    }
                }
                *open_k = track.in_contact();
            }
        }
        // The extra pairs (open contacts no longer listed): every step.
        for (k, (&(i, j), track)) in list.extra.iter().zip(&mut tracks.extra).enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (g, motion, owner) = state(i, j);
            if track.stays_apart(g.overlap) {
                track.advance_apart(g.overlap, g.overlap_rate, motion);
                continue;
            }
            advance(&mut log, i, owner, g, motion, track, histories.extra(k));
        }
        let wc = &mut world.wall_contacts;
        if wc.bodies() == n && wc.track.len() == wc.key.len() {
            let mut next = 0;
            while next < n {
                let i = next;
                // The ranges ascend with the body: eight bodies whose
                // first and last bounds are equal have no entries.
                if i + 8 <= n && wc.start[i] == wc.start[i + 8] {
                    next += 8;
                    continue;
                }
                next += 1;
                if bodies.fixed[i] {
                    continue;
                }
                for k in wc.range(i) {
                    let key = wc.key[k];
                    let surface = &world.surfaces[key.wall as usize];
                    let c = surface.contact(
                        key.element,
                        bodies.position[i],
                        bodies.velocity[i],
                        bodies.radius[i],
                    );
                    let (h, rate) = (c.overlap, c.rate);
                    let track = &mut wc.track[k];
                    // Only couples near contact are worth tracking.
                    let far = h < -world.skin;
                    if far && !track.is_known() {
                        continue;
                    }
                    let v = bodies.velocity[i];
                    let motion = Motion {
                        tangential: friction::tangential(v, c.normal),
                        spin_i: spin(i),
                        spin_j: [0.0; 3],
                    };
                    if track.stays_apart(h) {
                        if far {
                            *track = Track::default();
                        } else {
                            track.advance_apart(h, rate, motion);
                        }
                        continue;
                    }
                    let law = laws.wall(bodies, i, surface.law_slot(key.element));
                    let hist = wc.history.get(k).unwrap_or(&contacts::NO_HISTORY);
                    if let Some((c, before, after)) =
                        track.advance_with_motion(t, dt, h, rate, motion, |h, r| {
                            law.force(h, r, hist)
                        })
                    {
                        let spins = |m: &Motion| [m.spin_i, [0.0; 3]];
                        let triangle = surface.mesh().and_then(|m| {
                            // A moving mesh: the centre in its reference
                            // placement.
                            let x = bodies.position[i];
                            let x = surface.moving().map_or(x, |s| s.unplace(x));
                            m.triangle_of(key.element, x, bodies.radius[i])
                        });
                        let j = Partner::Wall(surface.file_index());
                        let row = Collision::completed(
                            bodies.id[i] as usize,
                            j,
                            &c,
                            &before,
                            &after,
                            spins,
                            triangle,
                        );
                        log.push(row);
                    }
                    if far {
                        *track = Track::default();
                    }
                }
            }
        }
        // A fixed order within the step: by pair.
        log.sort_by_key(|c| (c.i, partner_key(c.j)));
        world.collisions.extend(log);
        if !every_pair {
            logged.keep(world, open);
            if let Some(t) = world.tracks.as_mut() {
                t.logged = Some(logged);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::dynamics::friction_observables::tests::scene;
    use crate::{SceneSetup, Simulation};

    /// Everything the log has shown or would carry: the rows so far and
    /// the tracks a list build or a checkpoint saves (pairs and walls), as
    /// Debug text (NaN equals NaN).
    fn logged(sim: &Simulation) -> String {
        let c = sim.checkpoint();
        format!(
            "{:?}\n{:?}\n{:?}",
            sim.collisions(),
            c.pair_tracks,
            c.plane_tracks
        )
    }

    /// `scene()` with every sphere's velocity jittered by up to 0.2 m/s a
    /// component (xorshift, fixed seed): many impacts of every angle.
    fn jittered(mut s: SceneSetup) -> SceneSetup {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for b in &mut s.spheres {
            for v in &mut b.velocity {
                *v += 0.4 * next();
            }
        }
        s
    }

    /// The stage visits only pairs that touch or were in contact and
    /// reads the others' last state from the copy of the last step
    /// (`LoggedStep`); the reference is the path before it, every listed
    /// pair visited and stored every step (`Tracks::every_pair`). Both run
    /// the same scene: a jittered lattice of two sizes dropping in a box
    /// of six planes with Mindlin friction and rolling (spins, plane
    /// tracks), and the same frictionless and periodic along x and y
    /// (ghost pairs, extra pairs). After every step the rows logged so far
    /// and the pair and plane tracks a checkpoint carries must be the same
    /// text; midway the new path is checkpointed, restored and continued
    /// against the reference. No tolerance: the same arithmetic on the
    /// same inputs.
    #[test]
    fn touching_pairs_only_log_what_visiting_every_pair_logs() {
        let mut periodic = jittered(scene());
        periodic.friction = None;
        periodic.walls.drain(0..4);
        periodic.domain.periodic = [true, true, false];
        for (name, mut setup) in [("friction", jittered(scene())), ("periodic", periodic)] {
            setup.collisions = true;
            let mut reference = Simulation::new(setup.clone(), 1).unwrap();
            if let Some(t) = reference.world.tracks.as_mut() {
                t.every_pair = true;
            }
            let mut fast = Simulation::new(setup.clone(), 2).unwrap();
            let (steps, restart) = (600, 300);
            for step in 1..=steps {
                reference.step(1);
                fast.step(1);
                assert_eq!(logged(&fast), logged(&reference), "{name} step {step}");
                if step == restart {
                    let c = fast.checkpoint();
                    fast = Simulation::restore(setup.clone(), &c, 1).unwrap();
                }
            }
            // The run exercised the paths: many contacts logged, lists
            // rebuilt, open contacts at the restart and at the end.
            let rows = reference.collisions().len();
            assert!(rows > 500, "{name}: {rows} rows");
            assert!(reference.list_builds() > 5, "{name}");
            assert!(
                fast.checkpoint()
                    .pair_tracks
                    .iter()
                    .any(|t| t.2.in_contact()),
                "{name}"
            );
        }
    }
}
