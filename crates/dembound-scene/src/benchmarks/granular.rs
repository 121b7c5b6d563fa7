//! What the many-grain benchmarks (Janssen's silo, the column collapse)
//! share: the grains (a frictional, dissipative, slightly polydisperse
//! sphere), a deterministic generator for their placement, the time step
//! and a stepping loop that reports its progress.

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_physics::material::Material;

use crate::setup::{
    DomainSetup, FrictionSetup, NamedMaterial, RunLength, SceneSetup, SphereInit, TimeStep,
};
use crate::{SceneError, Simulation};

/// Gravitational acceleration, m/s².
pub(super) const G: f64 = 9.81;

/// The grains: glass-like density, a soft modulus (the stresses of a bed
/// of a few centimetres are ~1 kPa, so E = 5 MPa keeps every overlap below
/// 0.5 % of a diameter while allowing a time step of ~10 µs: quasi-static
/// results do not depend on E once the overlaps are that small).
#[derive(Debug, Clone, Copy)]
pub(super) struct Grains {
    /// Mean radius, m.
    pub radius: f64,
    /// Radii uniform in radius × (1 ± spread).
    pub spread: f64,
    pub material: Material,
    /// Sliding friction between grains.
    pub friction: f64,
    /// Rolling friction between grains (dimensionless, the engine's μ_r).
    pub rolling_friction: f64,
    /// Normal coefficient of restitution (Tsuji damping).
    pub restitution: f64,
}

impl Grains {
    pub fn contact(&self) -> ContactModel {
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(
                DampingKind::Tsuji,
                Dissipation::Restitution(self.restitution),
            ),
        )
    }

    pub fn friction_model(&self) -> FrictionModel {
        FrictionModel {
            tangential: TangentialKind::Mindlin,
            friction: self.friction,
            rolling_friction: self.rolling_friction,
        }
    }

    pub fn describe(&self) -> String {
        format!(
            "grains: R = {} mm ± {} % (uniform), ρ = {} kg/m³, E = {} MPa, ν = {}; Hertz–Mindlin, \
             Tsuji damping at e = {}, μ = {}, μ_r = {}",
            self.radius * 1e3,
            self.spread * 100.0,
            self.material.density,
            self.material.youngs_modulus / 1e6,
            self.material.poisson_ratio,
            self.restitution,
            self.friction,
            self.rolling_friction
        )
    }

    /// An empty scene of these grains (material 0) in `domain`, gravity
    /// −z, friction on, Δt = `steps_per_contact`-th of the Hertz contact
    /// time at `impact_speed` (the engine's estimate).
    pub fn scene(
        &self,
        domain: DomainSetup,
        impact_speed: f64,
        steps_per_contact: f64,
    ) -> SceneSetup {
        let mut s = SceneSetup::new(
            domain,
            self.contact(),
            TimeStep::Eta {
                eta: 1.0 / steps_per_contact,
                impact_speed,
            },
            RunLength::Steps(0),
        );
        s.materials.push(NamedMaterial {
            name: "grain".into(),
            material: self.material,
        });
        s.gravity = [0.0, 0.0, -G];
        s.friction = Some(FrictionSetup::uniform(self.friction_model()));
        s
    }

    /// A grain of material 0 at `position`, at rest, of a radius drawn
    /// from `rng`.
    pub fn sphere(&self, position: [f64; 3], rng: &mut Rng) -> SphereInit {
        SphereInit {
            position,
            velocity: [0.0; 3],
            radius: self.radius * (1.0 + self.spread * rng.symmetric()),
            material: 0,
            fixed: false,
            group: None,
        }
    }

    /// The largest radius drawn.
    pub fn max_radius(&self) -> f64 {
        self.radius * (1.0 + self.spread)
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): the placements are the same on
/// every machine and run.
#[derive(Debug, Clone)]
pub(super) struct Rng(pub u64);

impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [−1, 1).
    pub fn symmetric(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
}

/// Steps `sim` for `duration` s in chunks of about 1 % of it, checking
/// the state is finite, and reports `stage` with the time reached every
/// quarter.
pub(super) fn advance(
    sim: &mut Simulation,
    duration: f64,
    stage: &str,
    progress: &dyn Fn(&str),
) -> Result<(), SceneError> {
    let steps = (duration / sim.dt()).ceil() as u64;
    let chunk = (steps / 100).max(1);
    let mut done = 0;
    let mut next_report = steps / 4;
    while done < steps {
        let n = chunk.min(steps - done);
        sim.step_checked(n)?;
        done += n;
        if done >= next_report && done < steps {
            progress(&format!(
                "{stage}: t = {:.3} s ({} spheres, {:.0} %)",
                sim.time(),
                sim.body_count(),
                100.0 * done as f64 / steps as f64
            ));
            next_report += steps / 4;
        }
    }
    Ok(())
}

/// Σ m over the spheres of `setup` (none fixed), kg.
pub(super) fn total_mass(setup: &SceneSetup) -> f64 {
    setup
        .spheres
        .iter()
        .map(|s| setup.materials[s.material].material.sphere_mass(s.radius))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_generator_is_uniform_enough_and_repeatable() {
        let mut a = Rng(3);
        let xs: Vec<f64> = (0..10_000).map(|_| a.next_f64()).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        // Mean of 10,000 uniforms: σ = 0.29/100 = 0.003; 5σ.
        assert!((mean - 0.5).abs() < 0.015, "{mean}");
        assert!(xs.iter().all(|&x| (0.0..1.0).contains(&x)));
        let mut b = Rng(3);
        assert_eq!(b.next_f64(), xs[0]);
    }
}
