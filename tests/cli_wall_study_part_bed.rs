//! `dembound wall-study --wall SURFACE`: the bed and the discharge on the
//! part (issue 29 item 4), through the real binary. A flat square part
//! gives the plane study's bed (the same spheres on the same floor: an
//! independent route to the same numbers); on the hopper, the mesh wall's
//! discharge rate is what `dembound scene` gives for the same scene; bad
//! values are refused naming the option, with nothing written.

mod common;

use common::dembound;
use std::path::{Path, PathBuf};

fn run(args: &[&str], out: &Path) -> std::process::Output {
    dembound()
        .args(["wall-study", "--quiet"])
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// (wall or floor, quantity) → (value, standard error) of a CSV whose
/// first three columns are those and the value, the fourth the error.
fn table(csv: &Path) -> Vec<(String, String, f64, f64)> {
    let mut r = csv::Reader::from_path(csv).unwrap();
    r.records()
        .map(|row| {
            let row = row.unwrap();
            (
                row[0].to_string(),
                row[1].to_string(),
                row[2].parse().unwrap(),
                row[3].parse().unwrap_or(f64::NAN),
            )
        })
        .collect()
}

fn find(t: &[(String, String, f64, f64)], wall: &str, quantity: &str) -> (f64, f64) {
    t.iter()
        .find(|r| r.0 == wall && r.1 == quantity)
        .map(|r| (r.2, r.3))
        .unwrap_or_else(|| panic!("no {wall} / {quantity} in {t:?}"))
}

/// The plane study's bed and the part study's bed on `square:SIDE`, for
/// SIDE the plane study's box. The spheres are the same when:
/// - the box is the same: the plane study's side is max(√(N V/(12 R)),
///   6 R); for N = 100 that is 6 R, the part's box;
/// - Δt is the same: ζ = 1 and the reference is the particles' material
///   (both then take the flat-wall contact time of the same E*);
/// - the lattices coincide: the plane study tiles from the box's centre
///   (3 R, 3 R), the covering of a flat patch from the point nearest the
///   origin; with spacing 2 r R = R (r = 0.5) the centre is a site, and
///   with R = 2⁻¹¹ m every site is a dyadic number, exact in both.
///
/// Then the bed height (the 95th percentile of the tops above the floor)
/// is the same to the bit on the mesh wall (the plane floor's) and on the
/// covering (the tiling's). The packing at the wall is measured two ways:
/// the plane study integrates the spheres' slab volumes exactly over
/// 0 ≤ z ≤ 2 R, the part study samples random points of the shell; they
/// agree within the sampling's binomial standard error: 4 of them (a
/// false alarm 1 in 16,000).
#[test]
fn flat_square_bed_is_the_plane_studys_bed() {
    let dir = tempfile::tempdir().unwrap();
    let r = 2f64.powi(-11);
    let side = 6.0 * r;
    let (r_text, side_text) = (format!("{r:e}"), format!("square:{side:e}"));
    let common = [
        "--particles",
        "100",
        "--radius",
        &r_text,
        "--radius-ratios",
        "0.5",
        "--modulus-ratios",
        "1",
        "--tilings",
        "square",
        "--settle-time",
        "0.05",
        "--impacts",
        "1",
        "--angles",
        "0",
        "--seed",
        "3",
    ];
    let plane_dir = dir.path().join("plane");
    let mut args = common.to_vec();
    args.extend(["--chute-time", "0"]);
    let p = run(&args, &plane_dir);
    assert!(p.status.success(), "{}", String::from_utf8_lossy(&p.stderr));
    let part_dir = dir.path().join("part");
    let mut args = common.to_vec();
    args.extend(["--wall", &side_text, "--packing-points", "200000"]);
    let q = run(&args, &part_dir);
    assert!(q.status.success(), "{}", String::from_utf8_lossy(&q.stderr));
    let plane = table(&plane_dir.join("summary.csv"));
    let part = table(&part_dir.join("bed.csv"));
    for (floor, wall) in [
        ("plane", "mesh wall"),
        ("r=0.5 zeta=1 square", "r=0.5 zeta=1 square"),
    ] {
        let (h_plane, _) = find(&plane, floor, "bed height (mm)");
        let (h_part, _) = find(&part, wall, "bed height (mm)");
        assert_eq!(h_plane, h_part, "{wall}: bed height (mm)");
        let (phi_plane, _) = find(&plane, floor, "packing fraction 0–2R (1)");
        let (phi_part, se) = find(&part, wall, "packing at the wall (1)");
        assert!(se > 0.0 && se < 0.002, "{wall}: standard error {se}");
        assert!(
            (phi_part - phi_plane).abs() < 4.0 * se,
            "{wall}: packing {phi_part} ± {se}, the plane study's {phi_plane}"
        );
    }
    // A flat square has no outlet: no discharge.
    assert!(!part_dir.join("discharge.csv").exists());
    let report = std::fs::read_to_string(part_dir.join("report.md")).unwrap();
    assert!(report.contains("No outlet"), "{report}");
}

fn hopper() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/hopper.stl")
}

/// The hopper (`hopper.stl`, 6 mm outlet radius at z = 0, 20 mm bin,
/// normals outward: `--flip`), 300 grains of R = 1 mm. The study writes
/// the mesh wall's run as a scene file; `dembound scene` runs it in
/// another process, through the scene file's reader, and this test takes
/// the rate from its series.csv: the mass the outlet removed from the
/// first row 0.06 s or more after the opening (the plug's motion start)
/// to the last, over that time. The same scene, the same bits: the rates
/// agree to round-off (1e-12 relative: the two sides divide the same two
/// differences). The written scene holds the documented region: the pour
/// box inscribed in the 20 mm bin (±14 mm, f = 0.7), the plug at the
/// outlet plane, the outlet box 10 R below it.
#[test]
fn hopper_mesh_wall_rate_is_dembound_scenes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let stl = hopper();
    let r = run(
        &[
            "--wall",
            stl.to_str().unwrap(),
            "--flip",
            "--quick",
            "--impacts",
            "0",
            "--radius",
            "1e-3",
            "--density",
            "2500",
            "--friction",
            "0",
            "--reference-material",
            "5e7,0.3,7800",
            "--particles",
            "300",
            "--settle-time",
            "0.15",
        ],
        &out,
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let (rate, se) = find(
        &table(&out.join("bed.csv")),
        "mesh wall",
        "discharge rate (g/s)",
    );
    assert!(rate > 0.0 && se.is_finite(), "rate {rate} ± {se} g/s");
    let scene_file = out.join("scene_mesh_wall.toml");
    let text = std::fs::read_to_string(&scene_file).unwrap();
    let start: f64 = text
        .split("start = ")
        .nth(1)
        .and_then(|t| t.split(',').next())
        .unwrap()
        .parse()
        .unwrap();
    // hopper.stl's bin radius, 20 mm, read as f32: the pour box is f = 0.7
    // of it, ±14 mm; the plug at z = 0, normal +z; the outlet box's top at
    // −10 R = −10 mm.
    let bin = f64::from(0.02_f32);
    let edge = format!("{:?}", 0.7 * bin);
    assert!(
        text.contains(&format!("lower = [-{edge}, -{edge}, ")),
        "pour box ±{edge} m:\n{text}"
    );
    assert!(text.contains("plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }"));
    assert!(text.contains(", -0.01] } }"), "{text}");
    let sc = dir.path().join("scene");
    let s = dembound()
        .args(["scene", "-q", "--threads", "1", "--out"])
        .arg(&sc)
        .arg(&scene_file)
        .output()
        .unwrap();
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    let mut csv = csv::Reader::from_path(sc.join("series.csv")).unwrap();
    let h = csv.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|x| x == n).unwrap();
    let (t, m) = (col("time_s"), col("outlet0_mass_kg"));
    let rows: Vec<(f64, f64)> = csv
        .records()
        .map(|x| {
            let x = x.unwrap();
            (x[t].parse().unwrap(), x[m].parse().unwrap())
        })
        .collect();
    let skip = 0.06; // --quick's --discharge-skip
    let first = rows
        .iter()
        .find(|(ti, _)| ti - start >= skip)
        .copied()
        .unwrap();
    let last = *rows.last().unwrap();
    let scene_rate = (last.1 - first.1) / (last.0 - first.0) * 1e3;
    assert!(
        (scene_rate - rate).abs() <= 1e-12 * rate,
        "study {rate} g/s, dembound scene {scene_rate} g/s"
    );
    // A covering's rate is there too, judged against the mesh wall's.
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("| r=1 zeta=100 square | discharge rate (g/s) |"),
        "{report}"
    );
    assert!(out.join("discharge.png").exists());
}

#[test]
fn bad_bed_values_are_refused_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let hopper_text = hopper().to_str().unwrap().to_string();
    for (args, key) in [
        (vec!["--flip"], "--flip"),
        (vec!["--tolerance", "3%"], "--tolerance"),
        (vec!["--discharge-time", "0.2"], "--discharge-time"),
        (
            vec!["--wall", "square:0.01", "--tolerance=-3%"],
            "--tolerance",
        ),
        (
            vec!["--wall", "square:0.01", "--discharge-time", "0"],
            "--discharge-time",
        ),
        (
            vec![
                "--wall",
                "square:0.01",
                "--discharge-time",
                "0.1",
                "--discharge-skip",
                "0.1",
            ],
            "--discharge-skip",
        ),
        (
            vec!["--wall", "square:0.01", "--packing-points", "10"],
            "--packing-points",
        ),
        (
            vec!["--wall", "square:0.01", "--settle-time=-1"],
            "--settle-time",
        ),
        (
            vec![
                "--wall",
                "square:0.01",
                "--particles",
                "0",
                "--discharge-skip",
                "0.01",
            ],
            "--discharge-skip",
        ),
        // The square's particles are on its normals' side (+z): flipped,
        // no pour column lies on the particles' side.
        (vec!["--wall", "square:0.01", "--flip"], "--wall"),
        // hopper.stl's normals point outward: without --flip the pour box
        // over its bounding box would land around the bin (its corner
        // columns miss the part) or on the cone's outside; the flipped
        // part takes the grains: refused naming --flip.
        (vec!["--wall", &hopper_text, "--radius", "1e-3"], "--flip"),
    ] {
        let out = dir.path().join("never");
        let r = run(&args, &out);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(key), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote output");
    }
}

/// More grains than hopper.stl holds are refused before anything runs,
/// naming --particles and the largest count that fits. That count against
/// the hopper's closed-form volume (examples/scenes/make_hopper.py: outlet
/// radius r1 = 6 mm, top radius r2 = 20 mm, the cone's half-angle 30°, so
/// its height h = (r2 − r1)/tan 30°, a 70 mm bin above; 48 facets around,
/// so every circle is the 48-gon of area factor (48/2π) sin(2π/48)):
/// V = [π h/3 (r1² + r1 r2 + r2²) + π r2² 70 mm] × that factor, and
/// N = ⌊0.55 V / (4/3 π R³)⌋ at the documented loose packing 0.55.
/// Tolerance 0.5 %: the program surveys the interior by 256² column
/// midpoints, whose count of a disc of radius ρ on a grid of spacing c errs
/// by O((ρ/c)^(2/3)) cells (the Gauss circle problem), ≈ 25 of ≈ 51,000
/// (0.05 %); the STL's single-precision vertices add 1e-7.
#[test]
fn too_many_grains_for_the_hopper_are_refused_with_the_count_that_fits() {
    use std::f64::consts::PI;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let stl = hopper();
    let r = run(
        &[
            "--wall",
            stl.to_str().unwrap(),
            "--flip",
            "--quick",
            "--radius",
            "1e-3",
            "--particles",
            "20000",
        ],
        &out,
    );
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(err.contains("--particles = 20000"), "{err}");
    assert!(!out.exists(), "wrote output");
    let fits: f64 = err
        .split("1 to ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no count in {err}"));
    let (r1, r2, bin) = (6e-3, 20e-3, 70e-3);
    let h = (r2 - r1) / (PI / 6.0).tan();
    let polygon = 48.0 / (2.0 * PI) * (2.0 * PI / 48.0).sin();
    let volume = (PI * h / 3.0 * (r1 * r1 + r1 * r2 + r2 * r2) + PI * r2 * r2 * bin) * polygon;
    let expected = (0.55 * volume / (4.0 / 3.0 * PI * 1e-9)).floor();
    assert!(
        (fits / expected - 1.0).abs() < 5e-3,
        "fits {fits}, closed form {expected}"
    );
}
