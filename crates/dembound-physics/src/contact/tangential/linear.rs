//! Linear (Cundall–Strack) tangential spring, LAMMPS `linear_history`:
//! a constant k_t. Here k_t = (2/7) E_eff R_eff, 2/7 of the linear normal
//! law's k (eq 4 with α = 1): for a sphere that ratio gives the tangential
//! and normal oscillations of a contact the same period (the tangential
//! effective mass of a sphere with I = 2/5 m R² is 2/7 m).

use super::{TangentialSetup, TangentialSubModel};

/// k_t = (2/7) E_eff R_eff, N/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearTangential {
    /// k_t, N/m.
    pub stiffness: f64,
}

impl TangentialSubModel for LinearTangential {
    fn new(setup: &TangentialSetup) -> Self {
        Self {
            stiffness: 2.0 / 7.0 * setup.pair.modulus * setup.pair.radius,
        }
    }

    #[inline(always)]
    fn stiffness(&self, _overlap: f64) -> f64 {
        self.stiffness
    }
}
