//! `[[outlet]] region = { cylinder = { center, axis, radius, length } }`
//! (issue 28; the region type of the inlets, `dembound_scene::region`):
//! free-falling spheres whose centres enter the cylinder are removed at
//! the closed-form times; one inside the cylinder's bounding box but
//! outside its radius is not; bad cylinders are refused naming the key.

mod common;

use common::scene_text;
use common::shaft::{number, parse_json};

const G: f64 = 9.81;
/// Sphere radius, m, and density, kg/m³.
const R: f64 = 1e-3;
const RHO: f64 = 2500.0;
/// The list skin, m: a sphere is removed at the first list rebuild after
/// its centre entered, and rebuilds come whenever a sphere moved skin/2.
const SKIN: f64 = 2e-4;
const DT: f64 = 1e-5;
const STEPS: u64 = 8000;
/// The outlet: a vertical cylinder about (10 mm, 10 mm), radius 4 mm,
/// from z = 0 to its top face at z = 5 mm.
const AXIS_X: f64 = 0.01;
const RADIUS: f64 = 0.004;
const TOP: f64 = 0.005;
/// (x offset from the axis, y offset, drop height of the centre above the
/// top face), m. A on the axis and B 3.5 mm off it (< 4 mm) enter; C at
/// (3.5, 3.5) mm is 4.95 mm off the axis (> 4 mm) though inside the
/// cylinder's bounding box (each offset ≤ 4 mm). 3.5 mm or more apart
/// across, they fall side by side without touching.
const DROPS: [(f64, f64, f64); 3] = [
    (0.0, 0.0, 0.005),
    (0.0035, 0.0, 0.010),
    (0.0035, 0.0035, 0.007),
];

/// The three spheres at rest above the outlet, a floor plane at z = 0
/// (C lands on it, inside the bounding box, and stays there), the
/// cylinder written with the axis `axis` (a non-unit vector is the same
/// cylinder) and `radius`.
fn scene(axis: &str, radius: f64) -> String {
    let spheres: Vec<String> = DROPS
        .iter()
        .map(|&(dx, dy, d)| {
            format!(
                "{{ position = [{:e}, {:e}, {:e}], radius = {R:e} }}",
                AXIS_X + dx,
                AXIS_X + dy,
                TOP + d
            )
        })
        .collect();
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.02, 0.02, 0.03]

[[material]]
name = "g"
density = {RHO:e}
youngs_modulus = 1e7
poisson_ratio = 0.3

[[particles]]
material = "g"
spheres = [{}]

[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "g"

[[outlet]]
region = {{ cylinder = {{ center = [{AXIS_X:e}, {AXIS_X:e}, {:e}], axis = {axis}, radius = {radius:e}, length = {TOP:e} }} }}

[motion]
gravity = [0.0, 0.0, -{G:e}]

[integration]
scheme = "verlet"
dt = {DT:e}
steps = {STEPS}
skin = {SKIN:e}

[output]
series_every = 1
"#,
        spheres.join(", "),
        0.5 * TOP
    )
}

/// A and B removed, C not; each removal at its closed-form time: the
/// centre crosses the top face at t = √(2 d / g) (Verlet's positions are
/// exact under constant g) and goes at the first list rebuild after, at
/// most (skin/2)/v + Δt later (v = √(2 g d) its speed there), plus a step
/// for the series row. The axis is written as (0, 0, 2): the same
/// cylinder.
#[test]
fn a_cylinder_outlet_removes_what_enters_it_and_only_that() {
    let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * R * R * R;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (code, stdout, stderr) = scene_text(
        &scene("[0.0, 0.0, 2.0]", RADIUS),
        dir.path(),
        &["--json", "-q", "--out", out.to_str().unwrap()],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let j = parse_json(&stdout);
    assert_eq!(j["deleted_particles"], 2, "{j}");
    assert_eq!(j["outlets"][0]["count"], 2, "{j}");
    // A sum of two equal f64: exact to a rounding.
    assert!((number(&j["outlets"][0], "mass") - 2.0 * m).abs() <= 1e-15 * m);

    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let header: Vec<&str> = series.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<f64>> = series
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    let (time, removed) = (col("time_s"), col("outlet0_removed"));
    // A (d = 5 mm) enters first, then B (d = 10 mm).
    for (n, d) in [DROPS[0].2, DROPS[1].2].into_iter().enumerate() {
        let t_in = (2.0 * d / G).sqrt();
        let late = 0.5 * SKIN / (2.0 * G * d).sqrt() + 2.0 * DT;
        let t = rows
            .iter()
            .find(|r| r[removed] >= (n + 1) as f64)
            .map(|r| r[time])
            .unwrap_or_else(|| panic!("sphere {n} never removed"));
        assert!(
            t >= t_in && t <= t_in + late,
            "sphere {n}: removed at {t} s, enters at {t_in} s"
        );
    }
    assert_eq!(rows.last().unwrap()[removed], 2.0);
}

/// The same spheres with a radius of 5 mm (> C's 4.95 mm off the axis):
/// C is removed too, so the radius, not the bounding box, decided.
#[test]
fn a_wider_cylinder_takes_the_third_sphere() {
    let dir = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = scene_text(
        &scene("[0.0, 0.0, 1.0]", 0.005),
        dir.path(),
        &["--json", "-q"],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let j = parse_json(&stdout);
    assert_eq!(j["outlets"][0]["count"], 3, "{j}");
}

/// Bad cylinders exit 2 naming the key; an unknown key in the cylinder
/// is refused too.
#[test]
fn bad_cylinders_are_refused_naming_the_key() {
    for (axis, radius, key) in [
        ("[0.0, 0.0, 0.0]", RADIUS, "outlet[0].region.cylinder.axis"),
        ("[0.0, nan, 1.0]", RADIUS, "outlet[0].region.cylinder.axis"),
        ("[0.0, 0.0, 1.0]", -1e-3, "outlet[0].region.cylinder.radius"),
        ("[0.0, 0.0, 1.0]", 0.0, "outlet[0].region.cylinder.radius"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let (code, _, stderr) = scene_text(&scene(axis, radius), dir.path(), &["-q"]);
        assert_eq!(code, Some(2), "{axis} {radius}: {stderr}");
        assert!(stderr.contains(key), "{axis} {radius}: {stderr}");
    }
    let dir = tempfile::tempdir().unwrap();
    let text = scene("[0.0, 0.0, 1.0]", RADIUS).replacen("length =", "height = 1.0, length =", 1);
    let (code, _, stderr) = scene_text(&text, dir.path(), &["-q"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("height"), "{stderr}");
    let dir = tempfile::tempdir().unwrap();
    let text =
        scene("[0.0, 0.0, 1.0]", RADIUS).replacen(&format!("length = {TOP:e}"), "length = -1.0", 1);
    let (code, _, stderr) = scene_text(&text, dir.path(), &["-q"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("outlet[0].region.cylinder.length"),
        "{stderr}"
    );
}
