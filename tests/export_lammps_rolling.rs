//! Rolling friction of sphere pairs and on a plane against LAMMPS's
//! `pair granular … rolling sds` and `fix wall/gran granular … rolling sds`
//! (issue 32's chute, examples/compare/chute.toml, isolated): a sphere
//! dropped off-centre onto a frozen one rolls over and off it (a
//! sphere–sphere contact with tangential and rolling springs for about
//! 16 ms; k_r = 2.25 k μ_r² R_eff² = 7.0e-8 N m/rad reaches its limit
//! μ_r R_eff F_n ≈ 1.3e-10 N m after 2e-3 rad, and the sphere turns through
//! radians, so the limit acts), and a
//! sphere thrown along the floor slides, rolls and strikes a third. Hooke
//! k = 50 N/m, μ = 0.5, μ_r = 0.1, undamped, `torque_arm =
//! "contact_point"` (LAMMPS's arm, docs/export-lammps.md), 20,000 steps of
//! 2 µs. The two codes are the same model here, so the states must agree
//! to round-off; and the rolling springs matter: the same scene without
//! them parts from LAMMPS's run by far more than that (the test can fail).
//!
//! Without `lmp` on PATH the test fails under CI and skips elsewhere.

mod common;

use common::peer::{export_lammps, missing, read_dump, run_lmp};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::Simulation;

/// Box 12 × 12 × 10 mm, a plane floor; sphere 0 frozen on it, sphere 1
/// 1.0002 mm from it and 0.2 mm off its axis (it falls into the contact and
/// rolls off), sphere 2 thrown at 0.05 m/s towards sphere 3 (contact at
/// ~9 ms). R = 0.5 mm, ρ = 1000 kg/m³.
fn scene(rolling: f64) -> String {
    format!(
        r#"[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.012, 0.012, 0.01]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = {{ hooke = 50.0 }}
friction = 0.5
rolling_friction = {rolling:?}
torque_arm = "contact_point"
[[particles]]
spheres = [{{ position = [0.005, 0.006, 0.0005], radius = 0.5e-3 }}]
material = "grain"
fixed = true
[[particles]]
spheres = [{{ position = [0.0052, 0.006, 0.00148], radius = 0.5e-3 }}, {{ position = [0.002, 0.003, 0.0005], radius = 0.5e-3, velocity = [0.05, 0.0, 0.0] }}, {{ position = [0.0035, 0.0032, 0.0005], radius = 0.5e-3 }}]
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2.0e-6
steps = 20000
[output]
series_every = 500
"#
    )
}

/// The largest difference between LAMMPS's dumped rows and dembound's run
/// of `text` at the same steps, over the free spheres: |Δx| / R, and |Δv|,
/// |Δω| over the largest |v|, |ω| of that row.
fn worst_against(dump: &std::collections::BTreeMap<u64, common::peer::State>, text: &str) -> f64 {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let file = config::load(text, "rolling", &[]).expect("a valid scene");
    let setup = resolve(&file, dir.path()).expect("resolves").setup;
    let mut sim = Simulation::new(setup, 1).expect("runs");
    let fixed = sim.fixed();
    let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let diff = |a: &[f64], b: [f64; 3]| norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
    let mut worst = 0.0f64;
    for (&step, row) in dump {
        sim.step(step - sim.steps_done());
        let (x, v, w) = (sim.positions(), sim.velocities(), sim.angular_velocities());
        let free: Vec<usize> = (0..x.len()).filter(|&i| !fixed[i]).collect();
        let vmax = free.iter().map(|&i| norm(v[i])).fold(0.0, f64::max);
        let wmax = free.iter().map(|&i| norm(w[i])).fold(0.0, f64::max);
        for &i in &free {
            worst = worst.max(diff(&row[i][0..3], x[i]) / 0.5e-3);
            if vmax > 0.0 {
                worst = worst.max(diff(&row[i][3..6], v[i]) / vmax);
            }
            if wmax > 0.0 {
                worst = worst.max(diff(&row[i][6..9], w[i]) / wmax);
            }
        }
    }
    worst
}

#[test]
fn rolling_sphere_pairs_and_plane_agree_with_lammps_rolling_sds() {
    if missing("lmp", "lammps", "rolling sds against LAMMPS") {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let text = scene(0.1);
    let path = dir.path().join("rolling.toml");
    std::fs::write(&path, &text).expect("written");
    let deck = dir.path().join("deck");
    export_lammps(&path, &[] as &[&str], &deck, "rolling");
    // A rolling scene's deck does not sort atoms: sorting hands contacts to
    // their other sphere, and LAMMPS then flips the rolling spring's sign
    // (docs/export-lammps.md, "Rolling history in LAMMPS").
    let input = std::fs::read_to_string(deck.join("in.lammps")).expect("in.lammps");
    assert!(input.contains("atom_modify  sort 0 0.0"), "{input}");
    run_lmp(&deck, "rolling");
    let dump = read_dump(&deck.join("particles.dump"));
    // 41 rows (every 500 steps from 0 to 20000), or the test shows nothing.
    assert_eq!(dump.len(), 41);
    // The same model: only the floating-point order differs (~1e-16 a
    // step), amplified by a few contacts over 40 ms (measured 2.6e-13 of
    // R for the positions); 1e-9 is issue 32's "identical" bar.
    let same = worst_against(&dump, &text);
    assert!(
        same <= 1e-9,
        "rolling sds: dembound parts from LAMMPS by {same:e}"
    );
    // Without the rolling springs the run is another one: the spins of the
    // sphere rolling over the frozen one and of the thrown one differ by
    // far more than 1e-6 of their size.
    let without = worst_against(&dump, &scene(0.0));
    assert!(
        without > 1e-6,
        "the rolling springs did not matter: {without:e}"
    );
}
