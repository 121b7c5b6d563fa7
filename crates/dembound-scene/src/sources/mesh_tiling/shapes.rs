//! Simple surfaces as triangle soups, for `particle-wall` without a file
//! and for the covering's tests and benchmarks: a square plane patch, a
//! box, a faceted cylinder and a hopper (a cone with an outlet).

use crate::walls::mesh::Triangle;
use std::f64::consts::PI;

/// The square [0, side]² at z = 0, normal +z, as 2 triangles.
pub fn square(side: f64) -> Vec<Triangle> {
    let (a, b, c, d) = (
        [0.0, 0.0, 0.0],
        [side, 0.0, 0.0],
        [side, side, 0.0],
        [0.0, side, 0.0],
    );
    vec![[a, b, c], [a, c, d]]
}

/// The closed box [lo, hi], 12 triangles, normals outward.
pub fn cube(lo: [f64; 3], hi: [f64; 3]) -> Vec<Triangle> {
    let corner = |i: usize| {
        [
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        ]
    };
    // Each face: four corners counter-clockwise seen from outside.
    let faces = [
        [0, 4, 6, 2], // −x
        [1, 3, 7, 5], // +x
        [0, 1, 5, 4], // −y
        [2, 6, 7, 3], // +y
        [0, 2, 3, 1], // −z
        [4, 5, 7, 6], // +z
    ];
    let mut out = Vec::new();
    for f in faces {
        let [a, b, c, d] = f.map(corner);
        out.push([a, b, c]);
        out.push([a, c, d]);
    }
    out
}

/// A ring of `facets` points of radius `radius` at height z.
fn ring(radius: f64, z: f64, facets: usize) -> Vec<[f64; 3]> {
    (0..facets)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / facets as f64;
            [radius * a.cos(), radius * a.sin(), z]
        })
        .collect()
}

/// The band between two rings (same facet count), split into `rows`
/// rows; normals outward (away from the axis) when `outward`.
fn band(
    lower: (f64, f64),
    upper: (f64, f64),
    facets: usize,
    rows: usize,
    outward: bool,
) -> Vec<Triangle> {
    let mut out = Vec::new();
    for j in 0..rows {
        let f0 = j as f64 / rows as f64;
        let f1 = (j + 1) as f64 / rows as f64;
        let lerp = |f: f64| {
            (
                lower.0 + f * (upper.0 - lower.0),
                lower.1 + f * (upper.1 - lower.1),
            )
        };
        let (r0, z0) = lerp(f0);
        let (r1, z1) = lerp(f1);
        let (a, b) = (ring(r0, z0, facets), ring(r1, z1, facets));
        for k in 0..facets {
            let k1 = (k + 1) % facets;
            let (p, q, r, s) = (a[k], a[k1], b[k1], b[k]);
            if outward {
                out.push([p, q, r]);
                out.push([p, r, s]);
            } else {
                out.push([p, r, q]);
                out.push([p, s, r]);
            }
        }
    }
    out
}

/// A disk of `facets` triangles about (0, 0, z), normal +z if `up`.
fn disk(radius: f64, z: f64, facets: usize, up: bool) -> Vec<Triangle> {
    let rim = ring(radius, z, facets);
    let centre = [0.0, 0.0, z];
    (0..facets)
        .map(|k| {
            let (p, q) = (rim[k], rim[(k + 1) % facets]);
            if up {
                [centre, p, q]
            } else {
                [centre, q, p]
            }
        })
        .collect()
}

/// The closed cylinder of radius `radius` about the z axis from z = 0 to
/// `height`: `facets` around, `rows` along, flat caps; normals outward.
pub fn cylinder(radius: f64, height: f64, facets: usize, rows: usize) -> Vec<Triangle> {
    let mut out = band((radius, 0.0), (radius, height), facets, rows, true);
    out.extend(disk(radius, 0.0, facets, false));
    out.extend(disk(radius, height, facets, true));
    out
}

/// A hopper, open at both ends, normals inward (the particles inside): a
/// cone from the outlet (radius `outlet` at z = 0) to radius `radius` at
/// z = `cone_height`, then a cylinder up to `cone_height + height`.
pub fn hopper(
    outlet: f64,
    radius: f64,
    cone_height: f64,
    height: f64,
    facets: usize,
) -> Vec<Triangle> {
    let mut out = band((outlet, 0.0), (radius, cone_height), facets, 1, false);
    out.extend(band(
        (radius, cone_height),
        (radius, cone_height + height),
        facets,
        1,
        false,
    ));
    out
}
