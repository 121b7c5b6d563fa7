//! The physics registry's laws beyond the paper's (`hooke`, `hertz-kn`)
//! through `dembound run`: usable by name with `contact.stiffness`, checked
//! against the registry's ranges (exit 2 naming key, value and range), and
//! equal to the paper's laws when given the paper's stiffness.

mod common;

use common::dembound;
use serde_json::Value;

/// The default scenario's pair (particle R = 0.5 mm, E = 1e10 Pa, ν = 0.3;
/// boundary r = ζ = 100, same ν), from the formulas of eqs 5–6 (ERRATA 2),
/// not from the program: E_eff = 4/3 / ((1−ν²)/E_m + (1−ν²)/E_b) and
/// R_eff = R r/(1 + r).
fn default_pair() -> (f64, f64) {
    let (radius, modulus, nu, ratio) = (0.5e-3, 1e10, 0.3, 100.0);
    let compliance = (1.0 - nu * nu) / modulus + (1.0 - nu * nu) / (ratio * modulus);
    (4.0 / 3.0 / compliance, radius * ratio / (1.0 + ratio))
}

fn run(sets: &[String]) -> std::process::Output {
    let mut cmd = dembound();
    cmd.arg("run").arg("--json");
    for s in sets {
        cmd.arg("--set").arg(s);
    }
    cmd.output().expect("the binary runs")
}

fn contacts(sets: &[String]) -> Vec<Value> {
    let out = run(sets);
    assert!(
        out.status.success(),
        "{sets:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    json["contacts"].as_array().expect("contacts").clone()
}

fn sets(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| s.to_string()).collect()
}

/// Same contacts to `tol` relative, same step counts.
fn assert_same(a: &[Value], b: &[Value], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b) {
        for key in ["restitution", "max_overlap", "duration", "max_force"] {
            let (u, v) = (x[key].as_f64().unwrap(), y[key].as_f64().unwrap());
            assert!((u / v - 1.0).abs() <= tol, "{what} {key}: {u} vs {v}");
        }
        assert_eq!(x["steps"], y["steps"], "{what} steps");
    }
}

#[test]
fn hooke_with_the_paper_stiffness_is_the_linear_law() {
    // F = k_n h with k_n = E_eff R_eff is eq 4 at α = 1. The two laws are
    // separate types (rounding of k differs by at most an ulp or two):
    // 1e−12 relative, the equality harness's tolerance.
    let (modulus, radius) = default_pair();
    let k = format!("contact.stiffness={:e}", modulus * radius);
    let hooke = contacts(&[sets(&["contact.law=hooke"]), vec![k.clone()]].concat());
    let linear = contacts(&sets(&["contact.law=linear"]));
    assert_same(&hooke, &linear, 1e-12, "hooke elastic");
    // With viscous damping: the spring–dashpot, calibrated alike.
    let damped = ["contact.damping=viscous", "contact.restitution=0.5"];
    let hooke = contacts(&[sets(&["contact.law=hooke"]), vec![k], sets(&damped)].concat());
    let linear = contacts(&[sets(&["contact.law=linear"]), sets(&damped)].concat());
    assert_same(&hooke, &linear, 1e-12, "hooke + viscous");
}

#[test]
fn hertz_kn_with_the_pair_modulus_is_hertz() {
    // LAMMPS granular `hertz`, F = k_n √R_eff h^(3/2): with k_n = E_eff it
    // is eq 4 at α = 3/2. It runs through the registry's generic path (no
    // code of its own in the bounce crate), Hertz through its own type: the
    // same force up to the order of two multiplications, 1e−12.
    let (modulus, _) = default_pair();
    let k = format!("contact.stiffness={modulus:e}");
    let given = contacts(&[sets(&["contact.law=hertz-kn"]), vec![k.clone()]].concat());
    let hertz = contacts(&sets(&["contact.law=hertz"]));
    assert_same(&given, &hertz, 1e-12, "hertz-kn elastic");
    let damped = ["contact.damping=tsuji", "contact.restitution=0.5"];
    let given = contacts(&[sets(&["contact.law=hertz-kn"]), vec![k], sets(&damped)].concat());
    let hertz = contacts(&[sets(&["contact.law=hertz"]), sets(&damped)].concat());
    assert_same(&given, &hertz, 1e-12, "hertz-kn + tsuji");
}

#[test]
fn registry_parameters_are_checked_with_key_value_and_range() {
    for (args, key, value, allowed) in [
        (
            vec!["contact.law=hooke"],
            "contact.stiffness",
            "missing",
            "finite and > 0",
        ),
        (
            vec!["contact.law=hooke", "contact.stiffness=-1"],
            "contact.stiffness",
            "-1",
            "finite and > 0",
        ),
        (
            vec!["contact.law=hertz", "contact.stiffness=5"],
            "contact.stiffness",
            "5",
            "\"hooke\" or \"hertz-kn\"",
        ),
        (
            vec![
                "contact.law=hertz-kn",
                "contact.stiffness=1e9",
                "contact.damping=viscous",
            ],
            "contact.damping",
            "viscous",
            "\"tsuji\"",
        ),
        (
            vec!["contact.law=hooke", "contact.stifness=1e5"],
            "contact.stifness",
            "unknown field",
            "`stiffness`",
        ),
        (
            vec!["contact.law={power=1.25}", "contact.exponent=1.5"],
            "contact.exponent",
            "1.5",
            "no law takes it as a key",
        ),
        (
            vec!["contact.law=nope"],
            "contact.law",
            "nope",
            "\"hertz-kn\"",
        ),
    ] {
        let out = run(&sets(&args));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}: no output on bad input");
        for part in [key, value, allowed] {
            assert!(err.contains(part), "{args:?}: {part} not in {err}");
        }
    }
}
