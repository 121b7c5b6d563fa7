//! Edges, vertices and concave corners: one force per contact.

use super::fixtures::{cube, fine_cube, mesh, open_box, wedge};
use super::*;
use crate::walls::{plane_overlap, PlaneWall, WallPoint};

/// Every patch's contact with overlap > 0 (all patches asked, not only
/// the near ones: the rule must hold whoever asks).
fn touching(m: &MeshGeometry, x: [f64; 3], r: f64) -> Vec<(u32, WallPoint)> {
    (0..m.patch_count())
        .map(|p| (p, m.patch_contact(p, x, [0.0; 3], r)))
        .filter(|(_, c)| c.overlap > 0.0)
        .collect()
}

/// f = k Σ h n over the touching patches (a linear law).
fn force(m: &MeshGeometry, x: [f64; 3], r: f64, k: f64) -> [f64; 3] {
    let mut f = [0.0; 3];
    for (_, c) in touching(m, x, r) {
        f = geometry::add(f, geometry::scale(c.normal, k * c.overlap));
    }
    f
}

/// The largest component of |a − b|.
fn max_diff(a: [f64; 3], b: [f64; 3]) -> f64 {
    geometry::sub(a, b).iter().fold(0.0, |m, c| m.max(c.abs()))
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = geometry::norm(v);
    v.map(|c| c / l)
}

/// A sphere over the convex edge of a 90° wedge, on the bisector
/// (1, 0, 1)/√2 at distance 0.06 < r = 0.1: one touching element, normal
/// along the bisector to 1e-12, overlap r − 0.06.
#[test]
fn convex_wedge_edge_gives_one_contact_along_the_bisector() {
    let m = mesh(&wedge());
    assert_eq!(m.patch_count(), 2);
    let b = unit([1.0, 0.0, 1.0]);
    for y in [-0.7, 0.0, 0.3] {
        let x = [0.06 * b[0], y, 0.06 * b[2]];
        let t = touching(&m, x, 0.1);
        assert_eq!(t.len(), 1, "{t:?}");
        let c = t[0].1;
        assert!((c.overlap - 0.04).abs() < 1e-15);
        assert!(max_diff(c.normal, b) < 1e-12, "{:?}", c.normal);
    }
}

/// A sphere over face A near the convex edge with B: A's face contact
/// alone (B's edge point is 0.051 from the centre, within r, but A's
/// closest point is inside A, so B's candidate is dropped).
#[test]
fn face_near_a_convex_edge_hides_the_other_face() {
    let m = mesh(&wedge());
    let x = [-0.01, 0.2, 0.05];
    let t = touching(&m, x, 0.1);
    assert_eq!(t.len(), 1, "{t:?}");
    let (p, c) = t[0];
    assert_eq!(m.patches.patches[p as usize].normal, [0.0, 0.0, 1.0]);
    assert!((c.overlap - 0.05).abs() < 1e-15 && c.normal == [0.0, 0.0, 1.0]);
    // Mirrored: over B near A.
    let t = touching(&m, [0.05, -0.4, -0.01], 0.1);
    assert_eq!(t.len(), 1);
    assert_eq!(t[0].1.normal, [1.0, 0.0, 0.0]);
}

/// A cube's corner along the bisector (1, 1, 1)/√3 at 0.05 < r = 0.1:
/// one touching element, normal along the bisector to 1e-12.
#[test]
fn cube_corner_gives_one_contact_along_the_bisector() {
    let m = mesh(&cube([-1.0; 3], [0.0; 3]));
    assert_eq!(m.patch_count(), 6);
    let b = unit([1.0, 1.0, 1.0]);
    let t = touching(&m, b.map(|c| 0.05 * c), 0.1);
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0].1.overlap - 0.05).abs() < 1e-15);
    assert!(max_diff(t[0].1.normal, b) < 1e-12, "{t:?}");
}

/// The exact offset: the point of the solid box [lo, hi] closest to w
/// (w outside it), and the centre at distance ρ from the box along w's
/// direction from it, with its unit normal.
fn offset(w: [f64; 3], lo: [f64; 3], hi: [f64; 3], rho: f64) -> ([f64; 3], [f64; 3]) {
    let y = [0, 1, 2].map(|k| w[k].clamp(lo[k], hi[k]));
    let n = unit(geometry::sub(w, y));
    ([0, 1, 2].map(|k| y[k] + rho * n[k]), n)
}

/// Sweeps of 10⁴ centres at distance ρ = 0.06 from the cube [−1, 0]³
/// (12 triangles; and 2000 on a cube of 72-triangle faces)
/// (r = 0.1, so the true overlap is r − ρ = 0.04 everywhere), along a
/// path w(s) that turns around an edge (then around the corner): the
/// summed force k Σ h n equals the exact k (r − ρ) n̂ (n̂ the offset
/// surface's normal) to 1e-12, the summed overlap never exceeds r − ρ
/// (never doubled), and the force moves between neighbouring samples by
/// at most k (r − ρ) |Δn̂| ≤ k (r − ρ) |Δw|/dist(w, cube): the normal of
/// the distance function is 1/dist-Lipschitz, and dist(w) ≥ 0.03 here.
#[test]
fn force_around_an_edge_and_a_vertex_is_continuous_and_never_doubled() {
    let (lo, hi) = ([-1.0; 3], [0.0; 3]);
    // The 12-triangle cube, 10⁴ centres per path; and a cube whose faces
    // are 6 × 6 grids (72 triangles a face: the grid-searched path),
    // 2000 centres per path.
    for (m, n) in [
        (mesh(&cube(lo, hi)), 10_000),
        (mesh(&fine_cube(lo, hi, 6)), 2_000),
    ] {
        assert_eq!(m.patch_count(), 6);
        sweep(&m, lo, hi, n);
    }
}

fn sweep(m: &MeshGeometry, lo: [f64; 3], hi: [f64; 3], n: usize) {
    let (r, rho, k) = (0.1, 0.06, 1e4);
    let two_pi = std::f64::consts::TAU;
    // Around the edge x = z = 0 (along y): w on a circle of radius 0.05
    // about the edge, from over the face x = 0 (a = −1.2) around to over
    // the face z = 0 (a = π/2 + 1.2); dist(w) ≥ 0.05 cos 1.2 = 0.0181.
    let edge_path = |s: f64| {
        let a = -1.2 + (std::f64::consts::FRAC_PI_2 + 2.4) * s;
        [0.05 * a.cos(), -0.5, 0.05 * a.sin()]
    };
    // Around the corner: a circle of radius 0.05 about (−0.02, −0.02)
    // at height 0.03 (always above the top face z = 0: dist(w) ≥ 0.03),
    // over the top face, the edges x = 0 and y = 0, and the corner.
    let vertex_path = |s: f64| {
        let a = two_pi * s;
        [-0.02 + 0.05 * a.cos(), -0.02 + 0.05 * a.sin(), 0.03]
    };
    for (name, path, min_dist, regions) in [
        (
            "edge",
            &edge_path as &dyn Fn(f64) -> [f64; 3],
            0.018,
            vec![1, 2],
        ),
        (
            "vertex",
            &vertex_path as &dyn Fn(f64) -> [f64; 3],
            0.03,
            vec![1, 2, 3],
        ),
    ] {
        let mut previous: Option<([f64; 3], [f64; 3])> = None;
        let mut visited = std::collections::BTreeSet::new();
        for i in 0..=n {
            let w = path(i as f64 / n as f64);
            // 1: over a face, 2: an edge, 3: the corner (how many
            // coordinates lie outside the box).
            let outside = (0..3).filter(|&a| w[a] < lo[a] || w[a] > hi[a]).count();
            assert!(outside > 0, "{name}: the path must stay outside");
            visited.insert(outside);
            let (x, normal) = offset(w, lo, hi, rho);
            let t = touching(m, x, r);
            let total: f64 = t.iter().map(|(_, c)| c.overlap).sum();
            assert!(total <= (r - rho) + 1e-12, "{name} {i}: doubled {t:?}");
            let f = force(m, x, r, k);
            for a in 0..3 {
                assert!(
                    (f[a] - k * (r - rho) * normal[a]).abs() < 1e-12 * k,
                    "{name} {i}: {f:?}"
                );
            }
            if let Some((fp, wp)) = previous {
                let dw = geometry::norm(geometry::sub(w, wp));
                let bound = k * (r - rho) * dw / min_dist;
                let df = geometry::norm(geometry::sub(f, fp));
                assert!(
                    df <= bound * (1.0 + 1e-9) + 1e-12 * k,
                    "{name} {i}: jump {df} > {bound}"
                );
            }
            previous = Some((f, w));
        }
        // The path really crossed faces and edges (and the corner).
        assert_eq!(visited.into_iter().collect::<Vec<_>>(), regions, "{name}");
    }
}

/// A sphere in the inside corner of an open box [0, 1]³ (no top): three
/// face contacts, each equal to its analytic plane's (x = 0, y = 0,
/// z = 0, normals into the box).
#[test]
fn concave_corner_gives_the_three_planes() {
    let m = mesh(&open_box([0.0; 3], [1.0; 3]));
    let (x, r) = ([0.07, 0.05, 0.08], 0.1);
    let v = [0.3, -0.2, 0.5];
    let mut got: Vec<(f64, f64, [f64; 3])> = (0..m.patch_count())
        .map(|p| m.patch_contact(p, x, v, r))
        .filter(|c| c.overlap > 0.0)
        .map(|c| (c.overlap, c.rate, c.normal))
        .collect();
    let mut want: Vec<(f64, f64, [f64; 3])> = (0..3)
        .map(|a| {
            let mut n = [0.0; 3];
            n[a] = 1.0;
            let p = PlaneWall {
                wall: 0,
                point: [0.0; 3],
                normal: n,
                slot: 0,
                moving: None,
            };
            let (h, rate) = plane_overlap(&p, x, v, r);
            (h, rate, n)
        })
        .collect();
    let key = |a: &(f64, f64, [f64; 3])| a.0;
    got.sort_by(|a, b| key(a).total_cmp(&key(b)));
    want.sort_by(|a, b| key(a).total_cmp(&key(b)));
    assert_eq!(got, want);
    // The box's faces are oriented (outward of an open surface: from the
    // first triangle), but the contact is two-sided: inside the box the
    // normals point inward, as the planes' do.
}

/// Outside the box, below its floor's corner edge: the floor and the wall
/// meet at a convex edge seen from there: one contact.
#[test]
fn open_box_seen_from_outside_is_convex() {
    let m = mesh(&open_box([0.0; 3], [1.0; 3]));
    let b = unit([-1.0, 0.0, -1.0]);
    let x = [0.04 * b[0], 0.5, 0.04 * b[2]];
    let t = touching(&m, x, 0.1);
    assert_eq!(t.len(), 1, "{t:?}");
    assert!(max_diff(t[0].1.normal, b) < 1e-12, "{t:?}");
    // Over the rim (a free edge): the rim's rounded edge, from above.
    let t = touching(&m, [0.5, -0.03, 1.04], 0.1);
    assert_eq!(t.len(), 1);
    assert!((t[0].1.overlap - (0.1 - 0.05)).abs() < 1e-15, "{t:?}");
}

/// near_elements lists every patch that touches (and only patches within
/// the range), ascending.
#[test]
fn near_elements_lists_the_touching_patches() {
    let w = MeshWall {
        wall: 2,
        slot: 7,
        mesh: std::sync::Arc::new(mesh(&cube([-1.0; 3], [0.0; 3]))),
        moving: None,
    };
    use crate::walls::Wall;
    let x = [0.03, 0.04, -0.5];
    let mut seen = Vec::new();
    w.near_elements(x, 0.1, 0.0, &mut |e| seen.push(e));
    // Within 0.1 of x: the faces x = 0 (0.03 away) and y = 0 (0.04).
    let mut want: Vec<u32> = (0..6)
        .filter(|&p| {
            let q = &w.mesh.patches.patches[p as usize];
            (q.normal[0] == 1.0) || (q.normal[1] == 1.0)
        })
        .collect();
    want.sort();
    assert_eq!(seen, want);
    assert_eq!((w.elements(), w.law_slot(3), w.file_index()), (6, 7, 2));
    assert_eq!(w.bounding_box(), ([-1.0; 3], [0.0; 3]));
    // The surface centroid of a cube is its centre.
    for c in w.torque_point() {
        assert!((c + 0.5).abs() < 1e-15);
    }
}

/// A sphere inside the closed cube [0, 1]³ (the lattice drop's box as one
/// 12-triangle mesh): each face patch's contact equals its analytic
/// plane's (point on the face, normal into the box) bit for bit, at 2000
/// random centres, touching or not (an interior point projects inside
/// every face of a box, and −(a·n) is exactly (a·(−n))).
#[test]
fn closed_cube_from_inside_is_six_planes() {
    use rand::{Rng, SeedableRng};
    let m = mesh(&cube([0.0; 3], [1.0; 3]));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(6);
    let planes: Vec<PlaneWall> = (0..m.patch_count())
        .map(|p| {
            let q = &m.patches.patches[p as usize];
            PlaneWall {
                wall: 0,
                // The face's centre.
                point: geometry::add([0.5; 3], geometry::scale(q.normal, 0.5)),
                normal: q.normal.map(|c| -c),
                slot: 0,
                moving: None,
            }
        })
        .collect();
    let r = 0.05;
    for _ in 0..2000 {
        let x = [0, 1, 2].map(|_| rng.gen_range(0.001..0.999));
        let v = [0, 1, 2].map(|_| rng.gen_range(-1.0..1.0));
        for (p, plane) in planes.iter().enumerate() {
            let c = m.patch_contact(p as u32, x, v, r);
            let (h, rate) = plane_overlap(plane, x, v, r);
            assert_eq!((c.overlap, c.rate, c.normal), (h, rate, plane.normal));
        }
    }
}

/// Convex solids seen from outside, not aligned with the axes (a cube
/// turned 30° about (1, 2, 3), a regular octahedron turned 50° about
/// (−2, 1, 0.5), a cube of 5 × 5-grid faces turned 70° about (3, −1, 2),
/// its faces flat to round-off so one patch each): at 10⁴ random centres
/// each at distance 0.01–0.09 from
/// the surface (r = 0.1), exactly one patch touches, with overlap r − δ
/// (δ the brute-force distance to the nearest triangle) to 1e-12 and
/// normal (x − y)/δ (y that nearest point) to 1e-9 (a direction from
/// points known to ~1e-12, divided by δ ≥ 0.01).
#[test]
fn convex_solids_from_outside_give_exactly_the_closest_point() {
    use rand::{Rng, SeedableRng};
    let turn = |soup: Vec<Triangle>, axis: [f64; 3], angle: f64| -> MeshGeometry {
        let t = Transform {
            axis,
            angle_degrees: angle,
            translate: [0.1, -0.2, 0.3],
            ..Default::default()
        };
        MeshGeometry::from_triangles(Path::new("turned.stl"), &soup, &t, &MeshOptions::default())
            .unwrap()
    };
    let o = |a: usize, s: f64| {
        let mut p = [0.0; 3];
        p[a] = s;
        p
    };
    // Octahedron: faces (±x, ±y, ±z) octants, outward.
    let mut octa = Vec::new();
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                let (a, b, c) = (o(0, sx), o(1, sy), o(2, sz));
                octa.push(if sx * sy * sz > 0.0 {
                    [a, b, c]
                } else {
                    [a, c, b]
                });
            }
        }
    }
    let solids = [
        (
            "cube",
            turn(cube([-0.5; 3], [0.5; 3]), [1.0, 2.0, 3.0], 30.0),
            6,
        ),
        ("octahedron", turn(octa, [-2.0, 1.0, 0.5], 50.0), 8),
        (
            "fine cube",
            turn(fine_cube([-0.5; 3], [0.5; 3], 5), [3.0, -1.0, 2.0], 70.0),
            6,
        ),
    ];
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
    let r = 0.1;
    for (name, m, patches) in &solids {
        assert_eq!(m.patch_count(), *patches, "{name}");
        assert_eq!(m.report.open_edges, 0);
        let mut done = 0;
        while done < 10_000 {
            let x = [0, 1, 2].map(|_| rng.gen_range(-1.2..1.2));
            let (delta, y) = m
                .patches
                .tri
                .iter()
                .map(|g| {
                    let y = geometry::closest_on_triangle(x, g.corner[0], g.corner[1], g.corner[2]);
                    (geometry::norm(geometry::sub(x, y)), y)
                })
                .fold(
                    (f64::INFINITY, [0.0; 3]),
                    |a, b| if b.0 < a.0 { b } else { a },
                );
            // Outside: the nearest point's outward normal faces x.
            let outside = (0..m.patch_count()).all(|p| {
                let q = &m.patches.patches[p as usize];
                geometry::dot(geometry::sub(x, q.point), q.normal) < 0.0
            });
            if outside || !(0.01..0.09).contains(&delta) {
                continue;
            }
            done += 1;
            let t = touching(m, x, r);
            assert_eq!(t.len(), 1, "{name} at {x:?}: {t:?}");
            let c = t[0].1;
            assert!(
                (c.overlap - (r - delta)).abs() < 1e-12,
                "{name}: {c:?} δ = {delta}"
            );
            let n = geometry::scale(geometry::sub(x, y), 1.0 / delta);
            assert!(
                max_diff(c.normal, n) < 1e-9,
                "{name}: {:?} vs {n:?}",
                c.normal
            );
        }
    }
}

/// A closed slab thinner than the sphere (0.02 thick, r = 0.1): a sphere
/// 0.03 above its top face reaches the bottom face 0.05 away through the
/// slab; the bottom face is hidden behind the top one, so only the top
/// pushes (overlap 0.07). Without the slab's top (an open tray, the
/// bottom a lone plate), the bottom pushes (overlap 0.05).
#[test]
fn a_face_behind_another_is_hidden() {
    let slab = mesh(&cube([0.0, 0.0, 0.0], [1.0, 1.0, 0.02]));
    let x = [0.5, 0.4, 0.05];
    let t = touching(&slab, x, 0.1);
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0].1.overlap - 0.07).abs() < 1e-15 && t[0].1.normal == [0.0, 0.0, 1.0]);
    let tray = mesh(&open_box([0.0, 0.0, 0.0], [1.0, 1.0, 0.02]));
    let t = touching(&tray, x, 0.1);
    assert_eq!(t.len(), 1, "{t:?}");
    assert!((t[0].1.overlap - 0.05).abs() < 1e-15 && t[0].1.normal == [0.0, 0.0, 1.0]);
}

/// A valley: face A (z = 0, −1 ≤ x ≤ 0) and face B rising from the edge
/// x = 0 at angle α (z = x tan α, 0 ≤ x ≤ cos α), −1 ≤ y ≤ 1, both
/// normals up (the concave side).
fn valley(alpha: f64) -> Vec<Triangle> {
    let (c, s) = (alpha.cos(), alpha.sin());
    let a = [
        [-1.0, -1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];
    let b = [[0.0, -1.0, 0.0], [c, -1.0, s], [c, 1.0, s], [0.0, 1.0, 0.0]];
    vec![
        [a[0], a[1], a[2]],
        [a[0], a[2], a[3]],
        [b[0], b[1], b[2]],
        [b[0], b[2], b[3]],
    ]
}

/// A sphere pressed into A near a concave fold (overlap 0.03 > r(1 −
/// cos α) = 0.0015 for α = 10°, r = 0.1) crossing the line where its
/// projection enters B (x on B's normal through the edge): B's contact
/// must start at zero jump, its edge contact r − |x − e| turning into the
/// face contact r − d_B. The total force of a linear law on both sides of
/// the line 1e-9 apart agrees to 1e-7 k r (the force's slope there times
/// 2e-9 is ~1e-9 k r); dropping B's edge point (the convex rule) gave a
/// jump of k (r − d_B) ≈ 0.03 k r.
#[test]
fn a_concave_fold_is_crossed_without_a_force_jump() {
    let alpha = 10f64.to_radians();
    let m = mesh(&valley(alpha));
    assert_eq!(m.patch_count(), 2);
    let r = 0.1;
    // B's normal line through the edge point (0, y, 0): t (−sin α, cos α);
    // the point on it at distance 0.07 < r from the edge.
    let n_b = [-alpha.sin(), 0.0, alpha.cos()];
    for y in [-0.5, 0.0, 0.25] {
        let on = [0.07 * n_b[0], y, 0.07 * n_b[2]];
        let before = [on[0] - 1e-9, on[1], on[2]];
        let after = [on[0] + 1e-9, on[1], on[2]];
        let (fb, fa) = (force(&m, before, r, 1.0), force(&m, after, r, 1.0));
        assert!(max_diff(fb, fa) < 1e-7 * r, "{fb:?} {fa:?}");
        // Both faces push there: A (face, overlap r − z) and B.
        assert_eq!(touching(&m, before, r).len(), 2, "{:?}", touching(&m, before, r));
        assert_eq!(touching(&m, after, r).len(), 2);
    }
}
