//! The mesh walls' per-triangle loads through the CLI (issue 26):
//! `dembound scene examples/scenes/mesh_box.toml --out DIR` writes one
//! `wall_0_NNNNNN.vtp` per snapshot, listed in `snapshots.pvd` as part 1;
//! each file's arrays have the documented names, sizes and units, and
//! agree with what can be computed from the file itself (areas and
//! normals from the points, pressure and shear from the forces) and with
//! the wall's total force in `--json`; 1 and 2 threads write the same
//! bytes. `--json` names each wall's triangle count.

mod common;

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use common::dembound;
use std::path::Path;

/// The mesh box (12 triangles, faces of the box [0, 0.0246]² × [0, 0.03] m
/// at f32 precision) with its 8 × 8 × 10 spheres, 1000 steps of 2 µs (the
/// bottom layer, 5 µm above the floor, lands after ~1 ms), a snapshot
/// every 500 steps, on `threads` threads: (the JSON document, the output
/// directory's path).
fn run(dir: &Path, threads: &str) -> serde_json::Value {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/mesh_box.toml");
    let o = dembound()
        .arg("scene")
        .arg(scene)
        .args([
            "--set",
            "particles.0.lattice.counts=[8,8,10]",
            "--set",
            "integration.steps=1000",
            "--set",
            "output.every=500",
            "--json",
            "--quiet",
            "--threads",
            threads,
            "--out",
        ])
        .arg(dir)
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

/// The bytes of array `name` of a `.vtp` file (base64, 8-byte length
/// header, little-endian), as a VTK reader decodes them; and the tag's
/// attributes.
fn array(text: &str, name: &str) -> (Vec<u8>, String) {
    let tag = format!("Name=\"{name}\"");
    let line = text
        .lines()
        .find(|l| l.contains(&tag))
        .unwrap_or_else(|| panic!("no array {name}"));
    let open = &line[..line.find('>').unwrap()];
    let data = &line[line.find('>').unwrap() + 1..line.rfind("</").unwrap()];
    let block = STANDARD.decode(data).unwrap();
    let len = u64::from_le_bytes(block[..8].try_into().unwrap()) as usize;
    assert_eq!(len, block.len() - 8, "{name}: length header");
    (block[8..].to_vec(), open.to_string())
}

fn f64s(b: &[u8]) -> Vec<f64> {
    b.chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn i64s(b: &[u8]) -> Vec<i64> {
    b.chunks(8)
        .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn mesh_box_writes_per_triangle_loads_listed_in_the_pvd() {
    let tmp = tempfile::tempdir().unwrap();
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    let json = run(&one, "1");
    run(&two, "2");
    assert_eq!(json["wall_triangle_counts"], serde_json::json!([12]));

    // Three snapshots (steps 0, 500, 1000), each with its wall file, the
    // wall as part 1 beside the spheres at the same time.
    let pvd = std::fs::read_to_string(one.join("snapshots.pvd")).unwrap();
    for k in 0..3 {
        let name = format!("wall_0_{k:06}.vtp");
        let a = std::fs::read(one.join(&name)).unwrap();
        let b = std::fs::read(two.join(&name)).unwrap();
        // Same bits on 2 threads (records merged by input id).
        assert!(a == b, "{name} differs between 1 and 2 threads");
        let line = pvd
            .lines()
            .find(|l| l.contains(&name))
            .unwrap_or_else(|| panic!("{name} not in the pvd: {pvd}"));
        assert!(line.contains("part=\"1\""), "{line}");
        let spheres = format!("snapshot_{k:06}.vtp");
        let time = |l: &str| l.split('"').nth(1).unwrap().to_string();
        let sphere_line = pvd.lines().find(|l| l.contains(&spheres)).unwrap();
        assert_eq!(time(line), time(sphere_line));
    }
    assert!(!one.join("wall_0_000003.vtp").exists());

    // The last file, read as a VTK reader does.
    let text = std::fs::read_to_string(one.join("wall_0_000002.vtp")).unwrap();
    assert!(text.contains("NumberOfPoints=\"8\"") && text.contains("NumberOfPolys=\"12\""));
    for unit in ["points m", "force N", "pressure Pa", "shear Pa", "area m2"] {
        assert!(text.contains(unit), "the units comment lacks {unit:?}");
    }
    let (points, _) = array(&text, "position");
    let points = f64s(&points);
    let (connectivity, _) = array(&text, "connectivity");
    let connectivity = i64s(&connectivity);
    let (offsets, _) = array(&text, "offsets");
    assert_eq!(i64s(&offsets), (1..=12).map(|i| 3 * i).collect::<Vec<_>>());
    let (force, attrs) = array(&text, "force");
    assert!(attrs.contains("NumberOfComponents=\"3\""), "{attrs}");
    let force = f64s(&force);
    let pressure = f64s(&array(&text, "pressure").0);
    let shear = f64s(&array(&text, "shear").0);
    let area = f64s(&array(&text, "area").0);
    let (ids, attrs) = array(&text, "triangle_id");
    assert!(attrs.contains("type=\"Int32\""), "{attrs}");
    let ids: Vec<i32> = ids
        .chunks(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert_eq!(ids, (0..12).collect::<Vec<_>>());
    assert_eq!(
        (points.len(), connectivity.len(), force.len()),
        (24, 36, 36)
    );
    assert_eq!((pressure.len(), shear.len(), area.len()), (12, 12, 12));

    // Per triangle, from the file's own points: area ½|(b − a) × (c − a)|
    // (the faces are 0.0246 × 0.0246 or 0.0246 × 0.03 m at f32 precision:
    // half of that each), pressure |F·n̂|/A and shear |F − (F·n̂)n̂|/A.
    // Relative 1e-12: a few roundings of the same formulas in another
    // order.
    let p = |v: i64| -> [f64; 3] {
        let v = v as usize;
        [points[3 * v], points[3 * v + 1], points[3 * v + 2]]
    };
    let (side, height) = (0.0246_f32 as f64, 0.03_f32 as f64);
    let mut floor_load = 0.0;
    let mut total = [0.0; 3];
    for t in 0..12 {
        let [a, b, c] = [0, 1, 2].map(|k| p(connectivity[3 * t + k]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        let twice = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = n.map(|x| x / twice);
        let a_t = 0.5 * twice;
        let nominal = if n[2].abs() > 0.5 {
            0.5 * side * side
        } else {
            0.5 * side * height
        };
        assert!((area[t] - nominal).abs() <= 1e-12 * nominal, "area {t}");
        assert!((area[t] - a_t).abs() <= 1e-12 * a_t, "area {t}");
        let f = [force[3 * t], force[3 * t + 1], force[3 * t + 2]];
        let fn_ = f[0] * n[0] + f[1] * n[1] + f[2] * n[2];
        let ft = [f[0] - fn_ * n[0], f[1] - fn_ * n[1], f[2] - fn_ * n[2]];
        let ft = (ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]).sqrt();
        let scale = (f[0].abs() + f[1].abs() + f[2].abs()) / a_t;
        assert!(
            (pressure[t] - fn_.abs() / a_t).abs() <= 1e-12 * scale,
            "pressure {t}"
        );
        assert!((shear[t] - ft / a_t).abs() <= 1e-12 * scale, "shear {t}");
        // The box's faces are outward: the floor's normal is −z; spheres
        // resting on it push it down (force −z on the wall, along the
        // outward normal), a positive pressure.
        if n[2] < -0.5 {
            assert!(f[2] <= 0.0 && pressure[t] >= 0.0, "floor {t}: {f:?}");
            floor_load += f[2];
        }
        for k in 0..3 {
            total[k] += f[k];
        }
    }
    // The floor carries the landed layer: some force on it.
    assert!(floor_load < 0.0, "the bottom layer has landed");
    // Σ triangles = the wall's force in --json (the same records in
    // another grouping: ≤ 12 + (contacts) roundings, ~1e-15 relative;
    // 1e-12 catches one lost or doubled contact).
    let wall = &json["wall_forces"][0];
    for k in 0..3 {
        let w = wall[k].as_f64().unwrap();
        assert!(
            (total[k] - w).abs() <= 1e-12 * total[2].abs(),
            "component {k}: Σ triangles {total:?} vs wall {wall}"
        );
    }
}

/// A scene with no mesh wall writes no wall file, and its `--json` has no
/// `wall_triangle_counts`.
#[test]
fn a_scene_without_mesh_walls_writes_no_wall_files() {
    let tmp = tempfile::tempdir().unwrap();
    let o = dembound()
        .arg("scene")
        .arg(common::lattice_drop())
        .args([
            "--set",
            "integration.steps=10",
            "--json",
            "--quiet",
            "--out",
        ])
        .arg(tmp.path().join("out"))
        .output()
        .expect("the binary runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(json.get("wall_triangle_counts").is_none());
    let pvd = std::fs::read_to_string(tmp.path().join("out/snapshots.pvd")).unwrap();
    assert!(
        !pvd.contains("wall_") && !pvd.contains("part=\"1\""),
        "{pvd}"
    );
}
