//! Friction and rotation (issue 13): the tangential spring with Coulomb
//! limit and the rolling resistance of the physics crate
//! (`contact::tangential`, `contact::rolling`) for sphere pairs and walls,
//! each contact's tangential displacement (a 3-vector) kept beside the
//! neighbour list and carried across rebuilds, reordering and checkpoints
//! by input ids. Every contact is the composer's
//! (`dembound_physics::contact::model`): this module stores the springs
//! and runs the loops.
//!
//! Geometry (LAMMPS `GranularModel`, LIGGGHTS `surface_model_default`): for
//! bodies i, j with unit normal n from i to j, the contact point lies at
//! R_i n from i and −R_j n from j (the undeformed radii as lever arms, so
//! that in gross sliding the spin change is exactly (5/2) μ J_n/(m R)); the
//! slip velocity is v_c = v_i − v_j + (R_i ω_i + R_j ω_j) × n, its
//! tangential part v_t drives the spring; the tangential force F_t acts on
//! i (−F_t on j), with torques R_i n × F_t on i and R_j n × F_t on j
//! (under `contact.torque_arm = "contact_point"`, LAMMPS's R − δ/2 for a
//! sphere pair: `ContactLaw::torque_arm`). A
//! wall is side 2 with no radius, spin or 1/I, moving at its surface
//! velocity, with n the wall's normal reversed.
//!
//! Kept apart from the frictionless force loop (`contacts.rs`), which stays
//! as it was: a scene without friction runs the same instructions.
//!
//! Files: `table.rs` (the friction laws per class pair and wall row),
//! `springs.rs` (spring storage: pairs' and walls' springs, saved and
//! restored by input ids), `pairs.rs` and `pair_batch.rs` (the pair force
//! loop, row by row and batched), `row_laws.rs` (the batched loop's law
//! lookup: the class table, or one law without per-contact dispatch),
//! `turn_four.rs` (a batch's springs turned or cleared four at a time), `walls.rs` (the per-body wall pass and
//! the walls' tangential observables).

mod pair_batch;
mod pairs;
mod row_laws;
mod springs;
mod table;
mod turn_four;
mod walls;

pub(crate) use pairs::add_pair_forces_then;
pub use pairs::{add_pair_forces, add_pair_forces_tallied, PairForceInput, PairTally};
pub use springs::{active_shear, active_shear_map, restore_shear, PairShear, Springs, WallShear};
pub use table::{FrictionLaw, FrictionTable};
pub use walls::{
    add_plane_forces, body_force, gravity_force, planes_are_hertz_mindlin, prefetch_wall_springs,
    prefetch_wall_springs_of, BodyForceInput,
};

#[inline(always)]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

// The in-place sums, shared with the frictionless loops.
use super::contacts::{add, sub};

/// The tangential part of `v` for unit normal `n`.
#[inline(always)]
pub fn tangential(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let a = dot(v, n);
    [v[0] - a * n[0], v[1] - a * n[1], v[2] - a * n[2]]
}
