//! `dembound restitution`, through the real binary: the sweep's outputs,
//! exit codes, and the reverse question's answers entered back.

mod common;

use common::dembound;
use serde_json::Value;
use std::path::Path;

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = match std::fs::read_dir(dir) {
        Ok(entries) => entries
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect(),
        Err(_) => Vec::new(),
    };
    names.sort();
    names
}

/// Rows of a CSV file as header → value maps.
fn csv_rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            header
                .iter()
                .cloned()
                .zip(r.iter().map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn sweep_writes_csv_markdown_and_figures_and_says_which_calibration_is_which() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let assert = dembound()
        .args([
            "restitution",
            "--law",
            "tsuji,walton-braun",
            "--e",
            "0.5",
            "--r",
            "10,inf",
            "--zeta",
            "10,inf",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
    assert!(
        stdout.contains("wall: raw coefficient calibrated"),
        "{stdout}"
    );
    assert!(
        stdout.contains("pair: raw coefficient calibrated"),
        "{stdout}"
    );
    assert!(stdout.contains("r = ζ = 10"), "{stdout}");
    let names = files_in(&out);
    assert!(names.contains(&"restitution.csv".to_string()), "{names:?}");
    assert!(names.contains(&"restitution.md".to_string()));
    // 2 laws × (3 quantities against r + restitution against ζ) × (svg, png).
    let figures = names
        .iter()
        .filter(|n| n.ends_with(".svg") || n.ends_with(".png"))
        .count();
    assert_eq!(figures, 16, "{names:?}");
    assert!(!names.iter().any(|n| n.ends_with(".tmp")));
    let rows = csv_rows(&out.join("restitution.csv"));
    // 2 laws × 2 calibrations × 1 target × 2 r × 2 ζ.
    assert_eq!(rows.len(), 16);
    for row in &rows {
        let e: f64 = row["restitution"].parse().unwrap();
        assert!(e > 0.0 && e < 1.0, "{row:?}");
        let pair_or_wall = &row["calibration"];
        assert!(pair_or_wall == "wall" || pair_or_wall == "pair");
    }
    // On the wall itself both calibrations are the same coefficient and run.
    let on_wall: Vec<_> = rows
        .iter()
        .filter(|r| r["radius_ratio"] == "inf" && r["modulus_ratio"] == "inf")
        .collect();
    assert_eq!(on_wall.len(), 4);
    for law in ["tsuji", "walton-braun"] {
        let of = |cal: &str| {
            on_wall
                .iter()
                .find(|r| r["law"] == law && r["calibration"] == cal)
                .map(|r| (r["coefficient"].clone(), r["restitution"].clone()))
                .unwrap()
        };
        assert_eq!(of("wall"), of("pair"), "{law}");
    }
    let md = std::fs::read_to_string(out.join("restitution.md")).unwrap();
    assert!(md.contains("**wall**") && md.contains("**pair**"));
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--e", "1.5"], "0 < e ≤ 1"),
        (vec!["--e", "0"], "0 < e ≤ 1"),
        (vec!["--r", "0"], "> 0"),
        (vec!["--zeta", "-3"], "> 0"),
        (vec!["--r", "big"], "not a number"),
        (vec!["--law", "nonsense"], "unknown law"),
        (
            vec![
                "--law",
                "viscoelastic",
                "--e",
                "0.001",
                "--r",
                "1",
                "--zeta",
                "1",
            ],
            "out of reach",
        ),
        (
            // With LIGGGHTS' mapping and the clamp the rebound tends to
            // e⁻² ≈ 0.135 as e → 0 (the exact calibration reaches 0.02).
            vec![
                "--target",
                "0.02",
                "--law",
                "tsuji",
                "--r",
                "3",
                "--zeta",
                "3",
                "--set",
                "contact.calibration=formula",
            ],
            "out of reach",
        ),
        (vec!["--calibrate", "floor"], "floor"),
        (vec!["--json"], "--target"),
        (vec!["--set", "boundary.fixed=false"], "fixed boundary"),
        (vec!["--set", "motion.gap=-1"], "motion.gap"),
        (vec!["--target", "0.5"], "--law"),
        (
            vec!["--target", "0.5", "--law", "viscous", "--r", "100"],
            "--zeta",
        ),
        (
            vec![
                "--target", "0.5", "--law", "viscous", "--r", "1,2", "--zeta", "3",
            ],
            "exactly one --r",
        ),
        (
            vec![
                "--target", "1.2", "--law", "viscous", "--r", "100", "--zeta", "100",
            ],
            "0 < E < 1",
        ),
        // Walton–Braun with the wall's k₂ on r = ζ = 1: e ≤ √(1/4) = 0.5.
        (
            vec![
                "--target",
                "0.9",
                "--law",
                "walton-braun",
                "--r",
                "1",
                "--zeta",
                "1",
            ],
            "out of reach",
        ),
        // e = 1e-6 on the rigid wall: Walton–Braun's k₂ = k₁/e² is far
        // beyond what the default step resolves (ω₂Δt ≤ 0.9); it printed
        // a rebound of 2e6 (648 km/s), exit 0.
        (
            vec![
                "--law",
                "walton-braun",
                "--e",
                "1e-6",
                "--r",
                "inf",
                "--zeta",
                "inf",
            ],
            "contact.restitution",
        ),
        // E = 0.01 on r = ζ = 1 with the wall's k₂ needs an entered e the
        // step does not resolve: refused naming --target and the reachable
        // range, not the internal e (session 34: `contact.restitution`:
        // 0.005).
        (
            vec![
                "--target",
                "0.01",
                "--law",
                "walton-braun",
                "--r",
                "1",
                "--zeta",
                "1",
            ],
            "invalid value for `--target`: 0.01 (allowed: 0.0",
        ),
    ];
    for (args, needle) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("never");
        let mut cmd = dembound();
        cmd.arg("restitution").args(&args);
        if !args.contains(&"--target") && !args.contains(&"--json") {
            cmd.arg("--out").arg(&out);
        }
        let output = cmd.output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        assert!(files_in(&out).is_empty(), "{args:?}");
    }
}

/// `restitution --target E ... --json`: the answers.
fn reverse(law: &str, calibrate: &str, target: f64, r: &str, zeta: &str) -> Vec<Value> {
    let out = dembound()
        .args([
            "restitution",
            "--json",
            "--law",
            law,
            "--calibrate",
            calibrate,
        ])
        .args(["--target", &target.to_string(), "--r", r, "--zeta", zeta])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{law} {calibrate}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    v.as_array().unwrap().clone()
}

/// The rebound of a sweep point, entered as `--e`.
fn sweep_restitution(law: &str, calibrate: &str, e: f64, r: &str, zeta: &str) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    dembound()
        .args(["restitution", "--law", law, "--calibrate", calibrate])
        .args(["--e", &e.to_string(), "--r", r, "--zeta", zeta, "--out"])
        .arg(dir.path())
        .assert()
        .success();
    let rows = csv_rows(&dir.path().join("restitution.csv"));
    assert_eq!(rows.len(), 1);
    rows[0]["restitution"].parse().unwrap()
}

/// The rebound of `dembound run` with the given contact keys on (r, ζ).
fn run_restitution(sets: &[String], r: &str, zeta: &str) -> f64 {
    let out = dembound()
        .args(["run", "--json", "--set", "motion.contacts=1"])
        .args(["--set", &format!("boundary.radius_ratio={r}")])
        .args(["--set", &format!("boundary.modulus_ratio={zeta}")])
        .args(sets.iter().flat_map(|s| ["--set", s.as_str()]))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{sets:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    v["contacts"][0]["restitution"].as_f64().unwrap()
}

fn contact_keys(law: &str) -> [&'static str; 2] {
    match law {
        "viscous" => ["contact.law=linear", "contact.damping=viscous"],
        "tsuji" => ["contact.law=hertz", "contact.damping=tsuji"],
        "viscoelastic" => ["contact.law=hertz", "contact.damping=viscoelastic"],
        _ => ["contact.law=walton-braun", "contact.damping=none"],
    }
}

#[test]
fn entering_the_answer_of_the_reverse_question_reproduces_the_target() {
    let target = 0.5;
    for law in ["viscous", "tsuji", "viscoelastic", "walton-braun"] {
        for (r, zeta) in [("100", "100"), ("3", "10")] {
            // Wall convention: enter e, calibrated on the wall, reused on the pair.
            let wall = &reverse(law, "wall", target, r, zeta)[0];
            assert_eq!(wall["calibration"], "wall");
            let e = wall["enter"].as_f64().unwrap();
            let got = sweep_restitution(law, "wall", e, r, zeta);
            assert!((got - target).abs() < 1e-4, "{law} wall {r} {zeta}: {got}");
            // ...or the raw coefficient straight into a scenario.
            if law != "walton-braun" {
                let c = wall["coefficient"].as_f64().unwrap();
                let mut sets: Vec<String> =
                    contact_keys(law).iter().map(|s| s.to_string()).collect();
                sets.push(format!("contact.damping_coefficient={c:e}"));
                let got = run_restitution(&sets, r, zeta);
                assert!((got - target).abs() < 1e-4, "{law} raw {r} {zeta}: {got}");
            }
            // Pair convention: enter e as contact.restitution of the pair.
            let pair = &reverse(law, "pair", target, r, zeta)[0];
            let e = pair["enter"].as_f64().unwrap();
            let mut sets: Vec<String> = contact_keys(law).iter().map(|s| s.to_string()).collect();
            sets.push(format!("contact.restitution={e}"));
            let got = run_restitution(&sets, r, zeta);
            assert!((got - target).abs() < 1e-4, "{law} pair {r} {zeta}: {got}");
        }
    }
}

#[test]
fn reverse_text_output_names_the_convention_and_the_keys() {
    let assert = dembound()
        .args(["restitution", "--target", "0.7", "--law", "tsuji"])
        .args(["--r", "100", "--zeta", "100", "--calibrate", "both"])
        .assert()
        .success();
    let stdout = String::from_utf8_lossy(&assert.get_output().stdout).into_owned();
    assert!(stdout.contains("wall calibration"), "{stdout}");
    assert!(stdout.contains("pair calibration"), "{stdout}");
    assert!(stdout.contains("enter e = "), "{stdout}");
    assert!(stdout.contains("contact.damping_coefficient="), "{stdout}");
    assert!(stdout.contains("N s/m^(5/4)"), "{stdout}");
}
