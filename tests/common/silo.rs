//! The flat-bottomed silo of the LAMMPS flow comparisons
//! (tests/export_lammps_flow_compare.rs, draining;
//! tests/export_lammps_inlet_compare.rs, fed from above).

/// Time step, s.
pub const DT: f64 = 4e-6;
/// Gravity, m/s² (along −z).
pub const G: f64 = 9.81;
/// The spheres' radius (free and floor), m.
pub const R: f64 = 1e-3;
/// The glass spheres' density, kg/m³.
pub const RHO: f64 = 2500.0;
/// The floor's sites: a square grid of this pitch (m), 9 × 9 sites, those
/// within [`ORIFICE`] of the axis left out.
pub const PITCH: f64 = 2.05e-3;
pub const ORIFICE: f64 = 5e-3;

/// The scene: `count` glass spheres (R, Hertz with Tsuji damping, e =
/// 0.5, frictionless) placed at random (seed 3) with centres between z =
/// 2 mm and `fill_top` m in a 20 mm square silo of four plane side walls
/// and a plane 30 mm below, over a floor of 60 fixed steel spheres with an
/// orifice, an outlet box below the orifice, `extra` (TOML, e.g. an
/// `[[inlet]]`) after it; `steps` steps of [`DT`], a series row every
/// `series_every`.
pub fn silo_scene(count: f64, fill_top: f64, extra: &str, steps: u64, series_every: u64) -> String {
    let mut floor = Vec::new();
    for i in -4i32..=4 {
        for j in -4i32..=4 {
            let (x, y) = (f64::from(i) * PITCH, f64::from(j) * PITCH);
            if x.hypot(y) >= ORIFICE {
                floor.push(format!(
                    "{{ position = [{x:e}, {y:e}, 0.0], radius = {R:e} }}"
                ));
            }
        }
    }
    assert_eq!(floor.len(), 60, "the floor's sites");
    let plane = |p: &str, n: &str| {
        format!("[[wall]]\nplane = {{ point = {p}, normal = {n} }}\nmaterial = \"steel\"\n")
    };
    format!(
        r#"
[domain]
lower = [-0.01, -0.01, -0.03]
upper = [0.01, 0.01, 0.07]
[[material]]
name = "glass"
density = {RHO:e}
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "steel"
density = 7800.0
youngs_modulus = 5.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
[[particles]]
random = {{ count = {count}, radius = {R:e}, lower = [-0.009, -0.009, 0.002], upper = [0.009, 0.009, {fill_top}], seed = 3 }}
material = "glass"
[[particles]]
spheres = [ {} ]
material = "steel"
fixed = true
{}{}{}{}{}
[[outlet]]
region = {{ box = {{ lower = [-0.01, -0.01, -0.03], upper = [0.01, 0.01, -0.01] }} }}
{extra}[motion]
gravity = [0.0, 0.0, -{G}]
[integration]
scheme = "verlet"
dt = {DT:e}
steps = {steps}
[output]
series_every = {series_every}
"#,
        floor.join(", "),
        plane("[0.0, 0.0, -0.03]", "[0.0, 0.0, 1.0]"),
        plane("[-0.01, 0.0, 0.0]", "[1.0, 0.0, 0.0]"),
        plane("[0.01, 0.0, 0.0]", "[-1.0, 0.0, 0.0]"),
        plane("[0.0, -0.01, 0.0]", "[0.0, 1.0, 0.0]"),
        plane("[0.0, 0.01, 0.0]", "[0.0, -1.0, 0.0]"),
    )
}

/// Asserts that `compare --json`'s late-window means of quantity `name`
/// agree: the LAMMPS and dembound means within 3 combined standard errors
/// of each other (two realisations of one flow that parted at the first
/// collisions: their difference is about normal with the combined error
/// as its deviation, so 3 of those bound it but for a 0.3 % chance), and
/// on each side a positive mean with a standard error above 0 and below
/// `max_relative_se` of it (an error that is there, and a mean that is).
/// Prints both.
pub fn assert_windows_agree(report: &serde_json::Value, name: &str, max_relative_se: f64) {
    let q = super::quantity(report, name);
    let (c, d) = (&q["code_window"], &q["dembound_window"]);
    let mean = |w: &serde_json::Value| w["mean"].as_f64().expect("a window mean");
    let se = |w: &serde_json::Value| w["standard_error"].as_f64().expect("a standard error");
    let both = format!(
        "{name}: LAMMPS {} ± {}, dembound {} ± {}",
        mean(c),
        se(c),
        mean(d),
        se(d)
    );
    eprintln!("{both}");
    assert!(
        (mean(c) - mean(d)).abs() <= 3.0 * se(c).hypot(se(d)),
        "{both}"
    );
    for (side, w) in [("LAMMPS", c), ("dembound", d)] {
        assert!(
            mean(w) > 0.0 && se(w) > 0.0 && se(w) < max_relative_se * mean(w),
            "{side} {name}: {} ± {}",
            mean(w),
            se(w)
        );
    }
}
