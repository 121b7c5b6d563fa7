//! The sphere–patch contact and the one-force rule (see the module doc of
//! `walls::mesh` for the rules and why).

use super::geometry::{
    closest_on_segment, closest_on_triangle, dot, norm, scale, segment_meets_triangle, sub,
};
use super::MeshGeometry;
use crate::walls::WallPoint;

/// Patches of at most this many triangles are tested directly, without
/// the grid (a flat rectangle is 2).
pub(super) const SMALL_PATCH: u32 = 8;

/// A patch's closest point lies on this feature of its boundary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// A vertex (mesh vertex index).
    Vertex(u32),
    /// The inside of edge k of triangle t.
    Edge(u32, u8),
}

/// The closest point of a patch's boundary to a centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryPoint {
    pub point: [f64; 3],
    pub feature: Feature,
    pub distance: f64,
}

/// Overlap −∞: the element does not face the sphere (another element
/// carries the contact, or none).
pub const NOT_TOUCHING: WallPoint = WallPoint {
    overlap: f64::NEG_INFINITY,
    rate: 0.0,
    normal: [0.0; 3],
};

impl MeshGeometry {
    /// Signed distance of x from patch p's plane, with
    /// `walls::plane::plane_overlap`'s arithmetic.
    #[inline(always)]
    pub(super) fn plane_distance(&self, p: u32, x: [f64; 3]) -> f64 {
        let q = &self.patches.patches[p as usize];
        let (n, o) = (q.normal, q.point);
        (x[0] - o[0]) * n[0] + (x[1] - o[1]) * n[1] + (x[2] - o[2]) * n[2]
    }

    /// Is x over triangle t (its projection along the patch normal inside,
    /// within the inside tolerance)?
    #[inline(always)]
    pub(super) fn over_triangle(&self, t: u32, x: [f64; 3]) -> bool {
        let g = &self.patches.tri[t as usize];
        let e = -self.inside_tolerance;
        dot(g.inward[0], sub(x, g.corner[0])) >= e
            && dot(g.inward[1], sub(x, g.corner[1])) >= e
            && dot(g.inward[2], sub(x, g.corner[2])) >= e
    }

    /// Is x over patch p (over one of its triangles)? `d` is x's signed
    /// distance from the patch plane (to look the projection up in the
    /// grid).
    pub(super) fn over_patch(&self, p: u32, x: [f64; 3], d: f64) -> bool {
        let patch = &self.patches.patches[p as usize];
        if patch.count <= SMALL_PATCH {
            return self.patches.of(p).iter().any(|&t| self.over_triangle(t, x));
        }
        let q = sub(x, scale(patch.normal, d));
        let Some(r) = self.grid.range(q, q) else {
            return false;
        };
        let mut over = false;
        self.grid.each_cell(&r, |c| {
            if !over {
                over =
                    self.grid.cell_items(c).iter().any(|&t| {
                        self.patches.tri[t as usize].patch == p && self.over_triangle(t, x)
                    });
            }
        });
        over
    }

    /// The boundary edges of triangle t tested against x, improving `best`.
    #[inline]
    fn boundary_of_triangle(&self, t: u32, x: [f64; 3], best: &mut Option<BoundaryPoint>) {
        let g = &self.patches.tri[t as usize];
        for k in 0..3 {
            if !g.boundary[k] {
                continue;
            }
            let (a, b) = (g.corner[k], g.corner[(k + 1) % 3]);
            let (mut c, _) = closest_on_segment(x, a, b);
            // A point within the snap tolerance of an end is that vertex.
            let feature = if norm(sub(c, a)) <= self.snap_tolerance {
                c = a;
                Feature::Vertex(g.vertex[k])
            } else if norm(sub(c, b)) <= self.snap_tolerance {
                c = b;
                Feature::Vertex(g.vertex[(k + 1) % 3])
            } else {
                Feature::Edge(t, k as u8)
            };
            let distance = norm(sub(x, c));
            if best.is_none_or(|b| distance < b.distance) {
                *best = Some(BoundaryPoint {
                    point: c,
                    feature,
                    distance,
                });
            }
        }
    }

    /// The point of patch p's boundary closest to x. The grid is searched
    /// in boxes of half-width `reach` (m), doubled until the best point
    /// found lies within the box (then no closer one lies outside).
    pub fn boundary_closest(&self, p: u32, x: [f64; 3], reach: f64) -> Option<BoundaryPoint> {
        let patch = self.patches.patches.get(p as usize)?;
        let mut best = None;
        if patch.count <= SMALL_PATCH {
            for &t in self.patches.of(p) {
                self.boundary_of_triangle(t, x, &mut best);
            }
            return best;
        }
        let mut h = reach.max(self.grid.cell);
        for _ in 0..128 {
            let range = self.grid.range(x.map(|c| c - h), x.map(|c| c + h));
            if let Some(r) = range {
                self.grid.each_cell(&r, |c| {
                    for &t in self.grid.cell_items(c) {
                        if self.patches.tri[t as usize].patch == p {
                            self.boundary_of_triangle(t, x, &mut best);
                        }
                    }
                });
                let done = best.is_some_and(|b: BoundaryPoint| b.distance <= h);
                if done || self.grid.covers_all(&r) {
                    return best;
                }
            }
            h *= 2.0;
        }
        None
    }

    /// The one-force rule for a boundary point `b` of patch p: kept iff no
    /// other patch touching b's feature has a lower id, and each of them
    /// has b as its own closest point (its centre's projection outside
    /// it, its boundary point within the agreement tolerance of b).
    ///
    /// Except at a concave fold: when b lies inside an edge of p and the
    /// other patch q both carries x (its projection inside q) and rises
    /// from the edge toward x's side of q's plane (p's surface turns
    /// toward the sphere: a valley seen from x), q's face contact does not
    /// hide p's edge point. The sphere then touches both faces, and p's
    /// contact r − |x − b| becomes p's face contact r − d_p continuously
    /// as x's projection enters p (at that line x − b is along p's
    /// normal). Dropping it made p's contact appear with a finite overlap
    /// there: a force jump that created energy in polygonal drums.
    pub(super) fn owns(&self, p: u32, x: [f64; 3], reach: f64, b: &BoundaryPoint) -> bool {
        let others = match b.feature {
            Feature::Vertex(v) => self.patches.around(v),
            Feature::Edge(t, k) => self.patches.across(t, k as usize),
        };
        let valley = |q: u32| -> bool {
            let Feature::Edge(t, k) = b.feature else {
                return false;
            };
            let into_p = self.patches.tri[t as usize].inward[k as usize];
            let n_q = self.patches.patches[q as usize].normal;
            let d_q = self.plane_distance(q, x);
            dot(n_q, into_p) * d_q > 0.0 && self.over_patch(q, x, d_q)
        };
        if others.iter().any(|&q| q < p && !valley(q)) {
            return false;
        }
        for &q in others {
            if q == p || valley(q) {
                continue;
            }
            if self.over_patch(q, x, self.plane_distance(q, x)) {
                return false;
            }
            match self.boundary_closest(q, x, reach) {
                Some(c) if norm(sub(c.point, b.point)) <= self.snap_tolerance => {}
                _ => return false,
            }
        }
        true
    }

    /// Is the contact point c of patch p hidden from the centre x by
    /// another patch: does the segment from x to c meet a triangle of
    /// another patch farther than the tolerance from c (a sphere does not
    /// touch a surface through another one: near a sharp vertex of a
    /// solid, the faces on its far side are within a radius of the centre
    /// through the solid)?
    pub fn hidden(&self, p: u32, x: [f64; 3], c: [f64; 3]) -> bool {
        if self.patches.patches.len() < 2 {
            return false;
        }
        let lo = [0, 1, 2].map(|k| x[k].min(c[k]));
        let hi = [0, 1, 2].map(|k| x[k].max(c[k]));
        let Some(range) = self.grid.range(lo, hi) else {
            return false;
        };
        let tolerance = self.snap_tolerance + 1e-9 * norm(sub(x, c));
        let mut hidden = false;
        self.grid.each_cell(&range, |cell| {
            if hidden {
                return;
            }
            // A cell's triangles come grouped by patch: one side test per
            // patch (both ends on one side of its plane: no crossing; its
            // triangles lie within the patch's deviation, ≤ 1e-6 of its
            // extent, of that plane), then the exact test per triangle.
            let mut skip = u32::MAX;
            let mut open = u32::MAX;
            for &t in self.grid.cell_items(cell) {
                let g = &self.patches.tri[t as usize];
                if g.patch == p || g.patch == skip {
                    continue;
                }
                if g.patch != open {
                    let q = &self.patches.patches[g.patch as usize];
                    if dot(sub(x, q.point), q.normal) * dot(sub(c, q.point), q.normal) > 0.0 {
                        skip = g.patch;
                        continue;
                    }
                    open = g.patch;
                }
                let [a, b, e] = g.corner;
                if let Some(h) = segment_meets_triangle(x, c, a, b, e) {
                    if norm(sub(h, c)) > tolerance {
                        hidden = true;
                        return;
                    }
                }
            }
        });
        hidden
    }

    /// The contact of patch p with a sphere at x, velocity v, radius r.
    pub fn patch_contact(&self, p: u32, x: [f64; 3], v: [f64; 3], r: f64) -> WallPoint {
        if p as usize >= self.patches.patches.len() {
            return NOT_TOUCHING;
        }
        let d = self.plane_distance(p, x);
        if self.over_patch(p, x, d) {
            // The plane's contact, two-sided: the normal toward the side
            // the centre is on.
            let n = self.patches.patches[p as usize].normal;
            let point = if d >= 0.0 {
                WallPoint {
                    overlap: r - d,
                    rate: -(v[0] * n[0] + v[1] * n[1] + v[2] * n[2]),
                    normal: n,
                }
            } else {
                let m = n.map(|c| -c);
                WallPoint {
                    overlap: r + d,
                    rate: -(v[0] * m[0] + v[1] * m[1] + v[2] * m[2]),
                    normal: m,
                }
            };
            if point.overlap > 0.0 && self.hidden(p, x, sub(x, scale(n, d))) {
                return NOT_TOUCHING;
            }
            return point;
        }
        let Some(b) = self.boundary_closest(p, x, r) else {
            return NOT_TOUCHING;
        };
        if !self.owns(p, x, r, &b) || (r > b.distance && self.hidden(p, x, b.point)) {
            return NOT_TOUCHING;
        }
        let normal = if b.distance > 0.0 {
            scale(sub(x, b.point), 1.0 / b.distance)
        } else {
            self.patches.patches[p as usize].normal
        };
        WallPoint {
            overlap: r - b.distance,
            rate: -dot(v, normal),
            normal,
        }
    }

    /// Calls `found` with each patch (ascending, once) with a point within
    /// `reach` (m) of x.
    pub fn patches_within(&self, x: [f64; 3], reach: f64, found: &mut dyn FnMut(u32)) {
        let Some(r) = self.grid.range(x.map(|c| c - reach), x.map(|c| c + reach)) else {
            return;
        };
        let mut hits: Vec<u32> = Vec::new();
        self.grid.each_cell(&r, |c| {
            for &t in self.grid.cell_items(c) {
                let g = &self.patches.tri[t as usize];
                if hits.last() == Some(&g.patch) {
                    continue;
                }
                let y = closest_on_triangle(x, g.corner[0], g.corner[1], g.corner[2]);
                if norm(sub(x, y)) < reach {
                    hits.push(g.patch);
                }
            }
        });
        hits.sort_unstable();
        hits.dedup();
        for p in hits {
            found(p);
        }
    }
}
