//! dembound-scene: a many-particle 3D DEM engine for scenes of spheres,
//! boundary particles and plane walls (issue 12). No I/O in the engine:
//! a [`setup::SceneSetup`] in, a [`Simulation`] to step and query.
//!
//! - [`bodies`]: the body store (structure of arrays).
//! - [`geometry`]: box, cells, Verlet lists, ghost layer.
//! - [`dynamics`]: pair contacts, plane walls, integrators, collision log.
//! - [`pipeline`]: one step as named stages over the [`pipeline::World`].
//! - [`simulation`]: the public [`Simulation`] API and its checkpoint.
//!
//! Around the engine, with files (helper "scene-io"):
//! - [`sources`]: where the spheres come from (lattice, random insertion,
//!   LAMMPS data, CSV) and the boundary-particle walls (`tiling`).
//! - [`io`]: the scene file, VTK snapshots, the time series, checkpoints.

/// Four 3-vectors stored one after another in three AVX registers,
/// `[x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3]`, as their x, y and z
/// registers (lane k: vector k): two blends and a permute each. Used by
/// the AVX2 passes over bodies and contacts (`pipeline::verlet`,
/// `pipeline::verlet_four`, `pipeline::closing_kick`,
/// `dynamics::friction::turn_four`); a macro, not a function, so that it
/// is compiled inside their AVX2 functions (the intrinsics are the
/// caller's imports). Defined before the modules so that all see it.
#[cfg(target_arch = "x86_64")]
macro_rules! lanes_to_xyz {
    ($s:expr) => {{
        let [s0, s1, s2] = $s;
        let x = _mm256_blend_pd::<0b0010>(_mm256_blend_pd::<0b0100>(s0, s1), s2);
        let y = _mm256_blend_pd::<0b0100>(_mm256_blend_pd::<0b1001>(s0, s1), s2);
        let z = _mm256_blend_pd::<0b1001>(_mm256_blend_pd::<0b0010>(s0, s1), s2);
        [
            _mm256_permute4x64_pd::<0x6C>(x),
            _mm256_permute_pd::<0b0101>(y),
            _mm256_permute4x64_pd::<0xC6>(z),
        ]
    }};
}

/// The inverse of [`lanes_to_xyz`]: x, y and z registers of four vectors
/// back to `[x0 y0 z0 x1] [y1 z1 x2 y2] [z2 x3 y3 z3]`.
#[cfg(target_arch = "x86_64")]
macro_rules! xyz_to_lanes {
    ($x:expr, $y:expr, $z:expr) => {{
        let x = _mm256_permute4x64_pd::<0x6C>($x); // [x0 x3 x2 x1]
        let y = _mm256_permute_pd::<0b0101>($y); // [y1 y0 y3 y2]
        let z = _mm256_permute4x64_pd::<0xC6>($z); // [z2 z1 z0 z3]
        [
            _mm256_blend_pd::<0b0100>(_mm256_blend_pd::<0b0010>(x, y), z),
            _mm256_blend_pd::<0b0100>(_mm256_blend_pd::<0b0010>(y, z), x),
            _mm256_blend_pd::<0b0100>(_mm256_blend_pd::<0b0010>(z, x), y),
        ]
    }};
}

pub mod balance;
pub mod benchmarks;
pub mod bodies;
pub mod comm;
pub mod dynamics;
pub mod energy_guard;
pub mod error;
pub mod fingerprint;
pub mod geometry;
pub mod inlets;
pub mod io;
pub mod limits;
pub mod outlets;
pub mod parallel;
pub mod pipeline;
pub mod region;
pub mod removal;
pub(crate) mod restart_walls;
pub mod setup;
pub mod setup_checks;
pub mod simulation;
pub mod sources;
pub mod spheres;
pub mod time_step;
pub mod wall_study;
pub mod walls;

pub use dynamics::collisions::{Collision, Partner};
pub use energy_guard::EnergyBalance;
pub use error::SceneError;
pub use removal::Removed;
pub use setup::SceneSetup;
pub use simulation::{Checkpoint, Observation, Simulation, TimeStepReport};
