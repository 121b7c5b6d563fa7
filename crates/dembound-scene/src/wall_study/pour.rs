//! The pour of a bed, shared by the plane study's bed
//! ([`super::bed`]) and the part study's ([`super::part_bed`]): equal
//! spheres dropped from a loose random packing in a box above the floor,
//! inside four frictionless side walls, under g = 9.81 m/s² along −z; the
//! floor (a plane, a tiling, a mesh or its covering) is added by the
//! caller. The same box, seed and time step give the same spheres, in the
//! same order, whichever study pours them.

use std::f64::consts::PI;

use super::{base_setup, insert_at_rest, StudyConfig};
use crate::setup::{Plane, SceneSetup, WallSetup};
use crate::SceneError;

/// Solid fraction of the loose packing the spheres start from.
pub const FILL: f64 = 0.18;

/// g, m/s² (along −z).
pub const GRAVITY: f64 = 9.81;

/// Where a bed is poured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pour {
    /// Spheres.
    pub count: usize,
    /// Their radius R, m.
    pub radius: f64,
    /// The insertion box, m (the spheres inside it whole).
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    /// The side walls' x and y (lower, upper), m; normals inward.
    pub sides: [[f64; 2]; 2],
    /// The simulation domain, m.
    pub domain_lower: [f64; 3],
    pub domain_upper: [f64; 3],
    /// The lowest point a sphere falls to (the floor's contact plane, the
    /// part's bottom), m: the fall time is from `upper[2]` to it.
    pub base: f64,
}

impl Pour {
    /// The height of the insertion box over `sx` × `sy` (m) that holds
    /// `count` spheres of radius `r` at the solid fraction [`FILL`], plus
    /// one diameter, m.
    pub fn fill_height(count: usize, r: f64, sx: f64, sy: f64) -> f64 {
        count as f64 * (4.0 / 3.0) * PI * r * r * r / (FILL * sx * sy) + 2.0 * r
    }

    /// The scene of the pour: `c`'s particles (material 0) in the box,
    /// then the four side walls (walls 0–3, material 0), gravity; Δt `dt`.
    pub fn scene(&self, c: &StudyConfig, dt: f64) -> Result<SceneSetup, SceneError> {
        let r = self.radius;
        let mut s = base_setup(c, self.domain_lower, self.domain_upper, dt);
        s.gravity = [0.0, 0.0, -GRAVITY];
        insert_at_rest(&mut s, c, "bed", self.count, r, self.lower, self.upper)?;
        // Four frictionless side walls (they would hold part of the weight).
        let [[x0, x1], [y0, y1]] = self.sides;
        for (point, normal) in [
            ([x0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            ([x1, 0.0, 0.0], [-1.0, 0.0, 0.0]),
            ([0.0, y0, 0.0], [0.0, 1.0, 0.0]),
            ([0.0, y1, 0.0], [0.0, -1.0, 0.0]),
        ] {
            s.walls.push(WallSetup::Plane(Plane {
                point,
                normal,
                material: 0,
            }));
        }
        Ok(s)
    }

    /// The free fall from the top of the box to the base, s.
    pub fn fall_time(&self) -> f64 {
        (2.0 * (self.upper[2] - self.base) / GRAVITY).sqrt()
    }

    /// The steps of the fall and `settle` s more, at Δt `dt`.
    pub fn settle_steps(&self, settle: f64, dt: f64) -> u64 {
        ((self.fall_time() + settle) / dt).ceil() as u64
    }

    /// Threads for a bed of `count` spheres.
    pub fn threads(&self) -> usize {
        if self.count >= 5000 {
            2
        } else {
            1
        }
    }
}
