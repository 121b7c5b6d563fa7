//! Seam invariance at the geometry level: a mesh of a plane, however it
//! is triangulated, gives the analytic plane's contact.

use super::fixtures::{fan, mesh, square};
use super::read::{write_ascii_stl, write_binary_stl};
use super::*;
use crate::walls::{plane_overlap, PlaneWall};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn plane(point: [f64; 3], normal: [f64; 3]) -> PlaneWall {
    PlaneWall {
        wall: 0,
        point,
        normal,
        slot: 0,
        moving: None,
    }
}

/// The mesh's contact on element 0 equals the plane's bit for bit
/// (overlap, rate, normal) at `x` for a sphere of radius r moving at v.
fn assert_same_as_plane(m: &MeshGeometry, p: &PlaneWall, x: [f64; 3], v: [f64; 3], r: f64) {
    let c = m.patch_contact(0, x, v, r);
    let (h, rate) = plane_overlap(p, x, v, r);
    assert_eq!(
        (c.overlap, c.rate, c.normal),
        (h, rate, p.normal),
        "x = {x:?}"
    );
}

fn random_velocity(rng: &mut ChaCha8Rng) -> [f64; 3] {
    [0, 1, 2].map(|_| rng.gen_range(-2.0..2.0))
}

/// 2-triangle square at z = 0.37: 4000 random centres over it, the
/// diagonal seam (x = y exactly), its four sides and corners, heights
/// from touching to deep: the plane's numbers exactly.
#[test]
fn square_of_two_triangles_is_the_plane() {
    let m = mesh(&square(0.37));
    assert_eq!(m.patch_count(), 1);
    let p = plane([0.5, 0.5, 0.37], [0.0, 0.0, 1.0]);
    let mut rng = ChaCha8Rng::seed_from_u64(26);
    let r = 0.1;
    for i in 0..4000 {
        let h = rng.gen_range(0.0..r);
        let (u, w) = match i % 4 {
            0 | 1 => (rng.gen_range(0.0..=1.0), rng.gen_range(0.0..=1.0)),
            2 => {
                let t = rng.gen_range(0.0..=1.0);
                (t, t) // on the seam
            }
            _ => {
                let t: f64 = rng.gen_range(0.0..=1.0);
                [(t, 0.0), (1.0, t), (t, 1.0), (0.0, t)][rng.gen_range(0..4)]
            }
        };
        assert_same_as_plane(&m, &p, [u, w, 0.37 + h], random_velocity(&mut rng), r);
    }
    for corner in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]] {
        assert_same_as_plane(&m, &p, [corner[0], corner[1], 0.4], [0.0, 0.0, -1.0], r);
    }
}

/// A disk of 64 fan triangles about (0.3, −0.2) at z = −1.25: centres
/// over it (inside the inscribed polygon, radius R cos(π/64)), on the
/// spokes, and exactly over the centre vertex where all 64 meet.
#[test]
fn fan_disk_of_64_triangles_is_the_plane() {
    let (cx, cy, z, radius) = (0.3, -0.2, -1.25, 1.0);
    let m = mesh(&fan(64, cx, cy, z, radius));
    assert_eq!(m.patch_count(), 1);
    assert_eq!(m.report.open_edges, 64);
    let p = plane([cx, cy, z], [0.0, 0.0, 1.0]);
    let inscribed = radius * (std::f64::consts::PI / 64.0).cos();
    let mut rng = ChaCha8Rng::seed_from_u64(64);
    let r = 0.05;
    for i in 0..4000 {
        let h = rng.gen_range(0.0..r);
        let (rho, a) = if i % 2 == 0 {
            (
                inscribed * rng.gen_range(0.0f64..1.0).sqrt(),
                rng.gen_range(0.0..std::f64::consts::TAU),
            )
        } else {
            // On a spoke (up to the round-off of cos and sin).
            let k = rng.gen_range(0..64) as f64;
            (
                rng.gen_range(0.0..inscribed),
                std::f64::consts::TAU * k / 64.0,
            )
        };
        let x = [cx + rho * a.cos(), cy + rho * a.sin(), z + h];
        assert_same_as_plane(&m, &p, x, random_velocity(&mut rng), r);
    }
    assert_same_as_plane(&m, &p, [cx, cy, z + 0.01], [0.3, 0.0, -1.0], r);
    assert_same_as_plane(&m, &p, [cx, cy, z], [0.0; 3], r);
}

/// A flat 50 × 50 grid of 5000 triangles (one patch, looked up through
/// the search grid rather than tested triangle by triangle): the plane's
/// numbers at 3000 centres, a third on grid lines and diagonals.
#[test]
fn large_flat_patch_uses_the_grid_and_is_the_plane() {
    let n = 50;
    let z = 2.5;
    let mut soup = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x0, y0) = (i as f64 / n as f64, j as f64 / n as f64);
            let (x1, y1) = ((i + 1) as f64 / n as f64, (j + 1) as f64 / n as f64);
            soup.push([[x0, y0, z], [x1, y0, z], [x1, y1, z]]);
            soup.push([[x0, y0, z], [x1, y1, z], [x0, y1, z]]);
        }
    }
    let m = mesh(&soup);
    assert_eq!((m.patch_count(), m.triangles.len()), (1, 2 * n * n));
    let p = plane([0.0, 0.0, z], [0.0, 0.0, 1.0]);
    let mut rng = ChaCha8Rng::seed_from_u64(50);
    let r = 0.02;
    for i in 0..3000 {
        let (u, w): (f64, f64) = (rng.gen_range(0.0..=1.0), rng.gen_range(0.0..=1.0));
        let (u, w) = match i % 3 {
            0 => (u, w),
            1 => ((u * n as f64).round() / n as f64, w), // on a grid line
            _ => (u, u),                                 // on diagonals
        };
        let x = [u, w, z + rng.gen_range(0.0..r)];
        assert_same_as_plane(&m, &p, x, random_velocity(&mut rng), r);
    }
}

/// A tilted square (rotated 30° about (1, 1, 0), shifted): its patch
/// normal comes from the rotated vertices' cross products, the plane's
/// from rotating (0, 0, 1): each agrees with the exact normal to a few
/// ulp (~1e-15 allowed per component), and the plane points lie on the
/// exact plane to ~1e-16, so with |x − p| ≤ 2 the distances, hence the
/// overlaps, agree to 5e-15 m (5e-14 of r).
#[test]
fn tilted_square_matches_its_plane_to_round_off() {
    let t = Transform {
        scale: 1.0,
        translate: [0.2, -0.1, 0.7],
        axis: [1.0, 1.0, 0.0],
        angle_degrees: 30.0,
    };
    let m = MeshGeometry::from_triangles(
        Path::new("tilted.stl"),
        &square(0.0),
        &t,
        &MeshOptions::default(),
    )
    .unwrap();
    assert_eq!(m.patch_count(), 1);
    let origin = t.apply([0.0; 3]);
    let up = geometry::sub(t.apply([0.0, 0.0, 1.0]), origin);
    let p = plane(origin, up);
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let r = 0.1;
    for _ in 0..2000 {
        let local = [
            rng.gen_range(0.0..=1.0),
            rng.gen_range(0.0..=1.0),
            rng.gen_range(0.0..r),
        ];
        let x = t.apply(local);
        let v = random_velocity(&mut rng);
        let c = m.patch_contact(0, x, v, r);
        let (h, rate) = plane_overlap(&p, x, v, r);
        assert!((c.overlap - h).abs() <= 5e-15, "{} {h}", c.overlap);
        // |v| ≤ 3.5 m/s times the normals' difference.
        assert!((c.rate - rate).abs() <= 1e-14, "{} {rate}", c.rate);
        let diff = geometry::sub(c.normal, up);
        assert!(diff.iter().all(|d| d.abs() <= 1e-15), "{diff:?}");
    }
}

/// The square and the fan written as ASCII and as binary STL read back
/// to the same triangles, and the read fan is still exactly its plane
/// (z = 0.5 and the rim's f32 coordinates are exact in f64).
#[test]
fn ascii_and_binary_stl_read_back_alike() {
    let dir = tempfile::tempdir().unwrap();
    let disk = fan(64, 0.0, 0.0, 0.5, 1.0);
    for (name, soup) in [("square", square(0.5)), ("disk", disk)] {
        let ascii = dir.path().join(format!("{name}_ascii.stl"));
        let binary = dir.path().join(format!("{name}_binary.stl"));
        write_ascii_stl(&ascii, &soup).unwrap();
        write_binary_stl(&binary, &soup).unwrap();
        let a = MeshGeometry::load(&ascii, &Transform::default(), &MeshOptions::default()).unwrap();
        let b =
            MeshGeometry::load(&binary, &Transform::default(), &MeshOptions::default()).unwrap();
        assert_eq!(a.vertices, b.vertices);
        assert_eq!(a.triangles, b.triangles);
        assert_eq!(a.patch_count(), 1);
        // Every vertex within f32 rounding (2⁻²⁴ relative, |c| ≤ 1) of the
        // f64 original.
        for (t, orig) in a.triangles.iter().zip(&soup) {
            for (i, o) in t.iter().zip(orig) {
                let diff = geometry::sub(a.vertices[*i as usize], *o);
                assert!(diff.iter().all(|d| d.abs() <= 6e-8), "{diff:?}");
            }
        }
        let p = plane([0.0, 0.0, 0.5], [0.0, 0.0, 1.0]);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..500 {
            let (rho, ang) = (
                0.95 * rng.gen_range(0.0f64..1.0).sqrt(),
                rng.gen_range(0.0..std::f64::consts::TAU),
            );
            let (u, w) = if name == "square" {
                (rng.gen_range(0.0..=1.0), rng.gen_range(0.0..=1.0))
            } else {
                (rho * f64::cos(ang), rho * f64::sin(ang))
            };
            let x = [u, w, 0.5 + rng.gen_range(0.0..0.1)];
            assert_same_as_plane(&b, &p, x, random_velocity(&mut rng), 0.1);
        }
    }
}

/// Cost of a face contact against the plane's (prints ns per call; no
/// assertion on time): `cargo test --release -p dembound-scene --lib
/// contact_cost -- --ignored --nocapture`.
#[test]
#[ignore]
fn contact_cost() {
    use std::hint::black_box;
    use std::time::Instant;
    let p = plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let floor = mesh(&square(0.0));
    let tray = mesh(&super::fixtures::open_box([0.0; 3], [1.0, 1.0, 0.5]));
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let xs: Vec<[f64; 3]> = (0..4096)
        .map(|_| {
            [
                rng.gen_range(0.1..0.9),
                rng.gen_range(0.1..0.9),
                rng.gen_range(0.0..0.02),
            ]
        })
        .collect();
    let floor_patch = (0..tray.patch_count())
        .find(|&q| tray.patches.patches[q as usize].normal[2] != 0.0)
        .unwrap();
    let reps = 500;
    let time = |f: &dyn Fn([f64; 3]) -> f64| {
        let start = Instant::now();
        let mut s = 0.0;
        for _ in 0..reps {
            for x in &xs {
                s += f(black_box(*x));
            }
        }
        black_box(s);
        start.elapsed().as_secs_f64() * 1e9 / (reps * xs.len()) as f64
    };
    let v = [0.0, 0.0, -1.0];
    let tp = time(&|x| plane_overlap(&p, x, v, 0.01).0);
    let tf = time(&|x| floor.patch_contact(0, x, v, 0.01).overlap);
    let tt = time(&|x| tray.patch_contact(floor_patch, x, v, 0.01).overlap);
    eprintln!("ns per contact: plane {tp:.1}, 2-triangle floor {tf:.1}, floor of a 10-triangle tray {tt:.1}");
}
