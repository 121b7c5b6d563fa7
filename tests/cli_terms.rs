//! Answers in the user's terms, through the real binary: the boundary in SI
//! (`boundary.radius`, `boundary.youngs_modulus`) in and out, `recommend`
//! against a rigid or a flat elastic wall with its trade-off curve, one list
//! and law syntax and one `--help` layout for every subcommand, and the
//! glass-on-steel questions answered and checked independently.

mod common;

use common::{dembound, json};

/// Runs and expects exit 2 with every needle in stderr.
fn bad_input(args: &[&str], needles: &[&str]) {
    let out = dembound().args(args).output().expect("the binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: `{needle}` not in {err}");
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// Glass beads (R = 1 mm, E = 63 GPa, ν = 0.22, ρ = 2500 kg/m³) dropped
/// 0.1 m onto a boundary with ν_b = 0.3.
const GLASS: [&str; 12] = [
    "--set",
    "particle.radius=1e-3",
    "--set",
    "particle.youngs_modulus=63e9",
    "--set",
    "particle.poisson_ratio=0.22",
    "--set",
    "particle.density=2500",
    "--set",
    "motion.gap=0.1",
    "--set",
    "boundary.poisson_ratio=0.3",
];

fn with_glass(args: &[&'static str]) -> Vec<&'static str> {
    let mut v = args.to_vec();
    v.extend(GLASS);
    v
}

/// The one limit of a `recommend --json` answer.
fn only_limit(v: &serde_json::Value) -> &serde_json::Value {
    let limits = v["limits"].as_array().expect("limits");
    assert_eq!(limits.len(), 1, "{v}");
    &limits[0]
}

#[test]
fn glass_on_steel_answers_match_an_independent_computation() {
    // The expected values come from tests/independent/glass_on_steel.py
    // (mpmath, 30 digits, not dembound): Hertz, T_c within 0.5 %, the
    // general eq 6 mixing 1/E* = (1 − ν_m²)/E_m + (1 − ν_b²)/E_b, R* =
    // R_m R_b/(R_m + R_b). With gravity during the contact, T_c by
    // tanh-sinh quadrature of the energy integral and the limit by a root
    // finder: (a) E_b = 4.80167300758e12 Pa, (b) R_b = 0.039602198435 m.
    // Gravity-free closed form T_c ∝ (m²/(E*² R* v))^(1/5): (a) E_b =
    // (1 − ν_b²) E_m/((1 − ν_m²)(1.005^2.5 − 1)) = 4.80165094431e12 Pa,
    // (b) R_b = R_m/(1.005^5 − 1) = 0.0396019949951 m.
    //
    // Tolerances: both sides solve the same equation, dembound by Brent to
    // 1e−14 on a quadrature good to 1e−15, the script to 30 digits; the
    // deviation's rounding floor at T = 0.005 is 1e−16/T = 2e−14. 1e−8
    // leaves a wide margin over those and is still 500 times finer than
    // the gravity effect (below), so it would catch gravity left out. The
    // gravity-free forms differ from the answers by 4.6e−6 and 5.1e−6 (the
    // script), bounded by γ = 2 g h_max/v_c² = 2.4e−5: checked to 2e−5.
    let a = json(&with_glass(&[
        "recommend",
        "--tolerance",
        "0.5%",
        "--law",
        "hertz",
        "--quantity",
        "duration",
        "--r",
        "inf",
        "--json",
    ]));
    let l = only_limit(&a);
    let eb = l["boundary_youngs_modulus"].as_f64().unwrap();
    assert!(rel(eb, 4.80167300758e12) < 1e-8, "{l}");
    assert!(rel(eb, 4.80165094431e12) < 2e-5, "{l}");
    let zeta = l["outcome"]["value"].as_f64().unwrap();
    assert!(rel(zeta * 63e9, eb) < 1e-15, "{l}");
    // The "closed form" column is the ν_b-correct gravity-free one.
    assert!(rel(l["gravity_free"].as_f64().unwrap(), 4.80165094431e12 / 63e9) < 1e-10);
    assert_eq!(l["boundary_radius"], "inf");

    let b = json(&with_glass(&[
        "recommend",
        "--reference",
        "half-space",
        "--set",
        "boundary.youngs_modulus=200e9",
        "--tolerance",
        "0.5%",
        "--law",
        "hertz",
        "--quantity",
        "duration",
        "--json",
    ]));
    assert_eq!(b["reference"], "half-space");
    let l = only_limit(&b);
    let rb = l["boundary_radius"].as_f64().unwrap();
    assert!(rel(rb, 0.039602198435) < 1e-8, "{l}");
    assert!(rel(rb, 0.0396019949951) < 2e-5, "{l}");
    assert!(rel(l["boundary_youngs_modulus"].as_f64().unwrap(), 200e9) < 1e-15);
    assert!(rel(l["gravity_free"].as_f64().unwrap(), 39.6019949951) < 1e-10);
    // The integrator confirms both limits (its own reference runs).
    for l in [only_limit(&a), l] {
        let sim = l["simulated_deviation"].as_f64().unwrap();
        assert!((sim - 0.005).abs() < 1e-8, "{l}");
    }
}

#[test]
fn recommend_answers_in_si_and_says_against_what() {
    let out = dembound()
        .args(with_glass(&[
            "recommend",
            "--reference",
            "half-space",
            "--set",
            "boundary.youngs_modulus=200e9",
            "--tolerance",
            "0.5%",
            "--law",
            "hertz",
            "--quantity",
            "duration",
        ]))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for needle in [
        "flat wall",
        "E_b = 2e11 Pa",
        "R_b (m)",
        "0.0396022",
        "q(∞, ζ)",
        "c_ν",
    ] {
        assert!(text.contains(needle), "`{needle}` not in {text}");
    }
}

#[test]
fn recommend_prints_the_tradeoff_curve_and_a_pick() {
    // Both r and ζ free: the smallest ζ for each r, from just above the
    // smallest r (ζ = ∞) to r = ∞, and the balanced pick. Gravity-free
    // Hertz T_c, T = 1 %: every point satisfies ζ̄ r̄^(1/2) = 1.01^(−5/2)
    // (ERRATA 16) to the 1e−6 of the other closed-form checks.
    let v = json(&[
        "recommend",
        "--tolerance",
        "1%",
        "--law",
        "hertz",
        "--quantity",
        "duration",
        "--set",
        "motion.gravity=0",
        "--set",
        "motion.velocity=-0.3132",
        "--set",
        "motion.contacts=1",
        "--json",
    ]);
    let tr = &v["tradeoffs"][0];
    let k = 1.01f64.powf(-2.5);
    let bar = |x: f64| x / (x + 1.0);
    let zeta_of = |r: f64| {
        let zb = k / bar(r).sqrt();
        zb / (1.0 - zb)
    };
    let curve = tr["curve"].as_array().unwrap();
    assert!(curve.len() >= 8, "{tr}");
    for p in curve.iter().chain([&tr["pick"]]) {
        let z = p["modulus_ratio"].as_f64().unwrap();
        match p["radius_ratio"].as_f64() {
            Some(r) => {
                assert!(rel(z, zeta_of(r)) < 1e-6, "{p}");
                // R_b = r R_m and E_b = ζ E_m (the default particle).
                assert!(rel(p["boundary_radius"].as_f64().unwrap(), r * 5e-4) < 1e-15);
            }
            None => assert!(rel(z, 1.0 / (1.01f64.powf(2.5) - 1.0)) < 1e-6, "{p}"),
        }
        assert!(rel(p["boundary_youngs_modulus"].as_f64().unwrap(), z * 1e10) < 1e-15);
    }
    // The pick: r alone costs √1.01 − 1 (the balanced share): r̄^(1/2) =
    // 1.01^(−5/4).
    let rb = 1.01f64.powf(-2.5);
    let r_pick = rb / (1.0 - rb);
    assert!(
        rel(tr["pick"]["radius_ratio"].as_f64().unwrap(), r_pick) < 1e-6,
        "{tr}"
    );
    assert!(tr["pick_rule"].as_str().unwrap().contains("balanced"));

    let out = dembound()
        .args([
            "recommend",
            "--tolerance",
            "1%",
            "--law",
            "hertz",
            "--quantity",
            "T_c",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("smallest ζ for each r") && text.contains("pick: r ="),
        "{text}"
    );
}

#[test]
fn recommend_refuses_what_it_cannot_answer() {
    // Below what the numerics resolve: the flag, the value and the range.
    bad_input(
        &["recommend", "--tolerance", "1e-300"],
        &["`--tolerance`", "1e-300", "1e-8"],
    );
    bad_input(&["recommend", "--tolerance", "1e-9"], &["`--tolerance`"]);
    bad_input(
        &["recommend", "--tolerance", "1e5"],
        &["`--tolerance`", "100"],
    );
    // Against a flat wall only r varies.
    bad_input(
        &[
            "recommend",
            "--reference",
            "half-space",
            "--tolerance",
            "1%",
            "--r",
            "10",
        ],
        &["half-space", "--r"],
    );
    bad_input(
        &["recommend", "--reference", "flat", "--tolerance", "1%"],
        &["--reference", "flat"],
    );
    // A dissipative law: the reason, not "unknown".
    bad_input(
        &["recommend", "--tolerance", "1%", "--law", "tsuji"],
        &["`--law`", "tsuji", "dissipative"],
    );
    // A tolerance above 10 % given as a plain fraction: a warning.
    let out = dembound()
        .args([
            "recommend",
            "--tolerance",
            "0.2",
            "--law",
            "linear",
            "--quantity",
            "h_max",
            "--r",
            "inf",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("warning: --tolerance 0.2"));
}

#[test]
fn recommend_takes_lists_for_r_and_zeta() {
    let v = json(&[
        "recommend",
        "--tolerance",
        "1%",
        "--law",
        "hertz",
        "--quantity",
        "h_max",
        "--r",
        "log:100:1000:2,inf",
        "--json",
    ]);
    let limits = v["limits"].as_array().unwrap();
    assert_eq!(limits.len(), 3);
    // A larger r leaves more of the tolerance to ζ: the smallest ζ falls.
    let z: Vec<f64> = limits
        .iter()
        .map(|l| l["outcome"]["value"].as_f64().unwrap())
        .collect();
    assert!(z[0] > z[1] && z[1] > z[2], "{z:?}");
    let v = json(&[
        "recommend",
        "--r",
        "10,100",
        "--zeta",
        "100",
        "--law",
        "hertz",
        "--json",
    ]);
    assert_eq!(v["deviations"].as_array().unwrap().len(), 2);
    assert!(
        rel(
            v["deviations"][1]["boundary_radius"].as_f64().unwrap(),
            0.05
        ) < 1e-15
    );
}

#[test]
fn the_boundary_in_si_in_and_out_of_run() {
    // R_b = 20 mm and E_b = 200 GPa on the default particle (R_m = 0.5 mm,
    // E_m = 10 GPa) are r = 40 and ζ = 20.
    let si = [
        "run",
        "--set",
        "boundary.radius=0.02",
        "--set",
        "boundary.youngs_modulus=2e11",
    ];
    let mut args = si.to_vec();
    args.push("--json");
    let v = json(&args);
    let b = &v["scenario"]["boundary"];
    assert!(
        rel(b["radius_ratio"].as_f64().unwrap(), 40.0) < 1e-15,
        "{b}"
    );
    assert!(
        rel(b["modulus_ratio"].as_f64().unwrap(), 20.0) < 1e-15,
        "{b}"
    );
    assert!(
        rel(b["boundary_radius"].as_f64().unwrap(), 0.02) < 1e-15,
        "{b}"
    );
    assert!(
        rel(b["boundary_youngs_modulus"].as_f64().unwrap(), 2e11) < 1e-15,
        "{b}"
    );
    // The same run given as ratios gives the same contacts.
    let ratios = json(&[
        "run",
        "--set",
        "boundary.radius_ratio=40",
        "--set",
        "boundary.modulus_ratio=20",
        "--json",
    ]);
    for (a, b) in v["contacts"]
        .as_array()
        .unwrap()
        .iter()
        .zip(ratios["contacts"].as_array().unwrap())
    {
        // The ratio R_b/R_m may round differently from 40 in the last bit.
        let (x, y) = (
            a["duration"].as_f64().unwrap(),
            b["duration"].as_f64().unwrap(),
        );
        assert!(rel(x, y) < 1e-13, "{a} {b}");
    }
    // The header states both forms.
    let out = dembound().args(si).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("r = 40 (R_b = 0.02 m)") && text.contains("ζ = 20 (E_b = 2e11 Pa)"),
        "{text}"
    );
    // The resolved scenario.toml reproduces the run.
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("r");
    let mut args = si.to_vec();
    args.push("--out");
    dembound().args(&args).arg(&out_dir).assert().success();
    let file = out_dir.join("scenario.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("radius = 0.02 m"), "{text}");
    let again = json(&["run", file.to_str().unwrap(), "--json"]);
    assert_eq!(again["contacts"], v["contacts"]);
    // Both forms in one file: refused naming both keys.
    let both = dir.path().join("both.toml");
    std::fs::write(&both, "[boundary]\nradius = 0.02\nradius_ratio = 40\n").unwrap();
    bad_input(
        &["run", both.to_str().unwrap()],
        &["boundary.radius`", "boundary.radius_ratio"],
    );
    bad_input(
        &["run", "--set", "boundary.youngs_modulus=-1"],
        &["`boundary.youngs_modulus`", "Pa"],
    );
}

#[test]
fn sweep_names_laws_as_everywhere_and_gives_the_boundary_in_si() {
    bad_input(
        &["sweep", "--r", "1", "--zeta", "1", "--law", "tsuji"],
        &["`--law`", "tsuji", "dissipative", "restitution"],
    );
    bad_input(
        &["sweep", "--r", "1", "--zeta", "1", "--law", "cubic"],
        &["`--law`", "cubic", "walton-braun"],
    );
    let v = json(&[
        "sweep",
        "--r",
        "10",
        "--zeta",
        "lin:10:20:2",
        "--law",
        "hertz",
        "--json",
        "--quiet",
    ]);
    let key = &v["cases"][1]["key"];
    assert_eq!(key["modulus_ratio"], 20.0);
    assert!(
        rel(key["boundary_radius"].as_f64().unwrap(), 5e-3) < 1e-15,
        "{key}"
    );
    assert!(
        rel(key["boundary_youngs_modulus"].as_f64().unwrap(), 2e11) < 1e-15,
        "{key}"
    );
    assert!(v["variants"][0]["scenario"]["boundary"]["boundary_radius"].is_number());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s");
    dembound()
        .args(["sweep", "--r", "10", "--zeta", "inf", "--quiet", "--out"])
        .arg(&out)
        .assert()
        .success();
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.contains("r,zeta,boundary_radius_m,boundary_youngs_modulus_Pa"),
        "{header}"
    );
    assert!(
        csv.lines().nth(1).unwrap().contains("10,inf,0.005,inf"),
        "{csv}"
    );
}

#[test]
fn restitution_takes_the_same_lists_and_law_names() {
    bad_input(
        &["restitution", "--law", "hertz"],
        &["`--law`", "hertz", "elastic"],
    );
    bad_input(&["restitution", "--e", "lin:0.5:1.5:3"], &["`--e`", "1.5"]);
    bad_input(&["restitution", "--r", "log:0:1:3"], &["`--r`"]);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("e");
    dembound()
        .args([
            "restitution",
            "--law",
            "viscous",
            "--e",
            "lin:0.5:0.9:2",
            "--r",
            "log:10:100:2",
            "--zeta",
            "10",
            "--calibrate",
            "pair",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let csv = std::fs::read_to_string(out.join("restitution.csv")).unwrap();
    let mut lines = csv.lines();
    let header = lines.next().unwrap();
    assert!(
        header.contains("radius_ratio,modulus_ratio,boundary_radius_m,boundary_youngs_modulus_Pa"),
        "{header}"
    );
    assert_eq!(lines.count(), 2 * 2, "two e × two r");
    assert!(csv.contains(",10,10,0.005,100000000000,"), "{csv}");
    let v = json(&[
        "restitution",
        "--target",
        "0.5",
        "--law",
        "tsuji",
        "--r",
        "10",
        "--zeta",
        "10",
        "--json",
    ]);
    assert!(
        rel(v[0]["boundary_radius"].as_f64().unwrap(), 5e-3) < 1e-15,
        "{v}"
    );
}

#[test]
fn every_help_has_one_layout() {
    // The compact layout everywhere: no per-value help blocks, `-h` and
    // `--help` alike, every list flag shown as <LIST>, defaults as [default: …].
    for cmd in [
        "run",
        "exact",
        "validate",
        "sweep",
        "recommend",
        "paper",
        "restitution",
    ] {
        let long = dembound().args([cmd, "--help"]).output().unwrap();
        let short = dembound().args([cmd, "-h"]).output().unwrap();
        let text = String::from_utf8_lossy(&long.stdout).to_string();
        assert!(long.status.success());
        assert_eq!(text, String::from_utf8_lossy(&short.stdout), "{cmd}");
        assert!(!text.contains("Possible values"), "{cmd}: {text}");
        assert!(!text.contains("(default:"), "{cmd}: {text}");
        assert!(text.contains(&format!("Usage: dembound {cmd}")), "{text}");
        for flag in ["--r", "--zeta", "--law", "--e"] {
            if let Some(line) = text
                .lines()
                .find(|l| l.trim_start().starts_with(&format!("{flag} <")))
            {
                assert!(line.contains("<LIST>"), "{cmd}: {line}");
            }
        }
    }
}
