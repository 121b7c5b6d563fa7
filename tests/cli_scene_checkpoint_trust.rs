//! `dembound scene --restart` trusts nothing it is not sure of (issue 24):
//! a checkpoint with any byte changed, one of an older format, one written
//! by another scene (density, radius) and a run length shorter than the
//! steps done are each refused with exit 2, naming what differs, and no
//! output directory is made. (A matching restart continuing bit for bit
//! is `cli_scene::outputs_are_deterministic_and_restarts_continue_exactly`.)

mod common;

use common::{dembound, grain_floor_scene};
use std::path::{Path, PathBuf};

/// 27 spheres (3 × 3 × 3, R = 0.5 mm) falling at 1 m/s onto a plane
/// floor, damped; `steps` steps of 2 µs. The lowest spheres start 0.1 mm
/// above the floor: in contact from about step 50, so that a checkpoint at
/// step 100 holds live contact histories.
fn scene_file(dir: &Path, name: &str, density: f64, radius: f64, steps: u64) -> PathBuf {
    grain_floor_scene(
        dir,
        name,
        "[0.004, 0.004, 0.006]",
        density,
        "law = \"hertz\"\ndamping = \"tsuji\"\nrestitution = 0.5",
        &format!(
            "lattice = {{ counts = [3, 3, 3], spacing = [1.2e-3, 1.2e-3, 1.2e-3], origin = [0.8e-3, 0.8e-3, 0.6e-3], radius = {radius:?}, velocity = [0.0, 0.0, -1.0] }}"
        ),
        &format!("scheme = \"verlet\"\ndt = 2.0e-6\nsteps = {steps}"),
    )
}

/// Runs the scene to write its checkpoint into `dir/first`; returns the
/// checkpoint's path.
fn first_run(dir: &Path, scene: &Path) -> PathBuf {
    let out = dir.join("first");
    let o = dembound()
        .args(["scene", "-q"])
        .arg(scene)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out.join("checkpoint.cbor")
}

/// `dembound scene SCENE --restart CHECKPOINT --out DIR/again`: exit code,
/// stderr, and whether the output directory exists.
fn restart(dir: &Path, scene: &Path, checkpoint: &Path) -> (Option<i32>, String, bool) {
    let out = dir.join("again");
    let o = dembound()
        .args(["scene", "-q"])
        .arg(scene)
        .arg("--restart")
        .arg(checkpoint)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        out.exists(),
    )
}

/// Restarts `scene` from `checkpoint` and asserts it is refused: exit 2,
/// every one of `needles` in stderr, no output directory.
fn restart_refused(dir: &Path, scene: &Path, checkpoint: &Path, needles: &[&str]) {
    let (code, err, made) = restart(dir, scene, checkpoint);
    assert_eq!(code, Some(2), "{err}");
    assert!(needles.iter().all(|n| err.contains(n)), "{err}");
    assert!(!made);
}

#[test]
fn every_flipped_bit_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = scene_file(dir, "s.toml", 1000.0, 0.5e-3, 100);
    let longer = scene_file(dir, "long.toml", 1000.0, 0.5e-3, 200);
    let good = std::fs::read(first_run(dir, &scene)).unwrap();
    // The untouched file continues (so a refusal below is the flip's).
    let copy = dir.join("copy.cbor");
    std::fs::write(&copy, &good).unwrap();
    let (code, err, _) = restart(dir, &longer, &copy);
    assert_eq!(code, Some(0), "{err}");
    std::fs::remove_dir_all(dir.join("again")).unwrap();

    // 17 positions: the magic (bytes 0–25), the version (26–29), the
    // payload's first bytes, its middle (positions, velocities) and its
    // last byte, the trailer's length (n − 40 … n − 33) and checksum (the
    // last 32 bytes); each bit of a byte in turn.
    let n = good.len();
    let positions = [
        0,
        10,
        26,
        29,
        30,
        34,
        60,
        80,
        n / 4,
        n / 3,
        n / 2,
        2 * n / 3,
        n - 41,
        n - 40,
        n - 33,
        n - 20,
        n - 1,
    ];
    for (k, &at) in positions.iter().enumerate() {
        let mut bad = good.clone();
        bad[at] ^= 1 << (k % 8);
        let path = dir.join(format!("flip{k}.cbor"));
        std::fs::write(&path, &bad).unwrap();
        let (code, err, made) = restart(dir, &longer, &path);
        assert_eq!(code, Some(2), "byte {at} of {n}, bit {}: {err}", k % 8);
        assert!(
            err.contains("damaged") || err.contains("not a dembound") || err.contains("version"),
            "byte {at}: {err}"
        );
        assert!(!made, "byte {at}: an output directory was made");
    }
    // Cut short.
    let path = dir.join("cut.cbor");
    std::fs::write(&path, &good[..n - 1]).unwrap();
    restart_refused(dir, &longer, &path, &["cut"]);
}

#[test]
fn another_density_or_radius_is_refused_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let checkpoint = first_run(dir, &scene_file(dir, "s.toml", 1000.0, 0.5e-3, 100));
    let denser = scene_file(dir, "denser.toml", 2500.0, 0.5e-3, 200);
    restart_refused(
        dir,
        &denser,
        &checkpoint,
        &["material.0.density", "1000.0", "2500.0"],
    );
    let larger = scene_file(dir, "larger.toml", 1000.0, 0.55e-3, 200);
    restart_refused(
        dir,
        &larger,
        &checkpoint,
        &["sphere 0", "radius", "0.00055"],
    );
}

#[test]
fn fewer_steps_than_done_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let checkpoint = first_run(dir, &scene_file(dir, "s.toml", 1000.0, 0.5e-3, 100));
    let shorter = scene_file(dir, "short.toml", 1000.0, 0.5e-3, 60);
    restart_refused(
        dir,
        &shorter,
        &checkpoint,
        &["integration.steps = 60", "100 steps"],
    );
    // The same length runs no step and is accepted (the run's end again).
    let same = scene_file(dir, "same.toml", 1000.0, 0.5e-3, 100);
    let (code, err, _) = restart(dir, &same, &checkpoint);
    assert_eq!(code, Some(0), "{err}");
}

#[test]
fn a_checkpoint_of_the_old_format_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let scene = scene_file(dir, "s.toml", 1000.0, 0.5e-3, 100);
    // Version 1 was a bare CBOR map beginning with the format and the
    // version (then the scene and the state).
    let mut old = vec![0xa2];
    for (key, value) in [("format", None), ("version", Some(1u8))] {
        old.push(0x60 + key.len() as u8);
        old.extend_from_slice(key.as_bytes());
        match value {
            None => {
                let text = "dembound-scene checkpoint";
                old.push(0x78);
                old.push(text.len() as u8);
                old.extend_from_slice(text.as_bytes());
            }
            Some(v) => old.push(v),
        }
    }
    let path = dir.join("old.cbor");
    std::fs::write(&path, &old).unwrap();
    restart_refused(dir, &scene, &path, &["version 1", "versions 2 to 4"]);
}
