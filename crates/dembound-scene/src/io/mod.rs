//! Files: the scene file ([`config`]), VTK snapshots ([`vtk`]; the mesh
//! walls' loads [`vtk_walls`]), the time series ([`series`]) and
//! checkpoints ([`checkpoint`]; written per rank: [`checkpoint_parts`]).

pub mod checkpoint;
pub mod checkpoint_parts;
pub mod config;
pub mod exp_format;
pub mod labels;
pub mod memory;
pub mod resolve;
pub mod series;
pub mod vtk;
pub mod vtk_walls;
