//! Triangle-mesh walls (issue 26): a part read from STL or OBJ, placed,
//! cleaned, grouped into flat patches, searched through a uniform grid,
//! and answering sphere contacts with one force per contact.
//!
//! # Elements are flat patches
//!
//! The wall's elements are not triangles but flat patches ([`patch`]):
//! maximal edge-connected sets of triangles whose normals lie within
//! 1e-6 rad of the patch's first triangle's. Each patch is one plane
//! (n_P, p_P). A sphere whose centre projects inside the patch (inside any
//! of its triangles, seams included within the inside tolerance) gets the
//! plane's contact: overlap r − |(x − p_P)·n_P|, normal ±n_P toward the
//! centre's side (the wall is two-sided: a thin plate pushes from both
//! faces), with `walls::plane::plane_overlap`'s arithmetic, so a mesh of a
//! plane matches the analytic plane to round-off whatever its
//! triangulation, and the element id — the patch — keys the contact
//! history, so springs carry across seams inside a patch unchanged.
//!
//! Why 1e-6 rad: a flat CAD face exported as binary STL has f32 vertices,
//! whose rounding (2⁻²⁴ ≈ 6e-8 relative) tilts a triangle by ~6e-8 × (its
//! distance from the origin)/(its size): 1e-6 rad keeps such faces one
//! patch while any fold a designer draws (≥ 1e-3 rad) stays an edge. The
//! patch is then flat to 1e-6 × its extent (reported as
//! [`MeshGeometry::max_deviation`]). LIGGGHTS's `curvature` (by default
//! cos θ ≥ 1 − 1e-5, θ ≈ 4.5e-3 rad; settable in degrees up to 60°) plays the same
//! role of telling one surface from an edge, but LIGGGHTS keeps each
//! triangle's own plane; here the patch is one plane, so a looser
//! tolerance would move the surface by θ × extent: it is kept tight.
//!
//! # One force per contact: the closest-feature rule
//!
//! When the centre's projection falls outside patch P, P's candidate is
//! the closest point c of its boundary (edges not shared inside P), with
//! normal (x − c)/|x − c| and overlap r − |x − c|. It is kept only if
//! every other patch Q touching c's feature (the edge c lies inside, or
//! the vertex c is within the snap tolerance of) has c as its own closest
//! point — x's projection outside Q and Q's boundary point equal to c
//! within the tolerance — and P has the lowest id of them; otherwise P
//! reports no contact (overlap −∞, as the cylinder's caps do where they do
//! not face the sphere). Consequences:
//! - a convex edge or vertex seen from outside: every patch meeting there
//!   has c as closest point, the lowest id keeps one contact along the
//!   line from c to the centre (a sphere rolling over the edge sees a
//!   rounded edge, continuous in force);
//! - a sphere over face A near a convex edge with B: A's face contact
//!   only (B's candidate is dropped, A's closest point is inside A);
//! - a concave edge or corner: each face's projection is inside, one face
//!   contact per patch, as the planes would give;
//! - a sphere over face A near a concave edge with B (a valley: B rises
//!   toward the sphere), B's projection outside B: B's edge point is kept
//!   beside A's face contact, so B's contact grows continuously into its
//!   face contact as the projection enters B (dropping it, as at a convex
//!   edge, made B's contact appear with a finite overlap there: a force
//!   jump that created energy in polygonal drums).
//!
//! A sphere rolling over a convex edge from A to B is carried by A's face,
//! then by the edge's owner (the lower of A and B), then by B's face: the
//! force is continuous but the element, and so the contact history keyed
//! by it, changes once (carrying a spring across that change is left to
//! the engine).
//!
//! One more rule, visibility: a contact (face or boundary) whose point is
//! hidden from the centre by another patch — the segment from the centre
//! to the contact point meets a triangle of another patch before it — is
//! dropped. A sphere does not touch a surface through another one: near a
//! sharp vertex or along a thin part of a closed solid, faces on the far
//! side are within a radius of the centre through the solid (a regular
//! octahedron's faces near a vertex, a slab thinner than a diameter).
//! Tested only for contacts with a positive overlap, so the common case
//! (a sphere on a face, no other patch between) costs one walk over the
//! grid cells of a segment shorter than r.
//!
//! This is MercuryDPM's `MeshTriangle::checkInteractions` rule (face
//! before edge before vertex; of two triangles seeing the same edge or
//! vertex the lower id keeps it; Hu et al., doi:10.1002/nme.4487), applied
//! to patches instead of triangles and with the hiding decided by where
//! the other patch's closest point is rather than by the contact type.
//! LAMMPS's granular surfaces (`Howto_granular_surfaces`, PR 4213) walk
//! the connections of the touched triangles, merge flat-connected ones
//! into one composite force (overlap the largest, normal a weighted mean)
//! and hide triangles behind convex turns; the flat patches here give
//! their flat composite exactly (one plane, not a mean), and the closest
//! feature rule is their convex hiding without the weights. LAMMPS warns
//! that a sphere reaching around a thin feature touches its far side; the
//! visibility rule removes that. Limits: a T-junction (a vertex on
//! another triangle's edge, not welded) is not a connection, so a sphere
//! over it may get two contacts; two surfaces both within reach and in
//! sight (a narrow slot) both push, as they should.
//!
//! Tolerances, with S = max(bounding-box diagonal, largest |coordinate|):
//! inside 1e-12 S (the round-off of m·(x − a) is ~1e-15 S; shared seam
//! edges have exactly opposite in-plane normals, so a centre over a seam
//! is over at least one triangle); snap and agreement 1e-10 S (closest
//! points of one segment computed from either side agree to ~1e-15 S).
//!
//! # Search and memory
//!
//! A uniform grid ([`grid`]) over the mesh's box lists each triangle in
//! the cells its box (padded by the inside tolerance and the patches'
//! deviation) overlaps. `near_elements` visits the cells of the sphere's
//! box grown by the range and lists the patches of the triangles within
//! reach; `contact` tests a patch's triangles directly when it has at most
//! 8, else only those in the cell of the centre's projection (face) or in
//! growing boxes around the centre (boundary). Memory, per triangle:
//! 12 B vertex indices, 168 B contact geometry (corners, in-plane edge
//! normals, vertex ids, patch, boundary flags), 24 B edge adjacency,
//! ~14 B vertex adjacency, ~21 B grid (≤ 2 cells per triangle, ~3 entries
//! per triangle), 4 B patch membership, plus 24 B per vertex (~12 B per
//! triangle) and 64 B per patch: about 320 B per triangle for a curved
//! surface where every triangle is its own patch (322 B measured on a
//! 100,352-triangle mesh, [`MeshGeometry::bytes`]), about 260 B for a part
//! of large flat faces. One copy per process, shared read-only by its
//! threads; under MPI every rank holds a copy.
//!
//! # Loads per triangle
//!
//! The force pass records each contact's load on its element (the
//! patch); [`loads`] gives each contact to one triangle of that patch
//! after the step, from the sphere's position (the triangle under the
//! centre; on a seam, edge or vertex the lowest triangle id holding it)
//! and sums the forces per triangle in input-id order, so the per-triangle
//! loads cost nothing in the force pass and have the same bits on any
//! number of threads and ranks. Pressure |F·n̂|/A and shear
//! |F − (F·n̂) n̂|/A per triangle; written as `wall_K_NNNNNN.vtp`
//! (`io::vtk_walls`), offered to Python as NumPy arrays.
//!
//! The wall is fixed (surface velocity zero) and every patch is flat
//! (`Curvature::Flat`, one law row). A [`MeshWall`] holds its geometry
//! behind an `Arc`: cloning it is cheap, but it cannot be `Copy`, so the
//! engine's `Surface` enum, `Copy` today, must drop `Copy` to hold one
//! (nothing in the workspace relies on `Surface: Copy`: without it and
//! with a `Mesh(MeshWall)` variant and its four match arms in
//! `walls/mod.rs`, the workspace builds, MPI feature included).

pub mod clean;
pub mod contact;
pub mod geometry;
pub mod grid;
pub mod loads;
pub mod patch;
pub mod read;
pub mod transform;
mod wall_type;

#[cfg(test)]
mod fixtures;
#[cfg(test)]
mod tests_clean;
#[cfg(test)]
mod tests_edges;
#[cfg(test)]
mod tests_loads;
#[cfg(test)]
mod tests_motion;
#[cfg(test)]
mod tests_seam;

use std::path::Path;
use std::sync::Arc;

pub use clean::CleanReport;
pub use loads::{TriangleForce, TriangleLoads, TriangleLoadsError};
pub use read::{MeshError, Triangle};
pub use transform::Transform;
pub use wall_type::{Mesh, MeshConfig, RotateConfig};

use super::motion::WallState;
use super::{Wall, WallPoint};
use geometry::{add, cross, dot, norm, scale, sub};

/// Cleaning and patch tolerances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshOptions {
    /// Weld tolerance relative to the bounding-box diagonal.
    pub weld_relative: f64,
    /// Largest angle between a patch's triangles' normals, rad.
    pub flat_angle: f64,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            weld_relative: 1e-9,
            flat_angle: 1e-6,
        }
    }
}

/// A cleaned mesh with its patches and search grid.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshGeometry {
    /// Welded vertices, m.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles (vertex indices), consistently oriented.
    pub triangles: Vec<[u32; 3]>,
    /// What cleaning found.
    pub report: CleanReport,
    pub patches: patch::Patches,
    pub grid: grid::Grid,
    /// Bounding box, m.
    pub lo: [f64; 3],
    pub hi: [f64; 3],
    /// Area-weighted centroid, m; total area, m².
    pub centroid: [f64; 3],
    pub area: f64,
    /// Inside, snap and agreement tolerances, m (module doc).
    pub inside_tolerance: f64,
    pub snap_tolerance: f64,
}

impl MeshGeometry {
    /// Reads, places and builds the mesh of `path`.
    pub fn load(
        path: &Path,
        transform: &Transform,
        options: &MeshOptions,
    ) -> Result<MeshGeometry, MeshError> {
        let soup = read::read_triangles(path)?;
        MeshGeometry::from_triangles(path, &soup, transform, options)
    }

    /// Builds the mesh of `soup` (triangles as read), placed by
    /// `transform`; `file` names it in errors.
    pub fn from_triangles(
        file: &Path,
        soup: &[Triangle],
        transform: &Transform,
        options: &MeshOptions,
    ) -> Result<MeshGeometry, MeshError> {
        transform.validate()?;
        let mut placed = Vec::with_capacity(soup.len());
        for (i, t) in soup.iter().enumerate() {
            let p = t.map(|v| transform.apply(v));
            if !p.iter().flatten().all(|c| c.is_finite()) {
                return Err(MeshError::NonFinite {
                    file: file.to_path_buf(),
                    triangle: i,
                });
            }
            placed.push(p);
        }
        let cleaned = clean::clean(&placed, options.weld_relative);
        if cleaned.triangles.is_empty() {
            return Err(MeshError::Empty {
                file: file.to_path_buf(),
                read: soup.len(),
            });
        }
        let patches = patch::build(&cleaned.vertices, &cleaned.triangles, options.flat_angle);
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut largest: f64 = 0.0;
        for v in &cleaned.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
                largest = largest.max(v[k].abs());
            }
        }
        let s = norm(sub(hi, lo)).max(largest);
        let inside_tolerance = 1e-12 * s;
        let snap_tolerance = 1e-10 * s;
        let boxes: Vec<([f64; 3], [f64; 3])> = patches
            .tri
            .iter()
            .map(|g| {
                let [a, b, c] = g.corner;
                (
                    [0, 1, 2].map(|k| a[k].min(b[k]).min(c[k])),
                    [0, 1, 2].map(|k| a[k].max(b[k]).max(c[k])),
                )
            })
            .collect();
        let pad = 4.0 * inside_tolerance + patches.max_deviation;
        let group: Vec<u32> = patches.tri.iter().map(|g| g.patch).collect();
        let grid = grid::Grid::build(&boxes, &group, pad);
        let mut centroid = [0.0; 3];
        let mut area = 0.0;
        for g in &patches.tri {
            let [a, b, c] = g.corner;
            let w = 0.5 * norm(cross(sub(b, a), sub(c, a)));
            centroid = add(centroid, scale(add(add(a, b), c), w / 3.0));
            area += w;
        }
        let centroid = scale(centroid, 1.0 / area);
        // A mesh whose areas' squares overflow (edges above ~1e77 m, or a
        // flat patch's summed area vector above ~1.3e154 m²) gets a zero
        // patch normal (1/∞ = 0) and a NaN centroid (0 × ∞): refused.
        // Every other mesh's normals are unit to round-off (cleaning drops
        // the triangles whose squares underflow) and passes unchanged.
        let finite_unit = |n: [f64; 3]| (dot(n, n) - 1.0).abs() <= 1e-12;
        let sound = area.is_finite()
            && centroid.iter().all(|c| c.is_finite())
            && patches
                .patches
                .iter()
                .all(|p| p.area.is_finite() && finite_unit(p.normal));
        if !sound {
            return Err(MeshError::TooLarge {
                file: file.to_path_buf(),
            });
        }
        Ok(MeshGeometry {
            vertices: cleaned.vertices,
            triangles: cleaned.triangles,
            report: cleaned.report,
            patches,
            grid,
            lo,
            hi,
            centroid,
            area,
            inside_tolerance,
            snap_tolerance,
        })
    }

    /// Number of patches (the wall's elements).
    pub fn patch_count(&self) -> u32 {
        self.patches.patches.len() as u32
    }

    /// Largest distance of a vertex from its patch's plane, m.
    pub fn max_deviation(&self) -> f64 {
        self.patches.max_deviation
    }

    /// What a user is warned of after loading (empty when the file was
    /// clean): dropped triangles, open and non-manifold edges, reversed
    /// triangles, a non-orientable surface.
    pub fn warnings(&self) -> Vec<String> {
        let r = &self.report;
        let mut out = Vec::new();
        if r.degenerate > 0 {
            out.push(format!(
                "{} degenerate triangles dropped (zero area after welding vertices within {:e} m)",
                r.degenerate, r.weld_tolerance
            ));
        }
        if r.duplicate > 0 {
            out.push(format!("{} duplicate triangles dropped", r.duplicate));
        }
        if r.open_edges > 0 {
            out.push(format!(
                "{} open edges (the surface has a free boundary; spheres are pushed off its rim)",
                r.open_edges
            ));
        }
        if r.non_manifold_edges > 0 {
            out.push(format!(
                "{} non-manifold edges (three or more triangles on one edge)",
                r.non_manifold_edges
            ));
        }
        if r.reoriented > 0 {
            out.push(format!(
                "{} triangles reoriented to agree with their neighbours",
                r.reoriented
            ));
        }
        if r.orientation_conflicts > 0 {
            out.push(format!(
                "{} edges left with inconsistent orientation (a non-orientable surface)",
                r.orientation_conflicts
            ));
        }
        out
    }

    /// One line: triangles, vertices, patches, area (m²) and flatness.
    pub fn summary(&self) -> String {
        format!(
            "{} triangles ({} read), {} vertices, {} flat patches, area {:e} m², \
             largest distance of a vertex from its patch's plane {:e} m",
            self.triangles.len(),
            self.report.read,
            self.vertices.len(),
            self.patch_count(),
            self.area,
            self.max_deviation()
        )
    }

    /// Bytes held (vectors' capacities).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        let p = &self.patches;
        24 * self.vertices.capacity()
            + 12 * self.triangles.capacity()
            + size_of::<patch::Patch>() * p.patches.capacity()
            + 4 * p.triangles.capacity()
            + size_of::<patch::TriGeom>() * p.tri.capacity()
            + 4 * (p.edge_start.capacity() + p.edge_patches.capacity())
            + 4 * (p.vertex_start.capacity() + p.vertex_patches.capacity())
            + self.grid.bytes()
    }
}

/// A triangle-mesh wall.
#[derive(Clone, PartialEq)]
pub struct MeshWall {
    /// Index of the wall in file order.
    pub wall: usize,
    /// Its row of the law tables (one: every patch is flat).
    pub slot: usize,
    pub mesh: Arc<MeshGeometry>,
    /// Its pose and velocities when it moves (`walls::motion`). The
    /// triangles, patches and grid stay in the reference placement: a
    /// sphere's centre is taken into it by the inverse pose and the
    /// contact's normal turned back, so a moving mesh is never re-gridded
    /// (a rigid motion keeps every distance, so the overlap is the same
    /// number in either frame).
    pub moving: Option<WallState>,
}

impl std::fmt::Debug for MeshWall {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshWall")
            .field("wall", &self.wall)
            .field("slot", &self.slot)
            .field("triangles", &self.mesh.triangles.len())
            .field("patches", &self.mesh.patch_count())
            .finish()
    }
}

impl Wall for MeshWall {
    fn file_index(&self) -> usize {
        self.wall
    }

    fn elements(&self) -> u32 {
        self.mesh.patch_count()
    }

    fn near_elements(&self, x: [f64; 3], r: f64, range: f64, found: &mut dyn FnMut(u32)) {
        match &self.moving {
            None => self.mesh.patches_within(x, r + range, found),
            Some(m) => self.mesh.patches_within(m.unplace(x), r + range, found),
        }
    }

    #[inline]
    fn contact(&self, element: u32, x: [f64; 3], v: [f64; 3], r: f64) -> WallPoint {
        let Some(m) = &self.moving else {
            return self.mesh.patch_contact(element, x, v, r);
        };
        let c = self.mesh.patch_contact(element, m.unplace(x), [0.0; 3], r);
        if c.overlap == f64::NEG_INFINITY {
            return c;
        }
        let n = m.rotate(c.normal);
        let w = m.velocity_at([x[0] - r * n[0], x[1] - r * n[1], x[2] - r * n[2]]);
        let u = [v[0] - w[0], v[1] - w[1], v[2] - w[2]];
        WallPoint {
            overlap: c.overlap,
            rate: -(u[0] * n[0] + u[1] * n[1] + u[2] * n[2]),
            normal: n,
        }
    }

    fn moving(&self) -> Option<&WallState> {
        self.moving.as_ref()
    }

    fn posed(&self, state: &WallState) -> Option<crate::walls::Surface> {
        Some(crate::walls::Surface::Mesh(MeshWall {
            moving: Some(*state),
            ..self.clone()
        }))
    }

    fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        (self.mesh.lo, self.mesh.hi)
    }

    fn torque_point(&self) -> [f64; 3] {
        match &self.moving {
            None => self.mesh.centroid,
            Some(m) => m.place(self.mesh.centroid),
        }
    }

    fn law_slot(&self, _element: u32) -> usize {
        self.slot
    }
}
