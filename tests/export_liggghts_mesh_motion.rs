//! Issue 27: a mesh translating at a constant velocity is exported to
//! LIGGGHTS as `fix move/mesh ... linear` (crates/dembound-export/src/
//! liggghts_motion.rs says why the pose and the surface velocity are the
//! same in both codes up to the rounding of LIGGGHTS's running sum of
//! V Δt). Three spheres on a square mesh floor rising and drifting,
//! run in LIGGGHTS 3.8 and by dembound's engine, compared at every dump
//! row.
//!
//! Skips (saying so on stderr) when `liggghts` is not on PATH, except
//! under CI, where a missing LIGGGHTS fails the test (tests/common/peer.rs).

mod common;

use common::peer::{missing, read_liggghts_dump, run_liggghts};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::Simulation;

/// A square of side 16 mm at z = 0, centred on the axis, as two
/// triangles (normal +z), ASCII STL.
const FLOOR_STL: &str = "solid floor
facet normal 0 0 1
outer loop
vertex -0.008 -0.008 0
vertex 0.008 -0.008 0
vertex 0.008 0.008 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex -0.008 -0.008 0
vertex 0.008 0.008 0
vertex -0.008 0.008 0
endloop
endfacet
endsolid floor
";

/// Three frictionless spheres (Hertz, Tsuji damping for e = 0.5) let go
/// 0.2–0.4 mm above the floor mesh, which rises at 0.05 m/s and drifts
/// along x at 0.02 m/s from t = 0; Δt = 1 µs, 20 000 steps.
const SCENE: &str = r#"
[domain]
lower = [-0.01, -0.01, -0.002]
upper = [0.01, 0.01, 0.01]
[[material]]
name = "grain"
density = 2500.0
youngs_modulus = 1e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
[[particles]]
material = "grain"
spheres = [{ position = [-0.003, -0.002, 0.0012], radius = 0.001 }, { position = [0.003, 0.001, 0.0013], radius = 0.001 }, { position = [0.0, 0.004, 0.0011], radius = 0.0008 }]
[[wall]]
mesh = { file = "floor.stl" }
material = "grain"
motion = { velocity = [0.02, 0.0, 0.05] }
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
dt = 1e-6
steps = 20000
[output]
series_every = 500
"#;

/// The floor rises into the falling spheres and throws them up again
/// (the normal damping sees the wall's velocity V): positions and
/// velocities agree to 1e-9 relative. Why 1e-9: the same Hertz–Tsuji law
/// in both (tests/export_liggghts_friction.rs), the pose differing by the
/// rounding of LIGGGHTS's running sum of V Δt (≤ 1e-14 m here, module
/// doc of liggghts_motion.rs) against overlaps of ~1e-5 m; a floor
/// moved one step late is 5e-8 m off (V Δt), 5e-3 of the overlap.
#[test]
fn spheres_on_a_translating_mesh_as_in_liggghts() {
    if missing("liggghts", "liggghts", "the translating mesh export") {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    std::fs::write(dir.path().join("floor.stl"), FLOOR_STL).expect("written");
    let path = dir.path().join("floor.toml");
    std::fs::write(&path, SCENE).expect("written");
    let deck = dir.path().join("deck");
    run_liggghts(&path, &deck);
    let input = std::fs::read_to_string(deck.join("in.liggghts")).expect("in.liggghts");
    assert!(
        input.contains("move/mesh mesh mesh0 linear 2e-2 0 5e-2"),
        "the deck moves the floor:\n{input}"
    );
    let dump = read_liggghts_dump(&deck);
    let file = config::load(SCENE, "floor.toml", &[]).expect("a valid scene");
    let scene = resolve(&file, dir.path()).expect("resolves");
    let mut sim = Simulation::new(scene.setup, 1).expect("builds");
    let start = sim.positions();
    let (mut dx, mut dv, mut rise, mut contacts) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for (step, rows) in &dump {
        sim.step(step - sim.steps_done());
        let (x, v) = (sim.positions(), sim.velocities());
        assert_eq!(rows.len(), x.len());
        let vmax = v
            .iter()
            .map(|w| (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt())
            .fold(0.0, f64::max);
        for (i, l) in rows.iter().enumerate() {
            for a in 0..3 {
                dx = dx.max((l[3 + a] - x[i][a]).abs() / 0.01);
                if vmax > 0.0 {
                    dv = dv.max((l[6 + a] - v[i][a]).abs() / vmax);
                }
            }
            rise = rise.max(x[i][2] - start[i][2]);
        }
        contacts += sim.wall_contacts();
    }
    assert_eq!(sim.steps_done(), 20000, "every row compared");
    eprintln!(
        "translating mesh: positions {dx:.2e} (of 1 cm), velocities {dv:.2e} (of the largest \
         speed); spheres raised up to {rise:.3e} m; wall contacts summed over rows {contacts}"
    );
    assert!(dx < 1e-9 && dv < 1e-9, "x {dx:e}, v {dv:e}");
    // The floor (rising 1 mm in 20 ms) carried them above where they
    // started.
    assert!(
        rise > 1e-4 && contacts > 0,
        "rise {rise:e} m, contacts {contacts}"
    );
}
