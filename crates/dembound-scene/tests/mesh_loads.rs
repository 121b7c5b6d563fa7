//! Per-triangle loads on mesh walls (issue 26, `walls::mesh::loads`),
//! against statics: a sphere at rest on a 2-triangle floor loads the
//! triangle under it with its weight and the other with nothing; one on
//! the seam loads one triangle (the stated rule: the lowest id of the
//! triangles under it); a bed of sphere columns on a 16-triangle fan loads
//! each triangle with the weight of the columns standing on it, the
//! triangles' forces sum to the wall's, and the wall carries the bed's
//! weight. The collision log names the triangle hit.

mod common;

use common::grain;
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::setup::{
    DomainSetup, Mesh, NamedMaterial, Plane, RunLength, SphereInit, TimeStep, WallSetup,
};
use dembound_scene::walls::mesh::{Transform, Triangle, TriangleLoads, TriangleLoadsError};
use dembound_scene::{SceneSetup, Simulation};
use std::f64::consts::PI;
use std::path::Path;

const G: f64 = 9.81;

fn mass(r: f64) -> f64 {
    grain(1.0e7).density * 4.0 / 3.0 * PI * r.powi(3)
}

/// The square [−1, 1]² at z = 0 as 2 triangles, +z: triangle 0 below the
/// diagonal seam x = y (y < x), triangle 1 above it; each of area 2 m².
fn square() -> Vec<Triangle> {
    let (a, b, c, d) = (
        [-1.0, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    );
    vec![[a, b, c], [a, c, d]]
}

/// The disk of radius 0.5 m about the origin as a fan of `n` triangles
/// around its centre, triangle k spanning the angles [2πk/n, 2π(k+1)/n].
fn fan(n: usize) -> Vec<Triangle> {
    let rim = |k: usize| {
        let a = 2.0 * PI * (k % n) as f64 / n as f64;
        [0.5 * a.cos(), 0.5 * a.sin(), 0.0]
    };
    (0..n).map(|k| [[0.0; 3], rim(k), rim(k + 1)]).collect()
}

fn mesh_wall(soup: &[Triangle]) -> WallSetup {
    WallSetup::Mesh(
        Mesh::from_triangles(Path::new("floor.stl"), soup, Transform::default(), 0)
            .expect("a valid mesh"),
    )
}

/// Spheres of radius `r` at `centres` (at rest), Hertz + Tsuji e = 0.3,
/// frictionless, gravity −z, Δt = `dt`, on the mesh `floor`.
fn scene(floor: &[Triangle], centres: &[[f64; 3]], r: f64, dt: f64) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-1.0, -1.0, -0.01],
            upper: [1.0, 1.0, 1.0],
            periodic: [false; 3],
        },
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
        ),
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.gravity = [0.0, 0.0, -G];
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: grain(1.0e7),
    });
    for &position in centres {
        s.spheres.push(SphereInit {
            position,
            velocity: [0.0; 3],
            radius: r,
            material: 0,
            fixed: false,
            group: None,
        });
    }
    s.walls.push(mesh_wall(floor));
    s
}

/// Steps until the kinetic energy is below `rest` J, then averages the
/// per-triangle forces of wall 0 and its total force over `window`
/// steps, N.
fn settled(sim: &mut Simulation, rest: f64, window: u64) -> (Vec<[f64; 3]>, [f64; 3]) {
    sim.step((0.05 / sim.dt()).round() as u64);
    let mut done = 0;
    while sim.observe().kinetic_energy > rest {
        assert!(done < 4_000_000, "not at rest: {:?}", sim.observe());
        sim.step(1000);
        done += 1000;
    }
    let n = sim.wall_triangle_loads(0).unwrap().len();
    let (mut per, mut total) = (vec![[0.0; 3]; n], [0.0; 3]);
    for _ in 0..window {
        sim.step(1);
        let loads = sim.wall_triangle_loads(0).unwrap();
        let wall = sim.observe().wall_forces[0];
        for (sum, f) in per.iter_mut().zip(&loads.force) {
            for a in 0..3 {
                sum[a] += f[a] / window as f64;
            }
        }
        for a in 0..3 {
            total[a] += wall[a] / window as f64;
        }
    }
    (per, total)
}

/// A frictionless sphere (R = 1 mm) at rest on the 2-triangle floor at
/// (30, −20) mm, below the seam: triangle 0 carries its weight,
/// F = (0, 0, −m g) on the wall, triangle 1 nothing; the pressure is
/// m g / 2 m² and the shear 0.
///
/// Tolerance 1e-9 of m g, as the plane's load test (tests/wall_loads.rs):
/// at rest below 1e-22 J a residual ringing moves the contact force by
/// ~1e-10 m g, averaged over 1000 steps. Triangle 1 takes no contact, so
/// its force is exactly 0; the floor is exactly z = 0 (normal (0, 0, 1)
/// exactly), so the force has no tangential part and the shear is 0.
#[test]
fn a_sphere_at_rest_loads_the_triangle_under_it_with_its_weight() {
    let r = 1.0e-3;
    let mut sim = Simulation::new(scene(&square(), &[[0.03, -0.02, r]], r, 1.0e-6), 1).unwrap();
    let (per, total) = settled(&mut sim, 1e-22, 1000);
    let mg = mass(r) * G;
    println!("per triangle {per:?}, wall {total:?}, m g = {mg:e} N");
    assert!((per[0][2] + mg).abs() <= 1e-9 * mg, "{per:?}");
    assert_eq!((per[0][0], per[0][1]), (0.0, 0.0));
    assert_eq!(per[1], [0.0; 3]);
    // The wall's total is its one contact's: the same record, summed alone.
    let loads = sim.wall_triangle_loads(0).unwrap();
    assert_eq!(loads.force[0], sim.observe().wall_forces[0]);
    assert_eq!(loads.area, vec![2.0, 2.0]);
    let expected = -loads.force[0][2] / 2.0;
    assert_eq!(loads.pressure[0], expected);
    assert!((loads.pressure[0] - mg / 2.0).abs() <= 1e-9 * mg / 2.0);
    assert_eq!(
        (loads.shear[0], loads.pressure[1], loads.shear[1]),
        (0.0, 0.0, 0.0)
    );
    assert_eq!(loads.centroid[0], [1.0 / 3.0, -1.0 / 3.0, 0.0]);
    assert_eq!(loads.normal, vec![[0.0, 0.0, 1.0]; 2]);
}

/// A sphere exactly on the seam x = y (at (20, 20) mm): its centre is over
/// both triangles (within the inside tolerance); the rule gives the
/// contact to the lowest id, triangle 0, which carries m g; triangle 1
/// nothing. (Frictionless: the force is vertical, the centre never leaves
/// the seam.) Tolerance as above.
#[test]
fn a_sphere_on_the_seam_loads_one_triangle_by_the_rule() {
    let r = 1.0e-3;
    let mut sim = Simulation::new(scene(&square(), &[[0.02, 0.02, r]], r, 1.0e-6), 1).unwrap();
    let (per, total) = settled(&mut sim, 1e-22, 1000);
    let mg = mass(r) * G;
    assert_eq!(sim.positions()[0][0], sim.positions()[0][1]);
    assert!((per[0][2] + mg).abs() <= 1e-9 * mg, "{per:?}");
    assert_eq!(per[1], [0.0; 3]);
    assert!((total[2] + mg).abs() <= 1e-9 * mg, "{total:?}");
}

/// The fan triangle that the rule gives a sphere resting with its centre
/// over (x, y), from the fan's geometry alone: the sector of the centre's
/// angle; on a seam (the angle within 1e-9 rad of a multiple of 2π/n) the
/// lower of the two triangles meeting there; at the hub triangle 0 (all
/// meet there).
fn fan_triangle(x: f64, y: f64, n: usize) -> usize {
    if x == 0.0 && y == 0.0 {
        return 0;
    }
    let step = 2.0 * PI / n as f64;
    let s = y.atan2(x).rem_euclid(2.0 * PI) / step;
    let k = s.round();
    if (s - k).abs() * step < 1e-9 {
        let k = k as usize % n;
        return k.min((k + n - 1) % n);
    }
    s.floor() as usize % n
}

/// A bed of 25 columns of 4 spheres (R = 10 mm, on a 5 × 5 grid of
/// 50 mm pitch centred on the hub of a 16-triangle fan, 100 spheres) at
/// rest: frictionless, every contact vertical (columns stand straight:
/// their centres share x and y exactly, so every normal is exactly
/// vertical), so by statics each column loads the floor with 4 m g at
/// its centre and the wall carries the bed's weight 100 m g (the
/// Janssen bed without side walls). Each triangle carries 4 m g times
/// the number of columns the rule gives it ([`fan_triangle`]: 9 of the
/// columns stand on seams or the hub).
///
/// Tolerances: the columns ring down slowly (Tsuji damping of a chain
/// of Hertz contacts weakens as the ringing does: below 1e-25 J only
/// after 8 s of simulated time). At kinetic energy K below 1e-18 J a
/// column's bottom contact (stiffness k = 3F/(2δ) ≈ 7e3 N/m at F = 4 m g,
/// δ ≈ 36 µm) moves its force by up to √(2 k K) ≈ 1.2e-7 N, 7e-7 of 4 m g;
/// averaged over 1000 steps: 1e-5 of the load (measured 1.7e-6). A
/// contact given to the wrong triangle is off by 25 % or more; a triangle
/// with no column must carry exactly 0. Σ triangles against the wall's
/// force: the same 25 records summed per triangle then over 16 triangles
/// vs summed in one running sum, each a sum of at most 25 terms of one
/// sign: round-off ≤ 25 ε of the total, ~6e-15; 1e-12 leaves room and
/// would catch one lost or doubled contact (4 %).
#[test]
fn a_bed_on_a_fan_loads_each_triangle_with_its_columns_and_the_wall_with_its_weight() {
    let (r, n, pitch) = (0.01, 16, 0.05);
    let mut centres = Vec::new();
    let mut columns = vec![0usize; n];
    for i in -2i32..=2 {
        for j in -2i32..=2 {
            let (x, y) = (f64::from(i) * pitch, f64::from(j) * pitch);
            columns[fan_triangle(x, y, n)] += 1;
            for layer in 0..4 {
                centres.push([x, y, r + 2.0 * r * f64::from(layer)]);
            }
        }
    }
    let mut sim = Simulation::new(scene(&fan(n), &centres, r, 2.0e-6), 1).unwrap();
    let (per, total) = settled(&mut sim, 1e-18, 1000);
    let mg = mass(r) * G;
    println!("columns per triangle {columns:?}");
    for t in 0..n {
        let expected = -4.0 * mg * columns[t] as f64;
        println!("triangle {t}: {:e} N, expected {expected:e} N", per[t][2]);
        assert!(
            (per[t][2] - expected).abs() <= 1e-5 * 4.0 * mg,
            "triangle {t}: {per:?}"
        );
        if columns[t] == 0 {
            assert_eq!(per[t], [0.0; 3], "triangle {t}");
        }
    }
    assert!(
        (total[2] + 100.0 * mg).abs() <= 1e-5 * 100.0 * mg,
        "{total:?}"
    );
    let loads = sim.wall_triangle_loads(0).unwrap();
    let wall = sim.observe().wall_forces[0];
    let summed = loads
        .force
        .iter()
        .fold([0.0; 3], |s, f| [s[0] + f[0], s[1] + f[1], s[2] + f[2]]);
    for a in 0..3 {
        assert!(
            (summed[a] - wall[a]).abs() <= 1e-12 * wall[2].abs(),
            "Σ triangles {summed:?} vs wall {wall:?}"
        );
    }
}

/// The same bed on 1 and 2 threads: the per-triangle loads have the same
/// bits at every 500th step of the landing (records merged by input id,
/// summed per triangle in that order).
#[test]
fn triangle_loads_have_the_same_bits_on_one_and_two_threads() {
    let (r, pitch) = (0.01, 0.05);
    let mut centres = Vec::new();
    for i in -2i32..=2 {
        for j in -2i32..=2 {
            for layer in 0..4 {
                let (x, y) = (f64::from(i) * pitch, f64::from(j) * pitch);
                centres.push([x, y, 1.01 * r + 2.02 * r * f64::from(layer)]);
            }
        }
    }
    let mut one = Simulation::new(scene(&fan(16), &centres, r, 2.0e-6), 1).unwrap();
    let mut two = Simulation::new(scene(&fan(16), &centres, r, 2.0e-6), 2).unwrap();
    let mut loaded = 0;
    for _ in 0..20 {
        one.step(500);
        two.step(500);
        let a = one.wall_triangle_loads(0).unwrap();
        assert_eq!(two.wall_triangle_loads(0).unwrap(), a);
        loaded = loaded.max(a.force.iter().filter(|f| f[2] != 0.0).count());
    }
    // The bed did land on the 12 triangles the columns stand on.
    assert_eq!(loaded, 12);
}

/// Asking for the triangle loads of a wall that is not a mesh, or of no
/// wall, is an error naming the wall.
#[test]
fn triangle_loads_of_a_plane_or_a_missing_wall_are_refused() {
    let r = 1.0e-3;
    let mut s = scene(&square(), &[[0.0, 0.5, r]], r, 1.0e-6);
    s.walls.push(WallSetup::Plane(Plane {
        point: [0.0, 0.0, 0.5],
        normal: [0.0, 0.0, -1.0],
        material: 0,
    }));
    let sim = Simulation::new(s, 1).unwrap();
    assert_eq!(sim.mesh_walls(), vec![0]);
    assert_eq!(sim.wall_triangle_counts(), vec![Some(2), None]);
    let e = sim.wall_triangle_loads(1).unwrap_err();
    assert_eq!(e, TriangleLoadsError::NotMesh { wall: 1 });
    assert!(
        e.to_string().contains("wall 1 is not a triangle mesh"),
        "{e}"
    );
    let e = sim.wall_triangle_loads(2).unwrap_err();
    assert!(e.to_string().contains("wall 2 does not exist"), "{e}");
    let ok: TriangleLoads = sim.wall_triangle_loads(0).unwrap();
    assert_eq!(ok.len(), 2);
}

/// The collision log names the triangle hit: a sphere dropped onto the
/// 2-triangle floor at (0.3, −0.5) m (under triangle 0) and one at
/// (−0.3, 0.5) (under triangle 1) bounce once each (frictionless,
/// straight down); their rows are against wall 0 on triangles 0 and 1.
#[test]
fn the_collision_log_names_the_triangle_hit() {
    let r = 1.0e-3;
    let mut s = scene(
        &square(),
        &[[0.3, -0.5, 1.5 * r], [-0.3, 0.5, 1.5 * r]],
        r,
        1.0e-6,
    );
    s.collisions = true;
    let mut sim = Simulation::new(s, 1).unwrap();
    sim.step(40_000);
    let log: Vec<_> = sim.collisions().to_vec();
    assert!(log.len() >= 2, "{log:?}");
    for c in &log {
        assert_eq!(c.j, dembound_scene::Partner::Wall(0));
        assert_eq!(c.triangle, Some(c.i as u32), "{c:?}");
    }
    let mut csv = Vec::new();
    dembound_scene::io::series::write_collisions(&mut csv, &log, true).unwrap();
    let text = String::from_utf8(csv).unwrap();
    let mut lines = text.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("i,j,boundary_particle,triangle,t_start_s"));
    assert!(lines.next().unwrap().starts_with("0,wall:0,,0,"), "{text}");
}
