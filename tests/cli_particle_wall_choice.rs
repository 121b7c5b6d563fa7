//! `dembound particle-wall --tolerance` (issue 29 item 2): the chosen
//! sphere size against `recommend`'s answer for the same inputs and
//! against the gravity-free closed form; the leak limit; the deviations of
//! a given `--radius`; refusals exit 2 naming the option, writing nothing.

mod common;

use common::{dembound, json};

/// Glass beads (R = 1 mm) on a steel part: the README's materials.
const GLASS_ON_STEEL: [&str; 12] = [
    "--set",
    "particle.radius=1e-3",
    "--set",
    "particle.youngs_modulus=63e9",
    "--set",
    "particle.poisson_ratio=0.22",
    "--set",
    "particle.density=2500",
    "--set",
    "boundary.youngs_modulus=200e9",
    "--set",
    "boundary.poisson_ratio=0.3",
];

/// R_b of the written covering (spheres.csv, shortest round-trip decimals).
fn written_radius(out: &std::path::Path) -> f64 {
    let text = std::fs::read_to_string(out.join("spheres.csv")).unwrap();
    let line = text.lines().nth(1).expect("at least one sphere");
    line.rsplit(',').next().unwrap().parse().unwrap()
}

fn particle_wall(args: &[&str], out: &std::path::Path) -> std::process::Output {
    dembound()
        .arg("particle-wall")
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn chosen_radius_is_recommends_answer() {
    // The same particle, part and speed asked of `recommend` (the flat
    // wall of the boundary's material, the impact speed as an initial
    // velocity with no gap): the chosen r is the largest of its smallest
    // r over the asked quantities. Both reach the core's search from
    // their own argument parsing; equal to rounding of R_b = r R_m.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("chosen");
    let mut args = vec!["square:0.02", "--speed", "1", "--tolerance", "20%"];
    args.extend(["--quantity", "h_max,T_c"]);
    args.extend(GLASS_ON_STEEL);
    let run = particle_wall(&args, &out);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let mut rec = vec!["recommend", "--reference", "half-space", "--law", "hertz"];
    rec.extend(["--quantity", "h_max,T_c", "--tolerance", "20%", "--json"]);
    rec.extend(["--set", "motion.gap=0", "--set", "motion.velocity=-1"]);
    rec.extend(GLASS_ON_STEEL);
    let answer = json(&rec);
    let r = answer["limits"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["outcome"]["value"].as_f64().unwrap())
        .fold(f64::NEG_INFINITY, f64::max);
    let r_b = written_radius(&out);
    assert!(
        (r_b / 1e-3 / r - 1.0).abs() < 1e-14,
        "{r_b} against r = {r}"
    );
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("## Choice of R_b") && report.contains("## Friction added by the bumps")
    );
    assert!(report.contains("cannot pass"), "{report}");
}

#[test]
fn without_gravity_the_choice_is_the_closed_form() {
    // Without gravity T_c/T_c(∞, ζ) = r̄^(−(2−α)/(α+1)) (ERRATA 16; the
    // ζ factor cancels against a wall of the spheres' material), so the
    // smallest r within T for Hertz solves r̄ = (1 + T)^(−5): r = r̄/(1 − r̄).
    // Brent's tolerance (1e-14 relative in 1/r) and the exact model's
    // ~1e-12 leave 1e-9 of margin.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("g0");
    let mut args = vec!["square:0.02", "--speed", "2", "--tolerance", "0.1"];
    args.extend(["--quantity", "T_c", "--set", "motion.gravity=0"]);
    args.extend(["--set", "motion.contacts=1"]);
    args.extend(GLASS_ON_STEEL);
    let run = particle_wall(&args, &out);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let rb_bar = 1.1f64.powi(-5);
    let expected = rb_bar / (1.0 - rb_bar) * 1e-3;
    let r_b = written_radius(&out);
    assert!(
        (r_b / expected - 1.0).abs() < 1e-9,
        "{r_b} against {expected}"
    );
}

#[test]
fn spheres_that_leak_are_refused_naming_the_tolerance() {
    // Glass on steel within 3 %: recommend's r ≈ 6.3 gives touching
    // square holes of (√2 − 1) r R = 2.6 R: the particle passes. Refused
    // (exit 2), the message naming --tolerance and the leak-free limit
    // r < 1/(√2 − 1) = 2.4142; nothing written.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    let mut args = vec!["square:0.05", "--speed", "1", "--tolerance", "3%"];
    args.extend(GLASS_ON_STEEL);
    let run = particle_wall(&args, &out);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("`--tolerance`") && stderr.contains("r = 2.4142"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn a_given_radius_states_its_deviations() {
    // R_b = R_m (r = 1), no gravity: T_c deviates by r̄^(−1/5) − 1 =
    // 2^(1/5) − 1 = 14.87 % (Hertz, closed form as above), h_max the same.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("given");
    let mut args = vec!["square:0.02", "--radius", "1e-3", "--speed", "2"];
    args.extend(["--set", "motion.gravity=0", "--set", "motion.contacts=1"]);
    args.extend(GLASS_ON_STEEL);
    let run = particle_wall(&args, &out);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let expected = format!("| hertz | T_c | {:.2} % |", (2f64.powf(0.2) - 1.0) * 100.0);
    assert!(
        report.contains("## Single-contact deviations of R_b"),
        "{report}"
    );
    assert!(report.contains(&expected), "{expected} not in {report}");
}

#[test]
fn refusals_exit_2_naming_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never");
    for (args, named) in [
        (
            vec!["square:1", "--radius", "1e-3", "--tolerance", "3%"],
            "--tolerance",
        ),
        (vec!["square:1"], "--radius"),
        (
            vec!["square:1", "--tolerance", "3%", "--speed", "-1"],
            "--speed",
        ),
        (vec!["square:1", "--tolerance", "0"], "--tolerance"),
        (
            vec!["square:1", "--tolerance", "3%", "--quantity", "e"],
            "--quantity",
        ),
        (
            vec!["square:1", "--tolerance", "3%", "--law", "nonsense"],
            "--law",
        ),
        (
            vec!["square:1", "--tolerance", "3%", "--min-radius", "0"],
            "--min-radius",
        ),
        (
            vec![
                "square:1",
                "--tolerance",
                "3%",
                "--set",
                "particle.radius=-1",
            ],
            "particle.radius",
        ),
    ] {
        let run = particle_wall(&args, &out);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(named),
            "{args:?} should name {named}: {stderr}"
        );
        assert!(!out.exists(), "{args:?} left {}", out.display());
    }
}
