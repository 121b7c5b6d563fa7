//! Force-controlled walls in the step (issue 27 item 2, `walls::servo`):
//! after each force evaluation the push on each servo wall is summed over
//! every process from the force stage's records, as the wall loads are
//! (`wall_loads`: bodies by input id, one running sum per wall; under MPI
//! every rank merges every rank's records: the same bits on any number of
//! threads and ranks), and sets the wall's speed; the next placement
//! (`World::place_walls`, at the next step) moves it by Δt times that
//! speed. The wall's pose is its reference placement translated by s â;
//! it carries the speed it moved with over the last step, which its
//! contacts see (damping and friction) and its work counts.
//!
//! The state (s, its speed, s at the last list build) goes into
//! checkpoints ([`ServoRecord`]): a restart continues with the same bits.

use serde::{Deserialize, Serialize};

use super::wall_loads::{self, LoadRecord};
use super::World;
use crate::walls::motion::WallState;
use crate::walls::servo::Servo;
use crate::walls::{Surface, WallLoad};

/// A force-controlled surface: its index in `World::surfaces`, its
/// controller, its reference placement and its state.
#[derive(Debug, Clone)]
pub struct ServoDrive {
    pub surface: usize,
    pub servo: Servo,
    pub reference: Surface,
    /// s: the displacement along â from the reference placement, m.
    pub offset: f64,
    /// The speed along â set by the last force evaluation, m/s.
    pub velocity: f64,
    /// s at the last list build, m.
    pub built_offset: f64,
}

/// What a checkpoint keeps of a servo.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ServoRecord {
    /// m.
    pub offset: f64,
    /// m/s.
    pub velocity: f64,
    /// m.
    pub built_offset: f64,
}

impl ServoDrive {
    /// The drives of `servos` (file order, `None`: none) for the surfaces
    /// `surfaces`, at rest in their reference placement.
    pub fn all(servos: &[Option<Servo>], surfaces: &[Surface]) -> Vec<ServoDrive> {
        surfaces
            .iter()
            .enumerate()
            .filter_map(|(s, surface)| {
                let servo = servos.get(surface.file_index()).copied().flatten()?;
                Some(ServoDrive {
                    surface: s,
                    servo,
                    reference: surface.clone(),
                    offset: 0.0,
                    velocity: 0.0,
                    built_offset: 0.0,
                })
            })
            .collect()
    }

    /// The pose: translated by s â, moving at the speed of the last
    /// step.
    pub fn state(&self) -> WallState {
        let a = self.servo.axis;
        WallState {
            rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            center0: [0.0; 3],
            center: a.map(|x| x * self.offset),
            velocity: a.map(|x| x * self.velocity),
            spin: [0.0; 3],
        }
    }

    /// The checkpoint's record.
    pub fn record(&self) -> ServoRecord {
        ServoRecord {
            offset: self.offset,
            velocity: self.velocity,
            built_offset: self.built_offset,
        }
    }

    /// The wall's file index.
    pub fn file_index(&self) -> usize {
        self.reference.file_index()
    }
}

/// The servo walls' file indices (empty when there are none).
pub(crate) fn servo_file_indices(world: &World) -> Vec<usize> {
    world.moving.as_ref().map_or_else(Vec::new, |m| {
        m.servos.iter().map(ServoDrive::file_index).collect()
    })
}

/// The touching records of this process's free bodies on the servo walls
/// (`wall_loads::surface_load_records`, others dropped).
pub(crate) fn servo_load_records(world: &World, walls: &[usize]) -> Vec<LoadRecord> {
    let mut records = wall_loads::surface_load_records(world);
    records.retain(|r| walls.contains(&(r.wall as usize)));
    records
}

impl World {
    /// Whether a wall is force-controlled.
    pub fn has_servos(&self) -> bool {
        self.moving.as_ref().is_some_and(|m| !m.servos.is_empty())
    }

    /// Sets each servo's speed from the loads `loads` of every wall (file
    /// order, summed over every process) of the last force evaluation.
    pub(crate) fn steer_servos(&mut self, loads: &[WallLoad]) {
        let Some(m) = self.moving.as_mut() else {
            return;
        };
        for s in &mut m.servos {
            let load = loads
                .get(s.reference.file_index())
                .copied()
                .unwrap_or_default();
            s.velocity = s.servo.velocity(s.servo.push(load.force));
        }
    }

    /// A restart: the servos' state from `records` as at the list build
    /// (`at_build`) or as at the checkpoint's step, placed at `step`.
    pub(crate) fn restore_servos(&mut self, records: &[ServoRecord], at_build: bool, step: u64) {
        let Some(m) = self.moving.as_mut() else {
            return;
        };
        for (s, r) in m.servos.iter_mut().zip(records) {
            s.offset = if at_build { r.built_offset } else { r.offset };
            s.velocity = r.velocity;
            s.built_offset = r.built_offset;
        }
        // Placed where the record says, not advanced.
        m.placed_step = step;
    }
}
