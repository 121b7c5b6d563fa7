//! `dembound scene` refuses, before computing or writing anything, inputs
//! that would be read wrongly, never end, or abort (issue 24): a data file
//! cut inside its last line, an endless or oversized data file, a missing
//! one, a run of more steps than the stated limit without `--force`, and a
//! scene larger than the machine's memory. Each: exit 2, the key, the
//! value and the limit in stderr, no output directory.

mod common;

use common::{dembound, grain_floor_scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A scene of `particles` (a `[[particles]]` body) in a 1 m box with a
/// plane floor, 10 steps of 1 µs unless `integration` says otherwise.
fn scene(dir: &Path, particles: &str, integration: &str) -> PathBuf {
    grain_floor_scene(
        dir,
        "scene.toml",
        "[1.0, 1.0, 1.0]",
        1000.0,
        "law = \"hertz\"",
        particles,
        integration,
    )
}

const SHORT: &str = "scheme = \"verlet\"\ndt = 1.0e-6\nsteps = 10";

/// Runs `dembound scene FILE --out DIR/out ARGS`; (exit code, stderr,
/// whether the output directory exists).
fn run(dir: &Path, file: &Path, args: &[&str]) -> (Option<i32>, String, bool) {
    let out = dir.join("out");
    let o = dembound()
        .args(["scene", "-q"])
        .arg(file)
        .arg("--out")
        .arg(&out)
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        out.exists(),
    )
}

/// Writes the scene of `particles` and `integration`, runs it and asserts
/// it is refused: exit 2, every one of `needles` in stderr, no output
/// directory.
fn refused(dir: &Path, particles: &str, integration: &str, needles: &[&str]) {
    let file = scene(dir, particles, integration);
    let (code, err, made) = run(dir, &file, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(needles.iter().all(|n| err.contains(n)), "{err}");
    assert!(!made);
}

/// Runs `dembound scene -q ARGS FILE --out DIR/a-file` (a file, which
/// `--out` refuses after the step guard); (exit code, stderr).
fn out_refused(dir: &Path, args: &[&str], file: &Path) -> (Option<i32>, String) {
    std::fs::write(dir.join("a-file"), "x").unwrap();
    let o = dembound()
        .args(["scene", "-q"])
        .args(args)
        .arg(file)
        .arg("--out")
        .arg(dir.join("a-file"))
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A LAMMPS data file of `n` atoms (atom_style sphere, R = 0.5 mm,
/// density 1000 kg/m³) in a column of 1.2 mm cells; the last atom's z
/// is 0.001045 m.
fn data_file(n: usize) -> String {
    let mut s = format!(
        "LAMMPS data file\n\n{n} atoms\n1 atom types\n\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\nAtoms # sphere\n\n"
    );
    let side = 500;
    for k in 0..n {
        let (i, j) = (k % side, k / side);
        let z = if k + 1 == n { 0.001045 } else { 0.1 };
        writeln!(
            s,
            "{} 1 0.001 1000 {:?} {:?} {z}",
            k + 1,
            0.0006 + 0.0012 * i as f64,
            0.0006 + 0.0012 * j as f64
        )
        .unwrap();
    }
    s
}

#[test]
fn a_data_file_cut_inside_its_last_number_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for n in [4, 25_000] {
        let whole = data_file(n);
        assert!(whole.ends_with("0.001045\n"));
        // The whole file runs.
        std::fs::write(dir.join("atoms.data"), &whole).unwrap();
        let file = scene(dir, "lammps_data = \"atoms.data\"", SHORT);
        let (code, err, _) = run(dir, &file, &[]);
        assert_eq!(code, Some(0), "{n} atoms: {err}");
        std::fs::remove_dir_all(dir.join("out")).unwrap();
        // Cut after "0.00", "0.0010" and "0.00104": each still a number.
        let lines = whole.lines().count();
        for cut in [4, 2, 1] {
            let text = &whole[..whole.len() - 1 - cut];
            std::fs::write(dir.join("atoms.data"), text).unwrap();
            let (code, err, made) = run(dir, &file, &[]);
            assert_eq!(code, Some(2), "{n} atoms, cut {cut}: {err}");
            assert!(
                err.contains("atoms.data") && err.contains(&format!("line {lines}")),
                "{n} atoms, cut {cut}: {err}"
            );
            assert!(!made);
        }
    }
}

#[test]
fn a_csv_file_cut_inside_its_last_number_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("s.csv"),
        "x,y,z,radius\n0.5,0.5,0.001045,5e-4\n0.6,0.5,0.00",
    )
    .unwrap();
    refused(dir, "csv = \"s.csv\"", SHORT, &["s.csv", "line 3"]);
}

#[test]
fn special_missing_and_oversized_data_files_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // /dev/zero would be read until memory runs out.
    refused(
        dir,
        "lammps_data = \"/dev/zero\"",
        SHORT,
        &["particles[0].lammps_data", "/dev/zero"],
    );
    // A directory.
    refused(
        dir,
        &format!("csv = {:?}", dir.display().to_string()),
        SHORT,
        &["particles[0].csv", "directory"],
    );
    // Missing: bad input (exit 2), not a failure of the machine.
    refused(
        dir,
        "lammps_data = \"missing.data\"",
        SHORT,
        &["particles[0].lammps_data", "missing.data"],
    );
    // Over the limit: a sparse file of 4 GiB + 1 byte (no disk used).
    let big = std::fs::File::create(dir.join("big.data")).unwrap();
    big.set_len((4u64 << 30) + 1).unwrap();
    refused(
        dir,
        "lammps_data = \"big.data\"",
        SHORT,
        &["particles[0].lammps_data", "4294967297", "4294967296"],
    );
}

#[test]
fn runs_beyond_the_step_limit_need_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let one = "spheres = [{ position = [0.5, 0.5, 0.5], radius = 1e-3 }]";
    refused(
        dir,
        one,
        "scheme = \"verlet\"\ndt = 1.0e-6\nsteps = 1000000000000",
        &[
            "integration.steps = 1000000000000",
            "1000000000 steps",
            "--force",
        ],
    );
    // A duration of 10⁶ s at Δt = 1 µs: 10¹² steps.
    refused(
        dir,
        one,
        "scheme = \"verlet\"\ndt = 1.0e-6\nduration = 1.0e6",
        &[
            // 10¹² steps, give or take the rounding of 10⁶ s / 1 µs up.
            "integration.duration = 1000000 s (100000000000",
            "at most 1000000000 steps",
        ],
    );
    // The limit itself runs without --force: 10⁹ steps are allowed, so
    // the guard must pass them (checked by the --out refusal that comes
    // after it: `--out` a file).
    let at_limit = scene(
        dir,
        one,
        "scheme = \"verlet\"\ndt = 1.0e-6\nsteps = 1000000000",
    );
    let (code, err) = out_refused(dir, &[], &at_limit);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--out") && !err.contains("--force"), "{err}");
    // With --force the step guard passes 10¹² steps too (the same --out
    // refusal comes next).
    let beyond = scene(
        dir,
        one,
        "scheme = \"verlet\"\ndt = 1.0e-6\nsteps = 1000000000000",
    );
    let (code, err) = out_refused(dir, &["--force"], &beyond);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("--out") && !err.contains("integration.steps"),
        "{err}"
    );
}

#[test]
fn a_scene_larger_than_the_memory_is_refused_before_it_is_made() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // 10⁸ spheres (the lattice's own maximum) with Gear5 are charged
    // 95.2 GB: Gear5's measured 1040 B a sphere less the 88 B of the
    // sphere list a lattice does not make (952 B) — more than any machine
    // this runs on has available (24 GB here).
    let lattice = "lattice = { counts = [1000, 1000, 100], spacing = [1e-3, 1e-3, 1e-3], \
                   origin = [5e-4, 5e-4, 5e-4], radius = 4e-4 }";
    let gear5 = "scheme = \"gear5\"\ndt = 1.0e-6\nsteps = 10";
    let started = std::time::Instant::now();
    refused(
        dir,
        lattice,
        gear5,
        &[
            "particles[0].lattice.counts = [1000, 1000, 100]",
            "100000000 spheres",
            "95.200 GB",
            "available",
        ],
    );
    // Refused before the spheres are made (making them takes seconds).
    assert!(started.elapsed().as_secs_f64() < 5.0);
}
