//! Studies built on the scenario and the exact references: the paper's
//! validation (Tables 1–2) and convergence in the time step; the
//! restitution study of the dissipative laws against boundary particles.

pub mod restitution;
pub mod validation;
