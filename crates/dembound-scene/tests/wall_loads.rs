//! The loads on walls (`Observation::wall_forces`, `wall_torques`): a
//! sphere at rest on a plane, against a cylinder's wall and on a floor of
//! boundary particles, against the hand formulas of statics: the wall
//! carries the sphere's weight m g, and its torque about the wall's
//! torque point c is that of the weight acting at the contact.

mod common;

use common::{grain, sphere_on_plane};
use dembound_physics::contact::tangential::TangentialKind;
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::setup::{
    BoundaryParticles, Cylinder, DomainSetup, NamedMaterial, RunLength, Scheme, SphereInit,
    TimeStep, WallSetup,
};
use dembound_scene::{SceneSetup, Simulation};

const G: f64 = 9.81;
const R: f64 = 1.0e-3;

fn damped() -> ContactModel {
    ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
    )
}

fn mass(r: f64) -> f64 {
    grain(1.0e7).density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Steps `sim` 0.1 s (the drop onto the contact and its ringing), then
/// until its kinetic energy is below `rest` J (at most `max_steps`),
/// then returns the mean force and torque on wall `wall`
/// over `window` more steps, N and N m.
fn settled_load(
    sim: &mut Simulation,
    wall: usize,
    rest: f64,
    max_steps: u64,
    window: u64,
) -> ([f64; 3], [f64; 3]) {
    sim.step((0.1 / sim.dt()).round() as u64);
    let mut done = 0;
    while sim.observe().kinetic_energy > rest {
        assert!(done < max_steps, "not at rest: {:?}", sim.observe());
        sim.step(1000);
        done += 1000;
    }
    let (mut f, mut t) = ([0.0; 3], [0.0; 3]);
    for _ in 0..window {
        sim.step(1);
        let o = sim.observe();
        for a in 0..3 {
            f[a] += o.wall_forces[wall][a] / window as f64;
            t[a] += o.wall_torques[wall][a] / window as f64;
        }
    }
    (f, t)
}

/// |a − b| ≤ tol · scale, component by component.
fn assert_close(what: &str, a: [f64; 3], b: [f64; 3], scale: f64, tol: f64) {
    let worst = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
    println!(
        "{what}: largest deviation {:.1e} of the scale",
        worst / scale
    );
    for k in 0..3 {
        assert!(
            (a[k] - b[k]).abs() <= tol * scale,
            "{what}: {a:?} vs {b:?} (tolerance {tol} × {scale})"
        );
    }
}

/// A frictionless sphere at rest on the plane z = 0 at a horizontal
/// offset d = (30, −20) mm from the plane's point (the origin, its torque
/// point): the plane takes the weight, F = m g = (0, 0, −m g), and the
/// torque d × m g = (0.02 m g, 0.03 m g, 0) about the origin (the contact
/// point lies in the plane below the centre; (p − c) × F with p − c =
/// (d, −δ) and F vertical).
///
/// Tolerance 1e-9 of m g (of m g × |d| for the torque): the sphere is at
/// rest below 1e-22 J of kinetic energy (a residual oscillation of that
/// energy moves the contact force by ~1e-10 m g), averaged over 1000
/// steps; measured 2e-14. A wrong lever arm or sign is 100 % off.
#[test]
fn a_sphere_at_rest_on_a_plane_loads_it_with_its_weight() {
    let d = [0.03, -0.02];
    let mut s = sphere_on_plane(
        R,
        grain(1.0e7),
        [d[0], d[1], R],
        [0.0; 3],
        damped(),
        None,
        Scheme::Verlet,
        1.0e-6,
    );
    s.gravity = [0.0, 0.0, -G];
    let mut sim = Simulation::new(s, 1).unwrap();
    assert_eq!(sim.wall_torque_points(), vec![[0.0; 3]]);
    let (f, t) = settled_load(&mut sim, 0, 1e-22, 2_000_000, 1000);
    let mg = mass(R) * G;
    let weight = [0.0, 0.0, -mg];
    assert_close("force", f, weight, mg, 1e-9);
    assert_close(
        "torque",
        t,
        cross([d[0], d[1], 0.0], weight),
        mg * 0.036,
        1e-9,
    );
}

/// The same sphere with friction and rolling friction (μ = 0.5,
/// μ_r = 0.3) under gravity tilted 0.1 rad in x: friction holds it, the
/// rolling resistance keeps it from rolling. The plane takes m g (with a
/// tangential part), and its torque is −(p − c) × F − τ_roll with F the
/// force on the sphere and τ_roll the rolling torque on it; the sphere at
/// rest takes no net torque, (p − x) × F + τ_roll = 0, so the torque on
/// the plane is that of the weight at the sphere's centre x:
/// (x − c) × m g. (Leaving out τ_roll gives (p − c) × m g: off by
/// R m g sin 0.1 ≈ 0.3 % of the torque, 3e6 times the tolerance.)
///
/// Tolerance 1e-9 of m g (of m g × 36 mm for the torque), averaged over
/// 10⁴ steps of the rest (the springs could still ring: their forces
/// average to the static ones); measured 1e-13.
#[test]
fn a_sphere_held_by_rolling_friction_loads_the_plane_at_its_centre() {
    let d = [0.03, -0.02];
    let mut s = sphere_on_plane(
        R,
        grain(1.0e7),
        [d[0], d[1], R],
        [0.0; 3],
        damped(),
        Some((TangentialKind::Mindlin, 0.5, 0.3)),
        Scheme::Verlet,
        1.0e-6,
    );
    let theta: f64 = 0.1;
    let g = [G * theta.sin(), 0.0, -G * theta.cos()];
    s.gravity = g;
    let mut sim = Simulation::new(s, 1).unwrap();
    let (f, t) = settled_load(&mut sim, 0, 1e-22, 4_000_000, 10_000);
    let m = mass(R);
    let weight = g.map(|a| m * a);
    let x = sim.positions()[0];
    let mg = m * G;
    assert_close("force", f, weight, mg, 1e-9);
    assert_close("torque", t, cross(x, weight), mg * 0.036, 1e-9);
}

/// A scene of radius-`R` grains in a box from `lower` to `upper`, Hertz
/// + Tsuji (e = 0.3), Δt = 1 µs.
fn scene(lower: [f64; 3], upper: [f64; 3]) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower,
            upper,
            periodic: [false; 3],
        },
        damped(),
        TimeStep::Fixed(1.0e-6),
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: grain(1.0e7),
    });
    s
}

fn sphere(position: [f64; 3], fixed: bool, group: Option<usize>) -> SphereInit {
    SphereInit {
        position,
        velocity: [0.0; 3],
        radius: R,
        material: 0,
        fixed,
        group,
    }
}

/// A sphere pressed by gravity along +x against the inside of a vertical
/// tube (axis z through c = (0, 0, 0.05), R_c = 10 mm), h = 20 mm above
/// c: the tube takes F = (m g, 0, 0) at p = (R_c, 0, 0.05 + h), so its
/// torque about c is (p − c) × F = (R_c, 0, h) × (m g, 0, 0) =
/// (0, m g h, 0). Tolerance as the plane's.
#[test]
fn a_sphere_pressed_against_a_tube_loads_it_about_its_axis_point() {
    let (rc, h) = (0.01, 0.02);
    let mut s = scene([-0.02, -0.02, 0.0], [0.02, 0.02, 0.1]);
    s.gravity = [G, 0.0, 0.0];
    s.spheres.push(sphere([rc - R, 0.0, 0.05 + h], false, None));
    s.walls.push(WallSetup::Cylinder(Cylinder {
        point: [0.0, 0.0, 0.05],
        axis: [0.0, 0.0, 1.0],
        radius: rc,
        inside: true,
        length: None,
        material: 0,
    }));
    let mut sim = Simulation::new(s, 1).unwrap();
    assert_eq!(sim.wall_torque_points(), vec![[0.0, 0.0, 0.05]]);
    let (f, t) = settled_load(&mut sim, 0, 1e-22, 2_000_000, 1000);
    let mg = mass(R) * G;
    assert_close("force", f, [mg, 0.0, 0.0], mg, 1e-9);
    assert_close("torque", t, [0.0, mg * h, 0.0], mg * h, 1e-9);
}

/// A floor of three boundary particles (group 0) at (0, 0, 0), (4R, 0, 0)
/// and (0, 4R, 0), a free sphere resting on top of the second: the wall's
/// torque point is the centroid c = (4R/3, 4R/3, 0); its force is m g and
/// its torque (x₂ − c) × m g = (8R/3, −4R/3, 0) × (0, 0, −m g) =
/// (4R/3 m g, 8R/3 m g, 0) (the contact force runs through the
/// particle's centre, no friction). Tolerance as the plane's.
#[test]
fn a_sphere_on_a_boundary_particle_floor_loads_it_about_the_centroid() {
    let mut s = scene([-0.01, -0.01, -0.01], [0.01, 0.01, 0.01]);
    s.gravity = [0.0, 0.0, -G];
    for x in [[0.0, 0.0, 0.0], [4.0 * R, 0.0, 0.0], [0.0, 4.0 * R, 0.0]] {
        s.spheres.push(sphere(x, true, Some(0)));
    }
    s.spheres.push(sphere([4.0 * R, 0.0, 2.0 * R], false, None));
    s.walls
        .push(WallSetup::BoundaryParticles(BoundaryParticles {
            first_body: 0,
            count: 3,
        }));
    let mut sim = Simulation::new(s, 1).unwrap();
    let c = sim.wall_torque_points()[0];
    assert_close("centroid", c, [4.0 * R / 3.0, 4.0 * R / 3.0, 0.0], R, 1e-15);
    let (f, t) = settled_load(&mut sim, 0, 1e-22, 2_000_000, 1000);
    let mg = mass(R) * G;
    assert_close("force", f, [0.0, 0.0, -mg], mg, 1e-9);
    let expected = [4.0 * R / 3.0 * mg, 8.0 * R / 3.0 * mg, 0.0];
    assert_close("torque", t, expected, mg * R, 1e-9);
}
