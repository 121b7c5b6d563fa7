//! Many-particle 3D DEM scenes (issue 12).
//!
//! - [`sources`]: where the spheres come from (lattice, random insertion,
//!   LAMMPS data, CSV) and the boundary-particle walls (`tiling`).
//! - [`io`]: the scene file, VTK snapshots, the time series, checkpoints.

pub mod error;
pub mod io;
pub mod sources;

pub use error::SceneError;
