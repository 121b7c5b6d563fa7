//! Cleaning a triangle soup into an indexed, consistently oriented mesh.
//!
//! 1. Weld: vertices closer than τ = `weld_relative` × (diagonal of the
//!    bounding box of all vertices) become one (default 1e-9: STL stores
//!    every triangle's own copy of its vertices, so a mesh is only
//!    connected after welding; 1e-9 is far above the f64 round-off of a
//!    transform, ~1e-16 relative, and far below any feature of a part,
//!    while f32 STL copies of one vertex are bit-identical). Greedy in file
//!    order: a vertex joins the first kept vertex within τ (through a hash
//!    of cells of size τ, the 27 cells around it), else it is kept.
//! 2. Degenerate triangles dropped: two corners welded into one, or
//!    collinear corners (twice the area ≤ 1e-10 × longest edge², a height
//!    below 1e-10 of the length: such a triangle's normal would carry
//!    errors above the 1e-6 rad flatness tolerance of the patches), or a
//!    triangle so small that the square of twice its area is subnormal
//!    (below `f64::MIN_POSITIVE`, ≈ 2.2e-308 m⁴: edges below ~1e-77 m,
//!    a mesh scaled by 1e-80). Its normal, the area vector over the root
//!    of that square, would not be of unit length (1.0000056 at edges of
//!    1e-80 m, 1.012 at 3e-81 m: the subnormal square keeps a few bits).
//! 3. Duplicate triangles (the same three welded vertices, in any order or
//!    orientation) dropped but the first.
//! 4. Edges counted: open (one triangle), non-manifold (three or more).
//! 5. Orientation made consistent over each connected component by a
//!    breadth-first walk across manifold edges (two triangles): a
//!    neighbour that runs the shared edge the same way is flipped.
//!    Non-manifold edges do not carry orientation (three sheets meeting
//!    at an edge have no consistent choice); a component closed on itself
//!    (no open or non-manifold edge) is then turned outward (positive
//!    signed volume). A manifold edge found inconsistent after the walk
//!    (a non-orientable surface) is counted.

use std::collections::HashMap;

use super::geometry::{cross, dot, norm, sub};
use super::read::Triangle;

/// What cleaning found and did (counts are of triangles unless said).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CleanReport {
    /// Triangles read.
    pub read: usize,
    /// Vertices read (3 per triangle) and kept after welding.
    pub vertices_read: usize,
    pub vertices_kept: usize,
    /// The weld tolerance used, m.
    pub weld_tolerance: f64,
    /// Dropped: degenerate (zero area after welding).
    pub degenerate: usize,
    /// Dropped: duplicates of an earlier triangle.
    pub duplicate: usize,
    /// Edges with one triangle (the mesh's free boundary).
    pub open_edges: usize,
    /// Edges with three or more triangles.
    pub non_manifold_edges: usize,
    /// Triangles whose vertex order was reversed.
    pub reoriented: usize,
    /// Manifold edges left inconsistent (a non-orientable component).
    pub orientation_conflicts: usize,
    /// Connected components (through shared edges).
    pub components: usize,
}

/// An indexed mesh after cleaning.
#[derive(Debug, Clone, PartialEq)]
pub struct CleanMesh {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub report: CleanReport,
}

/// The triangles of each undirected edge (vertex pair, smaller first).
pub fn edge_map(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), Vec<u32>> {
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(t as u32);
        }
    }
    edges
}

/// Does triangle `tri` run the directed edge a → b?
fn runs(tri: &[u32; 3], a: u32, b: u32) -> bool {
    (0..3).any(|k| tri[k] == a && tri[(k + 1) % 3] == b)
}

/// Cleans `soup` with weld tolerance `weld_relative` × bounding-box
/// diagonal. Every coordinate must be finite (checked by the caller).
pub fn clean(soup: &[Triangle], weld_relative: f64) -> CleanMesh {
    let mut report = CleanReport {
        read: soup.len(),
        vertices_read: 3 * soup.len(),
        ..Default::default()
    };
    // 1. Weld.
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for v in soup.iter().flatten() {
        for a in 0..3 {
            lo[a] = lo[a].min(v[a]);
            hi[a] = hi[a].max(v[a]);
        }
    }
    let diagonal = if soup.is_empty() {
        0.0
    } else {
        norm(sub(hi, lo))
    };
    let tol = weld_relative * diagonal;
    report.weld_tolerance = tol;
    // Cells of size τ (a positive floor so that the keys stay finite).
    let cell = tol.max(f64::MIN_POSITIVE);
    let key =
        |v: [f64; 3]| -> [i64; 3] { [0, 1, 2].map(|a| ((v[a] - lo[a]) / cell).floor() as i64) };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut welded: Vec<[u32; 3]> = Vec::with_capacity(soup.len());
    for t in soup {
        let mut ids = [0u32; 3];
        for (k, &v) in t.iter().enumerate() {
            let c = key(v);
            let mut found = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let n = [c[0] + dx, c[1] + dy, c[2] + dz];
                        if let Some(list) = grid.get(&n) {
                            for &i in list {
                                if norm(sub(vertices[i as usize], v)) <= tol {
                                    found = Some(i);
                                    break 'search;
                                }
                            }
                        }
                    }
                }
            }
            ids[k] = found.unwrap_or_else(|| {
                let i = vertices.len() as u32;
                vertices.push(v);
                grid.entry(c).or_default().push(i);
                i
            });
        }
        welded.push(ids);
    }
    // 2, 3. Degenerate and duplicate triangles.
    let mut seen: HashMap<[u32; 3], ()> = HashMap::new();
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(welded.len());
    for ids in welded {
        let [a, b, c] = ids;
        if a == b || b == c || c == a {
            report.degenerate += 1;
            continue;
        }
        let (p, q, r) = (
            vertices[a as usize],
            vertices[b as usize],
            vertices[c as usize],
        );
        let area_vector = cross(sub(q, p), sub(r, p));
        let squared = dot(area_vector, area_vector);
        let twice_area = squared.sqrt();
        let longest = norm(sub(q, p)).max(norm(sub(r, q))).max(norm(sub(p, r)));
        if squared < f64::MIN_POSITIVE || twice_area <= 1e-10 * longest * longest {
            report.degenerate += 1;
            continue;
        }
        let mut sorted = ids;
        sorted.sort_unstable();
        if seen.insert(sorted, ()).is_some() {
            report.duplicate += 1;
            continue;
        }
        triangles.push(ids);
    }
    // Drop the vertices no triangle uses, renumbered in order of use.
    let mut renumber = vec![u32::MAX; vertices.len()];
    let mut kept = Vec::new();
    for t in &mut triangles {
        for i in t.iter_mut() {
            if renumber[*i as usize] == u32::MAX {
                renumber[*i as usize] = kept.len() as u32;
                kept.push(vertices[*i as usize]);
            }
            *i = renumber[*i as usize];
        }
    }
    let vertices = kept;
    report.vertices_kept = vertices.len();
    // 4. Edges.
    let edges = edge_map(&triangles);
    for list in edges.values() {
        match list.len() {
            1 => report.open_edges += 1,
            2 => {}
            _ => report.non_manifold_edges += 1,
        }
    }
    // 5. Orientation, component by component.
    let n = triangles.len();
    let mut component = vec![u32::MAX; n];
    let mut flipped = vec![false; n];
    let mut queue = std::collections::VecDeque::new();
    for seed in 0..n {
        if component[seed] != u32::MAX {
            continue;
        }
        let id = report.components as u32;
        report.components += 1;
        component[seed] = id;
        queue.push_back(seed);
        let mut members = vec![seed];
        let mut closed = true;
        while let Some(t) = queue.pop_front() {
            let tri = triangles[t];
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let list = &edges[&(a.min(b), a.max(b))];
                if list.len() != 2 {
                    closed = false;
                    // Connected, but no orientation carried.
                    for &u in list {
                        let u = u as usize;
                        if component[u] == u32::MAX {
                            component[u] = id;
                            members.push(u);
                            queue.push_back(u);
                        }
                    }
                    continue;
                }
                let u = if list[0] as usize == t {
                    list[1]
                } else {
                    list[0]
                } as usize;
                if component[u] == u32::MAX {
                    component[u] = id;
                    members.push(u);
                    if runs(&triangles[u], a, b) {
                        triangles[u].swap(1, 2);
                        flipped[u] = !flipped[u];
                    }
                    queue.push_back(u);
                }
            }
        }
        if closed {
            // Outward: the signed volume Σ p·(q × r)/6 positive (about the
            // first vertex, for round-off).
            let o = vertices[triangles[seed][0] as usize];
            let volume: f64 = members
                .iter()
                .map(|&t| {
                    let [p, q, r] = triangles[t].map(|i| sub(vertices[i as usize], o));
                    dot(p, cross(q, r))
                })
                .sum();
            if volume < 0.0 {
                for &t in &members {
                    triangles[t].swap(1, 2);
                    flipped[t] = !flipped[t];
                }
            }
        }
    }
    report.reoriented = flipped.iter().filter(|&&f| f).count();
    for (&(a, b), list) in &edges {
        if list.len() == 2 {
            let (t, u) = (&triangles[list[0] as usize], &triangles[list[1] as usize]);
            if runs(t, a, b) == runs(u, a, b) {
                report.orientation_conflicts += 1;
            }
        }
    }
    CleanMesh {
        vertices,
        triangles,
        report,
    }
}
