//! Per-triangle loads on a mesh wall (issue 26): which triangle of the
//! cleaned mesh a contact loads, and the loads of a wall's contacts summed
//! per triangle, with the pressure and shear stress they make.
//!
//! # Which triangle a contact loads
//!
//! A contact is on an element, a flat patch ([`super::patch`]); the force
//! pass records what the wall took from it (`WallLoad::of_contact`).
//! [`MeshGeometry::triangle_of`] names one triangle of that patch, from the
//! sphere's centre x and radius r, by the contact's own rule
//! (`walls::mesh` module doc):
//! - a face contact (x's projection along the patch normal inside the
//!   patch, within the inside tolerance): the triangle under the contact
//!   point p = x − r n̂, which projects where x does; a point on a seam
//!   between triangles of the patch (within the inside tolerance of both)
//!   goes to the lowest triangle id among them;
//! - an edge contact (the closest point of the patch's boundary inside an
//!   edge): the triangle of the patch holding that boundary edge (one: a
//!   boundary edge of a patch has one triangle of it);
//! - a vertex contact: the lowest-id triangle of the patch holding that
//!   vertex.
//!
//! Triangle ids are the cleaned mesh's order: the file's triangles in file
//! order, degenerate and duplicate ones dropped (`clean`), so triangle k
//! here is the k-th triangle kept.
//!
//! The rule reads the sphere's position at observation time. With Verlet
//! that is the position the force pass saw; with Gear5 the force pass saw
//! the predicted position and the observation reads the corrected one,
//! which differ by the corrector's step (so only a contact within that
//! distance of a seam could be named for the neighbouring triangle; the
//! wall's total does not change).
//!
//! # Sums
//!
//! [`TriangleLoads::sum`] adds each record's force into its triangle's
//! running sum, records in the order given. The engine gives them ordered
//! by the sphere's input id, a sphere's entries in (wall, element) order:
//! on any number of threads or ranks the same records in the same order,
//! so the same bits (`pipeline::triangle_loads`).

use super::contact::{Feature, SMALL_PATCH};
use super::geometry::{add, cross, dot, norm, scale, sub};
use super::MeshGeometry;

impl MeshGeometry {
    /// The triangle (cleaned-mesh id) of patch `p` that a contact of a
    /// sphere at `x` of radius `r` (m) loads, by the rule of the module
    /// doc; `None` when `p` is not a patch.
    pub fn triangle_of(&self, p: u32, x: [f64; 3], r: f64) -> Option<u32> {
        let patch = self.patches.patches.get(p as usize)?;
        let lowest_over = |t: u32, best: &mut Option<u32>| {
            if self.patches.tri[t as usize].patch == p
                && self.over_triangle(t, x)
                && best.is_none_or(|b| t < b)
            {
                *best = Some(t);
            }
        };
        let mut over = None;
        if patch.count <= SMALL_PATCH {
            for &t in self.patches.of(p) {
                lowest_over(t, &mut over);
            }
        } else {
            let q = sub(x, scale(patch.normal, self.plane_distance(p, x)));
            if let Some(range) = self.grid.range(q, q) {
                self.grid.each_cell(&range, |c| {
                    for &t in self.grid.cell_items(c) {
                        lowest_over(t, &mut over);
                    }
                });
            }
        }
        if over.is_some() {
            return over;
        }
        let holding = |v: u32| {
            self.patches
                .of(p)
                .iter()
                .copied()
                .filter(|&t| self.patches.tri[t as usize].vertex.contains(&v))
                .min()
        };
        let boundary = self
            .boundary_closest(p, x, r)
            .and_then(|b| match b.feature {
                Feature::Edge(t, _) => Some(t),
                Feature::Vertex(v) => holding(v),
            });
        boundary.or_else(|| self.patches.of(p).iter().copied().min())
    }

    /// Area (m²), unit normal and centroid (m) of cleaned triangle `t`, its
    /// normal along (b − a) × (c − a) of its vertices as stored (for a
    /// closed part, outward).
    pub fn triangle_frame(&self, t: usize) -> (f64, [f64; 3], [f64; 3]) {
        let [a, b, c] = self.triangles[t].map(|v| self.vertices[v as usize]);
        let area_vector = cross(sub(b, a), sub(c, a));
        let twice = norm(area_vector);
        let normal = if twice > 0.0 {
            scale(area_vector, 1.0 / twice)
        } else {
            area_vector
        };
        (0.5 * twice, normal, scale(add(add(a, b), c), 1.0 / 3.0))
    }
}

impl crate::walls::Surface {
    /// The mesh of a triangle-mesh wall (`None` for other walls).
    pub fn mesh(&self) -> Option<&MeshGeometry> {
        match self {
            crate::walls::Surface::Mesh(m) => Some(&m.mesh),
            _ => None,
        }
    }
}

/// One contact's force on the wall (N) and the triangle it loads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleForce {
    pub triangle: u32,
    pub force: [f64; 3],
}

/// The loads of one mesh wall per triangle (cleaned-mesh order), with the
/// mesh's vertices and triangles as placed in the world: what the VTK wall
/// files and `Scene.wall_triangle_loads` show.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleLoads {
    /// Welded vertices, m.
    pub vertices: Vec<[f64; 3]>,
    /// Vertex indices of each triangle, oriented as [`Self::normal`].
    pub triangles: Vec<[u32; 3]>,
    /// Force the spheres exert on each triangle (on the wall), N.
    pub force: Vec<[f64; 3]>,
    /// m².
    pub area: Vec<f64>,
    /// Unit normal (for a closed part, outward).
    pub normal: Vec<[f64; 3]>,
    /// m.
    pub centroid: Vec<[f64; 3]>,
    /// Normal stress |F·n̂|/A, Pa: the spheres' push on the triangle
    /// over its area. A contact only pushes (the normal force on a
    /// sphere is never attractive), so a triangle loaded from one side —
    /// a floor from above, a box's face from inside or a part from
    /// outside, whichever way the file orients it — gets the pressure of
    /// the spheres on it, positive; a thin plate loaded from both sides
    /// gets the net push.
    pub pressure: Vec<f64>,
    /// Shear stress |F − (F·n̂) n̂|/A, Pa.
    pub shear: Vec<f64>,
}

impl TriangleLoads {
    /// The loads of `mesh`'s triangles from `records` (any record naming
    /// no triangle of the mesh is skipped), each added to its triangle's
    /// running sum in the order given.
    pub fn sum(mesh: &MeshGeometry, records: &[TriangleForce]) -> TriangleLoads {
        let n = mesh.triangles.len();
        let mut force = vec![[0.0; 3]; n];
        for r in records {
            if let Some(f) = force.get_mut(r.triangle as usize) {
                *f = add(*f, r.force);
            }
        }
        let mut out = TriangleLoads {
            vertices: mesh.vertices.clone(),
            triangles: mesh.triangles.clone(),
            force: Vec::with_capacity(n),
            area: Vec::with_capacity(n),
            normal: Vec::with_capacity(n),
            centroid: Vec::with_capacity(n),
            pressure: Vec::with_capacity(n),
            shear: Vec::with_capacity(n),
        };
        for (t, f) in force.into_iter().enumerate() {
            out.push_triangle(mesh, t, f);
        }
        out
    }

    /// The loads of `mesh`'s triangles `range` (clamped to the mesh) from
    /// `records` (those of other triangles skipped), summed as
    /// [`Self::sum`] sums them: each triangle's values the same bits as
    /// its entry there. `vertices` holds the vertices these triangles use,
    /// in order of first use, and `triangles` indexes them: one piece of a
    /// wall written in pieces (`io::vtk_walls`).
    pub fn sum_range(
        mesh: &MeshGeometry,
        records: &[TriangleForce],
        range: std::ops::Range<usize>,
    ) -> TriangleLoads {
        let n = mesh.triangles.len();
        let range = range.start.min(n)..range.end.min(n);
        let mut force = vec![[0.0; 3]; range.len()];
        for r in records {
            let t = r.triangle as usize;
            if range.contains(&t) {
                force[t - range.start] = add(force[t - range.start], r.force);
            }
        }
        let mut out = TriangleLoads {
            vertices: Vec::new(),
            triangles: Vec::with_capacity(range.len()),
            force: Vec::with_capacity(range.len()),
            area: Vec::with_capacity(range.len()),
            normal: Vec::with_capacity(range.len()),
            centroid: Vec::with_capacity(range.len()),
            pressure: Vec::with_capacity(range.len()),
            shear: Vec::with_capacity(range.len()),
        };
        // Mesh vertex → its index here.
        let mut local: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
        for (t, f) in range.zip(force) {
            let corners = mesh.triangles[t].map(|v| {
                *local.entry(v).or_insert_with(|| {
                    out.vertices.push(mesh.vertices[v as usize]);
                    (out.vertices.len() - 1) as u32
                })
            });
            out.triangles.push(corners);
            out.push_triangle(mesh, t, f);
        }
        out
    }

    /// Appends triangle `t`'s loads from its summed force `f` (the
    /// triangle's corners are the caller's).
    fn push_triangle(&mut self, mesh: &MeshGeometry, t: usize, f: [f64; 3]) {
        let (area, normal, centroid) = mesh.triangle_frame(t);
        let fn_ = dot(f, normal);
        let tangential = sub(f, scale(normal, fn_));
        self.pressure.push(fn_.abs() / area);
        self.shear.push(norm(tangential) / area);
        self.force.push(f);
        self.area.push(area);
        self.normal.push(normal);
        self.centroid.push(centroid);
    }

    /// Triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }
}

/// Why a wall has no triangle loads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TriangleLoadsError {
    /// No wall of that index.
    NoSuchWall { wall: usize, walls: usize },
    /// The wall is not a triangle mesh.
    NotMesh { wall: usize },
}

impl std::fmt::Display for TriangleLoadsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            TriangleLoadsError::NoSuchWall { wall, walls: 0 } => {
                write!(f, "wall {wall} does not exist: the scene has no walls")
            }
            TriangleLoadsError::NoSuchWall { wall, walls } => write!(
                f,
                "wall {wall} does not exist: the scene has {walls} walls (indices 0 to {})",
                walls - 1
            ),
            TriangleLoadsError::NotMesh { wall } => write!(
                f,
                "wall {wall} is not a triangle mesh: triangle loads exist for `mesh` walls only"
            ),
        }
    }
}

impl std::error::Error for TriangleLoadsError {}

#[cfg(test)]
mod tests {
    use super::super::{MeshGeometry, MeshOptions, Transform};
    use super::*;

    /// A strip of four triangles along x (two unit squares, each cut on
    /// its diagonal), normal +z.
    fn strip() -> MeshGeometry {
        let v = |x: f64, y: f64| [x, y, 0.0];
        let soup = [
            [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0)],
            [v(0.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)],
            [v(1.0, 0.0), v(2.0, 0.0), v(2.0, 1.0)],
            [v(1.0, 0.0), v(2.0, 1.0), v(1.0, 1.0)],
        ];
        MeshGeometry::from_triangles(
            std::path::Path::new("strip.stl"),
            &soup,
            &Transform::default(),
            &MeshOptions::default(),
        )
        .expect("a valid mesh")
    }

    /// The pieces of any cut hold each triangle's loads with the bits of
    /// the whole sum and its corners at the whole mesh's vertices; a
    /// piece holds only the vertices its triangles use.
    #[test]
    fn pieces_hold_the_whole_sums_bits() {
        let mesh = strip();
        // Sums that round: the order of the additions shows in the bits.
        let records: Vec<TriangleForce> = [(2, 0.1), (0, 0.2), (2, 0.3), (3, 1e-17), (2, 1.0)]
            .iter()
            .map(|&(t, f)| TriangleForce {
                triangle: t,
                force: [f, -f, 3.0 * f],
            })
            .collect();
        let whole = TriangleLoads::sum(&mesh, &records);
        // 0.1 + 0.3 + 1.0 in that order, against the plain sum.
        assert_eq!(whole.force[2][0].to_bits(), ((0.1 + 0.3) + 1.0f64).to_bits());
        for cut in 0..=4 {
            let pieces = [
                TriangleLoads::sum_range(&mesh, &records, 0..cut),
                TriangleLoads::sum_range(&mesh, &records, cut..9),
            ];
            let mut t = 0;
            for p in &pieces {
                let used: std::collections::BTreeSet<u32> =
                    p.triangles.iter().flatten().copied().collect();
                assert_eq!(used.len(), p.vertices.len(), "cut {cut}");
                for k in 0..p.len() {
                    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&p.force[k]), bits(&whole.force[t]), "cut {cut}");
                    assert_eq!(p.pressure[k].to_bits(), whole.pressure[t].to_bits());
                    assert_eq!(p.shear[k].to_bits(), whole.shear[t].to_bits());
                    assert_eq!(p.area[k].to_bits(), whole.area[t].to_bits());
                    let corners = p.triangles[k].map(|v| p.vertices[v as usize]);
                    let expected = whole.triangles[t].map(|v| whole.vertices[v as usize]);
                    assert_eq!(corners, expected, "cut {cut}, triangle {t}");
                    t += 1;
                }
            }
            assert_eq!(t, 4, "cut {cut}: every triangle once");
        }
    }
}
