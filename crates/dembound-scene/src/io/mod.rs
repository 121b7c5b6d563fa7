//! Files: the scene file ([`config`]), VTK snapshots ([`vtk`]), the time
//! series ([`series`]) and checkpoints ([`checkpoint`]).

pub mod config;
