//! A damped bed settled on a floor carries its weight: the total force on
//! the floor is N m g, on a plane of the grains' own material and on a
//! floor of fixed boundary particles.
//!
//! At rest Σ F = d(Σ m v)/dt = 0, so the floor's vertical force equals the
//! weight exactly up to the residual motion (the side walls are vertical
//! and carry no vertical force; frictionless contacts). The test waits for
//! the kinetic energy to be tiny (so the residual accelerations are) and
//! asserts 1e-6 relative.

mod common;

use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::setup::{BoundaryParticles, SphereInit, WallSetup};
use dembound_scene::{SceneSetup, Simulation};

const G: f64 = 9.81;
/// The walls of `common::lattice_drop` are x−, x+, y−, y+, z−, z+: the
/// floor is the fifth.
const FLOOR: usize = 4;

/// The lattice-drop layout, 4 × 4 × 4 spheres in a 5.4 mm box, Hertz with
/// Tsuji damping (e = 0.3), stiffer grains (E = 1e8 Pa) so it settles in a
/// few thousand steps.
fn bed() -> SceneSetup {
    let mut s = common::lattice_drop(4, 4, 2.0e-6, 0);
    s.materials[0].material.youngs_modulus = 1.0e8;
    s.contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
    );
    s
}

/// Runs until the bed is at rest: the kinetic energy below 1e-12 of
/// N m g R (residual speeds ~1e-6 √(gR)) and the floor force steady to
/// 1e-9 relative over five checks 1,000 steps apart.
fn settle(setup: SceneSetup, floor: usize) -> Simulation {
    let mut sim = Simulation::new(setup, 2).unwrap();
    let scale = weight(&sim) * 0.5e-3;
    let mut last = f64::NAN;
    let mut steady = 0;
    for _ in 0..1000 {
        sim.step(1000);
        let f = sim.wall_forces()[floor][2];
        steady = if ((f - last) / f).abs() < 1e-9 {
            steady + 1
        } else {
            0
        };
        last = f;
        if steady >= 5 && sim.kinetic_energy() < 1e-12 * scale {
            return sim;
        }
    }
    panic!(
        "the bed did not settle: kinetic energy {} J",
        sim.kinetic_energy()
    );
}

fn weight(sim: &Simulation) -> f64 {
    let free = sim.fixed().iter().filter(|f| !**f).count() as f64;
    free * common::grain(1.0e8).sphere_mass(0.5e-3) * G
}

#[test]
fn bed_on_a_plane_floor_carries_its_weight() {
    let sim = settle(bed(), FLOOR);
    let floor = sim.wall_forces()[FLOOR];
    // The force on the floor points down.
    let rel = (-floor[2] / weight(&sim) - 1.0).abs();
    assert!(
        rel < 1e-6,
        "floor force {floor:?} N vs weight {} N: {rel:e}",
        weight(&sim)
    );
    assert!(sim.dissipated_energy() > 0.0);
}

#[test]
fn bed_on_a_particle_floor_carries_its_weight() {
    // The plane floor replaced by a square tiling of fixed spheres of the
    // grains' size, touching, their tops at z = 0 (the grains' cells).
    let mut setup = bed();
    setup.walls.remove(FLOOR);
    let first = setup.spheres.len();
    let side = 5;
    let spacing = 1.2e-3;
    for j in 0..side {
        for i in 0..side {
            setup.spheres.push(SphereInit {
                position: [i as f64 * spacing, j as f64 * spacing, -0.5e-3],
                velocity: [0.0; 3],
                radius: 0.6e-3,
                material: 0,
                fixed: true,
                group: Some(setup.walls.len()),
            });
        }
    }
    setup
        .walls
        .push(WallSetup::BoundaryParticles(BoundaryParticles {
            first_body: first,
            count: side * side,
        }));
    let wall = setup.walls.len() - 1;
    let sim = settle(setup, wall);
    let floor = sim.wall_forces()[wall];
    let rel = (-floor[2] / weight(&sim) - 1.0).abs();
    assert!(
        rel < 1e-6,
        "floor force {floor:?} N vs weight {} N: {rel:e}",
        weight(&sim)
    );
    assert!(sim.wall_contacts() > 0);
    // The floor's spheres on the box edges cut the side planes (centres on
    // x = 0 and y = 0, 0.6 mm deep); fixed bodies never touch a plane, so
    // the side walls carry only the grains' push, far below the weight
    // (counted, the cut would give ~2 N).
    for side in 0..4 {
        let f = sim.wall_forces()[side];
        let norm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        assert!(norm < weight(&sim), "side wall {side}: {f:?} N");
    }
}
