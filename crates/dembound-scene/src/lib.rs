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
pub mod time_step;
pub mod wall_study;
pub mod walls;

pub use dynamics::collisions::{Collision, Partner};
pub use energy_guard::EnergyBalance;
pub use error::SceneError;
pub use removal::Removed;
pub use setup::SceneSetup;
pub use simulation::{Checkpoint, Observation, Simulation, TimeStepReport};
