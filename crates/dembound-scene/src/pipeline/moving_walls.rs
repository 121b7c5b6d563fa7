//! Moving walls in the step (issue 27): each moving surface is placed at
//! the time of the force evaluation that follows (`walls::motion`: the
//! pose is a function of the step number, so restarts, threads and ranks
//! see the same walls), its displacement counts in the lists' skin, and
//! the power it puts into the spheres is integrated into the work done by
//! the walls.
//!
//! **When.** Verlet evaluates the forces of step n + 1 at x(t_{n+1}) (the
//! fused form evaluates those of step n + 2 inside step n + 1); Gear5 at
//! the predicted state of t_{n+1}; the start at t_n. The walls are placed
//! at that time just before: `Pipeline::step` calls [`World::place_walls`].
//!
//! **The skin.** A list build keeps the wall elements within one skin of
//! each sphere's surface, and the lists are rebuilt when a sphere moved
//! more than half a skin: a pair of element and sphere then closed in by
//! at most a skin and an element not listed is still apart. A moving wall
//! closes in too, so the budget of the spheres is half a skin less the
//! largest displacement of any wall's surface point inside the domain
//! since the build ([`World::rebuild_budget`],
//! `WallMotion::displacement_bound`); the walls are placed before the
//! check, so a wall that moves more than half a skin in one step gets its
//! lists rebuilt at every step, at its new pose, and never misses a
//! contact.
//!
//! **The work.** The wall's power into the spheres is, per contact, the
//! force on the sphere at the contact point times the wall's velocity
//! there, plus the rolling couple times the wall's spin (the couple M_r on
//! the sphere is −M_r on the wall): P = Σ F·v_w(p) + M_r·ω. From the load
//! the force pass records per contact (F_w = −F, τ_w = −(p − c) × F − M_r
//! about the torque point c) that is P = −(F_w·v_w(c) + τ_w·ω), because
//! v_w(p) = v_w(c) + ω × (p − c) (`walls::WallLoad::of_contact`). It is
//! summed over the touching contacts by input id, and integrated by the
//! trapezoidal rule over each step, W += Δt/2 (P_n + P_{n+1}), the rule
//! under which velocity Verlet's kinetic energy changes by the work of
//! the forces it applied (to second order).

use serde::{Deserialize, Serialize};

use super::servo_walls::{ServoDrive, ServoRecord};
use super::World;
use crate::walls::motion::WallMotion;
use crate::walls::servo::Servo;
use crate::walls::Surface;

/// A moving surface: its index in `World::surfaces`, its motion and its
/// reference placement (the scene file's).
#[derive(Debug, Clone)]
pub struct WallDrive {
    pub surface: usize,
    pub motion: WallMotion,
    pub reference: Surface,
}

/// The moving walls of a world and the work they did.
#[derive(Debug, Clone)]
pub struct MovingWalls {
    pub drives: Vec<WallDrive>,
    /// The force-controlled walls (`servo_walls`).
    pub servos: Vec<ServoDrive>,
    /// The step whose time t = step Δt the walls are placed at.
    pub placed_step: u64,
    /// `placed_step` at the last list build.
    pub built_step: u64,
    /// Work done on the spheres by the walls since t = 0, J.
    pub work: f64,
    /// Power into the spheres at the last force evaluation, W.
    pub power: f64,
    /// The moving groups of fixed spheres (`moving_groups`).
    pub groups: Vec<super::moving_groups::GroupDrive>,
    /// Their power into the spheres at the last pair forces, W.
    pub group_power: f64,
}

/// What a checkpoint keeps of the moving walls (their pose is a function
/// of the step): the step of the last list build's pose, the work and
/// the last power.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MovingWallsRecord {
    pub built_step: u64,
    /// J.
    pub work: f64,
    /// W.
    pub power: f64,
    /// The servos' state, wall order (absent without: the checkpoints of
    /// prescribed motions keep their bytes).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub servos: Vec<ServoRecord>,
    /// The moving groups' power at the last pair forces, W (absent
    /// without: the checkpoints of moving walls keep their bytes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group_power: Option<f64>,
}

impl MovingWalls {
    /// The checkpoint's record.
    pub fn record(&self) -> MovingWallsRecord {
        MovingWallsRecord {
            built_step: self.built_step,
            work: self.work,
            power: self.power,
            servos: self.servos.iter().map(ServoDrive::record).collect(),
            group_power: (!self.groups.is_empty()).then_some(self.group_power),
        }
    }

    /// The drives of `motions` and `servos` (file order, `None`: fixed)
    /// for the surfaces `surfaces`; `None` when no wall moves.
    pub fn new(
        motions: &[Option<WallMotion>],
        servos: &[Option<Servo>],
        surfaces: &[Surface],
    ) -> Option<Box<MovingWalls>> {
        let drives: Vec<WallDrive> = surfaces
            .iter()
            .enumerate()
            .filter_map(|(s, surface)| {
                let motion = motions.get(surface.file_index()).copied().flatten()?;
                Some(WallDrive {
                    surface: s,
                    motion,
                    reference: surface.clone(),
                })
            })
            .collect();
        let servos = ServoDrive::all(servos, surfaces);
        (!drives.is_empty() || !servos.is_empty()).then(|| {
            Box::new(MovingWalls {
                drives,
                servos,
                placed_step: 0,
                built_step: 0,
                work: 0.0,
                power: 0.0,
                groups: Vec::new(),
                group_power: 0.0,
            })
        })
    }
}

impl World {
    /// Places every moving wall at the time of step `step` (s = step Δt).
    pub fn place_walls(&mut self, step: u64) {
        let Some(m) = self.moving.as_mut() else {
            return;
        };
        let t = step as f64 * self.dt;
        for d in &m.drives {
            self.surfaces[d.surface] = d.reference.posed(&d.motion.state(t));
        }
        for s in &mut m.servos {
            // The next step: the wall moves by Δt at the speed the last
            // force evaluation set (`servo_walls`).
            if step == m.placed_step + 1 {
                s.offset += self.dt * s.velocity;
            }
            self.surfaces[s.surface] = s.reference.posed(&s.state());
        }
        m.placed_step = step;
        self.place_groups(t);
    }

    /// Half the skin less the largest displacement of a moving wall's
    /// surface point inside the domain since the last list build, m: the
    /// spheres' budget (module doc); half the skin when no wall moves.
    pub fn rebuild_budget(&self) -> f64 {
        let half = 0.5 * self.skin;
        // An insertion event rebuilds the lists at its step (`crate::inlets`).
        if self
            .inlets
            .as_ref()
            .is_some_and(|i| i.due_at(self.steps_done + 1))
        {
            return 0.0;
        }
        let Some(m) = self.moving.as_ref() else {
            return half;
        };
        let (from, to) = (
            m.built_step as f64 * self.dt,
            m.placed_step as f64 * self.dt,
        );
        let mut moved = 0.0f64;
        for d in &m.drives {
            let c = d.motion.state(from).center;
            // The farthest corner of the domain from the centre.
            let reach = (0..8)
                .map(|k| {
                    let corner = [0, 1, 2].map(|a| {
                        if k >> a & 1 == 0 {
                            self.domain.lower[a]
                        } else {
                            self.domain.upper[a]
                        }
                    });
                    crate::limits::norm([0, 1, 2].map(|a| corner[a] - c[a]))
                })
                .fold(0.0, f64::max);
            moved = moved.max(d.motion.displacement_bound(from, to, reach));
        }
        for s in &m.servos {
            moved = moved.max((s.offset - s.built_offset).abs());
        }
        moved = moved.max(self.groups_moved(from, to));
        half - moved
    }

    /// A list build happened at the walls' present pose.
    pub(crate) fn walls_listed(&mut self) {
        if let Some(m) = self.moving.as_mut() {
            m.built_step = m.placed_step;
            for s in &mut m.servos {
                s.built_offset = s.offset;
            }
        }
    }

    /// The power the moving walls put into the free spheres this process
    /// holds, from the last force pass's loads, W (module doc): touching
    /// entries by input id, a body's in (wall, element) order.
    pub fn wall_power(&self) -> f64 {
        let Some(m) = self.moving.as_ref() else {
            return 0.0;
        };
        let (b, wc) = (&self.bodies, &self.wall_contacts);
        let mut terms: Vec<(u32, usize)> = Vec::new();
        for i in 0..b.len().min(wc.bodies()) {
            if b.fixed[i] {
                continue;
            }
            for k in wc.range(i) {
                if wc.touching[k] && self.surfaces[wc.key[k].wall as usize].moving().is_some() {
                    terms.push((b.id[i], k));
                }
            }
        }
        terms.sort_unstable();
        let _ = m;
        let mut p = 0.0;
        for (_, k) in terms {
            let surface = &self.surfaces[wc.key[k].wall as usize];
            let Some(state) = surface.moving() else {
                continue;
            };
            let load = &wc.load[k];
            let v = state.velocity_at(surface.torque_point());
            let w = state.spin;
            p -= load.force[0] * v[0] + load.force[1] * v[1] + load.force[2] * v[2];
            p -= load.torque[0] * w[0] + load.torque[1] * w[1] + load.torque[2] * w[2];
        }
        p
    }

    /// After the force evaluation at the walls' pose: the work of the step
    /// just made (`integrate`: trapezoidal rule) or, at the start, the
    /// power only.
    pub(crate) fn account_wall_work(&mut self, integrate: bool) {
        if self.moving.is_none() {
            return;
        }
        let p = self.wall_power();
        let dt = self.dt;
        if let Some(m) = self.moving.as_mut() {
            if integrate {
                m.work += 0.5 * dt * (m.power + p);
            }
            m.power = p;
        }
    }
}
