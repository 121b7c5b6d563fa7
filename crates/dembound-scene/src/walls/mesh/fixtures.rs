//! Test meshes, as triangle soups (every triangle its own copy of its
//! vertices, as STL stores them).

use super::read::Triangle;
use super::{MeshGeometry, MeshOptions, Transform};
use std::path::Path;

/// The unit square [0, 1]² at height z, as 2 triangles, normal +z.
pub fn square(z: f64) -> Vec<Triangle> {
    let (a, b, c, d) = ([0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]);
    vec![[a, b, c], [a, c, d]]
}

/// A disk of radius `radius` about (cx, cy, z), a fan of `n` triangles
/// around its centre, normal +z.
pub fn fan(n: usize, cx: f64, cy: f64, z: f64, radius: f64) -> Vec<Triangle> {
    let rim = |k: usize| {
        let a = 2.0 * std::f64::consts::PI * (k % n) as f64 / n as f64;
        [cx + radius * a.cos(), cy + radius * a.sin(), z]
    };
    (0..n).map(|k| [[cx, cy, z], rim(k), rim(k + 1)]).collect()
}

/// The two outward triangles of the box face normal to `axis` on side
/// `upper`.
fn box_face(lo: [f64; 3], hi: [f64; 3], axis: usize, upper: bool) -> [Triangle; 2] {
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
    // (u, v, axis) is right-handed: a → b → c turns about +axis.
    if upper {
        [[a, b, c], [a, c, d]]
    } else {
        [[a, c, b], [a, d, c]]
    }
}

/// The closed box [lo, hi] as 12 outward triangles: faces in the order
/// −x, +x, −y, +y, −z, +z.
pub fn cube(lo: [f64; 3], hi: [f64; 3]) -> Vec<Triangle> {
    let mut out = Vec::new();
    for axis in 0..3 {
        for upper in [false, true] {
            out.extend(box_face(lo, hi, axis, upper));
        }
    }
    out
}

/// The closed box [lo, hi] with each face an n × n grid of squares, 2
/// triangles each (12 n² outward triangles; faces of more than 8
/// triangles are searched through the grid).
pub fn fine_cube(lo: [f64; 3], hi: [f64; 3], n: usize) -> Vec<Triangle> {
    let mut out = Vec::new();
    for axis in 0..3 {
        for upper in [false, true] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let at = |i: usize, j: usize| {
                let mut p = [0.0; 3];
                p[axis] = if upper { hi[axis] } else { lo[axis] };
                p[u] = lo[u] + (hi[u] - lo[u]) * i as f64 / n as f64;
                p[v] = lo[v] + (hi[v] - lo[v]) * j as f64 / n as f64;
                p
            };
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    if upper {
                        out.extend([[a, b, c], [a, c, d]]);
                    } else {
                        out.extend([[a, c, b], [a, d, c]]);
                    }
                }
            }
        }
    }
    out
}

/// The box [lo, hi] without its top (+z) face: 10 triangles.
pub fn open_box(lo: [f64; 3], hi: [f64; 3]) -> Vec<Triangle> {
    let mut t = cube(lo, hi);
    t.truncate(10);
    t
}

/// A 90° wedge: face A (z = 0, −1 ≤ x ≤ 0) and face B (x = 0,
/// −1 ≤ z ≤ 0), −1 ≤ y ≤ 1, meeting at the convex edge along y; normals
/// +z and +x (out of the solid x < 0, z < 0).
pub fn wedge() -> Vec<Triangle> {
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

/// The mesh of `soup` with default options, unplaced.
pub fn mesh(soup: &[Triangle]) -> MeshGeometry {
    MeshGeometry::from_triangles(
        Path::new("test.stl"),
        soup,
        &Transform::default(),
        &MeshOptions::default(),
    )
    .expect("a valid test mesh")
}
