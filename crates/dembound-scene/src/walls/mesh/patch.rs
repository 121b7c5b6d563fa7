//! Flat patches: the maximal edge-connected sets of triangles whose unit
//! normals are within `flat_angle` of the patch's first (lowest-index)
//! triangle's normal, oriented the same way. Each patch is one plane: unit
//! normal n_P (the direction of the sum of its triangles' area vectors,
//! exact for coplanar triangles) and point p_P (the patch vertex nearest
//! its area centroid, an input vertex, so that a plane through given
//! vertices is represented by the same numbers as an analytic plane
//! through them).
//!
//! Comparing with the first triangle (not the neighbour) bounds the
//! patch's departure from flatness: every triangle normal is within
//! `flat_angle` of the seed's, so every patch point is within
//! `flat_angle` × (patch extent) of the patch plane (reported as
//! [`Patches::max_deviation`]).
//!
//! Per triangle: its corners ordered so that its normal agrees with its
//! patch's, and for each edge the in-plane unit normal pointing into the
//! triangle, m = n_P × e/|e|: x is over the triangle (its projection along
//! n_P inside) when m·(x − a) ≥ −ε on all three edges. Each edge is
//! flagged as a patch boundary (not shared with another triangle of the
//! same patch). Adjacency for the one-force rule: for every triangle edge,
//! the other patches that share it; for every vertex, the patches that
//! touch it.

use std::collections::HashMap;

use super::clean::edge_map;
use super::geometry::{add, cross, dot, norm, scale, sub};

/// One flat patch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// Unit normal n_P (the orientation of its triangles).
    pub normal: [f64; 3],
    /// A point of its plane (one of its vertices), m.
    pub point: [f64; 3],
    /// Its triangles: `Patches::triangles[first..first + count]`.
    pub first: u32,
    pub count: u32,
    /// Area, m².
    pub area: f64,
}

/// A triangle as the contact tests read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriGeom {
    /// Corners, ordered so that (b − a) × (c − a) agrees with n_P.
    pub corner: [[f64; 3]; 3],
    /// Vertex indices of the corners.
    pub vertex: [u32; 3],
    /// In-plane inward unit normal of edge k (corner k → k+1).
    pub inward: [[f64; 3]; 3],
    /// The patch it belongs to.
    pub patch: u32,
    /// Edge k is on its patch's boundary.
    pub boundary: [bool; 3],
}

/// The patches of a cleaned mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Patches {
    pub patches: Vec<Patch>,
    /// Triangle indices grouped by patch.
    pub triangles: Vec<u32>,
    /// Per triangle (mesh order).
    pub tri: Vec<TriGeom>,
    /// For triangle edge slot 3 t + k: the other patches sharing that
    /// edge, `edge_patches[edge_start[s]..edge_start[s + 1]]`.
    pub edge_start: Vec<u32>,
    pub edge_patches: Vec<u32>,
    /// For vertex v: the patches touching it (ascending).
    pub vertex_start: Vec<u32>,
    pub vertex_patches: Vec<u32>,
    /// Largest distance of a patch vertex from its patch's plane, m.
    pub max_deviation: f64,
}

impl Patches {
    /// The other patches sharing edge k of triangle t.
    pub fn across(&self, t: u32, k: usize) -> &[u32] {
        let s = 3 * t as usize + k;
        &self.edge_patches[self.edge_start[s] as usize..self.edge_start[s + 1] as usize]
    }

    /// The patches touching vertex v.
    pub fn around(&self, v: u32) -> &[u32] {
        let v = v as usize;
        &self.vertex_patches[self.vertex_start[v] as usize..self.vertex_start[v + 1] as usize]
    }

    /// The triangles of patch p.
    pub fn of(&self, p: u32) -> &[u32] {
        let q = &self.patches[p as usize];
        &self.triangles[q.first as usize..(q.first + q.count) as usize]
    }
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = norm(v);
    if l > 0.0 {
        scale(v, 1.0 / l)
    } else {
        v
    }
}

/// Groups the triangles of a cleaned mesh into flat patches (normals
/// within `flat_angle` rad of the patch's first triangle's).
pub fn build(vertices: &[[f64; 3]], triangles: &[[u32; 3]], flat_angle: f64) -> Patches {
    let n = triangles.len();
    let pos = |i: u32| vertices[i as usize];
    let area_vector = |t: &[u32; 3]| cross(sub(pos(t[1]), pos(t[0])), sub(pos(t[2]), pos(t[0])));
    let unit_normal: Vec<[f64; 3]> = triangles.iter().map(|t| unit(area_vector(t))).collect();
    let edges = edge_map(triangles);
    let cos_flat = flat_angle.cos();
    let mut patch_of = vec![u32::MAX; n];
    let mut patches = Vec::new();
    let mut grouped: Vec<u32> = Vec::with_capacity(n);
    for seed in 0..n {
        if patch_of[seed] != u32::MAX {
            continue;
        }
        let id = patches.len() as u32;
        let first = grouped.len();
        patch_of[seed] = id;
        grouped.push(seed as u32);
        let ns = unit_normal[seed];
        let mut head = first;
        while head < grouped.len() {
            let t = grouped[head] as usize;
            head += 1;
            let tri = triangles[t];
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                for &u in &edges[&(a.min(b), a.max(b))] {
                    let u = u as usize;
                    if patch_of[u] == u32::MAX && dot(ns, unit_normal[u]) >= cos_flat {
                        patch_of[u] = id;
                        grouped.push(u as u32);
                    }
                }
            }
        }
        let members = &grouped[first..];
        let mut sum = [0.0; 3];
        let mut centroid = [0.0; 3];
        let mut area = 0.0;
        for &t in members {
            let av = area_vector(&triangles[t as usize]);
            sum = add(sum, av);
            let a = 0.5 * norm(av);
            let [p, q, r] = triangles[t as usize].map(pos);
            centroid = add(centroid, scale(add(add(p, q), r), a / 3.0));
            area += a;
        }
        let normal = unit(sum);
        let centroid = scale(centroid, 1.0 / area);
        let mut point = pos(triangles[seed][0]);
        let mut best = f64::INFINITY;
        for &t in members {
            for &v in &triangles[t as usize] {
                let d = norm(sub(pos(v), centroid));
                if d < best {
                    best = d;
                    point = pos(v);
                }
            }
        }
        patches.push(Patch {
            normal,
            point,
            first: first as u32,
            count: members.len() as u32,
            area,
        });
    }
    // Per-triangle geometry, boundary flags and edge adjacency.
    let mut tri = Vec::with_capacity(n);
    let mut edge_start = Vec::with_capacity(3 * n + 1);
    let mut edge_patches = Vec::new();
    edge_start.push(0u32);
    let mut max_deviation: f64 = 0.0;
    for (t, ids) in triangles.iter().enumerate() {
        let p = patch_of[t];
        let np = patches[p as usize].normal;
        let mut ids = *ids;
        if dot(area_vector(&ids), np) < 0.0 {
            ids.swap(1, 2);
        }
        let corner = ids.map(pos);
        let mut inward = [[0.0; 3]; 3];
        let mut boundary = [false; 3];
        for k in 0..3 {
            let (a, b) = (ids[k], ids[(k + 1) % 3]);
            inward[k] = unit(cross(np, sub(corner[(k + 1) % 3], corner[k])));
            let list = &edges[&(a.min(b), a.max(b))];
            boundary[k] = !list
                .iter()
                .any(|&u| u as usize != t && patch_of[u as usize] == p);
            let mut others: Vec<u32> = list
                .iter()
                .map(|&u| patch_of[u as usize])
                .filter(|&q| q != p)
                .collect();
            others.sort_unstable();
            others.dedup();
            edge_patches.extend_from_slice(&others);
            edge_start.push(edge_patches.len() as u32);
        }
        let plane = &patches[p as usize];
        for c in corner {
            max_deviation = max_deviation.max(dot(sub(c, plane.point), np).abs());
        }
        tri.push(TriGeom {
            corner,
            vertex: ids,
            inward,
            patch: p,
            boundary,
        });
    }
    // Patches around each vertex.
    let mut around: HashMap<u32, Vec<u32>> = HashMap::new();
    for (t, ids) in triangles.iter().enumerate() {
        for &v in ids {
            around.entry(v).or_default().push(patch_of[t]);
        }
    }
    let mut vertex_start = Vec::with_capacity(vertices.len() + 1);
    let mut vertex_patches = Vec::new();
    vertex_start.push(0u32);
    for v in 0..vertices.len() as u32 {
        if let Some(list) = around.get_mut(&v) {
            list.sort_unstable();
            list.dedup();
            vertex_patches.extend_from_slice(list);
        }
        vertex_start.push(vertex_patches.len() as u32);
    }
    edge_patches.shrink_to_fit();
    vertex_patches.shrink_to_fit();
    patches.shrink_to_fit();
    Patches {
        patches,
        triangles: grouped,
        tri,
        edge_start,
        edge_patches,
        vertex_start,
        vertex_patches,
        max_deviation,
    }
}
