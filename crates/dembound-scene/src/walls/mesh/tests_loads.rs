//! Which triangle a contact loads (`loads::triangle_of`), against the
//! rule worked out by hand from the triangles as written: the triangle
//! under the centre (on a seam or a grid vertex, the lowest id of those
//! containing the projection), the face triangle holding a convex edge,
//! the lowest-id face triangle holding a corner.

use super::fixtures::{cube, fine_cube, mesh};
use super::*;

/// The triangles of `soup` (ids as written: nothing is dropped from
/// these fixtures) that contain the point q of their plane, by
/// barycentric coordinates ≥ −1e-12.
fn containing(soup: &[Triangle], q: [f64; 3], ids: std::ops::Range<usize>) -> Vec<u32> {
    ids.filter(|&t| {
        let [a, b, c] = soup[t];
        let (v0, v1, v2) = (sub(b, a), sub(c, a), sub(q, a));
        let d = |u: [f64; 3], w: [f64; 3]| geometry::dot(u, w);
        let (d00, d01, d11, d20, d21) = (d(v0, v0), d(v0, v1), d(v1, v1), d(v2, v0), d(v2, v1));
        let den = d00 * d11 - d01 * d01;
        let v = (d11 * d20 - d01 * d21) / den;
        let w = (d00 * d21 - d01 * d20) / den;
        v >= -1e-12 && w >= -1e-12 && 1.0 - v - w >= -1e-12
    })
    .map(|t| t as u32)
    .collect()
}

/// A convex edge and a corner of the unit cube (faces −x, +x, −y, +y,
/// −z, +z, two triangles each, patches in that order): a sphere beyond
/// the edge x = y = 1 touches it once, on patch 1 (+x, the lower of +x
/// and +y); its triangle is the +x triangle (2 or 3) with two corners on
/// that edge. Beyond the corner (1, 1, 1): patch 1 again, and the lower
/// of the +x triangles with that corner.
#[test]
fn edge_and_vertex_contacts_go_to_the_face_triangle_holding_them() {
    let soup = cube([0.0; 3], [1.0; 3]);
    let m = mesh(&soup);
    assert_eq!(m.triangles.len(), 12);
    let (x, r) = ([1.1, 1.1, 0.5], 0.2);
    assert!(m.patch_contact(1, x, [0.0; 3], r).overlap > 0.0);
    let on_edge = |t: usize| soup[t].iter().filter(|v| v[0] == 1.0 && v[1] == 1.0).count() == 2;
    let expected: Vec<u32> = (2..4).filter(|&t| on_edge(t)).map(|t| t as u32).collect();
    assert_eq!(expected.len(), 1);
    assert_eq!(m.triangle_of(1, x, r), Some(expected[0]));
    let x = [1.1, 1.1, 1.1];
    assert!(m.patch_contact(1, x, [0.0; 3], r).overlap > 0.0);
    let expected = (2..4)
        .find(|&t| soup[t].contains(&[1.0, 1.0, 1.0]))
        .map(|t| t as u32);
    assert_eq!(m.triangle_of(1, x, r), expected);
    // Not a patch: none.
    assert_eq!(m.triangle_of(6, x, r), None);
}

/// Face contacts over a face of 32 triangles (searched through the grid):
/// centres over the middle of a triangle, on its seams and on grid
/// vertices where 6 triangles meet; the triangle is the lowest id of
/// those containing the projection.
#[test]
fn face_contacts_go_to_the_lowest_triangle_under_the_centre() {
    let soup = fine_cube([0.0; 3], [1.0; 3], 4);
    let m = mesh(&soup);
    // The +z face: the last 32 triangles (faces −x, +x, −y, +y, −z, +z).
    let face = 5 * 32..6 * 32;
    let p = m.patches.tri[face.start].patch;
    let r = 0.1;
    let mut seams = 0;
    for i in 0..=16 {
        for j in 0..=16 {
            let q = [f64::from(i) / 16.0, f64::from(j) / 16.0, 1.0];
            let x = [q[0], q[1], 1.0 + 0.05];
            let under = containing(&soup, q, face.clone());
            assert!(!under.is_empty(), "{q:?}");
            if under.len() > 1 {
                seams += 1;
            }
            assert_eq!(m.triangle_of(p, x, r), under.iter().copied().min(), "{q:?}");
        }
    }
    assert!(seams > 50, "{seams}");
}
