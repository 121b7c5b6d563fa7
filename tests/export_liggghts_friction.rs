//! Issue 26, "against a peer", with damping and friction:
//! `dembound export liggghts SCENE.toml` writes `model hertz tangential
//! history` (+ `limitForce on` for the clamp) with dembound's Tsuji
//! damping as a `coefficientRestitution` and its μ per type pair
//! (crates/dembound-export/src/liggghts_contact.rs says which formulas
//! are the same in both codes and which differ). Run in LIGGGHTS 3.8
//! against `dembound scene`.
//!
//! Skips (saying so on stderr) when `liggghts` is not on PATH, except
//! under CI, where a missing LIGGGHTS fails the test (tests/common/peer.rs).

mod common;

use common::dembound;
use common::peer::{missing, read_liggghts_dump as read_dump, run_liggghts};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::Simulation;
use std::path::Path;

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

/// A sphere (R = 1 mm, ρ = 1000 kg/m³, E = 1e7 Pa, ν = 0.3) thrown at
/// (1.5, 0, −0.5) m/s onto a 2-triangle STL floor (E = 2e8 Pa, ν = 0.25;
/// scaled, turned, lifted to z = 0.5 mm), elastic Hertz, μ = 0.3, Δt =
/// 1 µs, 3000 steps: the contact from t ≈ 1.97 ms to 2.1 ms, then flight
/// with the spin it took. The slip v_t = 3 v_n is more than one contact
/// can stop (a sphere's contact-point slip falls by (7/2) μ J/m = (7/2) μ
/// (1 + e) v_n = 1.05 v_n), so the contact slides from its first step to
/// its last. `DAMPED` is the same scene straight down, frictionless, with
/// Tsuji damping for e = 0.5 (dembound's exact calibration of the clamped
/// law: the deck gets the e′ of the same γ and `limitForce on`).
const IMPACT: &str = r#"
[domain]
lower = [-0.01, -0.01, 0.0]
upper = [0.01, 0.01, 0.01]
periodic = [false, false, false]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1e7
poisson_ratio = 0.3
[[material]]
name = "floor"
density = 7800.0
youngs_modulus = 2e8
poisson_ratio = 0.25
[contact]
law = "hertz"
friction = 0.3
[[particles]]
material = "grain"
spheres = [{ position = [0.001, 0.004, 0.0025], radius = 0.001, velocity = [1.5, 0.0, -0.5] }]
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
dt = 1e-6
steps = 3000
[output]
series_every = 1
[[wall]]
mesh = { file = "floor.stl", scale = 0.5, translate = [0.0, 0.0, 0.0005], rotate = { axis = [0.0, 0.0, 1.0], angle = 90.0 } }
material = "floor"
"#;

/// `IMPACT` damped (Tsuji, e = 0.5), frictionless, thrown straight down.
fn damped() -> String {
    IMPACT
        .replace("friction = 0.3", "damping = \"tsuji\"\nrestitution = 0.5")
        .replace("velocity = [1.5, 0.0, -0.5]", "velocity = [0.0, 0.0, -0.5]")
}

/// (largest |Δx|/R, largest |Δv|/0.5 m/s, final spin about y of dembound,
/// of LIGGGHTS, dembound's spin with each step's change scaled by
/// (1 − δ/(2R)), largest overlap δ) of `scene_text` run in both codes.
fn both(scene_text: &str, what: &str) -> Option<[f64; 6]> {
    if missing("liggghts", "liggghts", what) {
        return None;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    std::fs::write(dir.path().join("floor.stl"), FLOOR_STL).expect("written");
    let scene = dir.path().join("impact.toml");
    std::fs::write(&scene, scene_text).expect("written");
    let deck = dir.path().join("deck");
    run_liggghts(&scene, &deck);
    let dump = read_dump(&deck);
    let mut sim = simulation(scene_text, dir.path());
    let (r, floor): (f64, f64) = (1e-3, 5e-4);
    let (mut dx, mut dv, mut max_overlap) = (0.0f64, 0.0f64, 0.0f64);
    let (mut w_d, mut w_l, mut w_lever) = (0.0, 0.0, 0.0);
    for (step, rows) in dump.iter().filter(|(s, _)| *s >= 1) {
        sim.step(1);
        assert_eq!(*step, sim.steps_done(), "{what}: step");
        let (x, v, w) = (
            sim.positions()[0],
            sim.velocities()[0],
            sim.angular_velocities()[0],
        );
        let l = &rows[0];
        for a in 0..3 {
            dx = dx.max((l[3 + a] - x[a]).abs() / r);
            dv = dv.max((l[6 + a] - v[a]).abs() / 0.5);
        }
        let h = (floor + r - x[2]).max(0.0);
        max_overlap = max_overlap.max(h);
        // The torque of this step's force at R − δ/2 instead of R.
        w_lever += (w[1] - w_d) * (1.0 - h / (2.0 * r));
        w_d = w[1];
        w_l = l.get(10).copied().unwrap_or(0.0);
    }
    assert_eq!(sim.steps_done(), 3000, "{what}: every step compared");
    eprintln!(
        "{what}: largest differences x {dx:e} R, v {dv:e} of 0.5 m/s; max overlap {max_overlap:e} m; \
         final spin dembound {w_d} rad/s, LIGGGHTS {w_l} rad/s, dembound's with the lever arm \
         R - d/2 {w_lever} rad/s"
    );
    Some([dx, dv, w_d, w_l, w_lever, max_overlap])
}

/// The scene run by dembound's engine step by step.
fn simulation(scene_text: &str, dir: &Path) -> Simulation {
    let file = config::load(scene_text, "scene.toml", &[]).expect("a valid scene");
    let scene = resolve(&file, dir).expect("resolves");
    Simulation::new(scene.setup, 1).expect("builds")
}

/// The oblique impact, step by step. Positions and velocities: the same to
/// 1e-6 relative (of R and of the throw speed; the issue's tolerance): in
/// gross sliding both codes apply F_t = μ F_n against the slip (the same
/// Hertz F_n), so only round-off separates the trajectories (measured
/// 2e-16). The spin differs by the one law difference that acts here, the
/// lever arm: LIGGGHTS turns F_t into a torque at R − δ/2, dembound at R,
/// so each step's spin change in LIGGGHTS is dembound's × (1 − δ/(2R)).
/// Rebuilt so from dembound's own run, LIGGGHTS's final spin is predicted
/// to 1e-5 relative (Verlet's half-kicks pair each torque with the
/// overlap of the step before or after: O(Δt/T_c) = 1e-2 of the 1 %
/// correction; measured 1.3e-6), while the raw spins differ by 1 %
/// (asserted above 1e-3: the lever arm shows).
#[test]
fn oblique_frictional_impact_on_an_stl_floor_as_in_liggghts() {
    let what = "oblique frictional impact on the STL floor";
    let Some([dx, dv, w_d, w_l, w_lever, max_overlap]) = both(IMPACT, what) else {
        return;
    };
    assert!(max_overlap > 1e-5 && w_d.abs() > 100.0, "{what}: no bounce");
    assert!(dx < 1e-6 && dv < 1e-6, "{what}: trajectories differ");
    assert!(
        (w_l / w_lever - 1.0).abs() < 1e-5,
        "{what}: spin {w_l} vs {w_lever} with the lever arm"
    );
    assert!(
        (w_l / w_d - 1.0).abs() > 1e-3,
        "{what}: the lever arm should show"
    );
}

/// Straight down, frictionless, Tsuji damping for e = 0.5: the deck's
/// restitution e′ gives LIGGGHTS's hertz damping the γ of dembound's
/// exact calibration, `limitForce on` its clamp; the same force law, so
/// the trajectories agree to round-off (asserted 1e-6, the issue's; an
/// undamped LIGGGHTS or a γ off by 1e-4 would break it).
#[test]
fn damped_impact_on_an_stl_floor_as_in_liggghts() {
    let what = "damped impact on the STL floor";
    let scene = damped();
    let Some([dx, dv, _, _, _, max_overlap]) = both(&scene, what) else {
        return;
    };
    assert!(max_overlap > 1e-5, "{what}: no bounce");
    assert!(dx < 1e-6 && dv < 1e-6, "{what}: trajectories differ");
}

/// `IMPACT` damped (Tsuji, e = 0.5) and frictional (μ = 0.3), with
/// `contact.tangential_damping = tangential_damping`.
fn damped_frictional(tangential_damping: bool) -> String {
    IMPACT.replace(
        "friction = 0.3",
        &format!(
            "friction = 0.3\ndamping = \"tsuji\"\nrestitution = 0.5\ntangential_damping = {tangential_damping}"
        ),
    )
}

/// The oblique impact (v_t/v_n = 3, μ = 0.3) damped (Tsuji, e = 0.5) with
/// `contact.tangential_damping = false`, exported with LIGGGHTS's
/// `tangential_damping off`: neither code has a tangential dashpot, so
/// while the spring is below μ |F_n| (the first steps, when the damped
/// normal force ∝ h^(1/4) outgrows the spring ∝ h^(3/2)) both apply
/// −k_t δ, and once sliding both apply μ |F_n| along the slip. Positions
/// and velocities: the same to 1e-6 (of R, of the throw speed; measured
/// 3e-9: not round-off as above, since while the contact sticks the slip
/// velocity carries the spin at the lever arm, R − δ/2 against R, at a
/// tiny δ); LIGGGHTS's final spin is dembound's rebuilt with the lever arm
/// R − δ/2 to 1e-4 (measured 3.1e-5: the sticking steps' slip is not a
/// rescaled torque, so the rebuild is not as close as the sliding impact's
/// 1e-6; a dashpot or a γ off would move the spin by percents, below).
/// With the dashpot on (dembound's default, refused by the export),
/// dembound's final spin moves by 0.7 % (asserted > 1e-3, ten times the
/// spin's tolerance): the switch acts, and LIGGGHTS without its dashpot
/// is dembound without its, not with it.
#[test]
fn oblique_damped_frictional_impact_without_tangential_dashpot_as_in_liggghts() {
    let what = "oblique damped frictional impact, tangential_damping = false";
    let Some([dx, dv, w_d, w_l, w_lever, max_overlap]) = both(&damped_frictional(false), what)
    else {
        return;
    };
    assert!(max_overlap > 1e-5 && w_d.abs() > 100.0, "{what}: no bounce");
    assert!(dx < 1e-6 && dv < 1e-6, "{what}: trajectories differ");
    assert!(
        (w_l / w_lever - 1.0).abs() < 1e-4,
        "{what}: spin {w_l} vs {w_lever} with the lever arm"
    );
    // dembound alone with its dashpot (the default).
    let dir = tempfile::tempdir().expect("a temporary directory");
    std::fs::write(dir.path().join("floor.stl"), FLOOR_STL).expect("written");
    let mut sim = simulation(&damped_frictional(true), dir.path());
    sim.step(3000);
    let w_on = sim.angular_velocities()[0][1];
    eprintln!("{what}: final spin with the tangential dashpot {w_on} rad/s, without {w_d} rad/s");
    assert!(
        (w_on / w_lever - 1.0).abs() > 1e-3,
        "{what}: the dashpot should change the spin ({w_on} vs {w_d})"
    );
}

/// The same scene with the dashpot on is refused, the message naming the
/// switch.
#[test]
fn damped_frictional_scene_with_the_tangential_dashpot_is_refused() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    std::fs::write(dir.path().join("floor.stl"), FLOOR_STL).expect("written");
    let scene = dir.path().join("impact.toml");
    std::fs::write(&scene, damped_frictional(true)).expect("written");
    let o = dembound()
        .args(["export", "liggghts"])
        .arg(&scene)
        .arg("--out")
        .arg(dir.path().join("deck"))
        .output()
        .expect("dembound runs");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("contact.tangential_damping = false"), "{err}");
    assert!(!dir.path().join("deck").exists(), "no half-written deck");
}

/// 250 spheres of two materials and spread radii thrown into a box whose
/// floor is the 2-triangle STL and whose sides are four planes (as in
/// tests/export_liggghts_mesh.rs), elastic Hertz with μ = 0.5 on every
/// surface, 20,000 Verlet steps (11.4 ms): friction takes ~78 % of the
/// kinetic energy. Sliding contacts are chaotic: the two codes' kinetic
/// energies part by 1e-3 within ~500 steps, so the comparison is
/// statistical: five insertions (seeds), kinetic energy (translation +
/// rotation, LIGGGHTS's from its dump) at the last step. Asserted: the
/// mean over the seeds of KE_LIGGGHTS/KE_dembound − 1 within 3 % (the
/// issue's bound for the hopper; the seeds' spread is ~1 %), each seed
/// within 10 %. A friction coefficient off by 10 % moves the mean by more.
/// The lever arm (R − δ/2 against R) acts in every contact here (δ/R up
/// to ~4 % at 2 m/s): measured, LIGGGHTS's bed loses its energy slightly
/// faster early (−3.5 % mean at 2.9 ms, −2.4 % at 5.7 ms, +0.01 % at the end).
const BED: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.012]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 5.0e7
poisson_ratio = 0.22
[contact]
law = "hertz"
friction = 0.5
[[particles]]
random = { count = 150, radius = [0.3e-3, 0.6e-3], lower = [0.6e-3, 0.6e-3, 0.7e-3], upper = [9.4e-3, 9.4e-3, 0.0114], seed = SEED_A, velocity = [0.5, -0.3, -2.0] }
material = "grain"
[[particles]]
random = { count = 100, radius = [0.3e-3, 0.5e-3], lower = [0.6e-3, 0.6e-3, 0.7e-3], upper = [9.4e-3, 9.4e-3, 0.0114], seed = SEED_B, velocity = [-0.4, 0.2, 1.0] }
material = "glass"
[[wall]]
mesh = { file = "floor.stl", scale = 0.5, translate = [0.005, 0.005, 0.0] }
material = "glass"
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [1.0, 0.0, 0.0] }
material = "glass"
[[wall]]
plane = { point = [0.01, 0.0, 0.0], normal = [-1.0, 0.0, 0.0] }
material = "grain"
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
material = "grain"
[[wall]]
plane = { point = [0.0, 0.01, 0.0], normal = [0.0, -1.0, 0.0] }
material = "glass"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
eta = 0.02
steps = 20000
[output]
series_every = 20000
"#;

#[test]
fn frictional_bed_on_the_stl_floor_loses_its_energy_as_in_liggghts() {
    let what = "250-sphere frictional bed on the STL floor";
    if missing("liggghts", "liggghts", what) {
        return;
    }
    let density = |t: f64| if t == 1.0 { 1000.0 } else { 2500.0 };
    let mut ratios = Vec::new();
    for seed in [7u64, 11, 12, 13, 14] {
        let dir = tempfile::tempdir().expect("a temporary directory");
        std::fs::write(dir.path().join("floor.stl"), FLOOR_STL).expect("written");
        let text = BED
            .replace("SEED_A", &seed.to_string())
            .replace("SEED_B", &(seed + 50).to_string());
        let scene = dir.path().join("bed.toml");
        std::fs::write(&scene, &text).expect("written");
        let deck = dir.path().join("deck");
        run_liggghts(&scene, &deck);
        let dump = read_dump(&deck);
        let (step, rows) = dump.last().expect("a dump");
        assert_eq!(*step, 20000, "{what}: the last dump");
        let ke_l: f64 = rows
            .iter()
            .map(|r| {
                let m = density(r[1]) * 4.0 / 3.0 * std::f64::consts::PI * r[2].powi(3);
                let v2 = r[6] * r[6] + r[7] * r[7] + r[8] * r[8];
                let w2 = r[9] * r[9] + r[10] * r[10] + r[11] * r[11];
                0.5 * m * v2 + 0.5 * 0.4 * m * r[2] * r[2] * w2
            })
            .sum();
        let mut sim = simulation(&text, dir.path());
        let ke0 = sim.kinetic_energy();
        sim.step(20000);
        let ke_d = sim.kinetic_energy();
        let ratio = ke_l / ke_d - 1.0;
        eprintln!(
            "{what}, seed {seed}: kinetic energy at t = 0 {ke0:e} J, at step 20000 dembound \
             {ke_d:e} J, LIGGGHTS {ke_l:e} J (rel {ratio:+e})"
        );
        // Friction acted: most of the energy is gone.
        assert!(ke_d < 0.5 * ke0, "{what}: friction did not act");
        assert!(ratio.abs() < 0.1, "{what}, seed {seed}: {ratio:e}");
        ratios.push(ratio);
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    eprintln!("{what}: mean KE_LIGGGHTS/KE_dembound - 1 over the seeds {mean:+e}");
    assert!(mean.abs() < 0.03, "{what}: mean {mean:e}");
}
