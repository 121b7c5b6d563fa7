//! Boundary particles covering any triangle mesh (issue 29): the plane
//! tiling of [`super::tiling`] carried onto every flat patch of a part,
//! its edges and corners closed, with the largest hole and the bumpiness
//! measured ([`measure`]).
//!
//! **The side.** The spheres go behind the surface, on the side opposite
//! to the triangles' normals (the particles are on the normals' side);
//! `flip` swaps the sides. For a closed STL solid (outward normals) the
//! default covers the part seen from outside.
//!
//! **Where the spheres sit: no sphere crosses the surface, every sphere
//! touches it.** A candidate sphere of radius R_b is kept only if its
//! centre is at least R_b from every triangle of the mesh, less the
//! patches' flatness (`max_deviation`, the f32 rounding of an STL) and
//! 1e-9 R_b (no part of it pokes through the surface to the particles'
//! side); the
//! candidates are made so that they touch the surface:
//! 1. *Faces.* Each flat patch (normal n toward the particles) is tiled as
//!    a plane `boundary_particles` wall ([`super::tiling::Tiling`]) with
//!    the point where the patch's plane is nearest the origin, the same
//!    pattern, radius and spacing, over the patch's bounding box: centres
//!    at `site − R_b n`, tops on the surface. A patch that shares no edge
//!    with another keeps every site (the plane wall's tiling of its box,
//!    one site beyond each edge: a flat square STL gives exactly the
//!    plane wall's spheres, tested). Otherwise a site is kept if it lies
//!    on the patch, or within one spacing s of it where no other patch is
//!    within s (an open rim).
//! 2. *Corners* (vertices touching ≥ 2 patches) and 3. *feature edges*
//!    (edges between two patches, sampled at a spacing ≤ s, endpoints
//!    excluded): the centre is `p − R_b a`, with a = m / min_i(m·n_i),
//!    m the unit sum of the touching patches' normals n_i: the sphere is
//!    R_b or more behind every touching face's plane and exactly R_b
//!    behind the nearest (tangent to both faces of an edge). A convex edge
//!    is thus rounded by R_b, never sharpened by a sphere sticking out; a
//!    corner sharper than m·n_i < 0.1 (its sphere > 10 R_b deep) gets none.
//!
//! 4. *Fill.* Lattices of neighbouring patches meet at arbitrary
//!    offsets, so windows wider than the face lattice's can remain along
//!    edges. The centres' surface (the mesh offset inward by R_b,
//!    [`measure`]) is sampled every s/8; each sample farther than the
//!    lattice's window circumradius (s/√2 square, s/√3 hexagonal) from
//!    every centre gets a sphere centred there (it touches the surface
//!    and crosses none: the sample is R_b from the mesh), in sample order.
//!    Every sample then has a centre within the window circumradius, so
//!    the largest hole is the flat lattice's, plus at most the sampling.
//!
//! **Concave corners: no pile-ups.** Candidates are taken in the order
//! faces, corners, edges; one whose centre is closer than s/2 to a sphere
//! already kept is dropped. At a concave edge the two faces' lattices and
//! the edge line all put spheres near the valley; without the rule up to
//! three spheres would sit within a fraction of R_b of each other there,
//! and two lattices meeting at an arbitrary offset would leave slots
//! narrower than a particle between nearly coincident spheres, where a
//! particle wedges with nearly opposite contact normals (a lock). With
//! it, kept centres are ≥ s/2 apart (never more than R_b of overlap at
//! s = 2 R_b), and every window a particle could enter is measured by
//! the hole size: a particle larger than the largest hole touches the
//! spheres on the particles' side of their centres and cannot wedge
//! between two of them.
//!
//! Deterministic: no randomness; candidates in patch, vertex, edge and
//! sample order of the cleaned mesh, itself deterministic.

pub mod measure;
pub mod shapes;
pub mod slopes;

use super::tiling::{Extent, Pattern, Tiling};
use super::SourceSphere;
use crate::walls::mesh::geometry::{add, closest_on_triangle, dot, norm, scale, sub};
use crate::walls::mesh::{MeshGeometry, MeshOptions, Transform, Triangle};
use crate::SceneError;
use std::collections::HashMap;
use std::path::Path;

/// How to cover a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoveringOptions {
    /// Boundary-sphere radius R_b, m.
    pub radius: f64,
    /// Lattice spacing s, m (2 R_b: touching).
    pub spacing: f64,
    pub pattern: Pattern,
    /// Spheres on the normals' side (particles behind the triangles).
    pub flip: bool,
}

/// How a refusal names the covering's radius and spacing: the keys or
/// flags the user set them with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Names<'a> {
    /// R_b's key (`--radius`, or a scene wall's `radius_ratio`); the same
    /// as `spacing` when one key sets both (s = 2 R_b).
    pub radius: &'a str,
    /// s's key.
    pub spacing: &'a str,
}

impl Names<'static> {
    /// `dembound particle-wall`'s flags.
    pub const FLAGS: Names<'static> = Names {
        radius: "--radius",
        spacing: "--spacing",
    };
}

/// Where a sphere of the covering came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Origin {
    Face,
    Corner,
    Edge,
    /// Added where a hole remained (step 4).
    Fill,
}

/// A covered mesh: the spheres and the mesh they cover.
#[derive(Debug, Clone)]
pub struct Covering {
    pub spheres: Vec<SourceSphere>,
    /// What made each sphere (same order).
    pub origin: Vec<Origin>,
    pub mesh: MeshGeometry,
    pub options: CoveringOptions,
    /// Candidates dropped for crossing the surface / for a near duplicate.
    pub dropped_crossing: usize,
    pub dropped_duplicate: usize,
}

/// Largest sphere count of one covering (the plane wall's limit).
pub const MAX_COVERING_SPHERES: usize = super::tiling::MAX_WALL_SPHERES;

/// Smallest m·n_i of a corner or edge that gets a sphere (module doc).
const SHARPEST: f64 = 0.1;

/// A multiplicative hash of grid cells (the default SipHash took a
/// third of a covering's time).
#[derive(Default)]
pub(crate) struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 =
                (self.0.rotate_left(5) ^ u64::from(*b)).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
        }
    }
    fn write_i64(&mut self, v: i64) {
        self.0 = (self.0.rotate_left(5) ^ v as u64).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

type CellMap = HashMap<[i64; 3], Vec<u32>, std::hash::BuildHasherDefault<CellHasher>>;

/// A uniform hash grid of points (sphere centres).
pub(crate) struct PointGrid {
    cell: f64,
    cells: CellMap,
}

impl PointGrid {
    pub(crate) fn new(cell: f64) -> Self {
        PointGrid {
            cell,
            cells: CellMap::default(),
        }
    }

    fn key(&self, x: [f64; 3]) -> [i64; 3] {
        x.map(|c| (c / self.cell).floor() as i64)
    }

    pub(crate) fn insert(&mut self, x: [f64; 3], id: u32) {
        let k = self.key(x);
        self.cells.entry(k).or_default().push(id);
    }

    /// Calls `f` with every id in the cells within `reach` cells of x's.
    pub(crate) fn around(&self, x: [f64; 3], reach: i64, mut f: impl FnMut(u32)) {
        let k = self.key(x);
        for i in -reach..=reach {
            for j in -reach..=reach {
                for l in -reach..=reach {
                    if let Some(ids) = self.cells.get(&[k[0] + i, k[1] + j, k[2] + l]) {
                        ids.iter().for_each(|&id| f(id));
                    }
                }
            }
        }
    }
}

/// Whether some triangle of `mesh` is closer than `reach` to x.
pub(crate) fn any_triangle_within(mesh: &MeshGeometry, x: [f64; 3], reach: f64) -> bool {
    let Some(r) = mesh.grid.range(x.map(|c| c - reach), x.map(|c| c + reach)) else {
        return false;
    };
    let mut found = false;
    mesh.grid.each_cell(&r, |c| {
        if found {
            return;
        }
        for &t in mesh.grid.cell_items(c) {
            let g = &mesh.patches.tri[t as usize];
            let y = closest_on_triangle(x, g.corner[0], g.corner[1], g.corner[2]);
            if norm(sub(x, y)) < reach {
                found = true;
                return;
            }
        }
    });
    found
}

/// Distance from x to patch `p` if below `reach` (else `None`), and
/// whether another patch is within `reach`.
fn patch_distance(mesh: &MeshGeometry, p: u32, x: [f64; 3], reach: f64) -> (Option<f64>, bool) {
    let Some(r) = mesh.grid.range(x.map(|c| c - reach), x.map(|c| c + reach)) else {
        return (None, false);
    };
    let mut own: Option<f64> = None;
    let mut other = false;
    mesh.grid.each_cell(&r, |c| {
        for &t in mesh.grid.cell_items(c) {
            let g = &mesh.patches.tri[t as usize];
            if g.patch != p && other {
                continue;
            }
            let y = closest_on_triangle(x, g.corner[0], g.corner[1], g.corner[2]);
            let d = norm(sub(x, y));
            if d < reach {
                if g.patch == p {
                    own = Some(own.map_or(d, |o: f64| o.min(d)));
                } else {
                    other = true;
                }
            }
        }
    });
    (own, other)
}

/// The offset direction a (module doc) of unit normals `normals`, or
/// `None` for a corner sharper than [`SHARPEST`].
pub(crate) fn corner_offset(normals: &[[f64; 3]]) -> Option<[f64; 3]> {
    let sum = normals.iter().fold([0.0; 3], |s, n| add(s, *n));
    let l = norm(sum);
    if l < 1e-12 {
        return None;
    }
    let m = scale(sum, 1.0 / l);
    let least = normals
        .iter()
        .map(|n| dot(m, *n))
        .fold(f64::INFINITY, f64::min);
    (least >= SHARPEST).then(|| scale(m, 1.0 / least))
}

impl CoveringOptions {
    fn check(&self, names: Names<'_>) -> Result<(), SceneError> {
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err(SceneError::input(format!(
                "`{}` gives R_b = {:e} m: the boundary-sphere radius must be a finite length > 0 m",
                names.radius, self.radius
            )));
        }
        if !(self.spacing > 0.0 && self.spacing.is_finite()) {
            return Err(SceneError::input(format!(
                "`{}` = {:e} m: must be a finite length > 0 m",
                names.spacing, self.spacing
            )));
        }
        Ok(())
    }
}

/// Reads the mesh file `path` (STL or OBJ) and covers it.
pub fn cover_file(path: &Path, options: &CoveringOptions) -> Result<Covering, SceneError> {
    let soup = crate::walls::mesh::read::read_triangles(path)
        .map_err(|e| SceneError::input(e.to_string()))?;
    cover(path, &soup, options)
}

/// Covers the triangles `soup` (`file` names them in errors), a refusal
/// naming R_b and s as `dembound particle-wall`'s flags ([`Names::FLAGS`]).
pub fn cover(
    file: &Path,
    soup: &[Triangle],
    options: &CoveringOptions,
) -> Result<Covering, SceneError> {
    cover_named(file, soup, options, Names::FLAGS)
}

/// [`cover`], a refusal naming R_b and s by `names`.
pub fn cover_named(
    file: &Path,
    soup: &[Triangle],
    options: &CoveringOptions,
    names: Names<'_>,
) -> Result<Covering, SceneError> {
    options.check(names)?;
    let raise = if names.radius == names.spacing {
        format!("raise `{}`", names.radius)
    } else {
        format!("raise `{}` or `{}`", names.radius, names.spacing)
    };
    let mesh =
        MeshGeometry::from_triangles(file, soup, &Transform::default(), &MeshOptions::default())
            .map_err(|e| SceneError::input(e.to_string()))?;
    let side = if options.flip { -1.0 } else { 1.0 };
    let normal_of = |p: u32| scale(mesh.patches.patches[p as usize].normal, side);
    let (radius, s) = (options.radius, options.spacing);
    // A patch's triangles lie within `max_deviation` of its plane (f32
    // STL rounding, ~1e-9 m on a 2 cm part): a face sphere touching the
    // plane may be that much nearer to its own triangles.
    let slack = mesh.patches.max_deviation + mesh.inside_tolerance + 1e-9 * radius;
    let crossing = radius - slack;
    let merge = 0.5 * s;
    let mut kept = Covering {
        spheres: Vec::new(),
        origin: Vec::new(),
        mesh: mesh.clone(),
        options: *options,
        dropped_crossing: 0,
        dropped_duplicate: 0,
    };
    let mut grid = PointGrid::new(merge);
    let mut offer = |kept: &mut Covering, c: [f64; 3], origin: Origin| -> Result<(), SceneError> {
        if any_triangle_within(&mesh, c, crossing) {
            kept.dropped_crossing += 1;
            return Ok(());
        }
        let mut near = false;
        grid.around(c, 1, |id| {
            near |= norm(sub(kept.spheres[id as usize].position, c)) < merge;
        });
        if near {
            kept.dropped_duplicate += 1;
            return Ok(());
        }
        if kept.spheres.len() >= MAX_COVERING_SPHERES {
            return Err(SceneError::input(format!(
                "more than {MAX_COVERING_SPHERES} boundary spheres of radius {radius:e} m would cover \
                 the mesh; {raise}"
            )));
        }
        grid.insert(c, kept.spheres.len() as u32);
        kept.spheres.push(SourceSphere::at_rest(c, radius));
        kept.origin.push(origin);
        Ok(())
    };

    // 1. Faces.
    for p in 0..mesh.patch_count() {
        let n = normal_of(p);
        let patch = &mesh.patches.patches[p as usize];
        let point = scale(n, dot(n, patch.point));
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &t in mesh.patches.of(p) {
            for v in mesh.patches.tri[t as usize].corner {
                for k in 0..3 {
                    lo[k] = lo[k].min(v[k]);
                    hi[k] = hi[k].max(v[k]);
                }
            }
        }
        let tiling = Tiling {
            point,
            normal: n,
            radius,
            spacing: s,
            pattern: options.pattern,
        };
        let extent = Extent {
            lower: lo,
            upper: hi,
            periodic: [false; 3],
        };
        let on = mesh.patches.max_deviation + mesh.inside_tolerance + 1e-9 * s;
        // A patch meeting no other keeps the whole plane tiling of its box.
        let isolated = mesh
            .patches
            .of(p)
            .iter()
            .all(|&t| (0..3).all(|k| mesh.patches.across(t, k).is_empty()));
        // The plane tiling of a face's box: with R_b and s checked, a
        // unit normal and a finite box, the one refusal left is its count.
        let sites = tiling.spheres(&extent, "mesh").map_err(|_| {
            SceneError::input(format!(
                "more than {} boundary spheres of radius {radius:e} m at spacing {s:e} m would \
                 tile a face of the mesh ({} to {} m); {raise}",
                super::tiling::MAX_WALL_SPHERES,
                crate::walls::registry::show3(lo),
                crate::walls::registry::show3(hi),
            ))
        })?;
        for site in sites {
            let x = add(site.position, scale(n, radius));
            let (own, other) = patch_distance(&mesh, p, x, s * (1.0 + 1e-9));
            let keep = isolated
                || match own {
                    Some(d) => d <= on || !other,
                    None => false,
                };
            if keep {
                offer(&mut kept, site.position, Origin::Face)?;
            }
        }
    }

    // 2. Corners.
    for (v, x) in mesh.vertices.iter().enumerate() {
        let around = mesh.patches.around(v as u32);
        if around.len() < 2 {
            continue;
        }
        let normals: Vec<[f64; 3]> = around.iter().map(|&p| normal_of(p)).collect();
        if let Some(a) = corner_offset(&normals) {
            offer(&mut kept, sub(*x, scale(a, radius)), Origin::Corner)?;
        }
    }

    // 3. Feature edges, each once (from its lowest triangle, slot order).
    let mut seen: HashMap<(u32, u32), ()> = HashMap::new();
    for (t, g) in mesh.patches.tri.iter().enumerate() {
        for k in 0..3 {
            let others = mesh.patches.across(t as u32, k);
            if !g.boundary[k] || others.is_empty() {
                continue;
            }
            let (a, b) = (g.vertex[k], g.vertex[(k + 1) % 3]);
            if seen.insert((a.min(b), a.max(b)), ()).is_some() {
                continue;
            }
            let mut normals = vec![normal_of(g.patch)];
            normals.extend(others.iter().map(|&p| normal_of(p)));
            let Some(off) = corner_offset(&normals) else {
                continue;
            };
            let (pa, pb) = (g.corner[k], g.corner[(k + 1) % 3]);
            let length = norm(sub(pb, pa));
            let pieces = (length / s).ceil().max(1.0) as usize;
            for i in 1..pieces {
                let x = add(pa, scale(sub(pb, pa), i as f64 / pieces as f64));
                offer(&mut kept, sub(x, scale(off, radius)), Origin::Edge)?;
            }
        }
    }

    // 4. Fill: every sample of the centres' surface farther than the face
    // lattice's window circumradius from all centres gets a sphere there.
    let window = window_circumradius(options);
    let h = measure::sample_spacing(&kept);
    let mut near = PointGrid::new(window);
    for (i, b) in kept.spheres.iter().enumerate() {
        near.insert(b.position, i as u32);
    }
    let mut fill = Vec::new();
    measure::offset_samples(&mesh, radius, options.flip, h, |y| {
        let mut covered = false;
        near.around(y, 1, |id| {
            let c = if (id as usize) < kept.spheres.len() {
                kept.spheres[id as usize].position
            } else {
                fill[id as usize - kept.spheres.len()]
            };
            covered |= norm(sub(c, y)) <= window * (1.0 + 1e-9);
        });
        if !covered {
            near.insert(y, (kept.spheres.len() + fill.len()) as u32);
            fill.push(y);
        }
    });
    if kept.spheres.len() + fill.len() > MAX_COVERING_SPHERES {
        return Err(SceneError::input(format!(
            "more than {MAX_COVERING_SPHERES} boundary spheres of radius {radius:e} m would cover \
             the mesh; raise `--radius` or `--spacing`"
        )));
    }
    for y in fill {
        kept.spheres.push(SourceSphere::at_rest(y, radius));
        kept.origin.push(Origin::Fill);
    }
    Ok(kept)
}

/// The circumradius of a window of the face lattice: s/√2 (square), s/√3
/// (hexagonal); the largest hole of a flat wall is this minus R_b.
pub fn window_circumradius(options: &CoveringOptions) -> f64 {
    match options.pattern {
        Pattern::Square => options.spacing / 2f64.sqrt(),
        Pattern::Hexagonal => options.spacing / 3f64.sqrt(),
    }
}

#[cfg(test)]
mod tests;
