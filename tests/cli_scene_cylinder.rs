//! The cylinder wall through the scene file (issue 25): bad input is
//! refused naming the key (exit 2, nothing on stdout), the collision log
//! names the cylinder "wall:K", export refuses it by name.

mod common;

use common::{dembound, scene_text};
use std::path::Path;

/// A sphere (R = 1 mm) at the axis of a horizontal tube (axis x, R_c =
/// 10 mm, wall 1) above a floor plane (wall 0); gravity −z: it falls onto
/// the tube's bottom and bounces.
const BASE: &str = r#"
[domain]
lower = [-0.05, -0.02, -0.02]
upper = [0.05, 0.02, 0.02]
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
spheres = [{ position = [0.0, 0.0, 0.0], radius = 0.001 }]

[[wall]]
plane = { point = [0.0, 0.0, -0.02], normal = [0.0, 0.0, 1.0] }
material = "g"

[[wall]]
cylinder = { point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = 0.01 }
material = "g"

[integration]
dt = 2e-6
steps = 200000
"#;

const TUBE: &str = "cylinder = { point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = 0.01 }";

/// (exit code, stdout, stderr) of `dembound scene` on `text` with `args`.
fn run(text: &str, args: &[&str], dir: &Path) -> (Option<i32>, String, String) {
    scene_text(text, dir, &[&["--json"], args].concat())
}

#[test]
fn bad_cylinder_input_is_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &[&str]); 7] = [
        (
            TUBE,
            "cylinder = { point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = -0.01 }",
            &["wall[1].cylinder.radius", "-0.01"],
        ),
        (
            TUBE,
            "cylinder = { point = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 0.0], radius = 0.01 }",
            &["wall[1].cylinder.axis", "non-zero"],
        ),
        (
            TUBE,
            "cylinder = { point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = 0.01, \
             inside = false, length = 0.02 }",
            &["wall[1].cylinder.length", "post"],
        ),
        (
            "periodic = [false, false, false]",
            "periodic = [false, true, false]",
            &["wall[1].cylinder.axis", "periodic"],
        ),
        (
            // The sphere below the tube: outside it.
            "position = [0.0, 0.0, 0.0]",
            "position = [0.0, 0.0, -0.015]",
            &["wall[1].cylinder", "outside", "particles[0].spheres[0]"],
        ),
        (
            // No wider than the sphere.
            TUBE,
            "cylinder = { point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = 0.0009 }",
            &["wall[1].cylinder.radius", "largest free sphere"],
        ),
        (
            // A plane and a cylinder in one [[wall]].
            TUBE,
            "cylinder = { point = [0.0, 0.0, 0.0], axis = [1.0, 0.0, 0.0], radius = 0.01 }\n\
             plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }",
            &[
                "wall[1]",
                "exactly one of plane, cylinder, mesh, boundary_particles",
            ],
        ),
    ];
    for (from, to, needles) in cases {
        let text = BASE.replace(from, to);
        assert_ne!(text, BASE, "{from}");
        let (code, out, err) = run(&text, &[], dir.path());
        assert_eq!(code, Some(2), "{to}: {err}");
        assert!(out.is_empty(), "{to}: {out}");
        for n in needles {
            assert!(err.contains(n), "{to}: stderr lacks {n:?}: {err}");
        }
    }
}

#[test]
fn the_collision_log_names_the_cylinder_wall_k() {
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
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // The sphere rests on the tube's bottom: the tube carries its weight
    // (m g = 1000 · 4/3 π (1e-3)³ · 9.81 = 4.109e-5 N), the floor nothing.
    let forces = &json["wall_forces"];
    let tube_z = forces[1][2].as_f64().unwrap();
    assert!((tube_z / -4.109e-5 - 1.0).abs() < 0.01, "{forces}");
    assert_eq!(forces[0][2].as_f64().unwrap(), 0.0);
    let log = std::fs::read_to_string(out_dir.join("collisions.csv")).unwrap();
    let rows: Vec<&str> = log.lines().skip(1).collect();
    assert!(!rows.is_empty(), "{log}");
    assert!(rows.iter().all(|r| r.contains(",wall:1,")), "{log}");
}

#[test]
fn export_refuses_the_cylinder_by_name() {
    let dir = tempfile::tempdir().unwrap();
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
    assert!(err.contains("wall[1].cylinder"), "{err}");
}

/// Small initial overlaps with a plane and a cylinder (1 % < share ≤ 50 %)
/// run, with one warning line per wall type naming the count and the
/// largest. By hand: sphere 1 (R = 1 mm) at z = 0.97 mm overlaps the
/// floor z = 0 by 0.03 mm (3 %), sphere 0 at 0.98 mm by 2 %; sphere 1 is
/// 3 mm from the axis of a 3.95 mm tube: 3 + 1 − 3.95 = 0.05 mm (5 %),
/// sphere 0 on the axis does not touch it.
#[test]
fn small_initial_overlaps_are_one_warning_per_wall_type() {
    let dir = tempfile::tempdir().unwrap();
    let text = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "a"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
spheres = [ { position = [0.005, 0.005, 0.00098], radius = 1.0e-3 }, { position = [0.002, 0.005, 0.00097], radius = 1.0e-3 } ]
material = "a"
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "a"
[[wall]]
cylinder = { point = [0.005, 0.005, 0.0], axis = [0.0, 0.0, 1.0], radius = 0.00395 }
material = "a"
[integration]
dt = 1e-6
steps = 5
"#;
    let (code, _, err) = run(text, &[], dir.path());
    assert_eq!(code, Some(0), "{err}");
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.contains("start overlapping"))
        .collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(
        lines[0].contains("2 free sphere(s) start overlapping a plane wall")
            && lines[0].contains("input index 1) and `wall[0].plane`, 3.0000e-5 m (3 %)"),
        "{err}"
    );
    assert!(
        lines[1].contains("1 free sphere(s) start overlapping a cylinder wall")
            && lines[1].contains("input index 1) and `wall[1].cylinder`, 5.0000e-5 m (5 %)"),
        "{err}"
    );
}
