//! Cleaning counts, orientation, typed errors on bad files, no panic on
//! broken input, and a 100,000-triangle mesh.

use super::clean::{clean, edge_map};
use super::fixtures::{cube, fan, mesh, open_box, square};
use super::read::{write_ascii_stl, write_binary_stl};
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Every manifold edge is run once each way (a consistent orientation).
fn consistent(triangles: &[[u32; 3]]) -> bool {
    edge_map(triangles).iter().all(|(&(a, b), list)| {
        list.len() != 2 || {
            let runs = |t: &[u32; 3]| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
            runs(&triangles[list[0] as usize]) != runs(&triangles[list[1] as usize])
        }
    })
}

/// Signed volume (outward positive).
fn volume(m: &MeshGeometry) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [p, q, r] = t.map(|i| m.vertices[i as usize]);
            geometry::dot(p, geometry::cross(q, r)) / 6.0
        })
        .sum()
}

/// An unwelded cube (36 vertex copies, as STL stores them): 8 vertices,
/// 6 patches, no open edge, closed and outward (volume +1).
#[test]
fn unwelded_cube_welds_to_eight_vertices() {
    let m = mesh(&cube([0.0; 3], [1.0; 3]));
    let r = m.report;
    assert_eq!((r.read, r.vertices_read, r.vertices_kept), (12, 36, 8));
    assert_eq!((r.degenerate, r.duplicate, r.reoriented), (0, 0, 0));
    assert_eq!(
        (r.open_edges, r.non_manifold_edges, r.components),
        (0, 0, 1)
    );
    assert_eq!(m.patch_count(), 6);
    assert!((volume(&m) - 1.0).abs() < 1e-15);
    // τ = 1e-9 × √3.
    assert!((r.weld_tolerance - 1e-9 * 3f64.sqrt()).abs() < 1e-24);
}

/// The cube with a degenerate triangle (two corners the same), a
/// collinear one, a duplicate (a face's triangle again, reversed and
/// rotated) and one triangle flipped: 2 degenerate, 1 duplicate and 1
/// reoriented reported; the result consistent and outward.
#[test]
fn degenerate_duplicate_and_flipped_triangles_are_reported() {
    let mut soup = cube([0.0; 3], [1.0; 3]);
    let t3 = soup[3];
    soup[5] = [soup[5][0], soup[5][2], soup[5][1]];
    soup.push([[0.0; 3], [0.0; 3], [1.0, 1.0, 1.0]]);
    soup.push([[0.0; 3], [0.5, 0.5, 0.5], [1.0, 1.0, 1.0]]);
    soup.push([t3[2], t3[1], t3[0]]);
    let m = mesh(&soup);
    let r = m.report;
    assert_eq!(
        (r.read, r.degenerate, r.duplicate, r.reoriented),
        (15, 2, 1, 1)
    );
    assert_eq!(m.triangles.len(), 12);
    assert!(consistent(&m.triangles));
    assert_eq!((r.orientation_conflicts, r.open_edges), (0, 0));
    assert!((volume(&m) - 1.0).abs() < 1e-15);
    let w = m.warnings();
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].starts_with("2 degenerate") && w[1].starts_with("1 duplicate"));
    assert!(w[2].starts_with("1 triangles reoriented"));
    assert!(m
        .summary()
        .starts_with("12 triangles (15 read), 8 vertices, 6 flat patches"));
    // A whole cube given inward: every triangle reversed to outward.
    let inward: Vec<Triangle> = cube([0.0; 3], [1.0; 3])
        .into_iter()
        .map(|t| [t[0], t[2], t[1]])
        .collect();
    let m = mesh(&inward);
    assert_eq!(m.report.reoriented, 12);
    assert!((volume(&m) - 1.0).abs() < 1e-15);
}

/// Open edges by hand: an open box (5 faces of 2 triangles) has the 4
/// rim edges of the missing face open, of its 17 edges (12 of the cube,
/// 5 face diagonals); a lone square 4; the 64-fan disk its 64 rim edges.
/// A fin (three triangles on one edge) is one non-manifold edge.
#[test]
fn open_and_non_manifold_edges_are_counted() {
    let m = mesh(&open_box([0.0; 3], [1.0; 3]));
    assert_eq!(m.report.open_edges, 4);
    assert_eq!(edge_map(&m.triangles).len(), 17);
    assert!(consistent(&m.triangles));
    assert_eq!(mesh(&square(0.0)).report.open_edges, 4);
    assert_eq!(mesh(&fan(64, 0.0, 0.0, 0.0, 1.0)).report.open_edges, 64);
    let (a, b) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let fin = [
        [a, b, [0.5, 1.0, 0.0]],
        [b, a, [0.5, -1.0, 0.0]],
        [a, b, [0.5, 0.0, 1.0]],
    ];
    let c = clean(&fin, 1e-9);
    assert_eq!((c.report.non_manifold_edges, c.report.open_edges), (1, 6));
}

/// Weld: copies 1e-12 apart (below τ = 1e-9 × diagonal ≈ 1.4e-9) are
/// one vertex; 1e-6 apart are two.
#[test]
fn weld_tolerance_decides() {
    let mut soup = square(0.0);
    soup[1][0][0] += 1e-12;
    assert_eq!(clean(&soup, 1e-9).report.vertices_kept, 4);
    let mut soup = square(0.0);
    soup[1][0][0] += 1e-6;
    let c = clean(&soup, 1e-9);
    assert_eq!((c.report.vertices_kept, c.report.open_edges), (5, 6));
}

fn load(path: &Path) -> Result<MeshGeometry, MeshError> {
    MeshGeometry::load(path, &Transform::default(), &MeshOptions::default())
}

/// Missing file, garbage, truncated, empty and non-finite files: typed
/// errors naming the file.
#[test]
fn bad_files_are_typed_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| dir.path().join(name);
    let names = |e: &MeshError, p: &Path| e.to_string().contains(&p.display().to_string());

    let missing = at("missing.stl");
    let e = load(&missing).unwrap_err();
    assert!(
        matches!(e, MeshError::Unreadable { .. }) && names(&e, &missing),
        "{e}"
    );

    let garbage = at("garbage.stl");
    std::fs::write(&garbage, b"\x00\x01 this is not a mesh \xff\xfe").unwrap();
    let e = load(&garbage).unwrap_err();
    assert!(
        matches!(e, MeshError::Malformed { .. }) && names(&e, &garbage),
        "{e}"
    );

    // Binary with a count of 10 but 3 records: not 84 + 50 N bytes.
    let truncated = at("truncated.stl");
    write_binary_stl(&truncated, &cube([0.0; 3], [1.0; 3])).unwrap();
    let mut bytes = std::fs::read(&truncated).unwrap();
    bytes.truncate(84 + 150);
    std::fs::write(&truncated, &bytes).unwrap();
    assert!(matches!(load(&truncated), Err(MeshError::Malformed { .. })));

    // ASCII cut mid-facet.
    let cut = at("cut.stl");
    write_ascii_stl(&cut, &square(0.0)).unwrap();
    let text = std::fs::read(&cut).unwrap();
    std::fs::write(&cut, &text[..text.len() / 2]).unwrap();
    assert!(matches!(load(&cut), Err(MeshError::Malformed { .. })));

    // A binary STL of no triangle, and one of only degenerate ones.
    let empty = at("empty.stl");
    write_binary_stl(&empty, &[]).unwrap();
    let e = load(&empty).unwrap_err();
    assert!(
        matches!(e, MeshError::Empty { read: 0, .. }) && names(&e, &empty),
        "{e}"
    );
    let flat = at("flat.stl");
    write_binary_stl(&flat, &[[[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]]).unwrap();
    assert!(matches!(load(&flat), Err(MeshError::Empty { read: 1, .. })));

    // A NaN coordinate in a binary record.
    let nan = at("nan.stl");
    write_binary_stl(&nan, &[[[0.0; 3], [1.0, 0.0, 0.0], [0.0, f64::NAN, 0.0]]]).unwrap();
    let e = load(&nan).unwrap_err();
    assert!(
        matches!(e, MeshError::NonFinite { triangle: 0, .. }) && names(&e, &nan),
        "{e}"
    );

    let ply = at("part.ply");
    std::fs::write(&ply, b"ply\n").unwrap();
    assert!(matches!(load(&ply), Err(MeshError::UnknownFormat { .. })));

    // OBJ: a face referring to a vertex that does not exist.
    let obj = at("bad.obj");
    std::fs::write(&obj, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let e = load(&obj).unwrap_err();
    assert!(names(&e, &obj), "{e}");
}

/// A binary STL whose header starts with "solid" (as some exporters
/// write) is still binary; a bare "solid" line starts a valid ASCII file;
/// Windows line ends read; an OBJ quad is two triangles.
#[test]
fn stl_and_obj_variants_read() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("solid_header.stl");
    write_binary_stl(&bin, &square(0.0)).unwrap();
    let mut bytes = std::fs::read(&bin).unwrap();
    bytes[..6].copy_from_slice(b"solid ");
    std::fs::write(&bin, &bytes).unwrap();
    assert_eq!(load(&bin).unwrap().triangles.len(), 2);

    let ascii = dir.path().join("bare.stl");
    write_ascii_stl(&ascii, &square(0.0)).unwrap();
    let text = std::fs::read_to_string(&ascii).unwrap();
    std::fs::write(&ascii, text.replacen("solid dembound\n", "solid\n", 1)).unwrap();
    assert_eq!(load(&ascii).unwrap().triangles.len(), 2);
    // Windows line ends.
    std::fs::write(&ascii, text.replace('\n', "\r\n")).unwrap();
    assert_eq!(load(&ascii).unwrap().triangles.len(), 2);

    let obj = dir.path().join("quad.obj");
    std::fs::write(
        &obj,
        b"# a unit square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    let m = load(&obj).unwrap();
    assert_eq!((m.triangles.len(), m.patch_count()), (2, 1));
    assert!((m.area - 1.0).abs() < 1e-15);
}

/// Coordinates near the f64 limit, a transform that overflows, and
/// triangles far apart: errors or a mesh, never a panic.
#[test]
fn extreme_coordinates_do_not_panic() {
    let big = 1e308;
    let soup = vec![[[big, 0.0, 0.0], [-big, 0.0, 0.0], [0.0, big, 0.0]]];
    let _ = MeshGeometry::from_triangles(
        Path::new("big.stl"),
        &soup,
        &Transform::default(),
        &MeshOptions::default(),
    );
    let t = Transform {
        scale: 1e300,
        ..Default::default()
    };
    let e = MeshGeometry::from_triangles(Path::new("s.stl"), &soup, &t, &MeshOptions::default());
    assert!(matches!(e, Err(MeshError::NonFinite { .. })));
    // Two tiny triangles 1e6 m apart: a coarse grid, still exact answers.
    let mut far = square(0.0);
    far.extend(
        square(0.0)
            .into_iter()
            .map(|t| t.map(|v| [v[0] + 1e6, v[1], v[2]])),
    );
    let m = mesh(&far);
    assert_eq!(m.patch_count(), 2);
    let c = m.patch_contact(1, [1e6 + 0.5, 0.5, 0.01], [0.0; 3], 0.02);
    assert!((c.overlap - 0.01).abs() < 1e-12, "{c:?}");
    // A NaN centre: NaN or no contact (the plane gives NaN too), no panic.
    let c = m.patch_contact(0, [f64::NAN; 3], [0.0; 3], 0.02);
    assert!(c.overlap.is_nan() || c.overlap < 0.0);
}

/// The unit square [0, 1]² placed by `scale` s (edges s m).
fn scaled_square(s: f64) -> Result<MeshGeometry, MeshError> {
    let t = Transform {
        scale: s,
        ..Default::default()
    };
    MeshGeometry::from_triangles(Path::new("part.stl"), &square(0.0), &t, &MeshOptions::default())
}

/// A unit square scaled so small that the square of twice a triangle's
/// area, s⁴, is subnormal: 1e-316, 1e-320 and 8e-323 m⁴ at s = 1e-79,
/// 1e-80 and 3e-81. The normal over its root would be 1 + 8e-9, 1 +
/// 5.6e-6 and 1.012 long (the subnormal keeps 24, 11 and 4 bits), so
/// cleaning drops both triangles as degenerate and the mesh is refused as
/// empty. At s = 2e-77 (s⁴ = 1.6e-307 m⁴, normal) it is kept, its normal
/// (0, 0, 1) exactly (√(x²) = |x| when x² neither underflows nor
/// overflows), its area s² and centroid (s/2, s/2, 0) to round-off.
#[test]
fn areas_whose_squares_underflow_are_dropped_as_degenerate() {
    for s in [1e-79, 1e-80, 3e-81] {
        let e = scaled_square(s);
        assert!(matches!(e, Err(MeshError::Empty { read: 2, .. })), "{s}: {e:?}");
    }
    let s = 2e-77;
    let m = scaled_square(s).unwrap();
    assert_eq!(m.report.degenerate, 0);
    assert_eq!(m.patches.patches[0].normal, [0.0, 0.0, 1.0]);
    // Sums of two halves and a division by the area: a few ulps.
    assert!((m.area / (s * s) - 1.0).abs() < 1e-15, "{}", m.area);
    for (c, e) in m.centroid.iter().zip([0.5 * s, 0.5 * s, 0.0]) {
        assert!((c - e).abs() <= 1e-15 * s, "{:?}", m.centroid);
    }
}

/// A unit square scaled so large that squares of areas overflow. At s =
/// 1e77 each triangle's square (1e308 m⁴) is finite but the patch's
/// summed area vector's (4e308) is not, which made the patch normal 0
/// (1/∞); at 1e80 every square overflows (normal 0, centroid 0 × ∞ =
/// NaN: a scene with it printed NaN wall torques). Both refused, naming
/// the file and the allowed size.
#[test]
fn meshes_whose_area_squares_overflow_are_refused() {
    for s in [1e77, 1e80] {
        let e = scaled_square(s).unwrap_err();
        assert!(matches!(e, MeshError::TooLarge { .. }), "{s}: {e:?}");
        let text = e.to_string();
        assert!(text.contains("part.stl") && text.contains("1e76 m"), "{text}");
    }
}

/// 600 broken files (random bytes; valid ASCII, binary and OBJ files
/// truncated at random or with random bytes overwritten): each read
/// returns, Ok or Err, and never panics.
#[test]
fn broken_files_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(404);
    let soup = cube([0.0; 3], [1.0; 3]);
    let ascii = dir.path().join("a.stl");
    let binary = dir.path().join("b.stl");
    write_ascii_stl(&ascii, &soup).unwrap();
    write_binary_stl(&binary, &soup).unwrap();
    let obj_text = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n".to_vec();
    let sources = [
        std::fs::read(&ascii).unwrap(),
        std::fs::read(&binary).unwrap(),
        obj_text,
    ];
    for i in 0..600 {
        let which = i % 4;
        let (mut bytes, ext) = match which {
            3 => (
                (0..rng.gen_range(0..400))
                    .map(|_| rng.gen())
                    .collect::<Vec<u8>>(),
                "stl",
            ),
            k => (sources[k].clone(), if k == 2 { "obj" } else { "stl" }),
        };
        if which < 3 {
            if rng.gen_bool(0.5) {
                bytes.truncate(rng.gen_range(0..=bytes.len()));
            } else {
                for _ in 0..rng.gen_range(1..8) {
                    if !bytes.is_empty() {
                        let at = rng.gen_range(0..bytes.len());
                        bytes[at] = rng.gen();
                    }
                }
            }
        }
        let path = dir.path().join(format!("fuzz{i}.{ext}"));
        std::fs::write(&path, &bytes).unwrap();
        let _ = load(&path);
    }
}

/// 100,352 triangles (a 224 × 224 grid, 2 triangles per square, on a
/// wavy surface z = 0.02 sin(7x) cos(5y), so nearly every triangle is its
/// own patch): it builds within the stated memory (the module doc's
/// ~320 B per triangle for a mesh of one-triangle patches; ≤ 340 B), and at 200 random centres the deepest contact
/// equals r minus the brute-force distance to the nearest triangle (the
/// closest feature always keeps its contact) to 1e-12.
#[test]
fn hundred_thousand_triangles_load_and_answer() {
    let n = 224;
    let h = 1.0 / n as f64;
    let z = |x: f64, y: f64| 0.02 * (7.0 * x).sin() * (5.0 * y).cos();
    let p = |i: usize, j: usize| {
        let (x, y) = (i as f64 * h, j as f64 * h);
        [x, y, z(x, y)]
    };
    let mut soup = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            soup.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
            soup.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
    let m = mesh(&soup);
    assert_eq!(m.triangles.len(), 100_352);
    let per = m.bytes() as f64 / m.triangles.len() as f64;
    assert!(per <= 340.0, "{per} B per triangle");
    let mut rng = ChaCha8Rng::seed_from_u64(100);
    let r = 0.01;
    let wall = MeshWall {
        wall: 0,
        slot: 0,
        mesh: std::sync::Arc::new(m),
        moving: None,
    };
    use crate::walls::Wall;
    for _ in 0..200 {
        let (u, w) = (rng.gen_range(0.05..0.95), rng.gen_range(0.05..0.95));
        let x = [u, w, z(u, w) + rng.gen_range(-0.008..0.008)];
        let mut near = Vec::new();
        wall.near_elements(x, r, 0.0, &mut |e| near.push(e));
        let deepest = near
            .iter()
            .map(|&e| wall.contact(e, x, [0.0; 3], r).overlap)
            .fold(f64::NEG_INFINITY, f64::max);
        let brute = wall
            .mesh
            .patches
            .tri
            .iter()
            .map(|g| {
                let y = geometry::closest_on_triangle(x, g.corner[0], g.corner[1], g.corner[2]);
                geometry::norm(geometry::sub(x, y))
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            (deepest - (r - brute)).abs() < 1e-12,
            "{deepest} vs {}",
            r - brute
        );
    }
}
