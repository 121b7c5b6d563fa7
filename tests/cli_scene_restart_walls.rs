//! A restart into a scene whose walls changed (issue 28): a settled bed
//! (Hertz + Tsuji, Mindlin friction: every floor contact holds springs)
//! on a plug plane over a lower floor. Removing the plug from the scene
//! file continues the run (the bed falls), with one line naming the plug
//! and the spheres whose contact state went; adding a wall that touches
//! nothing continues with the trajectory of the restart without it, to the
//! bit; a wall added into the bed books its overlaps' energy as gate
//! energy (the dissipated energy does not jump); the refusals that still
//! mean something (another body count, a moving wall dropped) exit 2.

mod common;

use common::{exact_number, scene_text};
use dembound_scene::io::checkpoint;
use dembound_scene::io::config;
use dembound_scene::io::resolve::resolve;
use dembound_scene::Simulation;
use std::path::Path;

const PLUG: &str = "[[wall]]\nplane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }\nmaterial = \"grain\"\n";
const LOWER: &str = "[[wall]]\nplane = { point = [0.0, 0.0, -0.002], normal = [0.0, 0.0, 1.0] }\nmaterial = \"grain\"\n";

/// 3 × 3 × 3 spheres (R = 0.5 mm) in a 4.2 mm box (odd layers shifted by half a spacing); walls 0–3 the sides,
/// then `walls` (the plug, the lower floor, …) in that order; `steps` of
/// 5 µs.
fn scene(walls: &[&str], steps: u64) -> String {
    let mut text = format!(
        r#"
[domain]
lower = [0.0, 0.0, -0.003]
upper = [0.0042, 0.0042, 0.006]
periodic = [false, false, false]

[[material]]
name = "grain"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
friction = 0.5

[[particles]]
lattice = {{ counts = [3, 3, 3], spacing = [1.2e-3, 1.2e-3, 1.05e-3], origin = [0.6e-3, 0.6e-3, 0.52e-3], radius = 0.5e-3 }}
material = "grain"

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
scheme = "verlet"
dt = 5.0e-6
steps = {steps}

[output]
every = 1000
series_every = 100

[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [1.0, 0.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0042, 0.0, 0.0], normal = [-1.0, 0.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0042, 0.0], normal = [0.0, -1.0, 0.0] }}
material = "grain"
"#
    );
    for w in walls {
        text.push_str(w);
    }
    text
}

/// Settles the bed on the plug for 20 ms: the checkpoint in `dir/out`.
fn settle(dir: &Path, walls: &[&str]) -> std::path::PathBuf {
    settle_json(dir, walls).0
}

/// [`settle`], with the run's summary.
fn settle_json(dir: &Path, walls: &[&str]) -> (std::path::PathBuf, serde_json::Value) {
    let out = dir.join("out");
    let (code, stdout, stderr) = scene_text(
        &scene(walls, 4000),
        dir,
        &["--json", "-q", "--out", out.to_str().unwrap()],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    // The bed rests on the plug (its bottom layer, less a sphere or two
    // held up by the others).
    assert!(v["wall_contacts"].as_u64().unwrap() >= 6, "{v}");
    (out.join("checkpoint.cbor"), v)
}

#[test]
fn removing_the_plug_through_a_restart_drops_its_contacts_and_names_it() {
    let root = tempfile::tempdir().unwrap();
    let (cp, settled) = settle_json(root.path(), &[PLUG, LOWER]);
    // The checkpoint holds springs of the spheres on the plug (wall 4,
    // surface 4): the bottom layer's.
    let saved = checkpoint::read(&cp).unwrap().state;
    let on_plug: std::collections::BTreeSet<u32> = saved
        .plane_shear
        .iter()
        .filter(|r| r.1 == 4)
        .map(|r| r.0)
        .collect();
    assert!(on_plug.len() >= 6, "{on_plug:?}");
    let d = root.path().join("open");
    std::fs::create_dir_all(&d).unwrap();
    let (code, stdout, stderr) = scene_text(
        &scene(&[LOWER], 20_000),
        &d,
        &["--json", "-q", "--restart", cp.to_str().unwrap()],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let notes: Vec<&str> = stderr
        .lines()
        .filter(|l| l.starts_with("restart:"))
        .collect();
    assert_eq!(notes.len(), 1, "{stderr}");
    assert!(
        notes[0].contains("wall[4] (Plane { point: [0.0, 0.0, 0.0], normal: [0.0, 0.0, 1.0]")
            && notes[0].contains(&format!("of {} spheres", on_plug.len()))
            && notes[0].contains("not in the scene"),
        "{stderr}"
    );
    // The bed fell 2 mm onto the lower floor (now wall 4): its potential
    // energy dropped by M g · 2 mm (M: 27 spheres of 2500 kg/m³,
    // R = 0.5 mm), and by less than M g (2 mm + R) (the bed may pack
    // tighter on landing, not by more than a radius).
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["wall_forces"].as_array().unwrap().len(), 5);
    assert!(v["wall_forces"][4][2].as_f64().unwrap() < 0.0, "{v}");
    let mass = 27.0 * 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.5e-3f64.powi(3);
    let drop =
        settled["potential_energy"].as_f64().unwrap() - v["potential_energy"].as_f64().unwrap();
    let expected = mass * 9.81 * 0.002;
    assert!(
        drop > 0.98 * expected && drop < expected * 2.5 / 2.0,
        "{drop} J vs {expected} J"
    );
}

/// A lid added high above the bed touches nothing: the restart with it
/// continues with the bits of the restart without it; the note names it.
#[test]
fn adding_a_wall_that_touches_nothing_keeps_the_trajectory() {
    let root = tempfile::tempdir().unwrap();
    let cp = settle(root.path(), &[PLUG, LOWER]);
    let lid = "[[wall]]\nplane = { point = [0.0, 0.0, 0.006], normal = [0.0, 0.0, -1.0] }\nmaterial = \"grain\"\n";
    let run = |walls: &[&str], name: &str| {
        let d = root.path().join(name);
        std::fs::create_dir_all(&d).unwrap();
        let (code, stdout, stderr) = scene_text(
            &scene(walls, 6000),
            &d,
            &["--json", "-q", "--restart", cp.to_str().unwrap()],
        );
        assert_eq!(code, Some(0), "{stderr}");
        (stdout, stderr)
    };
    let (same, quiet) = run(&[PLUG, LOWER], "same");
    assert!(!quiet.contains("restart:"), "{quiet}");
    let (lidded, notes) = run(&[PLUG, LOWER, lid], "lid");
    assert!(
        notes.contains("restart: the scene's wall[6] (Plane { point: [0.0, 0.0, 0.006]")
            && notes.contains("not in the checkpoint"),
        "{notes}"
    );
    for key in ["kinetic_energy", "elastic_energy", "potential_energy"] {
        assert_eq!(
            exact_number(&lidded, key).to_bits(),
            exact_number(&same, key).to_bits(),
            "{key}"
        );
    }
    // The lid in another place of the list: the same.
    let (first, _) = run(&[lid, PLUG, LOWER], "lid_first");
    assert_eq!(
        exact_number(&first, "kinetic_energy").to_bits(),
        exact_number(&same, "kinetic_energy").to_bits()
    );
}

/// A floor added 0.1 mm into the settled bed through a restart: its
/// overlaps' elastic energy is booked as gate energy at the restart, so the
/// dissipated energy at the restart step is the checkpoint's (to rounding)
/// and the guard lets the run go on.
#[test]
fn a_wall_added_into_the_bed_books_its_overlaps() {
    let root = tempfile::tempdir().unwrap();
    let cp = settle(root.path(), &[PLUG, LOWER]);
    let saved = checkpoint::read(&cp).unwrap().state;
    let setup = |walls: &[&str]| {
        let file = config::load(&scene(walls, 6000), "x.toml", &[]).unwrap();
        resolve(&file, Path::new(".")).unwrap().setup
    };
    let before = Simulation::restore(setup(&[PLUG, LOWER]), &saved, 1)
        .unwrap()
        .observe();
    let raised = "[[wall]]\nplane = { point = [0.0, 0.0, 0.0001], normal = [0.0, 0.0, 1.0] }\nmaterial = \"grain\"\n";
    let mut sim = Simulation::restore(setup(&[PLUG, LOWER, raised]), &saved, 1).unwrap();
    assert_eq!(sim.restart_notes().len(), 1);
    let after = sim.observe();
    let gate = after.gate_energy.expect("booked");
    // The new floor's overlaps: 0.1 mm on 9 spheres, Hertz.
    assert!(gate < 0.0, "{gate}");
    let added = after.elastic_energy - before.elastic_energy;
    assert!((added + gate).abs() < 1e-9 * added, "{added} {gate}");
    let scale = before.kinetic_energy + before.elastic_energy + before.potential_energy.abs();
    assert!(
        (after.dissipated_energy - before.dissipated_energy).abs() < 1e-12 * scale,
        "{} {}",
        after.dissipated_energy,
        before.dissipated_energy
    );
    sim.step_checked(2000).unwrap();
    sim.observe_checked().expect("the guard lets it run");
}

/// What still does not fit is refused, exit 2, naming it: another number
/// of spheres; a moving wall dropped.
#[test]
fn restarts_that_do_not_fit_still_exit_2() {
    let root = tempfile::tempdir().unwrap();
    let cp = settle(root.path(), &[PLUG, LOWER]);
    let d = root.path().join("r");
    std::fs::create_dir_all(&d).unwrap();
    let more = scene(&[PLUG, LOWER], 6000).replace("counts = [3, 3, 3]", "counts = [3, 3, 2]");
    let (code, _, stderr) = scene_text(&more, &d, &["--restart", cp.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("it holds 27 bodies, the scene 18"),
        "{stderr}"
    );
    // A shaking lower floor in the checkpoint, fixed in the scene.
    let shaker =
        format!("{LOWER}oscillation = {{ amplitude = [0.0, 0.0, 1e-5], frequency = 50.0 }}\n");
    let e = root.path().join("shake");
    std::fs::create_dir_all(&e).unwrap();
    let cp2 = settle(&e, &[PLUG, &shaker]);
    let (code, _, stderr) = scene_text(
        &scene(&[PLUG, LOWER], 6000),
        &d,
        &["--restart", cp2.to_str().unwrap()],
    );
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("wall[5]") && stderr.contains("moves (motion or servo)"),
        "{stderr}"
    );
}
