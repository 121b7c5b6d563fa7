//! Forces and motion: pair contacts, plane walls, the integrators and the
//! collision log.

pub mod collisions;
pub mod contacts;
pub mod entry_tally;
pub mod friction;
pub mod friction_observables;
pub mod gear5_rotation;
pub mod halo_split;
pub mod integrate;
pub mod kinks;
pub mod spring_energy;
pub mod walls;
