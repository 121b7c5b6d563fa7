//! Energy with friction (issue 13): the elastic energy of the time series
//! includes the tangential springs' ½ k_t |δ|², so an elastic frictional
//! system that sticks conserves kinetic (translation and spin) + elastic +
//! potential energy.
//!
//! The system: two spheres stacked on a plane under gravity, each contact
//! at its Hertz equilibrium overlap, undamped; the top sphere is pushed
//! sideways at 1 mm/s with μ = 10, far from the Coulomb limit. Both
//! contacts shear elastically: the top sphere rocks on the bottom one,
//! which rocks on the plane, and the springs trade energy with the
//! motion for 100 tangential periods.

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, NormalLaw};
use dembound_physics::material::Material;
use dembound_scene::setup::{
    DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, SphereInit, TimeStep, WallSetup,
};
use dembound_scene::{SceneSetup, Simulation};
use std::f64::consts::PI;

const R: f64 = 1.0e-3;
const G: f64 = 9.81;
const MATERIAL: Material = Material {
    density: 2500.0,
    youngs_modulus: 1.0e8,
    poisson_ratio: 0.25,
};

/// Hertz equilibrium overlap under `load` (N) for effective radius `r`.
fn overlap(load: f64, r: f64) -> f64 {
    let e_eff = 4.0 / 3.0 * MATERIAL.youngs_modulus / (2.0 * (1.0 - 0.25 * 0.25));
    (load / (e_eff * r.sqrt())).powf(2.0 / 3.0)
}

fn stack(tangential: TangentialKind, dt: f64) -> Simulation {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-0.01, -0.01, -0.001],
            upper: [0.01, 0.01, 0.01],
            periodic: [false; 3],
        },
        ContactModel::elastic(NormalLaw::Hertz),
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.gravity = [0.0, 0.0, -G];
    s.materials.push(NamedMaterial {
        name: "glass".into(),
        material: MATERIAL,
    });
    let weight = 4.0 / 3.0 * PI * R * R * R * MATERIAL.density * G;
    let z_bottom = R - overlap(2.0 * weight, R);
    let z_top = z_bottom + 2.0 * R - overlap(weight, 0.5 * R);
    for (z, vx) in [(z_bottom, 0.0), (z_top, 1.0e-3)] {
        s.spheres.push(SphereInit {
            position: [0.0, 0.0, z],
            velocity: [vx, 0.0, 0.0],
            radius: R,
            material: 0,
            fixed: false,
            group: None,
        });
    }
    s.walls.push(WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    }));
    s.friction = Some(FrictionSetup::uniform(FrictionModel {
        tangential,
        friction: 10.0,
        rolling_friction: 0.0,
    }));
    Simulation::new(s, 1).unwrap()
}

/// (largest |E(t) − E(0)|, largest spring energy seen), J, over `steps`
/// steps sampled every `every`; E = kinetic + elastic + potential. The
/// spring energy is the elastic energy minus the normal laws' (Hertz,
/// (2/5) k h^(5/2) per contact), from the positions.
fn run(tangential: TangentialKind, dt: f64, steps: u64, every: u64) -> (f64, f64) {
    let mut sim = stack(tangential, dt);
    let total = |sim: &Simulation| {
        let o = sim.observe();
        o.kinetic_energy + o.elastic_energy + o.potential_energy
    };
    let normal = |sim: &Simulation| {
        let x = sim.positions();
        let e_eff = 4.0 / 3.0 * MATERIAL.youngs_modulus / (2.0 * (1.0 - 0.25 * 0.25));
        let hertz = |h: f64, r: f64| 0.4 * e_eff * r.sqrt() * h.max(0.0).powf(2.5);
        let d = ((0..3).map(|a| (x[1][a] - x[0][a]).powi(2)).sum::<f64>()).sqrt();
        hertz(R - x[0][2], R) + hertz(2.0 * R - d, 0.5 * R)
    };
    let e0 = total(&sim);
    let (mut worst, mut springs) = (0.0f64, 0.0f64);
    let mut done = 0;
    while done < steps {
        sim.step(every);
        done += every;
        worst = worst.max((total(&sim) - e0).abs());
        springs = springs.max(sim.elastic_energy() - normal(&sim));
    }
    (worst, springs)
}

#[test]
fn sticking_elastic_contacts_conserve_energy_with_the_spring_energy() {
    // Δt = 5e-7 s, 1/200 of the pair's tangential period (linear spring,
    // k_t = (2/7) E_eff R_eff = 1.0e4 N/m on a tangential mass of 2/7 m:
    // 1.1e-4 s); 20,000 steps, 10 ms, about 90 periods.
    for tangential in [TangentialKind::Linear, TangentialKind::Mindlin] {
        let (err, springs) = run(tangential, 5.0e-7, 20_000, 20);
        let (err2, _) = run(tangential, 2.5e-7, 40_000, 40);
        println!(
            "{tangential:?}: max |ΔE| {err:e} J at Δt, {err2:e} J at Δt/2; spring energy up to \
             {springs:e} J"
        );
        // The springs hold a good part of the push's ½ m v² = 5.2e-12 J
        // (measured: 16 %): without them in the sum the total would swing
        // by that much. With them, what is left is Verlet's error,
        // (ω Δt)²/8 ≈ 1e-4 of the oscillation energy at 200 steps a period
        // (and for Mindlin the work ½ (dk_t/dh) |δ|² dh of the rocking,
        // which no potential holds): 1e-3 of the springs' energy.
        let push = 0.5 * 4.0 / 3.0 * PI * R * R * R * MATERIAL.density * 1.0e-6;
        assert!(springs > 0.05 * push, "{springs:e} J of {push:e} J");
        assert!(err < 1.0e-3 * springs, "{tangential:?}: {err:e} J");
        // With the linear spring (a true potential) the rest is the
        // integrator's: second order in Δt (ratio 4 per halving; 3 to 5
        // for the sampled maximum). Measured: 3.2e-16 → 7.9e-17 J, 4.0.
        // Mindlin's spring, 12–15 times softer here (k_t = 8 G* √(R h) at
        // h ≈ 2e-7 m), leaves Verlet's error below the rocking's
        // non-potential work: 7.3e-17 → 5.4e-17 J, 9e-5 of the springs'.
        if tangential == TangentialKind::Linear {
            assert!(
                (3.0..5.0).contains(&(err / err2)),
                "{tangential:?}: {err:e} → {err2:e}"
            );
        }
    }
}
