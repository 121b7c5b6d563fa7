//! `dembound wall-study --wall SURFACE` (issue 29), through the real
//! binary: a flat square part gives the plane study's mesh-wall numbers,
//! one impact on a steel mesh wall follows Hertz's closed form, and each
//! bad value is refused naming its option.

mod common;

use common::dembound;
use std::path::Path;

/// (wall label, angle, normal_restitution, speed_ratio, contact_time_s)
/// of each row of a part study's impacts.csv, or (floor label, angle,
/// normal_restitution, NaN, contact_time_s) of a plane study's.
fn impacts(csv: &Path, part: bool) -> Vec<(String, f64, f64, f64, f64)> {
    let mut r = csv::Reader::from_path(csv).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|x| x == name).unwrap();
    let (a, en, tc) = (
        col("angle_deg"),
        col("normal_restitution"),
        col("contact_time_s"),
    );
    let sr = part.then(|| col("speed_ratio"));
    r.records()
        .map(|row| {
            let row = row.unwrap();
            let f = |k: usize| row[k].parse::<f64>().unwrap();
            (
                row[0].to_string(),
                f(a),
                f(en),
                sr.map_or(f64::NAN, f),
                f(tc),
            )
        })
        .collect()
}

fn run(args: &[&str], out: &Path) -> std::process::Output {
    dembound()
        .args(["wall-study", "--quiet"])
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// `--wall square:SIDE` against today's plane study, same seed and
/// particles. What holds exactly: every normal impact on a flat wall of
/// the particles' material gives the same rebound wherever it lands, and
/// Δt is the same (the flat-wall contact time of the same E*: ζ = 1, as
/// Δt follows the stiffest wall studied), so the
/// mesh wall's e_n and contact times equal the plane's. What does not:
/// the coverings' numbers, because the plane study draws its points in
/// one period cell of the tiling with seed + floor index, the part study
/// over the whole part with one stream shared by all walls (the same
/// point on every wall), so the particles hit other spots of the spheres.
#[test]
fn flat_square_part_matches_the_plane_study() {
    let dir = tempfile::tempdir().unwrap();
    let common = [
        "--quick",
        "--particles",
        "0",
        "--chute-time",
        "0",
        "--angles",
        "0",
        "--impacts",
        "3",
        "--radius-ratios",
        "1",
        "--modulus-ratios",
        "1",
        "--seed",
        "7",
    ];
    let plane = run(&common, &dir.path().join("plane"));
    assert!(
        plane.status.success(),
        "{}",
        String::from_utf8_lossy(&plane.stderr)
    );
    let mut args = common.to_vec();
    args.extend(["--wall", "square:0.01"]);
    let part = run(&args, &dir.path().join("part"));
    assert!(
        part.status.success(),
        "{}",
        String::from_utf8_lossy(&part.stderr)
    );
    let p = impacts(&dir.path().join("plane/impacts.csv"), false);
    let m = impacts(&dir.path().join("part/impacts.csv"), true);
    let plane_rows: Vec<_> = p.iter().filter(|r| r.0 == "plane").collect();
    let mesh_rows: Vec<_> = m.iter().filter(|r| r.0 == "mesh wall").collect();
    assert_eq!(plane_rows.len(), 3);
    assert_eq!(mesh_rows.len(), 3);
    for (a, b) in plane_rows.iter().zip(&mesh_rows) {
        // The plane's and the mesh's overlap are computed by different
        // code (a dot product against the triangle's closest point): equal
        // up to rounding of a few ulps of the position, amplified over a
        // few hundred steps; 1e-9 is far below any physical difference
        // (a 1e-3 change of E* moves e_n by ~1e-4 with Tsuji damping).
        assert!((a.2 - b.2).abs() < 1e-9, "e_n plane {} mesh {}", a.2, b.2);
        assert!(
            (a.4 - b.4).abs() <= 1e-9 * a.4,
            "contact time plane {} mesh {}",
            a.4,
            b.4
        );
    }
}

/// One normal impact on a steel mesh wall with e = 1: the rebound speed
/// equals the impact speed, and the contact lasts Hertz's
/// t_c = 2.9432 δ_max / v, δ_max = (15 m v² / (16 E* √R))^(2/5),
/// 1/E* = (1 − ν²)/E + (1 − ν_s²)/E_s (Johnson, Contact Mechanics,
/// §11.4), E_s = 207 GPa, ν_s = 0.30 (the value `steel` states).
#[test]
fn elastic_impact_on_steel_follows_hertz() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("steel");
    let r = run(
        &[
            "--wall",
            "square:0.01",
            "--reference-material",
            "steel",
            "--restitution",
            "1",
            "--friction",
            "0",
            "--angles",
            "0",
            "--impacts",
            "1",
            "--radius-ratios",
            "1",
            "--modulus-ratios",
            "1",
            "--tilings",
            "square",
            "--eta",
            "0.002",
            "--particles",
            "0",
        ],
        &out,
    );
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let rows = impacts(&out.join("impacts.csv"), true);
    let mesh = rows.iter().find(|r| r.0 == "mesh wall").unwrap();
    let (radius, rho, e, nu, v) = (0.5e-3_f64, 1000.0_f64, 1.0e7_f64, 0.3_f64, 1.0_f64);
    let (es, nus) = (207e9_f64, 0.30_f64);
    let e_star = 1.0 / ((1.0 - nu * nu) / e + (1.0 - nus * nus) / es);
    let m = 4.0 / 3.0 * std::f64::consts::PI * rho * radius.powi(3);
    let delta = (15.0 * m * v * v / (16.0 * e_star * radius.sqrt())).powf(0.4);
    let t_c = 2.9432 * delta / v;
    // Verlet at Δt = 0.002 t_c conserves the elastic energy to ~1e-5;
    // the rebound is read after the contact: 1e-3.
    assert!(
        (mesh.3 - 1.0).abs() < 1e-3,
        "rebound speed ratio {}",
        mesh.3
    );
    assert!((mesh.2 - 1.0).abs() < 1e-3, "e_n {}", mesh.2);
    // The contact's start and end are known to a step each: 2 Δt = 0.4 %
    // of t_c, plus the 4-digit constant: 1 %.
    assert!(
        (mesh.4 - t_c).abs() < 0.01 * t_c,
        "contact time {} s, Hertz {} s",
        mesh.4,
        t_c
    );
}

#[test]
fn bad_values_are_refused_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    for (args, key) in [
        (
            vec!["--wall", "square:0.01", "--reference-material", "wood"],
            "--reference-material",
        ),
        (
            vec!["--wall", "square:0.01", "--reference-material", "1e9,0.7"],
            "--reference-material",
        ),
        (
            vec![
                "--wall",
                "square:0.01",
                "--reference-material",
                "-1e9,0.3,7800",
            ],
            "--reference-material",
        ),
        (
            vec!["--reference-material", "steel"],
            "--reference-material",
        ),
        (vec!["--wall", "cylinder:-1,2"], "cylinder:RADIUS"),
        (vec!["--wall", "cone:1"], "SURFACE"),
        (
            vec!["--wall", "square:0.01", "--tol-angle=-1"],
            "--tol-angle",
        ),
        (
            vec!["--wall", "square:0.01", "--radius-ratios", "0.1"],
            "--radius-ratios",
        ),
        (
            vec!["--wall", "square:0.01", "--modulus-ratios", "0"],
            "--modulus-ratios",
        ),
        (vec!["--wall", "/nonexistent/part.stl"], "part.stl"),
    ] {
        let out = dir.path().join("never");
        let r = run(&args, &out);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(key), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote output");
    }
}
