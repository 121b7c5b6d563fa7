//! `domain.outside = "delete"` (issue 28): spheres lost for good are
//! removed, counted, their mass and the energy they carry out reported
//! (`--json`, series.csv), and the energy balance closes:
//! K + E + P + D + C = E₀ (C carried out). The same bits on 1 and 2
//! threads and across a restart from a checkpoint.

mod common;

use common::scene_text;
use common::shaft::{number, parse_json, read_output, run_json, shaft_scene};

/// Two spheres (R = 1 mm, ρ = 2500 kg/m³) in a 10 mm box with no walls,
/// gravity −z: both fall out through the floor (the default stops the
/// run: tests/cli_scene_outside.rs).
const OPEN_BOX: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
outside = "delete"

[[material]]
name = "g"
density = 2500.0
youngs_modulus = 1e7
poisson_ratio = 0.3

[[particles]]
material = "g"
spheres = [{ position = [0.005, 0.005, 0.008], radius = 1e-3 }, { position = [0.002, 0.002, 0.002], radius = 1e-3 }]

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
scheme = "verlet"
dt = 1e-5
duration = 0.1

[output]
series_every = 1
"#;

#[test]
fn deleted_spheres_are_counted_and_carry_their_energy_out() {
    // Sphere mass m = ρ 4/3 π R³; at t = 0 both rest (K = 0), so
    // E₀ = P₀ = m g (z₁ + z₂): what the two carry out once both are gone
    // (nothing dissipates: they never touch anything).
    let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-9;
    let e0 = m * 9.81 * (0.008 + 0.002);
    for scheme in ["verlet", "gear5"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let text = OPEN_BOX.replace("scheme = \"verlet\"", &format!("scheme = \"{scheme}\""));
        let (code, stdout, stderr) = scene_text(
            &text,
            dir.path(),
            &["--json", "-q", "--out", out.to_str().unwrap()],
        );
        assert_eq!(code, Some(0), "{scheme}: {stderr}");
        let j = parse_json(&stdout);
        assert_eq!(j["particles"], 2, "{scheme}");
        assert_eq!(j["deleted_particles"], 2, "{scheme}");
        // The mass: a sum of two equal f64 (exact to one rounding).
        let mass = number(&j, "deleted_mass");
        assert!((mass - 2.0 * m).abs() <= 1e-15 * m, "{scheme}: {mass}");
        let b = &j["energy_balance"];
        let carried = number(b, "carried_out_energy");
        // 1e-9 of E₀: Verlet conserves K + P of a free fall exactly (the
        // removal completes the half-step velocity by g Δt/2), Gear5's
        // predictor is exact for a constant acceleration; what remains is
        // the rounding of 10⁴ steps (~1e-12 relative).
        assert!(
            (carried - e0).abs() <= 1e-9 * e0,
            "{scheme}: {carried} vs {e0}"
        );
        assert!(
            (number(b, "total") - number(b, "total_initial")).abs() <= 1e-9 * e0,
            "{scheme}: {b}"
        );
        assert!((number(b, "total_initial") - e0).abs() <= 1e-12 * e0, "{b}");
        let d = number(&j, "dissipated_energy");
        assert!(d.abs() <= 1e-9 * e0, "{scheme}: D = {d}");
        assert_eq!(number(&j, "kinetic_energy"), 0.0);
        assert_eq!(number(&j, "potential_energy"), 0.0);
        // series.csv: the count, mass and energy columns after the others;
        // sphere 1 (z₀ = 2 mm) is removed first: no earlier than the step
        // it is wholly below the floor, n = ⌊√(2 (z₀ + R)/g)/Δt⌋ + 1 = 2474,
        // at the list rebuild that follows, well before sphere 0
        // (z₀ = 8 mm) is lost at step 4284 (the same formula).
        let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
        let header: Vec<&str> = series.lines().next().unwrap().split(',').collect();
        assert_eq!(
            header[header.len() - 3..],
            [
                "deleted_particles",
                "deleted_mass_kg",
                "carried_out_energy_J"
            ]
        );
        let first_step = |count: &str| {
            series
                .lines()
                .skip(1)
                .find(|l| l.split(',').nth(header.len() - 3) == Some(count))
                .and_then(|l| l.split(',').next()?.parse::<u64>().ok())
                .unwrap_or_else(|| panic!("{scheme}: no row with {count} deleted"))
        };
        let lost = |z0: f64| ((2.0 * (z0 + 1e-3) / 9.81f64).sqrt() / 1e-5).floor() as u64 + 1;
        assert_eq!((lost(0.002), lost(0.008)), (2474, 4284));
        let (one, two) = (first_step("1"), first_step("2"));
        assert!((2474..4284).contains(&one), "{scheme}: {one}");
        assert!(two >= 4284, "{scheme}: {two}");
    }
}

#[test]
fn one_and_two_threads_and_a_restart_give_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), shaft_scene(dir.path(), "")).unwrap();
    let one = run_json(dir.path(), "1", "one", &[]);
    // Some spheres fell out, not all, and they met on the way.
    let deleted = one["deleted_particles"].as_u64().unwrap();
    assert!((20..360).contains(&deleted), "{one}");
    assert_eq!(one["particles"], 360);
    let b = &one["energy_balance"];
    // The guard's rounding allowance is 1e-10 per joule; 1e-9 of E₀
    // leaves room for the contacts' integration error (Hertz, no
    // damping: D is that error only).
    assert!(
        (number(b, "total") - number(b, "total_initial")).abs()
            <= 1e-9 * number(b, "total_initial"),
        "{b}"
    );
    let two = run_json(dir.path(), "2", "two", &[]);
    assert_eq!(one, two);
    for file in ["series.csv", "snapshot_000003.vtp", "checkpoint.cbor"] {
        assert!(
            read_output(dir.path(), "one", file) == read_output(dir.path(), "two", file),
            "{file} differs on 2 threads"
        );
    }
    // Half, then from its checkpoint to the end: the one-go run's end.
    let half = run_json(
        dir.path(),
        "1",
        "half",
        &["--set", "integration.steps=13000"],
    );
    // The checkpoint holds some removed spheres, and more go after it.
    let before = half["deleted_particles"].as_u64().unwrap();
    assert!(before > 0 && before < deleted, "{before} of {deleted}");
    let cp = dir.path().join("half").join("checkpoint.cbor");
    let again = run_json(
        dir.path(),
        "2",
        "again",
        &["--restart", cp.to_str().unwrap()],
    );
    assert!(
        read_output(dir.path(), "again", "checkpoint.cbor")
            == read_output(dir.path(), "one", "checkpoint.cbor"),
        "the restarted run's checkpoint differs"
    );
    assert_eq!(again["deleted_particles"], one["deleted_particles"]);
    assert_eq!(again["deleted_mass"], one["deleted_mass"]);
    assert_eq!(
        again["energy_balance"]["carried_out_energy"],
        one["energy_balance"]["carried_out_energy"]
    );
}

/// The end state's ids, positions and velocities (columns 1..7 of
/// state.csv, shortest round-trip text: equal text is equal bits; the
/// last column is the rank).
#[cfg(feature = "mpi")]
fn state(dir: &std::path::Path, name: &str) -> Vec<String> {
    let text = String::from_utf8(read_output(dir, name, "state.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| l.split(',').take(7).collect::<Vec<_>>().join(","))
        .collect()
}

/// The removal under MPI: every rank books every rank's removals in
/// input-id order, so the count, mass and energy carried out are the one
/// process's bits; the end state (state.csv) is the same on 1, 2 and 3
/// ranks, and a checkpoint of 2 ranks (after some removals) continues on
/// 3 to the same end.
#[cfg(feature = "mpi")]
#[test]
fn one_two_three_ranks_remove_the_same_spheres() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), shaft_scene(dir.path(), "")).unwrap();
    let local = run_json(dir.path(), "1", "local", &[]);
    let one = common::shaft::mpirun_json(dir.path(), 1, "r1", &[]);
    let removed = |j: &serde_json::Value| {
        (
            j["deleted_particles"].clone(),
            j["deleted_mass"].clone(),
            j["energy_balance"]["carried_out_energy"].clone(),
        )
    };
    assert_eq!(removed(&one), removed(&local));
    let deleted = one["deleted_particles"].as_u64().unwrap();
    assert!(deleted > 20, "{one}");
    // The removed spheres are not in the end state.
    assert_eq!(state(dir.path(), "r1").len() as u64, 360 - deleted);
    for ranks in [2, 3] {
        let j = common::shaft::mpirun_json(dir.path(), ranks, &format!("r{ranks}"), &[]);
        assert_eq!(removed(&j), removed(&one), "{ranks} ranks");
        assert_eq!(
            state(dir.path(), &format!("r{ranks}")),
            state(dir.path(), "r1"),
            "{ranks} ranks"
        );
    }
    let half =
        common::shaft::mpirun_json(dir.path(), 2, "half", &["--set", "integration.steps=13000"]);
    assert!(half["deleted_particles"].as_u64().unwrap() > 0, "{half}");
    let cp = dir.path().join("half").join("checkpoint.cbor");
    let again =
        common::shaft::mpirun_json(dir.path(), 3, "again", &["--restart", cp.to_str().unwrap()]);
    assert_eq!(removed(&again), removed(&one));
    assert_eq!(state(dir.path(), "again"), state(dir.path(), "r1"));
}
