//! `domain.outside` (issue 28): a sphere lost for good (wholly outside the
//! box, moving away, gravity not bringing it back) stops the run with exit
//! 2 naming it, the step, its position and the key, and writes nothing; one
//! thrown out through the open top falls back and is not lost; `"keep"`
//! lets them go on; a bad value names the key.

mod common;

use common::scene_text;
use std::path::Path;

/// Two spheres (R = 1 mm) in a 10 mm box with no walls; gravity −z. Sphere
/// 1 starts at z = 2 mm and falls out through the floor of the box.
const OPEN_BOX: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]

[[material]]
name = "g"
density = 2500.0
youngs_modulus = 1e7
poisson_ratio = 0.3

[[particles]]
material = "g"
spheres = [{ position = [0.005, 0.005, 0.008], radius = 1e-3 }, { position = [0.002, 0.002, 0.002], radius = 1e-3 }]

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
scheme = "verlet"
dt = 1e-5
duration = 0.1

[output]
series_every = 1
"#;

/// (exit code, stdout, stderr) of `dembound scene` on `text` with `args`.
fn run(text: &str, args: &[&str], dir: &Path) -> (Option<i32>, String, String) {
    scene_text(text, dir, args)
}

#[test]
fn a_sphere_falling_out_of_an_open_box_stops_the_run_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (code, stdout, stderr) = run(OPEN_BOX, &["--out", out.to_str().unwrap()], dir.path());
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stdout.is_empty(), "{stdout}");
    // Wholly outside once z < −R: free fall from z₀ = 2 mm, Verlet exact
    // for a constant force (up to rounding), so the first step n with
    // z₀ − g (n Δt)²/2 < −R, checked at every step (series_every = 1):
    // n = ⌊√(2 (z₀ + R)/g)/Δt⌋ + 1 = ⌊2473.05⌋ + 1 = 2474 (the fraction
    // .05 is far from a rounding tie).
    let n = ((2.0 * (0.002 + 0.001) / 9.81f64).sqrt() / 1e-5).floor() as u64 + 1;
    assert_eq!(n, 2474);
    for part in [
        "sphere 1 left the domain for good".to_string(),
        format!("by step {n} "),
        "along z".into(),
        "domain.outside = \"keep\"".into(),
    ] {
        assert!(stderr.contains(&part), "`{part}` not in: {stderr}");
    }
    // The other sphere (0) fell too, but stays in the box until step
    // ⌊√(2 · 9 mm / g)/Δt⌋ + 1 = 4284 > 2474: only sphere 1 is named.
    assert!(!stderr.contains("sphere 0"), "{stderr}");
    assert!(!out.exists(), "no output for a stopped run");
}

#[test]
fn a_sphere_thrown_out_through_the_open_top_is_lost_only_below() {
    // One sphere at z₀ = 8 mm thrown up at 1 m/s: it leaves through the
    // open top (10 mm) on its way to 59 mm, falls back through the box and
    // is lost below it, at the first step n with z₀ + v n Δt − g (n Δt)²/2
    // < −R (Verlet is exact for a constant force, up to rounding).
    let one = OPEN_BOX
        .replace(
            "spheres = [{ position = [0.005, 0.005, 0.008], radius = 1e-3 }, { position = [0.002, 0.002, 0.002], radius = 1e-3 }]",
            "spheres = [{ position = [0.005, 0.005, 0.008], radius = 1e-3, velocity = [0.0, 0.0, 1.0] }]",
        )
        .replace("duration = 0.1", "duration = 0.3");
    let dir = tempfile::tempdir().unwrap();
    let (code, _, stderr) = run(&one, &["--json", "-q"], dir.path());
    assert_eq!(code, Some(2), "{stderr}");
    let (z0, v, g, r, dt) = (0.008, 1.0, 9.81f64, 0.001, 1e-5);
    let t = (v + (v * v + 2.0 * g * (z0 + r)).sqrt()) / g;
    let steps = t / dt;
    // Far from a tie between two steps (rounding cannot move it).
    assert!((steps - steps.round()).abs() > 1e-3, "{steps}");
    let n = steps.floor() as u64 + 1;
    for part in [
        "sphere 0 left the domain for good".to_string(),
        format!("by step {n} "),
    ] {
        assert!(stderr.contains(&part), "`{part}` not in: {stderr}");
    }
}

#[test]
fn keep_lets_the_spheres_go_on() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = run(
        OPEN_BOX,
        &["--json", "-q", "--set", "domain.outside=keep"],
        dir.path(),
    );
    assert_eq!(code, Some(0), "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // Free fall for 0.1 s: K = Σ ½ m (g t)² (no contact: the spheres
    // never meet); 1e-9 covers the rounding of 10⁴ Verlet steps.
    let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-9;
    let expected = 2.0 * 0.5 * m * (9.81f64 * 0.1).powi(2);
    let k = json["kinetic_energy"].as_f64().unwrap();
    assert!((k - expected).abs() <= 1e-9 * expected, "{k} vs {expected}");
}

#[test]
fn a_bad_value_names_the_key_and_the_allowed_values() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = run(
        OPEN_BOX,
        &["--json", "--set", "domain.outside=drop"],
        dir.path(),
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stdout.is_empty());
    for part in ["domain.outside", "drop", "`error`, `keep`, `delete`"] {
        assert!(stderr.contains(part), "`{part}` not in: {stderr}");
    }
}
