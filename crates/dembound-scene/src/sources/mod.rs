//! Where the spheres of a scene come from: generators (a lattice, random
//! insertion), readers (LAMMPS data files, CSV) and the boundary-particle
//! walls ([`tiling`]). Each gives plain [`SourceSphere`]s; the scene file
//! ([`crate::io::config`]) attaches the material and the fixed flag.

pub mod csv;
pub mod lammps_data;
pub mod lattice;
pub mod random;
pub mod tiling;

/// One sphere as a source gives it, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceSphere {
    /// Centre, m.
    pub position: [f64; 3],
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Radius, m.
    pub radius: f64,
}

impl SourceSphere {
    /// A sphere at rest.
    pub fn at_rest(position: [f64; 3], radius: f64) -> Self {
        Self {
            position,
            velocity: [0.0; 3],
            radius,
        }
    }
}

/// Squared distance between two points, m².
pub(crate) fn distance_squared(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}
