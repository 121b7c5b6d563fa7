//! Whether the bed fits in the part (`dembound wall-study --wall`): the
//! part's interior below its rim, surveyed by vertical columns, and the
//! checks built on it — before the run, that the pour lands inside the
//! part and that the poured grains fit below its rim; after the run, that
//! the settled bed is in the part.
//!
//! **A column** at (x, y) falls from above the part (gravity along −z).
//! It is *interior* when the first triangle it meets from above faces the
//! particles (the particles' normal has nz > 0: a grain falling down the
//! column lands on the part's inside), or when it meets none and passes
//! through the outlet (within its clear radius: the plug holds the grains
//! there while the bed settles). Its *floor* is that triangle's height at
//! (x, y), or the outlet's plane. A column meeting the part first from its
//! outside, or missing it away from an outlet, is not interior: grains
//! landing there go around the part.
//!
//! **The rim** is the part's top, z = max z of its vertices. A part lower
//! than 2 R (a plate, the plane study's floor) holds no bed below its
//! rim: its bed is held by the four side walls on its box (as the plane
//! study's), its rim is taken as +∞ and only the columns are checked.
//!
//! **The interior volume** below the rim: Σ over a [`SURVEY_COLUMNS`]²
//! grid of column midpoints on the part's box in x and y of (rim − floor)
//! × the cell's area, over the interior columns. The midpoint count of a
//! round outline of radius ρ on a grid of spacing c errs by
//! O((ρ/c)^(2/3)) cells (the Gauss circle problem's classical bound), far
//! below 1 % at 256 columns a side.
//!
//! **The capacity**: the largest N with N × 4/3 π R³ ≤ φ V, φ =
//! [`LOOSE_PACKING`] = 0.55, the random loose packing of equal spheres
//! (Onoda & Liniger 1990, Phys. Rev. Lett. 64, 2727: 0.555 as gravity
//! vanishes; a poured bed settles at 0.55–0.60 and lower near walls). The
//! loosest settled packing overestimates the bed's volume: N grains at φ
//! fill V, any denser bed fills less.

use crate::walls::mesh::geometry::{cross, norm, sub};
use crate::walls::mesh::MeshGeometry;

use super::part_bed::Outlet;

/// Columns a side of the interior survey.
pub const SURVEY_COLUMNS: usize = 256;
/// The solid fraction a poured bed is assumed to fill at most.
pub const LOOSE_PACKING: f64 = 0.55;
/// The fraction of settled grains allowed outside the interior or above
/// the rim: a grain may rest on the rim's edge with its centre above it;
/// more than 1 % is a bed spilling over or around the part.
pub const OUTSIDE_FRACTION: f64 = 0.01;

/// A triangle's projection on the xy plane with its heights and the
/// z-component of its normal toward the particles.
#[derive(Debug, Clone, Copy)]
struct Facet {
    v: [[f64; 3]; 3],
    nz: f64,
    lo: [f64; 2],
    hi: [f64; 2],
}

/// The part's interior, column by column.
#[derive(Debug, Clone)]
pub struct Interior {
    facets: Vec<Facet>,
    outlet: Option<Outlet>,
    /// The rim, m (+∞ for a part lower than 2 R).
    pub rim: f64,
}

impl Interior {
    /// The interior of `mesh` for spheres of radius `r` (module doc).
    pub fn new(mesh: &MeshGeometry, flip: bool, r: f64, outlet: Option<Outlet>) -> Self {
        let sign = if flip { -1.0 } else { 1.0 };
        let facets = mesh
            .triangles
            .iter()
            .filter_map(|t| {
                let v = t.map(|i| mesh.vertices[i as usize]);
                let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
                let len = norm(n);
                // Vertical faces (and degenerate ones) have no height over
                // a column: a column never lands on them.
                if len == 0.0 || n[2].abs() <= 1e-9 * len {
                    return None;
                }
                Some(Facet {
                    v,
                    nz: sign * n[2] / len,
                    lo: [0, 1].map(|k| v.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min)),
                    hi: [0, 1].map(|k| v.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max)),
                })
            })
            .collect();
        let rim = if mesh.hi[2] - mesh.lo[2] < 2.0 * r {
            f64::INFINITY
        } else {
            mesh.hi[2]
        };
        Interior {
            facets,
            outlet,
            rim,
        }
    }

    /// The floor of the column at (x, y), m, `None` when it is not interior.
    pub fn floor(&self, x: f64, y: f64) -> Option<f64> {
        let mut first: Option<(f64, f64)> = None;
        for f in &self.facets {
            if x < f.lo[0] || x > f.hi[0] || y < f.lo[1] || y > f.hi[1] {
                continue;
            }
            let [a, b, c] = f.v;
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            let u = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
            let w = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
            if u < 0.0 || w < 0.0 || u + w > 1.0 {
                continue;
            }
            let z = a[2] + u * (b[2] - a[2]) + w * (c[2] - a[2]);
            if first.is_none_or(|(z0, _)| z > z0) {
                first = Some((z, f.nz));
            }
        }
        match first {
            Some((z, nz)) => (nz > 0.0).then_some(z),
            None => self.outlet.and_then(|o| {
                let d = (x - o.centre[0]).hypot(y - o.centre[1]);
                (d < o.radius).then_some(o.z)
            }),
        }
    }

    /// The interior volume below the rim, m³, over the box `lo`–`hi` in x
    /// and y (+∞ for a part without a rim).
    pub fn volume(&self, lo: [f64; 2], hi: [f64; 2]) -> f64 {
        if self.rim.is_infinite() {
            return f64::INFINITY;
        }
        let n = SURVEY_COLUMNS;
        let (cx, cy) = ((hi[0] - lo[0]) / n as f64, (hi[1] - lo[1]) / n as f64);
        let mut height = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (lo[0] + (i as f64 + 0.5) * cx, lo[1] + (j as f64 + 0.5) * cy);
                if let Some(z) = self.floor(x, y) {
                    height += (self.rim - z).max(0.0);
                }
            }
        }
        height * cx * cy
    }

    /// Settled grains (centres `free`) outside the interior or above the
    /// rim: a column not interior, or a centre more than `depth` below
    /// its floor (a grain in the hollows of a covering sits below the
    /// surface: up to 2 R_b), or above the rim.
    pub fn outside(&self, free: &[[f64; 3]], depth: f64) -> usize {
        free.iter()
            .filter(|p| match self.floor(p[0], p[1]) {
                Some(z) => p[2] < z - depth || p[2] > self.rim,
                None => true,
            })
            .count()
    }
}

/// The largest count of spheres of radius `r` that fits in `volume` at
/// [`LOOSE_PACKING`].
pub fn capacity(volume: f64, r: f64) -> f64 {
    (LOOSE_PACKING * volume / (4.0 / 3.0 * std::f64::consts::PI * r.powi(3))).floor()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sources::mesh_tiling::shapes;
    use crate::walls::mesh::{MeshOptions, Transform};
    use std::path::Path;

    fn geometry(t: &[crate::walls::mesh::Triangle]) -> MeshGeometry {
        MeshGeometry::from_triangles(
            Path::new("t"),
            t,
            &Transform::default(),
            &MeshOptions::default(),
        )
        .unwrap()
    }

    #[test]
    fn a_closed_cylinder_from_outside_holds_nothing_and_a_plate_has_no_rim() {
        // The closed cylinder with the particles outside (normals outward,
        // no flip): every column over its disc meets its lid from above on
        // the particles' side: the lid is a floor at the top, volume 0.
        let m = geometry(&shapes::cylinder(5e-3, 20e-3, 96, 1));
        let i = Interior::new(&m, false, 0.5e-3, None);
        assert_eq!(i.floor(0.0, 0.0), Some(m.hi[2]));
        assert_eq!(i.volume([m.lo[0], m.lo[1]], [m.hi[0], m.hi[1]]), 0.0);
        // Flipped (the particles inside), the lid faces down: no column
        // lands inside.
        let i = Interior::new(&m, true, 0.5e-3, None);
        assert_eq!(i.floor(0.0, 0.0), None);
        // A flat square: no rim, infinite capacity.
        let m = geometry(&shapes::square(0.01));
        let i = Interior::new(&m, false, 1e-3, None);
        assert!(i.rim.is_infinite());
        assert_eq!(i.floor(0.005, 0.005), Some(0.0));
    }

    #[test]
    fn an_open_cone_holds_its_closed_form_volume() {
        // A hopper (outlet radius 2 mm, a cone 8 mm high to radius 10 mm,
        // a column 4 mm above), its outlet passed through: the interior
        // below the rim is the frustum π h/3 (r1² + r1 r2 + r2²) and the
        // column π r2² h2, of the 96-gon: area factor (n/2π) sin(2π/n),
        // the same for every circle of the part. Tolerance 0.5 %:
        // the midpoint count errs by O((ρ/c)^(2/3)) ≈ 40 cells of
        // (20 mm / 256)² in the outline, 0.02 % of the area.
        let m = geometry(&shapes::hopper(2e-3, 10e-3, 8e-3, 4e-3, 96));
        let n = 96.0;
        let polygon = n / (2.0 * std::f64::consts::PI) * (2.0 * std::f64::consts::PI / n).sin();
        let outlet = Outlet {
            z: 0.0,
            centre: [0.0, 0.0],
            radius: 2e-3 * (std::f64::consts::PI / n).cos(),
            edges: 96,
        };
        let i = Interior::new(&m, false, 0.5e-3, Some(outlet));
        let v = i.volume([m.lo[0], m.lo[1]], [m.hi[0], m.hi[1]]);
        let pi = std::f64::consts::PI;
        let exact = (pi * 8e-3 / 3.0 * (4e-6 + 20e-6 + 100e-6) + pi * 100e-6 * 4e-3) * polygon;
        assert!((v / exact - 1.0).abs() < 5e-3, "{v} vs {exact}");
    }

    #[test]
    fn grains_outside_the_interior_or_above_the_rim_are_counted() {
        // The open tube of radius 5 mm, 0–20 mm high (normals inward),
        // its bottom the outlet: a grain in it, one above its rim, one
        // beside it (outside the radius), one below the outlet's plane.
        let m = geometry(&shapes::hopper(5e-3, 5e-3, 10e-3, 10e-3, 96));
        let outlet = Outlet {
            z: 0.0,
            centre: [0.0, 0.0],
            radius: 4.9e-3,
            edges: 96,
        };
        let i = Interior::new(&m, false, 0.5e-3, Some(outlet));
        assert!((i.rim - m.hi[2]).abs() < 1e-15);
        let inside = [0.0, 0.0, 5e-3];
        assert_eq!(i.outside(&[inside], 0.0), 0);
        assert_eq!(i.outside(&[inside, [0.0, 0.0, 21e-3]], 0.5e-3), 1);
        assert_eq!(i.outside(&[inside, [6e-3, 0.0, 5e-3]], 0.5e-3), 1);
        assert_eq!(i.outside(&[inside, [0.0, 0.0, -1e-3]], 0.5e-3), 1);
    }
}
