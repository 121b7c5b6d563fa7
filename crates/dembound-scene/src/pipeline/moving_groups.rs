//! Moving groups of fixed spheres (issue 27 item 1): a `[[particles]]`
//! group with `fixed = true` and `motion`/`oscillation`, or a
//! `boundary_particles` wall with them, moves as one rigid body (a drum
//! lined with boundary spheres, a blade or a plate built of spheres).
//!
//! **The pose** is that of `walls::motion`: sphere k, at X_k at t = 0
//! (its position as the scene gives it), is at x_k(t) = c(t) + R(t)(X_k −
//! c₀), computed from X_k at every step (no accumulated drift), with the
//! velocity of the rigid body there, v_k = ḋ + ω × (x_k − c), and its
//! spin ω. The pair contact reads both (`friction::pairs::side`), so the
//! normal damping, the tangential spring and friction and the rolling
//! resistance see the surface's velocity at the contact point,
//! v_k + ω × (p − x_k). The spheres are placed where the walls are
//! ([`World::place_walls`]), at the time of the force evaluation that
//! follows; Verlet's fused step (which places the walls of step n + 2
//! before the pair forces of step n + 1) is not taken by scenes with a
//! moving group (`Pipeline::step`).
//!
//! **The skin**: a listed pair of a free sphere and a moving one closes
//! in by the free sphere's displacement plus the moving one's; the
//! moving sphere's since the list build is bounded as a wall's
//! (`WallMotion::displacement_bound`) with the reach max |X_k − c₀|,
//! which the rigid motion keeps (|x_k − c(t)| = |X_k − c₀|), and it is
//! taken off the free spheres' budget as a wall's
//! ([`World::rebuild_budget`]).
//!
//! **The work.** The power the group puts into the spheres it touches is
//! what the contacts take out of it: a contact's force F_k and torque τ_k
//! on sphere k (about its centre) move with the rigid body's velocity
//! there, so P = −Σ_k (F_k·v_k + τ_k·ω) (the force on the free sphere is
//! −F_k at the contact point p moving at v_k + ω × (p − x_k), and the
//! rolling couple on it is minus that on k: the same sum). It is summed
//! over the group's spheres by input id after the pair forces, and
//! integrated into the walls' work W by the trapezoidal rule over each
//! step, as a moving wall's (`moving_walls`).
//!
//! **Under MPI** (`comm::distributed`) every rank places every copy of a
//! group's spheres it holds, owned or halo, from the step number and the
//! sphere's input id alone (X_k is kept by id on every rank: a sphere
//! that migrates carries no motion state of its own, and the halo copies
//! need no exchange). A pair of a free sphere with a group's sphere is
//! listed only on the rank owning the free sphere (two bodies flagged
//! fixed, a halo copy being one, are never paired), so each rank's copies
//! hold the forces of its own pairs: the power, the work and the group's
//! force and torque are each rank's share, summed over the ranks (in
//! another order on another rank count: equal to round-off).
//!
//! No periodic axis (the spheres are not carried across).

use std::ops::Range;

use super::moving_walls::MovingWalls;
use super::{WallKind, World};
use crate::walls::motion::{WallMotion, WallState};

/// One moving group of fixed spheres.
#[derive(Debug, Clone)]
pub struct GroupDrive {
    /// The scene-file key that gave it (`particles[K]`, `wall[K]`).
    pub key: String,
    /// The input ids of its spheres.
    pub ids: Range<u32>,
    /// The boundary-particle wall it is (file order), if it is one: its
    /// torque point moves with it.
    pub wall: Option<usize>,
    /// The `[[particles]]` entry it is (file order), if it is one.
    pub particles: Option<usize>,
    pub motion: WallMotion,
    /// X_k: each sphere's position at t = 0, by id − `ids.start`, m.
    pub reference: Vec<[f64; 3]>,
    /// max |X_k − c₀|, m (with a relative 1e-12 for the rounding).
    pub reach: f64,
    /// The wall's torque point at t = 0 (`WallKind::Particles`), m.
    pub torque_point: [f64; 3],
}

impl GroupDrive {
    /// The drive of the spheres `ids` whose positions at t = 0 are
    /// `reference` (id order).
    pub fn new(
        key: String,
        ids: Range<u32>,
        (wall, particles): (Option<usize>, Option<usize>),
        motion: WallMotion,
        reference: Vec<[f64; 3]>,
        torque_point: [f64; 3],
    ) -> Self {
        let c = motion.center;
        let reach = reference
            .iter()
            .map(|x| crate::limits::norm([x[0] - c[0], x[1] - c[1], x[2] - c[2]]))
            .fold(0.0, f64::max)
            * (1.0 + 1e-12);
        Self {
            key,
            ids,
            wall,
            particles,
            motion,
            reference,
            reach,
            torque_point,
        }
    }
}

/// The moving walls with the groups `groups` added (`None` when nothing
/// moves).
pub(crate) fn with_groups(
    moving: Option<Box<MovingWalls>>,
    groups: Vec<GroupDrive>,
) -> Option<Box<MovingWalls>> {
    if groups.is_empty() {
        return moving;
    }
    let mut m = moving.unwrap_or_else(|| {
        Box::new(MovingWalls {
            drives: Vec::new(),
            servos: Vec::new(),
            placed_step: 0,
            built_step: 0,
            work: 0.0,
            power: 0.0,
            groups: Vec::new(),
            group_power: 0.0,
        })
    });
    m.groups = groups;
    Some(m)
}

impl World {
    /// Whether a group of fixed spheres moves.
    #[inline]
    pub fn has_moving_groups(&self) -> bool {
        self.moving.as_ref().is_some_and(|m| !m.groups.is_empty())
    }

    /// Whether the sphere of input id `id` belongs to a moving group.
    pub(crate) fn in_moving_group(&self, id: u32) -> bool {
        self.moving
            .as_ref()
            .is_some_and(|m| m.groups.iter().any(|g| g.ids.contains(&id)))
    }

    /// Places the moving groups' spheres at time `t` (s): positions,
    /// velocities and spins of the rigid bodies (module doc), and the
    /// torque points of the moving boundary-particle walls.
    pub(crate) fn place_groups(&mut self, t: f64) {
        let Some(m) = self.moving.as_ref() else {
            return;
        };
        if m.groups.is_empty() {
            return;
        }
        let states: Vec<WallState> = m.groups.iter().map(|g| g.motion.state(t)).collect();
        let b = &mut self.bodies;
        let spins = b.angular_velocity.len() == b.len();
        for i in 0..b.len() {
            if !b.fixed[i] {
                continue;
            }
            let id = b.id[i];
            let Some((g, s)) = m
                .groups
                .iter()
                .zip(&states)
                .find(|(g, _)| g.ids.contains(&id))
            else {
                continue;
            };
            let x = s.place(g.reference[(id - g.ids.start) as usize]);
            b.position[i] = x;
            b.velocity[i] = s.velocity_at(x);
            if spins {
                b.angular_velocity[i] = s.spin;
            }
        }
        for (g, s) in m.groups.iter().zip(&states) {
            if let Some(WallKind::Particles { torque_point }) =
                g.wall.and_then(|w| self.walls.get_mut(w))
            {
                *torque_point = s.place(g.torque_point);
            }
        }
    }

    /// The largest displacement of a moving group's sphere between times
    /// `from` and `to` (s), m (module doc).
    pub(crate) fn groups_moved(&self, from: f64, to: f64) -> f64 {
        self.moving.as_ref().map_or(0.0, |m| {
            m.groups
                .iter()
                .map(|g| g.motion.displacement_bound(from, to, g.reach))
                .fold(0.0, f64::max)
        })
    }

    /// The power the moving groups put into the spheres they touch, from
    /// the forces and torques of the last pair forces, W (module doc):
    /// their spheres (every copy this process holds) by input id.
    pub fn group_power(&self) -> f64 {
        let Some(m) = self.moving.as_ref() else {
            return 0.0;
        };
        if m.groups.is_empty() {
            return 0.0;
        }
        let b = &self.bodies;
        let torques = b.torque.len() == b.len() && b.angular_velocity.len() == b.len();
        let mut terms: Vec<(u32, usize)> = (0..b.len())
            .filter(|&i| b.fixed[i] && m.groups.iter().any(|g| g.ids.contains(&b.id[i])))
            .map(|i| (b.id[i], i))
            .collect();
        terms.sort_unstable();
        let mut p = 0.0;
        for (_, i) in terms {
            let (f, v) = (b.force[i], b.velocity[i]);
            p -= f[0] * v[0] + f[1] * v[1] + f[2] * v[2];
            if torques {
                let (t, w) = (b.torque[i], b.angular_velocity[i]);
                p -= t[0] * w[0] + t[1] * w[1] + t[2] * w[2];
            }
        }
        p
    }

    /// After the pair forces at the groups' pose: their work over the
    /// step just made (`integrate`: trapezoidal rule) or, at the start,
    /// their power only.
    pub(crate) fn account_group_work(&mut self, integrate: bool) {
        if !self.has_moving_groups() {
            return;
        }
        let p = self.group_power();
        let dt = self.dt;
        if let Some(m) = self.moving.as_mut() {
            if integrate {
                m.work += 0.5 * dt * (m.group_power + p);
            }
            m.group_power = p;
        }
    }
}

/// The moving groups of `setup` (its `group_motions`, then each
/// boundary-particle wall with a motion, file order), checked: fixed
/// spheres in range, no periodic axis. `kinds`: the walls as built (the
/// torque points at t = 0).
pub(crate) fn drives(
    setup: &crate::setup::SceneSetup,
    kinds: &[WallKind],
) -> Result<Vec<GroupDrive>, crate::error::SceneError> {
    use crate::error::SceneError;
    let mut out = Vec::new();
    let walls = setup.wall_motions.iter().enumerate().filter_map(|(w, m)| {
        let m = (*m)?;
        let wall = setup.walls.get(w).filter(|s| s.is_particles())?;
        Some((format!("wall[{w}]"), wall.bodies()?, (Some(w), None), m))
    });
    let groups = setup.group_motions.iter().map(|g| {
        let key = format!("particles[{}]", g.group);
        (key, g.spheres.clone(), (None, Some(g.group)), g.motion)
    });
    for (key, spheres, wall, motion) in groups.chain(walls) {
        let Some(list) = setup.spheres.range(spheres.clone()) else {
            return Err(SceneError::invalid(
                format!("{key}.motion"),
                format!("spheres {spheres:?}"),
                format!("input indices below {}", setup.spheres.len()),
            ));
        };
        if let Some(k) = list.clone().position(|s| !s.fixed) {
            return Err(SceneError::invalid(
                format!("{key}.motion"),
                format!(
                    "given for a group with a free sphere (input index {})",
                    spheres.start + k
                ),
                "a group of fixed spheres (fixed = true)",
            ));
        }
        if let Some(a) = setup.domain.periodic.iter().position(|&p| p) {
            return Err(SceneError::invalid(
                format!("{key}.motion"),
                format!("given in a domain periodic along axis {a}"),
                "a moving group of fixed spheres in a domain with no periodic axis",
            ));
        }
        if let Some(other) = out.iter().find(|g: &&GroupDrive| {
            (g.ids.start as usize) < spheres.end && spheres.start < g.ids.end as usize
        }) {
            return Err(SceneError::invalid(
                format!("{key}.motion"),
                format!("spheres {spheres:?}, shared with {}", other.key),
                "groups that share no sphere",
            ));
        }
        let torque_point = match wall.0.and_then(|w| kinds.get(w)) {
            Some(WallKind::Particles { torque_point }) => *torque_point,
            _ => motion.center,
        };
        out.push(GroupDrive::new(
            key,
            spheres.start as u32..spheres.end as u32,
            wall,
            motion,
            list.map(|s| s.position).collect(),
            torque_point,
        ));
    }
    Ok(out)
}

/// A moving `[[particles]]` group at an observation (issue 27 item 3):
/// its motion, as a moving wall's (`wall_states`), and the load the
/// spheres put on it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GroupMotionState {
    /// The `[[particles]]` entry, file order.
    pub group: usize,
    /// The displacement of the motion's centre since t = 0, d(t), m.
    pub position: [f64; 3],
    /// The angle turned about ω̂ since t = 0, rad.
    pub angle: f64,
    /// m/s.
    pub velocity: [f64; 3],
    /// rad/s.
    pub angular_velocity: [f64; 3],
    /// The force the spheres put on the group in the last force stage
    /// (the sum over its spheres), N.
    pub force: [f64; 3],
    /// Their torque about `torque_point`, Σ (x_k − c) × f_k + τ_k, N m.
    pub torque: [f64; 3],
    /// The motion's centre now, c(t), m.
    pub torque_point: [f64; 3],
}

impl World {
    /// Each moving `[[particles]]` group's motion and load now, file
    /// order (empty when none moves): its spheres summed by input id.
    pub fn group_motion_states(&self) -> Vec<GroupMotionState> {
        let Some(m) = self.moving.as_ref() else {
            return Vec::new();
        };
        let t = self.time();
        let b = &self.bodies;
        let by_id = if m.groups.iter().any(|g| g.particles.is_some()) {
            b.index_of_ids()
        } else {
            return Vec::new();
        };
        let torques = b.torque.len() == b.len();
        m.groups
            .iter()
            .filter_map(|g| {
                let group = g.particles?;
                let s = g.motion.state(t);
                let mut load = crate::walls::WallLoad::default();
                for id in g.ids.clone() {
                    let Some(&i) = by_id.get(id as usize) else {
                        continue;
                    };
                    if i == crate::bodies::REMOVED {
                        continue;
                    }
                    let i = i as usize;
                    let tau = if torques { b.torque[i] } else { [0.0; 3] };
                    super::wall_loads::add_particle_load(
                        &mut load,
                        b.position[i],
                        s.center,
                        b.force[i],
                        tau,
                    );
                }
                Some(GroupMotionState {
                    group,
                    position: [0, 1, 2].map(|a| s.center[a] - s.center0[a]),
                    angle: g.motion.angle(t),
                    velocity: s.velocity,
                    angular_velocity: s.spin,
                    force: load.force,
                    torque: load.torque,
                    torque_point: s.center,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::{DomainSetup, GroupMotion, RunLength, SceneSetup, SphereInit, TimeStep};
    use dembound_physics::contact::{ContactModel, NormalLaw};

    fn setup(fixed: [bool; 3]) -> SceneSetup {
        let mut s = SceneSetup::new(
            DomainSetup {
                lower: [-1.0; 3],
                upper: [1.0; 3],
                periodic: [false; 3],
            },
            ContactModel::elastic(NormalLaw::Hertz),
            TimeStep::Fixed(1e-6),
            RunLength::Steps(1),
        );
        for (k, f) in fixed.into_iter().enumerate() {
            s.spheres.push(SphereInit {
                position: [0.1 * k as f64, 0.3, 0.0],
                velocity: [0.0; 3],
                radius: 0.01,
                material: 0,
                fixed: f,
                group: None,
            });
        }
        s
    }

    fn turning(group: usize, spheres: Range<usize>) -> GroupMotion {
        GroupMotion {
            group,
            spheres,
            motion: WallMotion {
                velocity: [0.0; 3],
                angular_velocity: [0.0, 0.0, 1.0],
                center: [0.0; 3],
                start: 0.0,
                end: f64::INFINITY,
                oscillation: None,
            },
        }
    }

    /// The reach is the farthest sphere from the centre (by hand:
    /// |(0.2, 0.3, 0)| = √0.13), and the drive keeps the positions.
    #[test]
    fn a_drive_reaches_its_farthest_sphere() {
        let mut s = setup([false, true, true]);
        s.group_motions.push(turning(1, 1..3));
        let d = drives(&s, &[]).unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].ids, 1..3);
        assert_eq!(d[0].particles, Some(1));
        let reach = 0.13f64.sqrt();
        assert!(
            (d[0].reach - reach).abs() <= 2e-12 * reach,
            "{}",
            d[0].reach
        );
        assert_eq!(d[0].reference[1], [0.2, 0.3, 0.0]);
    }

    /// A group with a free sphere, out of range, sharing spheres with
    /// another, or in a periodic domain is refused naming its key.
    #[test]
    fn bad_groups_are_refused_naming_the_key() {
        let mut s = setup([false, true, true]);
        s.group_motions.push(turning(0, 0..2));
        let e = drives(&s, &[]).unwrap_err().to_string();
        assert!(
            e.contains("particles[0].motion") && e.contains("free sphere"),
            "{e}"
        );
        let mut s = setup([true, true, true]);
        s.group_motions.push(turning(2, 1..5));
        let e = drives(&s, &[]).unwrap_err().to_string();
        assert!(e.contains("particles[2].motion"), "{e}");
        let mut s = setup([true, true, true]);
        s.group_motions.push(turning(1, 0..2));
        s.group_motions.push(turning(2, 1..3));
        let e = drives(&s, &[]).unwrap_err().to_string();
        assert!(
            e.contains("particles[2].motion") && e.contains("particles[1]"),
            "{e}"
        );
        let mut s = setup([true, true, true]);
        s.domain.periodic = [false, true, false];
        s.group_motions.push(turning(1, 0..3));
        let e = drives(&s, &[]).unwrap_err().to_string();
        assert!(
            e.contains("particles[1].motion") && e.contains("periodic"),
            "{e}"
        );
    }
}
