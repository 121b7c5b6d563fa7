//! `dembound particle-wall` (issue 29): its files read back by dembound's
//! own readers equal the plane `boundary_particles` tiling of a flat
//! square; bad input exits 2 and writes nothing.

mod common;

use common::dembound;
use dembound_scene::sources::lammps_data::LammpsData;
use dembound_scene::sources::tiling::{Extent, Pattern, Tiling};

fn plane_floor(pattern: Pattern) -> Vec<[f64; 3]> {
    Tiling {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        radius: 1.0,
        spacing: 2.0,
        pattern,
    }
    .spheres(
        &Extent {
            lower: [0.0; 3],
            upper: [10.0, 10.0, 5.0],
            periodic: [false; 3],
        },
        "wall[0]",
    )
    .unwrap()
    .iter()
    .map(|s| s.position)
    .collect()
}

#[test]
fn square_files_are_the_plane_tiling() {
    let dir = tempfile::tempdir().unwrap();
    for (tiling, pattern) in [("square", Pattern::Square), ("hex", Pattern::Hexagonal)] {
        let out = dir.path().join(tiling);
        let run = dembound()
            .args([
                "particle-wall",
                "square:10",
                "--radius",
                "1",
                "--tiling",
                tiling,
            ])
            .args(["--min-radius", "0.9", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(run.status.code(), Some(0), "{run:?}");
        let expected = plane_floor(pattern);
        let csv = dembound_scene::sources::csv::read(&out.join("spheres.csv")).unwrap();
        // Shortest round-trip decimals: the same f64 bits back.
        assert_eq!(csv.iter().map(|s| s.position).collect::<Vec<_>>(), expected);
        assert!(csv.iter().all(|s| s.radius == 1.0));
        let data = LammpsData::read(&out.join("spheres.data")).unwrap();
        assert_eq!(
            data.spheres()
                .iter()
                .map(|s| s.position)
                .collect::<Vec<_>>(),
            expected
        );
        let png = std::fs::read(out.join("covering.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let vtp = std::fs::read_to_string(out.join("spheres.vtp")).unwrap();
        assert!(vtp.contains(&format!("NumberOfPoints=\"{}\"", expected.len())));
        let report = std::fs::read_to_string(out.join("report.md")).unwrap();
        assert!(report.contains("## Largest hole") && report.contains("## Bumpiness"));
        // R_min = 0.9 R_b is above both lattices' hole bound (0.414 + 0.25
        // and 0.155 + 0.25): leak-free.
        assert!(report.contains("cannot pass"), "{report}");
    }
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    // The run's standard error, asserted a refusal (exit 2) that wrote
    // nothing.
    let refused = |args: &[&str]| -> String {
        let run = dembound()
            .arg("particle-wall")
            .args(args)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr).into_owned();
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} left {}", out.display());
        stderr
    };
    for args in [
        vec!["square:10", "--radius", "-1"],
        vec!["square:10", "--radius", "1", "--spacing", "0"],
        vec!["cone:1", "--radius", "1"],
        vec!["missing.stl", "--radius", "1"],
    ] {
        let stderr = refused(&args);
        assert!(stderr.contains("error:"), "{stderr}");
    }
    // Too many spheres: (0.01 m / 2e-7 m)² = 2.5e9 on the square, beyond
    // the 2e7 a wall may hold. The message names the flags typed, not the
    // scene keys `radius_ratio`/`spacing` nor `mesh.boundary_particles`
    // (session 34).
    for args in [
        vec!["square:0.01", "--radius", "1e-7"],
        vec!["square:0.01", "--radius", "1e-3", "--spacing", "1e-12"],
    ] {
        let stderr = refused(&args);
        assert!(
            stderr.contains("raise `--radius` or `--spacing`"),
            "{args:?}: {stderr}"
        );
        for internal in ["radius_ratio", "`spacing`", "boundary_particles"] {
            assert!(!stderr.contains(internal), "{args:?}: {stderr}");
        }
    }
}
