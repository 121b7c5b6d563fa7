//! Forbids an attractive normal force: F = max(F, 0), as LAMMPS
//! `limit_damping` and LIGGGHTS `limitForce` do. With a dashpot the force
//! returns to zero while the spheres still overlap; from there on the
//! particle flies free until the overlap vanishes.

use super::NormalContactLaw;

/// `L` with its force clamped at zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoAttraction<L>(pub L);

impl<L: NormalContactLaw> NormalContactLaw for NoAttraction<L> {
    fn scaled(&self, factor: f64) -> Self {
        NoAttraction(self.0.scaled(factor))
    }
    fn onset(&self) -> super::Onset {
        self.0.onset()
    }

    type History = L::History;

    const NON_ATTRACTIVE: bool = true;

    fn name(&self) -> &'static str {
        self.0.name()
    }

    #[inline(always)]
    fn force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64 {
        self.0.force(overlap, overlap_rate, history).max(0.0)
    }

    #[inline(always)]
    fn unclamped_force(&self, overlap: f64, overlap_rate: f64, history: &Self::History) -> f64 {
        self.0.unclamped_force(overlap, overlap_rate, history)
    }

    #[inline(always)]
    fn update_history(&self, overlap: f64, overlap_rate: f64, history: &mut Self::History) {
        self.0.update_history(overlap, overlap_rate, history)
    }

    fn depends_on_rate(&self) -> bool {
        self.0.depends_on_rate()
    }

    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        self.0.contact_time_estimate(mass, impact_speed)
    }

    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        self.0.onset_derivatives(mass, overlap_rate, overlap_accel)
    }

    fn at_max_overlap(&self, overlap: f64, history: &mut Self::History) -> bool {
        self.0.at_max_overlap(overlap, history)
    }

    fn branch_derivatives(
        &self,
        mass: f64,
        overlap: f64,
        overlap_rate: f64,
        overlap_accel: f64,
        history: &Self::History,
    ) -> [f64; 3] {
        self.0
            .branch_derivatives(mass, overlap, overlap_rate, overlap_accel, history)
    }
}
