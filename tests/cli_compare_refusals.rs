//! The refusals of `dembound compare DECK` that no other test reaches
//! (issue 32: every refusal names what is wrong and the code): a scene
//! deck's dump that cannot be read, a dump of another run (a step beyond
//! the scene, a sphere id 0, spheres missing where the scene has no
//! outlet, a sphere back after its deletion), a bad walls.txt, and a
//! bounce deck without its scenario or with a trace that does not parse.
//! Each exits 2 naming the file (or the sphere, the step) and the code.
//! The table of compare's refusals and the tests of the others:
//! docs/export-refusals.md. No peer code is run: the decks are exported
//! and their outputs written by hand.

mod common;

use common::dembound;
use std::path::Path;

/// Two free spheres over a plane floor, 100 steps; `extra` appended.
fn scene(extra: &str) -> String {
    format!(
        r#"[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.02]
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
[[particles]]
material = "glass"
spheres = [ {{ position = [0.003, 0.005, 0.005], radius = 1.0e-3 }}, {{ position = [0.007, 0.005, 0.005], radius = 1.0e-3 }} ]
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "glass"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 1.0e-5
steps = 100
[output]
series_every = 50
{extra}"#
    )
}

/// Exports `text` to `code` into `root/deck` (exit 0 asserted).
fn export(root: &Path, code: &str, text: &str) -> std::path::PathBuf {
    let path = root.join("s.toml");
    std::fs::write(&path, text).expect("written");
    let deck = root.join("deck");
    let o = dembound()
        .args(["export", code])
        .arg(&path)
        .arg("--out")
        .arg(&deck)
        .output()
        .expect("dembound runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    deck
}

/// A LAMMPS dump row at `step` of the spheres `ids` where the scene has
/// them (their z unchanged: only the ids and the step matter here).
fn row(step: u64, ids: &[u64]) -> String {
    let mut s = format!(
        "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS mm mm mm\n\
         0 0.01\n0 0.01\n0 0.02\nITEM: ATOMS id x y z vx vy vz omegax omegay omegaz radius mass\n",
        ids.len()
    );
    for &id in ids {
        let x = if id == 1 { 0.003 } else { 0.007 };
        s.push_str(&format!(
            "{id} {x} 0.005 0.005 0 0 0 0 0 0 0.001 1.0471975511965979e-5\n"
        ));
    }
    s
}

/// `dembound compare deck ARGS` exits 2 and stderr holds every one of
/// `words`.
fn refused(deck: &Path, args: &[&str], words: &[&str]) {
    let o = dembound()
        .arg("compare")
        .arg(deck)
        .args(args)
        .output()
        .expect("dembound runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{words:?}: {err}");
    for w in words {
        assert!(err.contains(w), "`{w}` not in {err}");
    }
}

#[test]
fn scene_deck_refusals_name_the_file_and_the_code() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let deck = export(root.path(), "lammps", &scene(""));
    let dump = deck.join("particles.dump");
    // Not run yet: the dump and the command that writes it.
    refused(
        &deck,
        &[],
        &["particles.dump", "LAMMPS", "lmp -in in.lammps"],
    );
    // A dump cut short: its file, its line, the code.
    std::fs::write(&dump, "ITEM: TIMESTEP\n0\n").expect("written");
    refused(&deck, &[], &["particles.dump", "LAMMPS", "NUMBER OF ATOMS"]);
    // A row past the scene's 100 steps.
    std::fs::write(&dump, row(0, &[1, 2]) + &row(150, &[1, 2])).expect("written");
    refused(&deck, &[], &["step 150", "100 steps", "LAMMPS"]);
    // A sphere id 0.
    std::fs::write(&dump, row(0, &[1, 2]).replace("\n1 0.003", "\n0 0.003")).expect("written");
    refused(&deck, &[], &["sphere id 0", "LAMMPS"]);
    // A sphere missing where the scene has no outlet.
    std::fs::write(&dump, row(0, &[1, 2]) + &row(50, &[2])).expect("written");
    refused(&deck, &[], &["1 spheres", "no outlet", "LAMMPS"]);
    // walls.txt that does not parse.
    std::fs::write(&dump, row(0, &[1, 2]) + &row(50, &[1, 2])).expect("written");
    std::fs::write(deck.join("walls.txt"), "# step fx fy fz\n50 x y z\n").expect("written");
    std::fs::remove_file(deck.join("walls_mean.txt")).ok();
    refused(&deck, &[], &["walls.txt", "LAMMPS"]);
}

#[test]
fn a_sphere_back_after_its_deletion_is_refused() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let outlet =
        "[[outlet]]\nregion = { box = { lower = [0.0, 0.0, 0.0], upper = [0.01, 0.01, 0.002] } }\n";
    let deck = export(root.path(), "lammps", &scene(outlet));
    std::fs::write(
        deck.join("particles.dump"),
        row(0, &[1, 2]) + &row(50, &[2]) + &row(100, &[1, 2]),
    )
    .expect("written");
    refused(&deck, &[], &["sphere id 1", "back after", "LAMMPS"]);
}

#[test]
fn a_liggghts_deck_not_run_names_liggghts() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let deck = export(root.path(), "liggghts", &scene(""));
    refused(&deck, &[], &["particles.dump", "LIGGGHTS", "liggghts -in"]);
}

#[test]
fn bounce_deck_refusals_name_the_file_and_the_code() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let deck = root.path().join("deck");
    let o = dembound()
        .args(["export", "lammps", "--out"])
        .arg(&deck)
        .output()
        .expect("dembound runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // A trace that does not parse: the file and the code.
    std::fs::write(deck.join("trace.txt"), "# time_s overlap_m\n0 x\n").expect("written");
    refused(&deck, &[], &["trace.txt", "LAMMPS"]);
    // No scenario.toml: the option that gives it, and the code.
    std::fs::remove_file(deck.join("scenario.toml")).expect("removed");
    refused(&deck, &[], &["scenario.toml", "--scenario", "LAMMPS"]);
}

/// A LIGGGHTS dump row (no mass column) of `(id, type)` spheres, with or
/// without the radius column.
fn liggghts_row(step: u64, spheres: &[(u64, u64)], radius: bool) -> String {
    let mut s = format!(
        "ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS mm mm mm\n\
         0 0.01\n0 0.01\n0 0.02\nITEM: ATOMS id type {}x y z vx vy vz\n",
        spheres.len(),
        if radius { "radius " } else { "" }
    );
    for (id, kind) in spheres {
        let x = 0.001 + 0.002 * *id as f64;
        let r = if radius { "0.001 " } else { "" };
        s.push_str(&format!("{id} {kind} {r}{x} 0.005 0.005 0 0 0\n"));
    }
    s
}

/// An inserted sphere the scene's materials cannot give a mass: of a type
/// beyond them, or without a radius column. Exit 2 naming the step, the
/// id and the code.
#[test]
fn inserted_spheres_without_a_mass_are_refused() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let inlet = "[[inlet]]\n\
                 region = { box = { lower = [0.001, 0.001, 0.016], upper = [0.009, 0.009, 0.019] } }\n\
                 rate = { number = 100.0 }\n\
                 size = { fixed = 1.0e-3 }\n\
                 material = \"glass\"\n";
    let deck = export(root.path(), "liggghts", &scene(inlet));
    let dump = deck.join("particles.dump");
    let two = [(1, 1), (2, 1)];
    std::fs::write(
        &dump,
        liggghts_row(0, &two, true) + &liggghts_row(50, &[(1, 1), (2, 1), (3, 9)], true),
    )
    .expect("written");
    refused(&deck, &[], &["step 50", "sphere id 3", "type", "LIGGGHTS"]);
    std::fs::write(
        &dump,
        liggghts_row(0, &two, false) + &liggghts_row(50, &[(1, 1), (2, 1), (3, 1)], false),
    )
    .expect("written");
    refused(
        &deck,
        &[],
        &["step 50", "sphere id 3", "radius", "LIGGGHTS"],
    );
}
