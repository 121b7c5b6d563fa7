//! Stage "observe" for the collision log: every tracked couple (pairs
//! and sphere–wall) advanced at the end of the step, completed contacts
//! logged in a fixed order.

use super::{Pipeline, World};
use crate::bodies::NO_GROUP;
use crate::dynamics::collisions::{Collision, Motion, Partner, Track};
use crate::dynamics::contacts::{self, extended};
use crate::dynamics::friction;

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

impl Pipeline {
    /// Stage "observe": the collision log at the end of the step.
    pub fn observe(&mut self, world: &mut World) {
        let t = world.time();
        let Some(tracks) = world.tracks.as_mut() else {
            return;
        };
        let dt = world.dt;
        let bodies = &world.bodies;
        let n = bodies.len();
        let laws = &world.laws;
        let histories = &world.histories;
        let spins = &bodies.angular_velocity[..];
        let spin = |k: usize| spins.get(k).copied().unwrap_or([0.0; 3]);
        let mut log = Vec::new();
        // Entry k of the main rows (`extra` false) or of the extra pairs.
        let mut visit = |i: usize, j_ext: usize, track: &mut Track, k: usize, extra: bool| {
            let (xj, vj, owner) = extended(bodies, &world.ghosts, j_ext);
            let g = contacts::separation(
                bodies.position[i],
                bodies.velocity[i],
                bodies.radius[i],
                xj,
                vj,
                bodies.radius[owner],
            );
            let vi = bodies.velocity[i];
            let motion = Motion {
                tangential: friction::tangential(
                    [vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]],
                    g.normal,
                ),
                spin_i: spin(i),
                spin_j: spin(owner),
            };
            // Almost every listed pair: apart before and after the step.
            if track.stays_apart(g.overlap) {
                track.advance_apart(g.overlap, g.overlap_rate, motion);
                return;
            }
            let law = laws.pair(bodies, i, owner);
            let history = if extra {
                histories.extra(k)
            } else {
                histories.main(k)
            };
            if let Some((c, before, after)) =
                track.advance_with_motion(t, dt, g.overlap, g.overlap_rate, motion, |h, r| {
                    law.force(h, r, history)
                })
            {
                let (a, b) = (bodies.id[i] as usize, bodies.id[owner] as usize);
                let (i, j) = collision_pair(a, bodies.group[i], b, bodies.group[owner]);
                let (vt_in, vt_out) = Motion::tangential_pair(&before, &after);
                // The log's sphere i is the engine's owner, not i: spins swap.
                let swap = i != a;
                let pick =
                    |m: &Motion, first: bool| if first != swap { m.spin_i } else { m.spin_j };
                log.push(Collision {
                    i,
                    j,
                    t_start: c.t_start,
                    t_end: c.t_end,
                    duration: c.t_end - c.t_start,
                    max_overlap: c.max_overlap,
                    max_normal_force: c.max_force,
                    impact_normal_velocity: c.impact,
                    rebound_normal_velocity: c.rebound,
                    impact_tangential_velocity: vt_in,
                    rebound_tangential_velocity: vt_out,
                    impact_spin_i: pick(&before, true),
                    rebound_spin_i: pick(&after, true),
                    impact_spin_j: pick(&before, false),
                    rebound_spin_j: pick(&after, false),
                    triangle: None,
                });
            }
        };
        let list = &world.list;
        for i in 0..n {
            let (s, e) = (list.start[i] as usize, list.start[i + 1] as usize);
            for (k, (&j, track)) in list.j[s..e].iter().zip(&mut tracks.main[s..e]).enumerate() {
                visit(i, j as usize, track, s + k, false);
            }
        }
        for (k, (&(i, j), track)) in list.extra.iter().zip(&mut tracks.extra).enumerate() {
            visit(i as usize, j as usize, track, k, true);
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
                        let (vt_in, vt_out) = Motion::tangential_pair(&before, &after);
                        log.push(Collision {
                            i: bodies.id[i] as usize,
                            j: Partner::Wall(surface.file_index()),
                            t_start: c.t_start,
                            t_end: c.t_end,
                            duration: c.t_end - c.t_start,
                            max_overlap: c.max_overlap,
                            max_normal_force: c.max_force,
                            impact_normal_velocity: c.impact,
                            rebound_normal_velocity: c.rebound,
                            impact_tangential_velocity: vt_in,
                            rebound_tangential_velocity: vt_out,
                            impact_spin_i: before.spin_i,
                            rebound_spin_i: after.spin_i,
                            impact_spin_j: [0.0; 3],
                            rebound_spin_j: [0.0; 3],
                            triangle: surface.mesh().and_then(|m| {
                                // A moving mesh: the centre in its
                                // reference placement.
                                let x = bodies.position[i];
                                let x = surface.moving().map_or(x, |s| s.unplace(x));
                                m.triangle_of(key.element, x, bodies.radius[i])
                            }),
                        });
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
    }
}
