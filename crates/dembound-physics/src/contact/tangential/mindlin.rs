//! Mindlin no-slip tangential spring (Hertz–Mindlin as in LIGGGHTS
//! `tangential_model history` with `model hertz`, EDEM's default, LAMMPS
//! `tangential mindlin`): k_t = 8 G* a with the contact radius
//! a = √(R_eff h) and G* = 1/((2 − ν₁)/G₁ + (2 − ν₂)/G₂),
//! G = E/(2(1 + ν)) ([`super::effective_shear_modulus`]). The spring holds
//! the tangential displacement; the force is −k_t(h) δ with the current
//! stiffness (as LIGGGHTS and LAMMPS's `mindlin` without `/force`).

use super::{TangentialSetup, TangentialSubModel};

/// k_t = 8 G* √(R_eff h), N/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mindlin {
    /// 8 G* √R_eff, N/m^(3/2).
    pub coefficient: f64,
}

impl TangentialSubModel for Mindlin {
    fn new(setup: &TangentialSetup) -> Self {
        Self {
            coefficient: 8.0 * setup.shear_modulus * setup.pair.radius.sqrt(),
        }
    }

    #[inline(always)]
    fn stiffness(&self, overlap: f64) -> f64 {
        // |h| = h in contact: the same root as the Hertz force of the
        // pair, which the compiler then takes once.
        self.coefficient * overlap.abs().sqrt()
    }
}
