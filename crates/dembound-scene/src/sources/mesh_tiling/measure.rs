//! What a covering lets through and how bumpy it is.
//!
//! **Largest hole.** A particle (radius ρ) passing through the wall must
//! cross the surface on which the sphere centres lie: the inner offset of
//! the mesh at depth R_b (the set of points exactly R_b behind the
//! surface; a plane for a flat wall, ridges at convex edges, arcs at
//! concave ones). Where its centre Y crosses it, it overlaps no boundary
//! sphere only if |Y − c_i| ≥ R_b + ρ for every centre c_i. So the largest
//! particle that can pass has radius
//!
//!   ρ_hole = max over Y on the offset of (min_i |Y − c_i|) − R_b,
//!
//! the largest hole. For a flat touching tiling it is the classical
//! window: (√2 − 1) R_b ≈ 0.414 R_b (square: the window's circumradius
//! s/√2) and (2/√3 − 1) R_b ≈ 0.155 R_b (hexagonal: s/√3). The offset is
//! sampled: every triangle's offset on a barycentric grid of spacing
//! h ≤ s/8, every feature edge's ridge and arc (points ≤ h apart, at
//! most 9, between the two faces' normals) every h; samples nearer than R_b (1 − 1e-6) to
//! the mesh (less the patches' flatness) are not on the offset and are
//! skipped. Offsets of corners
//! (vertex fans) are not sampled beyond their edges' arcs. Since
//! min_i |Y − c_i| changes by at most |ΔY| between samples, the true
//! maximum is below the sampled one plus the largest distance from an
//! offset point to its nearest sample, ≤ h: `hole_bound` = sampled + h.
//!
//! **Bumpiness.** A particle of radius ρ resting on the spheres above a
//! face point X (moving along the face normal n) has its centre at height
//! t(X) = max_i [ (c_i − X)·n + √((R_b + ρ)² − d_i²) ] above the surface,
//! d_i the distance of c_i from the normal line through X (spheres with
//! d_i < R_b + ρ). t = ρ on top of a sphere and less in a hollow; the
//! bumpiness is max t − min t over the face samples whose neighbourhood
//! (radius R_b + ρ + s, eight in-plane directions) lies on their patch:
//! the largest height change a particle rolling on a face feels.

use super::{any_triangle_within, Covering, PointGrid};
use crate::walls::mesh::geometry::{add, closest_on_triangle, dot, norm, scale, sub};
use crate::walls::mesh::MeshGeometry;

/// The largest hole and the bumpiness of a covering.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Holes {
    /// Largest hole radius found on the samples, m (0 when every sample
    /// lies within R_b of a centre: no particle passes).
    pub hole: f64,
    /// Where (the offset point), m.
    pub at: [f64; 3],
    /// `hole` + the sample spacing: an upper bound, m.
    pub hole_bound: f64,
    /// Sample spacing h, m.
    pub spacing: f64,
    /// Offset samples taken.
    pub samples: usize,
}

/// Sample spacing of the offset: s/8.
pub(crate) fn sample_spacing(c: &Covering) -> f64 {
    c.options.spacing / 8.0
}

/// Centres grid of cell s, and the nearest-centre distance within s
/// (else s: "at least"; after the fill every sample has a centre within
/// the window circumradius < s).
struct Nearest<'a> {
    grid: PointGrid,
    c: &'a Covering,
}

impl<'a> Nearest<'a> {
    fn new(c: &'a Covering) -> Self {
        let mut grid = PointGrid::new(c.options.spacing);
        for (i, s) in c.spheres.iter().enumerate() {
            grid.insert(s.position, i as u32);
        }
        Nearest { grid, c }
    }

    fn distance(&self, y: [f64; 3]) -> f64 {
        let cap = self.c.options.spacing;
        let mut best = cap;
        self.grid.around(y, 1, |id| {
            best = best.min(norm(sub(self.c.spheres[id as usize].position, y)));
        });
        best
    }
}

fn side(c: &Covering) -> f64 {
    if c.options.flip {
        -1.0
    } else {
        1.0
    }
}

/// Calls `f(triangle, X)` for samples of every triangle no farther than h
/// from any of its points: from a corner of its shortest edge, a grid of
/// steps ≤ h along that edge and the other edge at that corner (every
/// point of a grid cell is within h of a cell corner), plus points every
/// ≤ h along the third edge (the grid's staircase ends within a cell of
/// it). A sliver triangle gets few samples across, many along.
fn face_samples(mesh: &MeshGeometry, h: f64, mut f: impl FnMut(usize, [f64; 3])) {
    for (t, g) in mesh.patches.tri.iter().enumerate() {
        let c = g.corner;
        let length = |k: usize| norm(sub(c[(k + 1) % 3], c[k]));
        let shortest = (0..3)
            .min_by(|&i, &j| length(i).total_cmp(&length(j)))
            .unwrap_or(0);
        // Corner a, its shortest edge to b, its other edge to d.
        let (a, b, d) = (c[shortest], c[(shortest + 1) % 3], c[(shortest + 2) % 3]);
        let m1 = (norm(sub(b, a)) / h).ceil().max(1.0) as usize;
        let m2 = (norm(sub(d, a)) / h).ceil().max(1.0) as usize;
        for i in 0..=m1 {
            let u = i as f64 / m1 as f64;
            for j in 0..=m2 {
                let v = j as f64 / m2 as f64;
                if u + v > 1.0 + 1e-12 {
                    break;
                }
                f(t, add(a, add(scale(sub(b, a), u), scale(sub(d, a), v))));
            }
        }
        let m3 = (norm(sub(d, b)) / h).ceil().max(1.0) as usize;
        for k in 1..m3 {
            f(t, add(b, scale(sub(d, b), k as f64 / m3 as f64)));
        }
    }
}

/// Calls `f(Y)` for the samples of the centres' surface (the inner
/// offset at depth R_b, module doc) of spacing ≤ h, faces then feature
/// edges, in mesh order.
pub(crate) fn offset_samples(
    mesh: &MeshGeometry,
    r: f64,
    flip: bool,
    h: f64,
    mut f: impl FnMut([f64; 3]),
) {
    let off = r * (1.0 - 1e-6) - mesh.patches.max_deviation - mesh.inside_tolerance;
    let sgn = if flip { -1.0 } else { 1.0 };
    let mut visit = |y: [f64; 3]| {
        if !any_triangle_within(mesh, y, off) {
            f(y);
        }
    };
    face_samples(mesh, h, |t, x| {
        let p = mesh.patches.tri[t].patch as usize;
        let n = scale(mesh.patches.patches[p].normal, sgn);
        visit(sub(x, scale(n, r)));
    });
    // Feature edges: ridge and arc.
    for (t, g) in mesh.patches.tri.iter().enumerate() {
        for k in 0..3 {
            let others = mesh.patches.across(t as u32, k);
            if !g.boundary[k] || others.is_empty() {
                continue;
            }
            let n1 = scale(mesh.patches.patches[g.patch as usize].normal, sgn);
            let (pa, pb) = (g.corner[k], g.corner[(k + 1) % 3]);
            let pieces = (norm(sub(pb, pa)) / h).ceil().max(1.0) as usize;
            for &q in others {
                let n2 = scale(mesh.patches.patches[q as usize].normal, sgn);
                let ridge = super::corner_offset(&[n1, n2]);
                // Arc points every ≤ h (length θ R_b), at most 8 pieces.
                let angle = dot(n1, n2).clamp(-1.0, 1.0).acos();
                let arc = ((angle * r / h).ceil() as usize).clamp(1, 8);
                for i in 0..=pieces {
                    let x = add(pa, scale(sub(pb, pa), i as f64 / pieces as f64));
                    if let Some(a) = ridge {
                        visit(sub(x, scale(a, r)));
                    }
                    for w in 1..arc {
                        let w = w as f64 / arc as f64;
                        let m = add(scale(n1, 1.0 - w), scale(n2, w));
                        let l = norm(m);
                        if l > 1e-9 {
                            visit(sub(x, scale(m, r / l)));
                        }
                    }
                }
            }
        }
    }
}

/// The largest hole of a covering (module doc), sampled every s/8.
pub fn holes(c: &Covering) -> Holes {
    holes_sampled(c, sample_spacing(c))
}

/// The largest hole sampled every `h` (≤ s/8 for the bound of the module
/// doc to hold; a finer `h` tightens `hole_bound` = sampled + h, at a cost
/// growing as 1/h²).
pub fn holes_sampled(c: &Covering, h: f64) -> Holes {
    let r = c.options.radius;
    let near = Nearest::new(c);
    let mut worst = Holes {
        hole: f64::NEG_INFINITY,
        at: [0.0; 3],
        hole_bound: f64::NEG_INFINITY,
        spacing: h,
        samples: 0,
    };
    offset_samples(&c.mesh, r, c.options.flip, h, |y| {
        worst.samples += 1;
        let hole = near.distance(y) - r;
        if hole > worst.hole {
            worst.hole = hole;
            worst.at = y;
        }
    });
    worst.hole_bound = worst.hole + h;
    if worst.samples > 0 && worst.hole < 0.0 {
        // Every sample lies within R_b of a centre (spheres overlapping
        // all over a surface smaller than their spacing): no particle
        // passes, a hole of radius 0, not the negative distance (a
        // 1 nm square under 1 mm spheres printed −1 R_b).
        worst.hole = 0.0;
        worst.hole_bound = worst.hole_bound.max(0.0);
    }
    worst
}

/// Whether x lies on patch p (within `tol`).
fn on_patch(mesh: &MeshGeometry, p: u32, x: [f64; 3], tol: f64) -> bool {
    let Some(r) = mesh.grid.range(x.map(|c| c - tol), x.map(|c| c + tol)) else {
        return false;
    };
    let mut found = false;
    mesh.grid.each_cell(&r, |cell| {
        for &t in mesh.grid.cell_items(cell) {
            let g = &mesh.patches.tri[t as usize];
            if !found && g.patch == p {
                let y = closest_on_triangle(x, g.corner[0], g.corner[1], g.corner[2]);
                found = norm(sub(x, y)) <= tol;
            }
        }
    });
    found
}

/// The bumpiness felt by a particle of radius `rho` on the faces (module
/// doc), m: (max t − min t, samples used); `None` when no face sample
/// has a whole neighbourhood on its patch.
pub fn bumpiness(c: &Covering, rho: f64) -> Option<(f64, usize)> {
    let (mut lo, mut hi, mut used) = (f64::INFINITY, f64::NEG_INFINITY, 0usize);
    resting_heights(c, rho, |_, _, top| {
        used += 1;
        lo = lo.min(top);
        hi = hi.max(top);
    });
    (used > 0).then_some((hi - lo, used))
}

/// Calls `f(X, n, t)` for every face sample X whose neighbourhood (radius
/// R_b + ρ + s, eight in-plane directions) lies on its patch and under
/// which some sphere holds a particle of radius `rho`: n the patch's
/// normal toward the particles, t the height of the resting particle's
/// centre above the surface (module doc), in sample order.
pub(crate) fn resting_heights(c: &Covering, rho: f64, mut f: impl FnMut([f64; 3], [f64; 3], f64)) {
    let mesh = &c.mesh;
    let r = c.options.radius;
    let reach = r + rho;
    let h = sample_spacing(c);
    let sgn = side(c);
    let mut grid = PointGrid::new(reach);
    for (i, s) in c.spheres.iter().enumerate() {
        grid.insert(s.position, i as u32);
    }
    let tol = mesh.inside_tolerance.max(1e-9 * c.options.spacing);
    face_samples(mesh, h, |t, x| {
        let p = mesh.patches.tri[t].patch;
        let n = scale(mesh.patches.patches[p as usize].normal, sgn);
        let (u, v) = super::super::tiling::plane_axes(n);
        let ring = reach + c.options.spacing;
        let whole = (0..8).all(|k| {
            let a = k as f64 * std::f64::consts::FRAC_PI_4;
            let y = add(x, add(scale(u, ring * a.cos()), scale(v, ring * a.sin())));
            on_patch(mesh, p, y, tol)
        });
        if !whole {
            return;
        }
        let mut top = f64::NEG_INFINITY;
        grid.around(x, 1, |id| {
            let w = sub(c.spheres[id as usize].position, x);
            let wn = dot(w, n);
            let lateral = norm(sub(w, scale(n, wn)));
            if lateral < reach {
                top = top.max(wn + (reach * reach - lateral * lateral).sqrt());
            }
        });
        if top.is_finite() {
            f(x, n, top);
        }
    });
}
