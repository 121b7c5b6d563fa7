//! Moving groups of fixed spheres through the CLI (issue 27 item 1):
//! `motion`/`oscillation` on a `[[particles]]` group with `fixed = true`
//! and on a `boundary_particles` wall; bad uses refused naming the key
//! (exit 2, nothing written); a moving boundary-particle wall reports its
//! motion in `--json wall_motions` and `series.csv`, and every moving
//! group its work in the energy balance.

mod common;

use common::scene_text;
use serde_json::Value;

/// A free sphere resting in a hollow of a lined plate (4 × 4 fixed
/// spheres of 1 mm, `[[particles]]` group 1) with `GROUP` in group 1's
/// entry, and a boundary-particle floor (wall 0) far below with `WALL`
/// in its entry.
fn scene(group: &str, wall: &str, periodic: &str) -> String {
    let mut plate = String::new();
    for i in 0..4 {
        for j in 0..4 {
            let (x, y) = (-3e-3 + 2e-3 * i as f64, -3e-3 + 2e-3 * j as f64);
            plate.push_str(&format!(
                "{{ position = [{x:e}, {y:e}, 0.0], radius = 1e-3 }}, "
            ));
        }
    }
    format!(
        r#"
[domain]
lower = [-0.01, -0.01, -0.01]
upper = [0.01, 0.01, 0.01]
periodic = {periodic}

[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
friction = 0.5

[[particles]]
spheres = [{{ position = [0.0, 0.0, 1.4143e-3], radius = 1e-3 }}]
material = "grain"

[[particles]]
spheres = [{plate}]
material = "grain"
fixed = true
{group}

[[wall]]
boundary_particles = {{ point = [0.0, 0.0, -0.009], normal = [0.0, 0.0, 1.0], radius_ratio = 1.0, modulus_ratio = 10.0 }}
material = "grain"
{wall}

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
dt = 1.0e-6
steps = 20000

[output]
series_every = 5000
"#
    )
}

#[test]
fn bad_uses_are_refused_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let free = scene("", "", "[false, false, false]").replace(
        "material = \"grain\"\n\n[[particles]]",
        "material = \"grain\"\nmotion = { velocity = [0.01, 0.0, 0.0] }\n\n[[particles]]",
    );
    for (text, needles) in [
        (free, vec!["particles[0].motion", "fixed = true", "allowed"]),
        (
            scene(
                "motion = { angular_velocity = [0.0, 0.0, 1e7] }",
                "",
                "[false, false, false]",
            ),
            vec!["particles[1].motion.angular_velocity", "1e6"],
        ),
        (
            scene(
                "oscillation = { amplitude = [1e-3, 0.0, 0.0], frequency = 0.0 }",
                "",
                "[false, false, false]",
            ),
            vec!["particles[1].oscillation.frequency", "> 0"],
        ),
        (
            scene(
                "motion = { velocity = [0.01, 0.0, 0.0] }",
                "",
                "[true, false, false]",
            ),
            vec!["particles[1].motion", "periodic"],
        ),
        (
            scene(
                "",
                "motion = { velocity = [0.01, 0.0, 0.0] }",
                "[false, true, false]",
            ),
            vec!["wall[0].motion", "periodic"],
        ),
        (
            scene(
                "",
                "servo = { force = 1.0, axis = [0.0, 0.0, 1.0], max_velocity = 0.1 }",
                "[false, false, false]",
            ),
            vec!["wall[0].servo", "no servo"],
        ),
        (
            scene("servo = { force = 1.0 }", "", "[false, false, false]"),
            vec!["servo"],
        ),
    ] {
        let out = tmp.path().join("out");
        let (code, _, err) = scene_text(
            &text,
            tmp.path(),
            &["--json", "-q", "--out", out.to_str().unwrap()],
        );
        assert_eq!(code, Some(2), "{err}");
        for n in needles {
            assert!(err.contains(n), "{n}: {err}");
        }
        assert!(!out.exists(), "something was written: {err}");
    }
}

/// A plate of spheres moving along x at 1 cm/s and a boundary-particle
/// floor oscillating (wall 0): both report their work (W > 0: the plate
/// drags the sphere up to its speed, ½ m V² and more), the floor its
/// motion in `wall_motions` and in series columns `wall0_position_x_m`
/// etc., with the closed-form position a sin(2π f t) at the last row.
#[test]
fn moving_groups_report_work_and_motion() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, f) = (1e-4, 50.0);
    let text = scene(
        "motion = { velocity = [0.01, 0.0, 0.0] }",
        &format!("oscillation = {{ amplitude = [{a:e}, 0.0, 0.0], frequency = {f} }}"),
        "[false, false, false]",
    );
    let out = tmp.path().join("out");
    let (code, stdout, err) = scene_text(
        &text,
        tmp.path(),
        &["--json", "-q", "--out", out.to_str().unwrap()],
    );
    assert_eq!(code, Some(0), "{err}");
    let j: Value = serde_json::from_str(&stdout).unwrap();
    let w = j["energy_balance"]["work_by_walls"].as_f64().unwrap();
    let m = 4.0 / 3.0 * std::f64::consts::PI * 1e-9 * 1000.0;
    assert!(w >= 0.5 * m * 0.01 * 0.01 * 0.9, "{w}");
    let motions = j["wall_motions"].as_array().expect("wall_motions");
    assert_eq!(motions.len(), 1, "{motions:?}");
    assert_eq!(motions[0]["wall"].as_u64(), Some(0));
    // t = 20000 × 1 µs = 0.02 s: x = a sin(2π f t) = a sin(2π) ≈ 0 (to
    // the rounding of 2π f t, ~1e-16 × a).
    let t = 20000.0 * 1e-6;
    let x = motions[0]["position"][0].as_f64().unwrap();
    let exact = a * (2.0 * std::f64::consts::PI * f * t).sin();
    assert!((x - exact).abs() <= 1e-15, "{x} vs {exact}");
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let header = series.lines().next().unwrap();
    assert!(header.contains("work_by_walls_J"), "{header}");
    assert!(header.contains("wall0_position_x_m"), "{header}");
    let total = j["energy_balance"]["total"].as_f64().unwrap();
    let initial = j["energy_balance"]["total_initial"].as_f64().unwrap();
    assert!((total - initial).abs() <= 1e-12 * initial.abs(), "{j}");
}
