//! Incremental Hertz–Mindlin spring (LAMMPS `tangential mindlin/force`,
//! Yade's `Law2_ScGeom_MindlinPhys_Mindlin`): the same stiffness as
//! [`super::mindlin::Mindlin`], k_t = 8 G* √(R_eff h), but the spring holds
//! the tangential FORCE F_s (N) and each step adds −k_t(h) v_t Δt with the
//! stiffness of that step: a force loaded at a small overlap keeps its size
//! when the overlap grows, where the total spring −k_t(h) δ would grow with
//! k_t. At a constant overlap the two are the same spring. The step is
//! [`super::FrictionPair::tangential_force_turned`]'s incremental branch.

use super::{TangentialSetup, TangentialSubModel};

/// k_t = 8 G* √(R_eff h), N/m, applied to the increments of a stored force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MindlinForce {
    /// 8 G* √R_eff, N/m^(3/2).
    pub coefficient: f64,
}

impl TangentialSubModel for MindlinForce {
    const STORES_FORCE: bool = true;

    fn new(setup: &TangentialSetup) -> Self {
        Self {
            coefficient: 8.0 * setup.shear_modulus * setup.pair.radius.sqrt(),
        }
    }

    #[inline(always)]
    fn stiffness(&self, overlap: f64) -> f64 {
        self.coefficient * overlap.abs().sqrt()
    }
}

#[cfg(test)]
#[path = "mindlin_force_tests.rs"]
mod tests;
