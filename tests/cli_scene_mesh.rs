//! The triangle-mesh wall through the scene file (issue 26): a scene
//! whose STL path is relative to the scene file runs from anywhere, the
//! collision log names the mesh "wall:K", its load is the resting
//! sphere's weight; bad input is refused naming the key and the file
//! (exit 2, nothing on stdout); export refuses the mesh by name.

mod common;

use common::{dembound, scene_text};
use std::path::Path;

/// A sphere (R = 1 mm, E = 1e7 Pa) dropped from 1 mm onto a floor made
/// of a 2-triangle STL (wall 0, `parts/floor.stl` next to the scene
/// file), gravity −z, Hertz + Tsuji e = 0.5: its bounces (flights of
/// 2 v/g, each half the last) end within 0.03 s; the run is 0.1 s.
const BASE: &str = r#"
[domain]
lower = [-0.02, -0.02, 0.0]
upper = [0.02, 0.02, 0.02]
periodic = [false, false, false]

[[material]]
name = "g"
density = 1000.0
youngs_modulus = 1e7
poisson_ratio = 0.3

[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5

[[particles]]
material = "g"
spheres = [{ position = [0.003, -0.002, 0.002], radius = 0.001 }]

[[wall]]
mesh = { file = "parts/floor.stl" }
material = "g"

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
dt = 2e-6
steps = 50000
"#;

const FLOOR: &str = r#"mesh = { file = "parts/floor.stl" }"#;

/// The square [−0.02, 0.02]² at z = 0 as an ASCII STL of 2 triangles.
const FLOOR_STL: &str = "solid floor
facet normal 0 0 1
outer loop
vertex -0.02 -0.02 0
vertex 0.02 -0.02 0
vertex 0.02 0.02 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex -0.02 -0.02 0
vertex 0.02 0.02 0
vertex -0.02 0.02 0
endloop
endfacet
endsolid floor
";

/// Writes the scene `text` and its parts into `dir`, runs `dembound
/// scene` from the system's temporary directory (not the scene's): (exit
/// code, stdout, stderr).
fn run(text: &str, args: &[&str], dir: &Path) -> (Option<i32>, String, String) {
    let parts = dir.join("parts");
    std::fs::create_dir_all(&parts).unwrap();
    std::fs::write(parts.join("floor.stl"), FLOOR_STL).unwrap();
    std::fs::write(parts.join("garbage.stl"), "this is not a mesh\n").unwrap();
    // One triangle whose corners coincide: nothing left after cleaning.
    std::fs::write(
        parts.join("point.stl"),
        FLOOR_STL
            .replace("vertex 0.02 -0.02 0", "vertex -0.02 -0.02 0")
            .replace("vertex 0.02 0.02 0", "vertex -0.02 -0.02 0")
            .replace("vertex -0.02 0.02 0", "vertex -0.02 -0.02 0"),
    )
    .unwrap();
    scene_text(text, dir, &[&["--json"], args].concat())
}

#[test]
fn a_mesh_scene_runs_with_a_relative_stl_and_logs_wall_k() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    let (code, stdout, err) = run(
        BASE,
        &[
            "--set",
            "output.collisions=true",
            "--out",
            out_dir.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert_eq!(code, Some(0), "{err}");
    // The cleaning's report reaches the user: a floor has 4 open edges.
    assert!(
        err.contains("wall[0].mesh") && err.contains("4 open edges"),
        "{err}"
    );
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // At rest on the floor after 0.1 s: the floor carries the weight m g = 1000 · 4/3 π (1e-3)³ · 9.81 =
    // 4.109e-5 N, to 1 % (the residual oscillation).
    let fz = json["wall_forces"][0][2].as_f64().unwrap();
    assert!(
        (fz / -4.109e-5 - 1.0).abs() < 0.01,
        "{}",
        json["wall_forces"]
    );
    let log = std::fs::read_to_string(out_dir.join("collisions.csv")).unwrap();
    let rows: Vec<&str> = log.lines().skip(1).collect();
    assert!(!rows.is_empty(), "{log}");
    assert!(rows.iter().all(|r| r.starts_with("0,wall:0,")), "{log}");
    // The resolved scene names the file by its absolute path: it runs
    // from anywhere.
    let resolved = std::fs::read_to_string(out_dir.join("scene.toml")).unwrap();
    let absolute = dir.path().join("parts").join("floor.stl");
    let absolute = std::path::absolute(&absolute).unwrap();
    assert!(
        resolved.contains(&format!("{:?}", absolute.display().to_string())),
        "{resolved}"
    );
}

#[test]
fn bad_mesh_input_is_refused_naming_the_key_and_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str]); 7] = [
        (
            r#"mesh = { file = "parts/missing.stl" }"#,
            &["wall[0].mesh.file", "missing.stl", "cannot be read"],
        ),
        (
            r#"mesh = { file = "parts/garbage.stl" }"#,
            &["wall[0].mesh.file", "garbage.stl", "not a valid mesh"],
        ),
        (
            r#"mesh = { file = "parts/point.stl" }"#,
            &["wall[0].mesh.file", "point.stl", "no triangle left"],
        ),
        (
            r#"mesh = { file = "parts/floor.ply" }"#,
            &["wall[0].mesh.file", "floor.ply", "unknown format"],
        ),
        (
            // Moved 1 m along x: 0.98 m beyond the domain.
            r#"mesh = { file = "parts/floor.stl", translate = [1.0, 0.0, 0.0] }"#,
            &["wall[0].mesh", "floor.stl", "does not meet the domain"],
        ),
        (
            r#"mesh = { file = "parts/floor.stl", scale = 0.0 }"#,
            &["wall[0].mesh.scale", "> 0"],
        ),
        (
            r#"mesh = { file = "parts/floor.stl", scale = -1.0 }"#,
            &["wall[0].mesh.scale", "-1"],
        ),
    ];
    for (to, needles) in cases {
        let text = BASE.replace(FLOOR, to);
        assert_ne!(text, BASE, "{to}");
        let (code, out, err) = run(&text, &[], dir.path());
        assert_eq!(code, Some(2), "{to}: {err}");
        assert!(out.is_empty(), "{to}: {out}");
        for n in needles {
            assert!(err.contains(n), "{to}: stderr lacks {n:?}: {err}");
        }
    }
    // A sphere sunk into the floor by 0.6 of its radius: refused, as a
    // plane refuses it (the limit is half the radius).
    let text = BASE.replace("0.003, -0.002, 0.002]", "0.003, -0.002, 0.0004]");
    let (code, _, err) = run(&text, &[], dir.path());
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("wall[0].mesh") && err.contains("overlaps the mesh"),
        "{err}"
    );
}

#[test]
fn export_refuses_the_mesh_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let parts = dir.path().join("parts");
    std::fs::create_dir_all(&parts).unwrap();
    std::fs::write(parts.join("floor.stl"), FLOOR_STL).unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, BASE).unwrap();
    let out = dembound()
        .args(["export", "lammps"])
        .arg(&path)
        .args(["--out", dir.path().join("deck").to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("wall[0].mesh"), "{err}");
    assert!(!dir.path().join("deck").exists(), "no half-written deck");
}
