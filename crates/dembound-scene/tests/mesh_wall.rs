//! Triangle-mesh walls in the engine (issue 26), against the analytic
//! walls: a sphere sliding and rolling across the seams of a 2-triangle
//! square and a 64-triangle fan is the plane's at every step; the lattice
//! drop in a box whose six faces are one 12-triangle STL is the six
//! planes' drop; a sphere thrown at a convex edge or a corner along the
//! bisector makes one contact and rebounds along the bisector with the
//! plane's restitution.
//!
//! Expected values come from the analytic plane (the same engine, another
//! wall type: its contact is `walls::plane::plane_overlap`, which a flat
//! patch repeats operation for operation) and from closed forms.

mod common;

use common::lattice_drop;
use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::setup::{
    DomainSetup, FrictionSetup, Mesh, NamedMaterial, Plane, RunLength, SphereInit, TimeStep,
    WallSetup,
};
use dembound_scene::walls::mesh::read::write_binary_stl;
use dembound_scene::walls::mesh::{Transform, Triangle};
use dembound_scene::{SceneSetup, Simulation};
use std::path::Path;

/// The square [0, 1]² at z = 0 as 2 triangles (seam along x = y), +z.
fn square() -> Vec<Triangle> {
    let (a, b, c, d) = (
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    );
    vec![[a, b, c], [a, c, d]]
}

/// The disk of radius 0.5 about (0.5, 0.5, 0) as a fan of `n` triangles
/// around its centre (every seam a radius, all meeting at the hub), +z.
fn fan(n: usize) -> Vec<Triangle> {
    let rim = |k: usize| {
        let a = 2.0 * std::f64::consts::PI * (k % n) as f64 / n as f64;
        [0.5 + 0.5 * a.cos(), 0.5 + 0.5 * a.sin(), 0.0]
    };
    (0..n)
        .map(|k| [[0.5, 0.5, 0.0], rim(k), rim(k + 1)])
        .collect()
}

/// The box [lo, hi] as 12 outward triangles, faces in the order −x, +x,
/// −y, +y, −z, +z (the order of `common::lattice_drop`'s planes).
fn cube(lo: [f64; 3], hi: [f64; 3]) -> Vec<Triangle> {
    let mut out = Vec::new();
    for axis in 0..3 {
        for upper in [false, true] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |su: bool, sv: bool| {
                let mut p = [0.0; 3];
                p[axis] = if upper { hi[axis] } else { lo[axis] };
                p[u] = if su { hi[u] } else { lo[u] };
                p[v] = if sv { hi[v] } else { lo[v] };
                p
            };
            let (a, b, c, d) = (
                corner(false, false),
                corner(true, false),
                corner(true, true),
                corner(false, true),
            );
            if upper {
                out.extend([[a, b, c], [a, c, d]]);
            } else {
                out.extend([[a, c, b], [a, d, c]]);
            }
        }
    }
    out
}

/// A 90° wedge, the solid x < 0, z < 0: face z = 0 (−1 ≤ x ≤ 0) and face
/// x = 0 (−1 ≤ z ≤ 0), −1 ≤ y ≤ 1, meeting at the convex edge along y;
/// its bisector is (1, 0, 1)/√2.
fn wedge() -> Vec<Triangle> {
    let a = [
        [-1.0, -1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];
    let b = [
        [0.0, -1.0, 0.0],
        [0.0, -1.0, -1.0],
        [0.0, 1.0, -1.0],
        [0.0, 1.0, 0.0],
    ];
    vec![
        [a[0], a[1], a[2]],
        [a[0], a[2], a[3]],
        [b[0], b[1], b[2]],
        [b[0], b[2], b[3]],
    ]
}

fn mesh_wall(soup: &[Triangle]) -> WallSetup {
    WallSetup::Mesh(
        Mesh::from_triangles(Path::new("test.stl"), soup, Transform::default(), 0)
            .expect("a valid mesh"),
    )
}

fn floor_plane() -> WallSetup {
    WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    })
}

/// One sphere (R = 20 mm, E = 1e7 Pa, ρ = 1000 kg/m³) on the floor z = 0
/// at (x0, y0), thrown along the floor at `v` with a backspin, Hertz +
/// Tsuji e = 0.5, Mindlin μ = 0.3 and rolling friction μ_r = 0.05,
/// gravity −z, Verlet at Δt = 5 µs: it slides, the friction turns the
/// spin until it rolls, the rolling friction slows it.
fn rolling_scene(wall: WallSetup, x0: [f64; 2], v: [f64; 3]) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-0.5, -0.5, -0.1],
            upper: [1.5, 1.5, 1.0],
            periodic: [false; 3],
        },
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        ),
        TimeStep::Fixed(5.0e-6),
        RunLength::Steps(0),
    );
    s.gravity = [0.0, 0.0, -9.81];
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: common::grain(1.0e7),
    });
    s.friction = Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.3,
        rolling_friction: 0.05,
    }));
    // Started just touching (overlap 0): it settles into the floor while
    // it slides.
    s.spheres.push(SphereInit {
        position: [x0[0], x0[1], 0.02],
        velocity: v,
        radius: 0.02,
        material: 0,
        fixed: false,
        group: None,
    });
    s.walls.push(wall);
    s
}

/// Runs the mesh scene and the plane scene side by side for `steps`
/// steps, comparing after every step: positions, velocities, spins, and
/// the wall contact's history and springs (element 0 of wall 0 in both:
/// the flat patch is the mesh's element 0). Returns the final position.
fn same_at_every_step(
    soup: &[Triangle],
    x0: [f64; 2],
    v: [f64; 3],
    spin: [f64; 3],
    steps: u64,
) -> [f64; 3] {
    let mut mesh = Simulation::new(rolling_scene(mesh_wall(soup), x0, v), 1).unwrap();
    let mut plane = Simulation::new(rolling_scene(floor_plane(), x0, v), 1).unwrap();
    assert!(mesh.set_angular_velocity(0, spin) && plane.set_angular_velocity(0, spin));
    for k in 1..=steps {
        mesh.step(1);
        plane.step(1);
        // Bit-equal: the flat patch computes the plane's overlap, rate and
        // normal with the same operations (walls::mesh module doc), and
        // the rest of the pipeline is shared. A relative 1e-12 would be
        // the fallback; bit equality is what holds, so it is asserted.
        let (a, b) = (mesh.positions()[0], plane.positions()[0]);
        assert_eq!(a, b, "position at step {k}");
        assert_eq!(
            mesh.velocities(),
            plane.velocities(),
            "velocity at step {k}"
        );
        assert_eq!(
            mesh.angular_velocities(),
            plane.angular_velocities(),
            "spin at step {k}"
        );
        if k % 50 == 0 {
            let (cm, cp) = (mesh.checkpoint(), plane.checkpoint());
            assert_eq!(
                format!("{:?} {:?}", cm.plane_histories, cm.plane_shear),
                format!("{:?} {:?}", cp.plane_histories, cp.plane_shear),
                "springs at step {k}"
            );
            assert!(cm.element_records.is_empty());
        }
    }
    mesh.positions()[0]
}

/// Seam invariance, 2 triangles: from (0.3, 0.45) at (1, 0.2) m/s with a
/// backspin of −40 rad/s about y, the centre crosses the diagonal seam
/// x = y (asserted) and stays over the square.
#[test]
fn sphere_sliding_and_rolling_across_a_two_triangle_seam_is_the_planes() {
    let end = same_at_every_step(
        &square(),
        [0.3, 0.45],
        [1.0, 0.2, 0.0],
        [0.0, -40.0, 0.0],
        120_000,
    );
    println!("2 triangles: end at {end:?}");
    assert!(end[0] > end[1], "crossed the seam x = y: {end:?}");
    assert!(
        end[0] < 1.0 && end[1] < 1.0,
        "stayed over the square: {end:?}"
    );
}

/// Seam invariance, a 64-triangle fan: across the hub, where all 64
/// triangles meet (along y = 0.5 exactly), and obliquely across a run of
/// radial seams, with a spin about an axis in the plane and one about z.
#[test]
fn sphere_sliding_and_rolling_across_a_64_triangle_fan_is_the_planes() {
    let fan = fan(64);
    let end = same_at_every_step(
        &fan,
        [0.25, 0.5],
        [1.2, 0.0, 0.0],
        [0.0, -10.0, 5.0],
        80_000,
    );
    println!("fan through the hub: end at {end:?}");
    assert!(end[0] > 0.5, "crossed the hub: {end:?}");
    let end = same_at_every_step(
        &fan,
        [0.3, 0.25],
        [0.6, 0.7, 0.0],
        [20.0, 10.0, -3.0],
        80_000,
    );
    println!("fan obliquely: end at {end:?}");
    let d = ((end[0] - 0.5).powi(2) + (end[1] - 0.5).powi(2)).sqrt();
    assert!(d < 0.5 - 0.02, "stayed over the disk: {end:?}");
}

/// The f32 value of x (what a binary STL stores).
fn f32_exact(x: f64) -> f64 {
    x as f32 as f64
}

/// Mesh = analytic: the lattice drop (8 × 8 × 12 = 768 spheres, elastic
/// Hertz, no damping or friction, 40,000 steps of 2 µs = 0.08 s: the
/// bottom layer, 5 µm above the floor, lands after 1 ms, the layers above
/// collapse onto it and the side walls, and the elastic pile bounces) in a
/// box whose six faces are one 12-triangle binary STL, against the six
/// planes on the same faces. The STL stores f32 coordinates, so both boxes
/// are the f32 values of the drop's box (shifted by < 1e-9 m).
///
/// Asserted: contact counts (particle and wall) and kinetic energy equal
/// at every step to 1e-9 relative, as asked; what holds is bit equality
/// throughout (each patch is its plane with the plane's arithmetic, and
/// its element order −x … +z is the planes' wall order, so every sphere's
/// forces are summed in the same order), and the final states are
/// compared bit for bit.
#[test]
fn lattice_drop_in_a_twelve_triangle_stl_box_is_the_six_planes() {
    let steps = 40_000;
    let planes = {
        let mut s = lattice_drop(8, 12, 2.0e-6, steps);
        s.domain.upper = s.domain.upper.map(f32_exact);
        for w in &mut s.walls {
            if let WallSetup::Plane(p) = w {
                p.point = p.point.map(f32_exact);
            }
        }
        s
    };
    let dir = tempfile::tempdir().unwrap();
    let stl = dir.path().join("box.stl");
    write_binary_stl(&stl, &cube(planes.domain.lower, planes.domain.upper)).unwrap();
    let meshed = {
        let mut s = planes.clone();
        let m = Mesh::load(&stl, Transform::default(), 0).expect("the STL loads");
        assert_eq!(
            (m.geometry.triangles.len(), m.geometry.patch_count()),
            (12, 6)
        );
        assert_eq!(
            (m.geometry.lo, m.geometry.hi),
            (s.domain.lower, s.domain.upper)
        );
        s.walls = vec![WallSetup::Mesh(m)];
        s
    };
    let mut a = Simulation::new(planes, 1).unwrap();
    let mut b = Simulation::new(meshed, 1).unwrap();
    let mut most_wall_contacts = 0;
    for k in 1..=steps {
        a.step(1);
        b.step(1);
        let (ka, kb) = (a.kinetic_energy(), b.kinetic_energy());
        assert!(
            (ka - kb).abs() <= 1e-9 * ka.abs(),
            "kinetic energy at step {k}: {ka} vs {kb}"
        );
        assert_eq!(ka, kb, "kinetic energy bits at step {k}");
        assert_eq!(
            (a.particle_contacts(), a.wall_contacts()),
            (b.particle_contacts(), b.wall_contacts()),
            "contact counts at step {k}"
        );
        most_wall_contacts = most_wall_contacts.max(a.wall_contacts());
    }
    // The drop did reach the walls: the floor carries the bottom layer.
    println!("lattice in an STL box: bit-equal for {steps} steps, up to {most_wall_contacts} wall contacts");
    assert!(most_wall_contacts >= 64, "{most_wall_contacts}");
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.velocities(), b.velocities());
    // The summed wall force is the same vector (one wall against six:
    // the planes' forces summed in wall order).
    let summed = a
        .wall_forces()
        .iter()
        .fold([0.0; 3], |s, f| [s[0] + f[0], s[1] + f[1], s[2] + f[2]]);
    let mesh_force = b.wall_forces()[0];
    for c in 0..3 {
        // Summation orders differ (per contact into one wall, or per wall
        // then across walls): round-off of a sum of ~100 terms, 1e-12 of
        // the weight.
        let weight = 768.0 * 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.5e-3f64.powi(3) * 9.81;
        assert!(
            (summed[c] - mesh_force[c]).abs() < 1e-12 * weight + 1e-9 * summed[c].abs(),
            "{summed:?} vs {mesh_force:?}"
        );
    }
}

/// One sphere (R = 1 mm, E = 1e7 Pa, elastic Hertz, no gravity or
/// friction) at `x` moving at `v` towards a fixed wall; Verlet at `dt`.
fn throw(wall: WallSetup, x: [f64; 3], v: [f64; 3], dt: f64) -> Simulation {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-1.0; 3],
            upper: [1.0; 3],
            periodic: [false; 3],
        },
        ContactModel::elastic(NormalLaw::Hertz),
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: common::grain(1.0e7),
    });
    s.spheres.push(SphereInit {
        position: x,
        velocity: v,
        radius: 1.0e-3,
        material: 0,
        fixed: false,
        group: None,
    });
    s.walls.push(wall);
    Simulation::new(s, 1).unwrap()
}

/// Throws the sphere from `gap` (m) beyond touching along −`unit` at
/// `speed` and runs until it has left contact and moved `gap` away; the
/// largest number of wall contacts at once and the final velocity.
fn bounce(
    wall: WallSetup,
    apex: [f64; 3],
    unit: [f64; 3],
    speed: f64,
    dt: f64,
) -> (usize, [f64; 3]) {
    let (r, gap) = (1.0e-3, 1.0e-4);
    let x = [0, 1, 2].map(|k| apex[k] + (r + gap) * unit[k]);
    let v = unit.map(|u| -speed * u);
    let mut sim = throw(wall, x, v, dt);
    let mut most = 0;
    // 2 gaps at the speed, plus the contact (Hertz contact time ≈ 0.3 ms
    // here), with margin.
    let steps = ((2.0 * gap / speed + 1.0e-3) / dt) as u64;
    for _ in 0..steps {
        sim.step(1);
        most = most.max(sim.wall_contacts());
    }
    assert_eq!(sim.wall_contacts(), 0, "left the wall");
    (most, sim.velocities()[0])
}

fn angle(a: [f64; 3], b: [f64; 3]) -> f64 {
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let c = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    c.atan2(dot)
}

fn length(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Edges and vertices: a sphere thrown at 0.1 m/s along the bisector onto
/// the convex edge of a 90° wedge (bisector (1, 0, 1)/√2) and onto a
/// cube's corner (bisector (1, 1, 1)/√3). One contact at a time (the edge
/// or the vertex, not two or three faces), the rebound along the bisector
/// to 1e-9 rad, and the restitution of the elastic contact equal to the
/// plane's: the closest-feature contact's overlap r − |x − c| is the
/// plane's r − d up to the round-off of a square root (the normal force is
/// the same flat Hertz law, R_eff = R), so the two restitutions agree to
/// 1e-12 while each differs from 1 by Verlet's error.
///
/// The integration error, bounded: Verlet's energy error over an elastic
/// Hertz contact is O((Δt/t_c)²); measured on the plane at Δt = 2 µs and
/// 1 µs (t_c ≈ 0.3 ms here: R = 1 mm, E = 1e7 Pa, 0.1 m/s), |e − 1| must
/// fall by ≥ 3 (second order: 4) and stay below 1e-3.
#[test]
fn a_sphere_on_a_convex_edge_or_corner_rebounds_along_the_bisector_like_on_a_plane() {
    let speed = 0.1;
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    let s3 = 1.0 / 3.0f64.sqrt();
    let plane_e = |dt: f64| {
        let (most, v) = bounce(floor_plane(), [0.0; 3], [0.0, 0.0, 1.0], speed, dt);
        assert_eq!(most, 1);
        v[2] / speed
    };
    let (coarse, fine) = (plane_e(2.0e-6), plane_e(1.0e-6));
    println!(
        "plane: e − 1 = {:.3e} at Δt = 2 µs, {:.3e} at 1 µs",
        coarse - 1.0,
        fine - 1.0
    );
    assert!((coarse - 1.0).abs() < 1e-3, "{coarse}");
    assert!(
        (fine - 1.0).abs() * 3.0 <= (coarse - 1.0).abs() || (fine - 1.0).abs() < 1e-12,
        "second order: {coarse} {fine}"
    );
    // (name, mesh, a point of the feature, the bisector)
    let cases = [
        ("wedge edge", wedge(), [0.0, 0.3, 0.0], [s2, 0.0, s2]),
        (
            "cube corner",
            cube([-1.0; 3], [0.0; 3]),
            [0.0; 3],
            [s3, s3, s3],
        ),
    ];
    for (name, soup, apex, unit) in cases {
        let dt = 1.0e-6;
        let (most, v) = bounce(mesh_wall(&soup), apex, unit, speed, dt);
        let e = length(v) / speed;
        let off = angle(v, unit);
        println!(
            "{name}: {most} contact(s), e − 1 = {:.3e}, {off:.2e} rad off the bisector",
            e - 1.0
        );
        assert_eq!(most, 1, "{name}: one contact at a time");
        assert!(off < 1e-9, "{name}: {off} rad off the bisector, v = {v:?}");
        assert!(
            (e - fine).abs() < 1e-12,
            "{name}: e = {e}, on a plane {fine}"
        );
    }
}

/// `common::frictional_lattice(8, 10)` (640 spheres, Mindlin μ = 0.5,
/// rolling friction 0.05, the collision log on) with its six planes
/// replaced by one mesh of the box (12 triangles, f64 corners) whose
/// faces take the model's friction.
fn frictional_mesh_box() -> SceneSetup {
    let mut s = common::frictional_lattice(8, 10, 2.0e-6);
    s.walls = vec![mesh_wall(&cube(s.domain.lower, s.domain.upper))];
    if let Some(f) = &mut s.friction {
        f.walls = vec![None];
    }
    s
}

/// Threads: the frictional drop in a mesh box on 1 and 2 threads ends in
/// the same state to the bit (positions, velocities, spins, forces,
/// torques, observables with the wall load, collision log).
#[test]
fn a_mesh_box_on_one_and_two_threads_is_the_same_to_the_bit() {
    let s = frictional_mesh_box();
    let mut one = Simulation::new(s.clone(), 1).unwrap();
    let mut two = Simulation::new(s, 2).unwrap();
    one.step(3000);
    two.step(3000);
    assert!(one.wall_contacts() > 50, "{}", one.wall_contacts());
    assert_eq!(common::state(&one), common::state(&two));
}

/// Checkpoints: the frictional drop in a mesh box stopped after 1,500
/// steps (on 2 threads), restored from its checkpoint and run 1,500 more
/// (on 1) is the uninterrupted run to the bit: the springs on the mesh's
/// patches (elements 0 … 5: the element records) are carried.
#[test]
fn a_mesh_box_restarted_from_a_checkpoint_is_the_uninterrupted_run() {
    let s = frictional_mesh_box();
    let mut straight = Simulation::new(s.clone(), 1).unwrap();
    straight.step(3000);
    let mut first = Simulation::new(s.clone(), 2).unwrap();
    first.step(1500);
    let cp = first.checkpoint();
    // Wall springs on patches other than element 0 are in the checkpoint.
    assert!(!cp.element_records.is_empty());
    let mut rest = Simulation::restore(s, &cp, 1).unwrap();
    rest.step(1500);
    assert_eq!(common::state(&straight), common::state(&rest));
    // Another mesh (the box 1 µm wider) is another wall: since restarts
    // into changed walls (issue 28 item 5, `restart_walls`) the old mesh
    // is dropped with its contacts' histories and the new one added, so
    // the restore is taken (it was refused before).
    let mut other = frictional_mesh_box();
    let (lo, mut hi) = (other.domain.lower, other.domain.upper);
    hi[0] += 1e-6;
    other.walls = vec![mesh_wall(&cube(lo, hi))];
    assert!(Simulation::restore(other, &cp, 1).is_ok());
}
