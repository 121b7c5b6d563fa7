//! The physics of dembound, shared by the bounce study (`dembound-core`),
//! the many-particle engine (`dembound-scene`) and the bindings: no I/O, no
//! time loop, no knowledge of how many bodies there are.
//!
//! - [`material`]: a material (ρ, E, ν), the effective properties of a pair
//!   of spheres or of a sphere and a plane (paper eqs 5–8, generalised to
//!   unequal Poisson ratios as in ERRATA item 2), exact for rigid materials
//!   and infinite radii.
//! - [`contact`]: per-pair contact models. A [`contact::ContactModel`] is
//!   what a user configures (normal law, damping, clamp); for one pair of
//!   bodies it gives a [`contact::PairLaw`], the coefficients of that pair,
//!   whose `force` and `update` are all a time loop needs. Sub-models and
//!   their parameters are rows of [`contact::registry`].
//! - [`integrate`]: Gear5 and velocity Verlet generic over the state they
//!   advance (a scalar, a [`integrate::Vec3`], an array of bodies).
//! - [`error`]: the crate's one error type, [`PhysicsError`].

pub mod contact;
pub mod error;
pub mod integrate;
pub mod material;

pub use error::PhysicsError;
