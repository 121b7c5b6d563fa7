//! Force-controlled walls (issue 27 item 2, `walls::servo`) against a
//! closed form: one sphere between a fixed floor and a servo piston, no
//! gravity. The piston comes down, presses, and stops where the push on
//! it is the target F: both contacts then carry F, each with the overlap
//! δ/2, so the total compression δ = 2R − (z_piston − z_floor) solves
//! F = E_eff √R (δ/2)^{3/2} with the code's sphere–plane modulus E_eff =
//! (4/3) E*, 1/E* = (1 − ν²)/E + (1 − ν²)/E (two Hertz contacts in
//! series). Also: the same bits on 1 and 2 threads and after a restart,
//! and the servo's energy in the balance.

mod common;

use common::grain;
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_physics::material::Material;
use dembound_scene::setup::Mesh;
use dembound_scene::setup::{
    DomainSetup, NamedMaterial, Plane, RunLength, Scheme, SphereInit, TimeStep, WallSetup,
};
use dembound_scene::walls::mesh::Transform;
use dembound_scene::walls::servo::Servo;
use dembound_scene::{SceneSetup, Simulation};
use std::path::Path;

const R: f64 = 1.0e-3;
const E: f64 = 1.0e9;
/// The gap between the sphere and the piston at the start, m.
const GAP: f64 = 5.0e-6;

fn material() -> Material {
    grain(E)
}

/// E_eff = (4/3) E*, 1/E* = 2 (1 − ν²)/E, written out.
fn e_eff() -> f64 {
    let m = material();
    4.0 / 3.0 / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus)
}

/// δ solving F = E_eff √R (δ/2)^{3/2}.
fn compression(force: f64) -> f64 {
    2.0 * (force / (e_eff() * R.sqrt())).powf(2.0 / 3.0)
}

/// The sphere at rest on the floor z = 0, the piston (normal −z) at
/// 2R + GAP with a servo pushing down at `force` N.
fn piston(scheme: Scheme, force: f64, dt: f64) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-0.01; 3],
            upper: [0.01; 3],
            periodic: [false; 3],
        },
        // Damped (Tsuji, e = 0.5): the sphere's ringing between the two
        // contacts dies out and the piston settles.
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        ),
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.integration.scheme = scheme;
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: material(),
    });
    s.spheres.push(SphereInit {
        position: [0.0, 0.0, R],
        velocity: [0.0; 3],
        radius: R,
        material: 0,
        fixed: false,
        group: None,
    });
    for (z, up) in [(0.0, true), (2.0 * R + GAP, false)] {
        s.walls.push(WallSetup::Plane(Plane {
            point: [0.0, 0.0, z],
            normal: [0.0, 0.0, if up { 1.0 } else { -1.0 }],
            material: 0,
        }));
    }
    s.wall_servos = vec![
        None,
        Some(Servo {
            force,
            axis: [0.0, 0.0, -1.0],
            max_velocity: 0.02,
            gain: 5.0,
        }),
    ];
    s
}

/// The piston's height now, m (its reference 2R + GAP moved by s â).
fn piston_height(sim: &Simulation) -> f64 {
    let o = sim.observe();
    let m = o.wall_motions.iter().find(|m| m.wall == 1).expect("servo");
    2.0 * R + GAP + m.position[2]
}

/// The piston stops at the compression of two Hertz contacts in series
/// carrying F. Numbers (F = 1 N): δ ≈ 24.6 µm, series stiffness
/// K = dF/dδ = 1.5 F/δ ≈ 6.1e4 N/m; the loop's Δt k v_max K/F = 3e-3 (≪ 1:
/// monotone), its time constant F/(k v_max K) ≈ 0.16 ms; the approach
/// (5 µm at v_max) 0.25 ms; 6 ms run: the controller's error is e^{-35}
/// of the start's, the sphere's ringing (period ≈ 26 µs, e = 0.5) long
/// gone. So δ and both forces are held to 1e-4 as the issue asks
/// (measured ~1e-12), on both schemes; the piston's speed to 1e-9 of
/// v_max.
#[test]
fn servo_piston_stops_at_two_hertz_contacts_in_series() {
    for scheme in [Scheme::Verlet, Scheme::Gear5] {
        for force in [1.0, 0.2] {
            let dt = 5.0e-7;
            let mut sim = Simulation::new(piston(scheme, force, dt), 1).unwrap();
            sim.step(12_000);
            let delta = 2.0 * R - piston_height(&sim);
            let want = compression(force);
            let o = sim.observe();
            let (floor, top) = (-o.wall_forces[0][2], o.wall_forces[1][2]);
            println!(
                "{scheme:?} F = {force} N: δ {delta:.6e} m vs {want:.6e} m ({:.1e}), \
                 forces {floor:.9} {top:.9} N",
                (delta - want) / want
            );
            assert!((delta - want).abs() <= 1e-4 * want, "δ {delta} vs {want}");
            for f in [floor, top] {
                assert!((f - force).abs() <= 1e-4 * force, "{f} vs {force}");
            }
            let v = o.wall_motions[0].velocity;
            assert!(v[2].abs() <= 1e-9 * 0.02, "still moving: {v:?}");
            assert_eq!(o.wall_motions[0].velocity[0], 0.0);
            // The piston's work went into the contacts (stored) and the
            // damping (dissipated): D = E₀ + W − (K + E + P) ≥ 0, and W
            // at least the energy stored, 2 × (2/5) E_eff √R (δ/2)^{5/2}.
            let stored = 0.8 * e_eff() * R.sqrt() * (0.5 * want).powf(2.5);
            let w = o.work_by_walls.unwrap();
            assert!(w >= stored * (1.0 - 1e-4) && o.dissipated_energy >= 0.0);
            assert!((o.elastic_energy - stored).abs() <= 1e-3 * stored);
        }
    }
}

/// 1 and 2 threads give the same bits; a run restarted from a checkpoint
/// taken while the piston is still moving continues with the same bits
/// (the offset, the speed and the lists' build offset are in it).
#[test]
fn servo_restart_and_threads_bit_for_bit() {
    for scheme in [Scheme::Verlet, Scheme::Gear5] {
        let s = piston(scheme, 1.0, 5.0e-7);
        let state = |sim: &Simulation| {
            format!(
                "{:?} {:?} {:?} {:?}",
                sim.positions(),
                sim.velocities(),
                sim.forces(),
                sim.observe()
            )
        };
        let (first, second) = (700, 900);
        let mut straight = Simulation::new(s.clone(), 1).unwrap();
        straight.step(first + second);
        let mut two = Simulation::new(s.clone(), 2).unwrap();
        two.step(first + second);
        assert_eq!(state(&straight), state(&two));
        let mut a = Simulation::new(s.clone(), 1).unwrap();
        a.step(first);
        let v = a.observe().wall_motions[0].velocity[2];
        assert!(v != 0.0, "the checkpoint is taken while the piston moves");
        let cp = a.checkpoint();
        let mut b = Simulation::restore(s, &cp, 2).unwrap();
        b.step(second);
        assert_eq!(state(&straight), state(&b));
    }
}

/// The piston as a triangle mesh (a 2-triangle square 4 mm wide; a mesh
/// is two-sided, it pushes the sphere below it down): the servo moves any
/// surface the same way, and the sphere under the square's middle meets
/// the same plane, so it stops at the same compression (1e-4, as above).
#[test]
fn servo_mesh_piston_stops_where_the_plane_does() {
    let z = 2.0 * R + GAP;
    let (a, b, c, d) = (
        [-2e-3, -2e-3, z],
        [2e-3, -2e-3, z],
        [2e-3, 2e-3, z],
        [-2e-3, 2e-3, z],
    );
    let mesh = Mesh::from_triangles(
        Path::new("piston.stl"),
        &[[a, b, c], [a, c, d]],
        Transform::default(),
        0,
    )
    .expect("a valid mesh");
    let mut s = piston(Scheme::Verlet, 1.0, 5.0e-7);
    s.walls[1] = WallSetup::Mesh(mesh);
    let mut sim = Simulation::new(s, 1).unwrap();
    sim.step(12_000);
    let delta = 2.0 * R - piston_height(&sim);
    let want = compression(1.0);
    println!("mesh piston: δ {delta:.6e} m vs {want:.6e} m");
    assert!((delta - want).abs() <= 1e-4 * want, "δ {delta} vs {want}");
    assert!((sim.observe().wall_forces[1][2] - 1.0).abs() <= 1e-4);
}
