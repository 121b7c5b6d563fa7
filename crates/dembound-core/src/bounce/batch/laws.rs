//! The laws the kernel runs in lanes (elastic Hertz and linear): their
//! force on vectors and their contact-time estimate with the law-only
//! factors computed once.

use super::simd::{Simd, V};
use crate::bounce::schedule::Grading;
use crate::contact::{Hertz, LinearSpring, NormalContactLaw, Onset};
use crate::material::ContactPair;
use std::sync::OnceLock;

/// A batched law for [`Problem::new`]: the law itself, with its
/// contact-time estimate from [`LaneLaw::estimate`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Planned<L>(pub(super) L);

impl<L: LaneLaw> NormalContactLaw for Planned<L> {
    type History = ();
    fn name(&self) -> &'static str {
        self.0.name()
    }
    fn force(&self, overlap: f64, overlap_rate: f64, history: &()) -> f64 {
        self.0.force(overlap, overlap_rate, history)
    }
    fn scaled(&self, factor: f64) -> Self {
        Planned(self.0.scaled(factor))
    }
    fn depends_on_rate(&self) -> bool {
        self.0.depends_on_rate()
    }
    fn contact_time_estimate(&self, mass: f64, impact_speed: f64) -> f64 {
        self.0.estimate(mass, impact_speed)
    }
    fn onset(&self) -> Onset {
        self.0.onset()
    }
    fn onset_derivatives(&self, mass: f64, overlap_rate: f64, overlap_accel: f64) -> [f64; 3] {
        self.0.onset_derivatives(mass, overlap_rate, overlap_accel)
    }
}

/// A law the kernel runs: its force in lanes, the same arithmetic as
/// [`NormalContactLaw::force`], which must be nondecreasing in the overlap
/// (also in floating point) for the peak force to be the deepest step's.
pub(super) trait LaneLaw: NormalContactLaw<History = ()> + Copy {
    const GRADING: Grading;
    fn for_pair(pair: &ContactPair) -> Self;
    fn with_stiffness(k: f64) -> Self;
    fn stiffness(&self) -> f64;
    /// [`NormalContactLaw::contact_time_estimate`], bit for bit (checked by
    /// a test), with the factors that depend on the law alone computed once.
    fn estimate(&self, mass: f64, impact_speed: f64) -> f64;
    fn lanes_force<S: Simd, const G: usize>(k: V<S, G>, overlap: V<S, G>) -> V<S, G>;
}

impl LaneLaw for Hertz {
    const GRADING: Grading = Grading::Power;
    fn for_pair(pair: &ContactPair) -> Self {
        pair.law::<Hertz>(&[])
    }
    fn with_stiffness(k: f64) -> Self {
        Hertz { stiffness: k }
    }
    fn stiffness(&self) -> f64 {
        self.stiffness
    }
    /// `power_law_free_contact(k, 1.5, m, v).1` with its Beta-function
    /// factor (three Γ calls) computed once.
    fn estimate(&self, mass: f64, speed: f64) -> f64 {
        static BETA_FACTOR: OnceLock<f64> = OnceLock::new();
        let beta = 1.5 + 1.0;
        let b = *BETA_FACTOR.get_or_init(|| {
            libm::tgamma(1.0 / beta) * libm::tgamma(0.5) / libm::tgamma(1.0 / beta + 0.5)
        });
        let max_overlap = (beta * mass * speed * speed / (2.0 * self.stiffness)).powf(1.0 / beta);
        2.0 * max_overlap / speed * b / beta
    }
    #[inline(always)]
    fn lanes_force<S: Simd, const G: usize>(k: V<S, G>, h: V<S, G>) -> V<S, G> {
        k * h * h.abs().sqrt()
    }
}

impl LaneLaw for LinearSpring {
    const GRADING: Grading = Grading::Uniform;
    fn for_pair(pair: &ContactPair) -> Self {
        pair.law::<LinearSpring>(&[])
    }
    fn with_stiffness(k: f64) -> Self {
        LinearSpring { stiffness: k }
    }
    fn stiffness(&self) -> f64 {
        self.stiffness
    }
    fn estimate(&self, mass: f64, speed: f64) -> f64 {
        self.contact_time_estimate(mass, speed)
    }
    #[inline(always)]
    fn lanes_force<S: Simd, const G: usize>(k: V<S, G>, h: V<S, G>) -> V<S, G> {
        k * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Boundary, Particle};

    #[test]
    fn cached_estimates_equal_the_laws_to_the_bit() {
        let mut checked = 0;
        for i in 0..200 {
            let u = |k: u32| ((i * k) % 997) as f64 / 997.0;
            let pair = ContactPair::new(
                Particle::PAPER,
                Boundary {
                    radius_ratio: 10f64.powf(-0.3 + 4.0 * u(7)),
                    modulus_ratio: 10f64.powf(-1.0 + 4.0 * u(13)),
                    poisson_ratio: None,
                },
            );
            let mass = 10f64.powf(-9.0 + 3.0 * u(17));
            let speed = 10f64.powf(-3.0 + 4.0 * u(19));
            let hertz = <Hertz as LaneLaw>::for_pair(&pair);
            let linear = <LinearSpring as LaneLaw>::for_pair(&pair);
            assert_eq!(
                hertz.estimate(mass, speed).to_bits(),
                hertz.contact_time_estimate(mass, speed).to_bits()
            );
            assert_eq!(
                linear.estimate(mass, speed).to_bits(),
                linear.contact_time_estimate(mass, speed).to_bits()
            );
            checked += 1;
        }
        assert_eq!(checked, 200);
    }
}
