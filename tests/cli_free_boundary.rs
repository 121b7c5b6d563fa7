//! `dembound run` with a free boundary particle, through the real binary.

mod common;

use common::dembound;
use serde_json::Value;

const HEAD_ON: [&str; 14] = [
    "--set",
    "boundary.fixed=false",
    "--set",
    "boundary.velocity=0.2",
    "--set",
    "motion.velocity=-0.3",
    "--set",
    "motion.gravity_on=none",
    "--set",
    "motion.contacts=1",
    "--set",
    "boundary.radius_ratio=1",
    "--set",
    "boundary.modulus_ratio=1",
];

#[test]
fn json_reports_each_spheres_velocities_and_the_resolved_keys() {
    let out = dembound()
        .arg("run")
        .args(HEAD_ON)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let c = &v["contacts"][0];
    let b = &c["bodies"];
    let get = |k: &str| b[k].as_f64().unwrap();
    assert!((get("particle_before") + 0.3).abs() < 1e-12);
    assert!((get("boundary_before") - 0.2).abs() < 1e-12);
    // Equal spheres, elastic: the velocities are exchanged.
    assert!((get("particle_after") - 0.2).abs() < 1e-6);
    assert!((get("boundary_after") + 0.3).abs() < 1e-6);
    assert!((c["impact_velocity"].as_f64().unwrap() + 0.5).abs() < 1e-12);
    // The resolved scenario names the free boundary's density and velocity.
    assert_eq!(v["scenario"]["boundary"]["fixed"], false);
    assert_eq!(v["scenario"]["boundary"]["density"], 1000.0);
    assert_eq!(v["scenario"]["motion"]["gravity_on"], "none");
}

#[test]
fn a_fixed_boundary_reports_no_bodies() {
    let out = dembound().args(["run", "--json"]).output().unwrap();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["contacts"][0].get("bodies").is_none());
    assert!(v["scenario"]["boundary"].get("fixed").is_none());
}

#[test]
fn csv_gets_four_velocity_columns() {
    let dir = tempfile::tempdir().unwrap();
    dembound()
        .arg("run")
        .args(HEAD_ON)
        .arg("--out")
        .arg(dir.path())
        .assert()
        .success();
    let text = std::fs::read_to_string(dir.path().join("contacts.csv")).unwrap();
    let header = text.lines().next().unwrap();
    assert!(header.ends_with(
        "particle_velocity_before_m_s,particle_velocity_after_m_s,\
         boundary_velocity_before_m_s,boundary_velocity_after_m_s"
    ));
    // The written scenario runs again to the same contact.
    let again = dembound()
        .arg("run")
        .arg(dir.path().join("scenario.toml"))
        .arg("--json")
        .output()
        .unwrap();
    assert!(again.status.success());
}

#[test]
fn bad_combinations_exit_2_naming_the_key() {
    let cases: [(&[&str], &str); 5] = [
        (&["--set", "boundary.density=2000"], "boundary.density"),
        (&["--set", "boundary.velocity=0.1"], "boundary.velocity"),
        (&["--set", "motion.gravity_on=both"], "motion.gravity_on"),
        (
            &[
                "--set",
                "boundary.fixed=false",
                "--set",
                "boundary.radius_ratio=inf",
            ],
            "boundary.radius_ratio",
        ),
        (
            &[
                "--set",
                "boundary.fixed=false",
                "--set",
                "motion.gravity_on=both",
            ],
            "motion.velocity",
        ),
    ];
    for (args, key) in cases {
        let out = dembound().arg("run").args(args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(key), "{args:?}: {stderr}");
    }
}
