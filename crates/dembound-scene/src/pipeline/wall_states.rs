//! The motion of each moving or force-controlled wall at an observation
//! (issue 27 item 3): where its reference point is and how far it turned,
//! and its velocities. The same on every thread and rank (a prescribed
//! pose is a function of the time; a servo's state is set from loads
//! summed over every process).

use serde::{Deserialize, Serialize};

use super::World;

/// One wall's motion now.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WallMotionState {
    /// The wall, file order.
    pub wall: usize,
    /// The displacement of its reference point since t = 0, m: the
    /// motion's `center` (d(t), `walls::motion`), a servo wall's s â.
    pub position: [f64; 3],
    /// The angle turned about ω̂ since t = 0, rad (0 for a servo).
    pub angle: f64,
    /// The velocity of the reference point, m/s (a servo: the speed its
    /// controller set from the last force evaluation, along â).
    pub velocity: [f64; 3],
    /// rad/s.
    pub angular_velocity: [f64; 3],
}

impl World {
    /// The moving and servo walls' motion at the present step, wall order
    /// (empty when every wall is fixed).
    pub fn wall_motion_states(&self) -> Vec<WallMotionState> {
        let Some(m) = self.moving.as_ref() else {
            return Vec::new();
        };
        let t = self.time();
        let mut out: Vec<WallMotionState> = m
            .drives
            .iter()
            .map(|d| {
                let s = d.motion.state(t);
                WallMotionState {
                    wall: d.reference.file_index(),
                    position: [0, 1, 2].map(|a| s.center[a] - s.center0[a]),
                    angle: d.motion.angle(t),
                    velocity: s.velocity,
                    angular_velocity: s.spin,
                }
            })
            .chain(m.servos.iter().map(|s| {
                let a = s.servo.axis;
                WallMotionState {
                    wall: s.file_index(),
                    position: a.map(|x| x * s.offset),
                    angle: 0.0,
                    velocity: a.map(|x| x * s.velocity),
                    angular_velocity: [0.0; 3],
                }
            }))
            .chain(m.groups.iter().filter_map(|g| {
                // A moving boundary-particle wall (`moving_groups`).
                let wall = g.wall?;
                let s = g.motion.state(t);
                Some(WallMotionState {
                    wall,
                    position: [0, 1, 2].map(|a| s.center[a] - s.center0[a]),
                    angle: g.motion.angle(t),
                    velocity: s.velocity,
                    angular_velocity: s.spin,
                })
            }))
            .collect();
        out.sort_by_key(|s| s.wall);
        out
    }
}
