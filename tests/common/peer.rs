//! Running the other codes (LAMMPS, LIGGGHTS, Yade) on exported decks:
//! finding them on PATH, the CI rule for a missing one, exporting a scene
//! and running `lmp` on its deck.

use super::dembound;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `name` on PATH, if any.
pub fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// Whether the peer codes are required (a missing one fails the test):
/// the environment variable `CI` set to anything but empty, `0` or `false`.
pub fn codes_required(ci: Option<&str>) -> bool {
    ci.is_some_and(|v| !matches!(v.trim().to_ascii_lowercase().as_str(), "" | "0" | "false"))
}

/// True when `bin` (Debian package `code`) is missing, so the caller must
/// skip `what`: says so on stderr. Under CI it panics instead, so CI cannot
/// pass without running the peer code.
pub fn missing(bin: &str, code: &str, what: &str) -> bool {
    let required = codes_required(std::env::var("CI").ok().as_deref());
    on_path(bin).is_none() && skip_or_fail(bin, code, what, required)
}

/// The missing-code branch of `missing`: fails when `required`, else says
/// why the check is skipped and returns true.
pub fn skip_or_fail(bin: &str, code: &str, what: &str, required: bool) -> bool {
    assert!(
        !required,
        "`{bin}` is not on PATH (Debian package {code}) and CI is set: {what} must be \
         checked under CI (.ci/run installs it)"
    );
    eprintln!(
        "SKIPPED: `{bin}` is not on PATH (Debian package {code}; .ci/run installs it), \
         so {what} is not checked here"
    );
    true
}

/// `dembound export lammps SCENE --set S… --out DECK`, expecting success
/// (`what` names the case in the failure message).
pub fn export_lammps<S: AsRef<str>>(scene: &Path, sets: &[S], deck: &Path, what: &str) {
    let out = dembound()
        .args(["export", "lammps"])
        .arg(scene)
        .args(sets.iter().flat_map(|s| ["--set", s.as_ref()]))
        .arg("--out")
        .arg(deck)
        .output()
        .expect("dembound runs");
    assert!(
        out.status.success(),
        "{what}: export failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `lmp` on the deck in `deck` (its log in `log.lammps`), expecting
/// success.
pub fn run_lmp(deck: &Path, what: &str) {
    let ran = Command::new("lmp")
        .args(["-in", "in.lammps", "-log", "log.lammps"])
        .current_dir(deck)
        .output()
        .expect("lmp runs");
    assert!(
        ran.status.success(),
        "{what}: lmp failed:\n{}",
        String::from_utf8_lossy(&ran.stdout)
    );
}

/// The lattice-drop packing of 384 spheres (8 × 8 × 6, r = 0.5 mm, E =
/// 1e7 Pa, odd layers shifted) in a 10.2 mm box between four plane side
/// walls of their material, thrown at `velocity`, under gravity: the
/// `[contact]` body `contact`, the floor's `[[wall]]` body `floor`,
/// `steps` Verlet steps of 2 µs, then `tail` (more tables, or nothing).
pub fn lattice_bed(contact: &str, velocity: &str, floor: &str, steps: u64, tail: &str) -> String {
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.0102, 0.0102, 0.02]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[[material]]
name = "steel"
density = 7800.0
youngs_modulus = 2.0e11
poisson_ratio = 0.3
[contact]
{contact}
[[particles]]
lattice = {{ counts = [8, 8, 6], spacing = [1.2e-3, 1.2e-3, 0.54e-3], origin = [0.6e-3, 0.6e-3, 0.505e-3], radius = 0.5e-3, velocity = {velocity} }}
material = "grain"
[[wall]]
{floor}
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [1.0, 0.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0102, 0.0, 0.0], normal = [-1.0, 0.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
material = "grain"
[[wall]]
plane = {{ point = [0.0, 0.0102, 0.0], normal = [0.0, -1.0, 0.0] }}
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2.0e-6
steps = {steps}
{tail}"#
    )
}

/// `lattice_bed`'s floor body for a plane of steel under the bed.
pub const STEEL_PLANE_FLOOR: &str =
    "plane = { point = [0.0051, 0.0051, 0.0], normal = [0.0, 0.0, 1.0] }\nmaterial = \"steel\"";

/// Exports `scene` to `deck` with `dembound export liggghts` and runs
/// LIGGGHTS there (`in.liggghts`, its log in `log.liggghts`).
pub fn run_liggghts(scene: &Path, deck: &Path) {
    export_then_run(
        "liggghts",
        scene,
        deck,
        &["-in", "in.liggghts", "-log", "log.liggghts"],
    );
}

/// Exports `scene` to `deck` with `dembound export yade` and runs Yade
/// there (`yade -n -j1 -x scene.py`: one thread, no GUI).
pub fn run_yade(scene: &Path, deck: &Path) {
    export_then_run("yade", scene, deck, &["-n", "-j1", "-x", "scene.py"]);
}

/// `dembound export CODE scene --out deck`, then the code's binary (named
/// as the code) with `args` in `deck`; each must succeed.
fn export_then_run(code: &str, scene: &Path, deck: &Path, args: &[&str]) {
    let o = dembound()
        .args(["export", code])
        .arg(scene)
        .arg("--out")
        .arg(deck)
        .output()
        .expect("dembound runs");
    assert!(
        o.status.success(),
        "export failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let ran = Command::new(code)
        .args(args)
        .current_dir(deck)
        .output()
        .expect("the code runs");
    assert!(
        ran.status.success(),
        "{code} failed: {}{}",
        String::from_utf8_lossy(&ran.stdout),
        String::from_utf8_lossy(&ran.stderr)
    );
}

/// A LIGGGHTS deck's particles.dump: per dump, (step, rows of id type
/// radius x y z vx vy vz [ωx ωy ωz]) sorted by id.
pub fn read_liggghts_dump(deck: &Path) -> Vec<(u64, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(deck.join("particles.dump")).expect("particles.dump");
    text.split("ITEM: TIMESTEP\n")
        .skip(1)
        .map(|block| {
            let mut lines = block.lines();
            let step: u64 = lines
                .next()
                .expect("a step")
                .trim()
                .parse()
                .expect("a step");
            let mut rows: Vec<Vec<f64>> = lines
                .skip_while(|l| !l.starts_with("ITEM: ATOMS"))
                .skip(1)
                .map(|l| {
                    l.split_whitespace()
                        .map(|w| w.parse().expect("a number"))
                        .collect()
                })
                .collect();
            rows.sort_by(|a, b| a[0].total_cmp(&b[0]));
            (step, rows)
        })
        .collect()
}

/// One row of a LAMMPS scene deck's `particles.dump`: per sphere (x, v, ω).
pub type State = Vec<[f64; 9]>;

/// `particles.dump` (a LAMMPS or Yade scene deck's): step → the spheres'
/// states in id order.
pub fn read_dump(path: &Path) -> BTreeMap<u64, State> {
    let text = std::fs::read_to_string(path).expect("particles.dump");
    let mut rows = BTreeMap::new();
    let mut lines = text.lines();
    while let Some(l) = lines.next() {
        if !l.starts_with("ITEM: TIMESTEP") {
            continue;
        }
        let number =
            |l: Option<&str>| -> u64 { l.expect("a line").trim().parse().expect("a count") };
        let step = number(lines.next());
        lines.next();
        let n = number(lines.next()) as usize;
        // LAMMPS writes the box (4 lines) before the ATOMS header, Yade's
        // deck does not.
        for l in lines.by_ref() {
            if l.starts_with("ITEM: ATOMS") {
                break;
            }
        }
        let state: State = (0..n)
            .map(|_| {
                let w: Vec<f64> = lines
                    .next()
                    .expect("an atom")
                    .split_whitespace()
                    .map(|x| x.parse().expect("a number"))
                    .collect();
                [w[1], w[2], w[3], w[4], w[5], w[6], w[7], w[8], w[9]]
            })
            .collect();
        rows.insert(step, state);
    }
    rows
}
