//! `dembound compare DECK` on a hand-written LIGGGHTS scene deck whose
//! dump rows vary in size (no peer code needed): two spheres falling
//! freely from rest, an outlet box at the bottom; the "LIGGGHTS" dump has
//! both at step 0 and sphere 2 alone at step 1000 (sphere 1 deleted by the
//! deck's check at step 900, its log says), so every expected value is
//! known by construction or by free fall:
//! - the peer's spheres in the domain 2 then 1, discharged 0 then 1 (the
//!   log's first row at a dump step, the last before it otherwise), the
//!   mass one sphere's ρ 4/3 π R³;
//! - dembound's sphere 1 at step 1000 has fallen 0.49 mm of its 49 mm to
//!   the outlet (½ g t², t = 10 ms): still there, so the comparison by id
//!   ends at step 1000 naming sphere 1 as only in dembound;
//! - refusals, exit 2: an id the scene cannot have (naming it and the
//!   missing inlet), an id back after its deletion without an inlet,
//!   `--window-from` outside the run (naming the option, the value and
//!   the range).

mod common;

use common::{dembound, numbers, quantity};
use serde_json::Value;
use std::f64::consts::PI;
use std::path::Path;

const SCENE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.02, 0.02, 0.06]
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
spheres = [{ position = [0.005, 0.01, 0.05], radius = 1.0e-3 }, { position = [0.015, 0.01, 0.05], radius = 1.0e-3 }]
material = "glass"
[[outlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.02, 0.02, 0.001] } }
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 1.0e-5
steps = 2000
[output]
series_every = 1000
"#;

/// One dump row of `spheres` (id, z, vz), LIGGGHTS's columns.
fn row(step: u64, spheres: &[(u64, f64, f64)]) -> String {
    let mut s = format!(
        "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS mm mm mm\n0 0.02\n0 0.02\n0 0.06\n\
         ITEM: ATOMS id type radius x y z vx vy vz\n",
        spheres.len()
    );
    for (id, z, vz) in spheres {
        let x = if *id == 1 { 0.005 } else { 0.015 };
        s.push_str(&format!("{id} 1 0.001 {x} 0.01 {z} 0 0 {vz}\n"));
    }
    s
}

/// The deck: scene.toml, an (empty) in.liggghts, the dump and the log.
fn deck(dir: &Path, dump: &str) {
    std::fs::create_dir_all(dir).expect("a directory");
    std::fs::write(dir.join("scene.toml"), SCENE).expect("written");
    std::fs::write(dir.join("in.liggghts"), "# hand-written\n").expect("written");
    std::fs::write(dir.join("particles.dump"), dump).expect("written");
    let m = 2500.0 * 4.0 / 3.0 * PI * 1e-9;
    std::fs::write(
        dir.join("log.liggghts"),
        format!(
            "Step Time KinEng out0_n out0_m \n0 0 0 0 0 \n900 0.009 1e-6 0 0 \n\
             Loop time of 0.01 on 1 procs for 900 steps with 2 atoms, finish time x\n\
             Deleted 1 atoms, new total = 1\n\
             Step Time KinEng out0_n out0_m \n900 0.009 1e-6 1 {m:e} \n1000 0.01 1e-6 1 {m:e} \n\
             Loop time of 0.002 on 1 procs for 100 steps with 1 atoms, finish time x\n"
        ),
    )
    .expect("written");
}

#[test]
fn rows_of_varying_size_compare_by_id() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let dir = root.path().join("deck");
    // Free fall from rest: z = 0.05 − ½ g t², v = −g t at t = 10 ms.
    let t: f64 = 0.01;
    let (z, v) = (0.05 - 0.5 * 9.81 * t * t, -9.81 * t);
    deck(
        &dir,
        &format!(
            "{}{}",
            row(0, &[(1, 0.05, 0.0), (2, 0.05, 0.0)]),
            row(1000, &[(2, z, v)])
        ),
    );
    let out = dembound()
        .arg("compare")
        .arg(&dir)
        .arg("--json")
        .output()
        .expect("dembound runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        numbers(&quantity(&report, "free spheres in the domain")["code"]),
        [2.0, 1.0]
    );
    assert_eq!(
        numbers(&quantity(&report, "free spheres in the domain")["dembound"]),
        [2.0, 2.0]
    );
    assert_eq!(
        numbers(&quantity(&report, "spheres discharged")["code"]),
        [0.0, 1.0]
    );
    assert_eq!(
        numbers(&quantity(&report, "spheres discharged")["dembound"]),
        [0.0, 0.0]
    );
    let m = 2500.0 * 4.0 / 3.0 * PI * 1e-9;
    let mass = numbers(&quantity(&report, "mass discharged")["code"]);
    // The log's %e: 7 significant digits.
    assert!(
        mass[0] == 0.0 && (mass[1] - m).abs() <= 1e-6 * m,
        "{mass:?}"
    );
    // The peer's kinetic energy at step 1000 is sphere 2's alone, ½ m v².
    let k = numbers(&quantity(&report, "kinetic energy")["code"]);
    assert!((k[1] - 0.5 * m * v * v).abs() <= 1e-12 * k[1], "{k:?}");
    let end = &report["state_end"];
    // 1000 Δt: 0.01 s to a rounding.
    let at = end["at"].as_f64().expect("a time");
    assert!((at - 0.01).abs() < 1e-15, "{end}");
    assert_eq!(end["compared_until"].as_f64(), Some(0.0), "{end}");
    let reason = end["reason"].as_str().expect("a reason");
    assert!(
        reason.contains("ids only in LIGGGHTS: none; only in dembound: 1"),
        "{reason}"
    );
    // Step 0 is the same state in both: identical there.
    assert_eq!(
        numbers(&quantity(&report, "state: max |Δx| / R_min")["relative_difference"]),
        [0.0]
    );
}

fn refused(dir: &Path, extra: &[&str], words: &[&str]) {
    let out = dembound()
        .arg("compare")
        .arg(dir)
        .args(extra)
        .output()
        .expect("dembound runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    for w in words {
        assert!(err.contains(w), "`{w}` not in {err}");
    }
}

#[test]
fn ids_the_scene_cannot_have_and_a_window_outside_the_run_are_refused() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let dir = root.path().join("deck");
    deck(
        &dir,
        &row(0, &[(1, 0.05, 0.0), (2, 0.05, 0.0), (3, 0.03, 0.0)]),
    );
    refused(
        &dir,
        &[],
        &["step 0", "sphere id 3", "no inlet", "not this deck's run"],
    );
    deck(&dir, &row(0, &[(1, 0.05, 0.0), (2, 0.05, 0.0)]));
    refused(
        &dir,
        &["--window-from", "5"],
        &["--window-from = 5 s", "[0, 0.02) s"],
    );
    refused(&dir, &["--window-from=-0.1"], &["--window-from = -0.1 s"]);
    // Sphere 1 deleted by step 1000 and back at step 2000: only an inlet
    // gives an id again (LIGGGHTS's `Atom::tag_extend`), and this scene
    // has none (compare_rows.rs `RowReader`).
    deck(
        &dir,
        &format!(
            "{}{}{}",
            row(0, &[(1, 0.05, 0.0), (2, 0.05, 0.0)]),
            row(1000, &[(2, 0.049, 0.0)]),
            row(2000, &[(1, 0.04, 0.0), (2, 0.048, 0.0)])
        ),
    );
    refused(
        &dir,
        &[],
        &[
            "step 2000",
            "sphere id 1 is back",
            "no inlet",
            "not this deck's run",
        ],
    );
}
