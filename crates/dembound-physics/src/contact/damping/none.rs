//! No damping: the normal law alone (elastic, or a law dissipative on its
//! own such as Walton–Braun).

use super::{DampingSetup, DampingSubModel};

/// Zero damping force.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoDamping;

impl DampingSubModel for NoDamping {
    fn new(_setup: &DampingSetup) -> Self {
        NoDamping
    }

    #[inline(always)]
    fn force(&self, _overlap: f64, _overlap_rate: f64) -> f64 {
        0.0
    }

    fn scaled(&self, _factor: f64) -> Self {
        NoDamping
    }
}
