//! `[[outlet]]` (issue 28): free spheres whose centres enter an outlet box
//! are removed (once they touch nothing), counted per outlet with their
//! mass and the mass flow rate (`--json` `outlets`, series.csv), the energy
//! they carry out booked; the same bits on 1 and 2 threads, across a
//! restart and on 1, 2 and 3 MPI ranks; bad boxes refused naming the key.

mod common;

use common::scene_text;
use common::shaft::{number, parse_json, read_output, run_json, shaft_scene};

const G: f64 = 9.81;
/// Sphere radius, m, and density, kg/m³.
const R: f64 = 1e-3;
const RHO: f64 = 2500.0;
/// The list skin, m: a sphere is removed at the first list rebuild after
/// its centre entered, and rebuilds come whenever a sphere moved skin/2.
const SKIN: f64 = 2e-4;
const DT: f64 = 1e-5;
const STEPS: u64 = 8000;
/// Drop heights of the centres above the outlets' top face (z = 5 mm), m:
/// column A (x = 2.5 mm, outlet 0) and column B (x = 7.5 mm, outlet 1),
/// 5 mm or more apart vertically and 5 mm across: starting at rest they
/// fall with the same velocity and never touch.
const DROPS_A: [f64; 3] = [0.005, 0.010, 0.015];
const DROPS_B: [f64; 2] = [0.007, 0.0125];

fn columns() -> String {
    let sphere = |x: f64, d: f64| {
        format!(
            "{{ position = [{x:e}, 5e-3, {:e}], radius = {R:e} }}",
            0.005 + d
        )
    };
    let spheres: Vec<String> = DROPS_A
        .iter()
        .map(|&d| sphere(0.0025, d))
        .chain(DROPS_B.iter().map(|&d| sphere(0.0075, d)))
        .collect();
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.03]

[[material]]
name = "g"
density = {RHO:e}
youngs_modulus = 1e7
poisson_ratio = 0.3

[[particles]]
material = "g"
spheres = [{}]

[[outlet]]
region = {{ box = {{ lower = [0.0, 0.0, 0.0], upper = [0.005, 0.01, 0.005] }} }}

[[outlet]]
region = {{ box = {{ lower = [0.005, 0.0, 0.0], upper = [0.01, 0.01, 0.005] }} }}

[motion]
gravity = [0.0, 0.0, -{G:e}]

[integration]
scheme = "verlet"
dt = {DT:e}
steps = {STEPS}
skin = {SKIN:e}

[output]
series_every = 1
"#,
        spheres.join(", ")
    )
}

#[test]
fn outlets_remove_a_free_falling_column_at_the_closed_form_times() {
    let m = RHO * 4.0 / 3.0 * std::f64::consts::PI * R * R * R;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (code, stdout, stderr) = scene_text(
        &columns(),
        dir.path(),
        &["--json", "-q", "--out", out.to_str().unwrap()],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let j = parse_json(&stdout);
    assert_eq!(j["deleted_particles"], 5, "{j}");
    let outlets = j["outlets"].as_array().expect("outlets");
    assert_eq!(outlets.len(), 2);
    assert_eq!(outlets[0]["count"], 3);
    assert_eq!(outlets[1]["count"], 2);
    // Sums of three and two equal f64: exact to a rounding or two.
    assert!((number(&outlets[0], "mass") - 3.0 * m).abs() <= 1e-15 * m);
    assert!((number(&outlets[1], "mass") - 2.0 * m).abs() <= 1e-15 * m);
    // Nothing touched anything: all the initial energy m g z₀ left with
    // them (Verlet is exact for a constant acceleration, the removal
    // completes the half-step velocity: rounding only, 1e-9 relative).
    let b = &j["energy_balance"];
    let e0: f64 = DROPS_A
        .iter()
        .chain(&DROPS_B)
        .map(|d| m * G * (0.005 + d))
        .sum();
    assert!(
        (number(b, "carried_out_energy") - e0).abs() <= 1e-9 * e0,
        "{b}"
    );
    assert!(number(&j, "dissipated_energy").abs() <= 1e-9 * e0, "{j}");

    // series.csv: per outlet the count, the mass and the rate columns last.
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    let header: Vec<&str> = series.lines().next().unwrap().split(',').collect();
    assert_eq!(
        header[header.len() - 6..],
        [
            "outlet0_removed",
            "outlet0_mass_kg",
            "outlet0_rate_kg_per_s",
            "outlet1_removed",
            "outlet1_mass_kg",
            "outlet1_rate_kg_per_s"
        ]
    );
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<f64>> = series
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    let time = col("time_s");
    // The removal times: the centre enters at t = √(2 d / g) (Verlet's
    // positions are exact under constant g); it goes at the first list
    // rebuild after, at most (skin/2)/v + Δt later, v = √(2 g d) its entry
    // speed (every sphere falls alike, each rebuild comes once they moved
    // skin/2), plus a step for the row.
    for (k, drops) in [(0, &DROPS_A[..]), (1, &DROPS_B[..])] {
        let c = col(&format!("outlet{k}_removed"));
        for (n, &d) in drops.iter().enumerate() {
            let t_in = (2.0 * d / G).sqrt();
            let late = 0.5 * SKIN / (2.0 * G * d).sqrt() + 2.0 * DT;
            let t = rows
                .iter()
                .find(|r| r[c] >= (n + 1) as f64)
                .map(|r| r[time])
                .unwrap_or_else(|| panic!("outlet {k}: sphere {n} never removed"));
            assert!(
                t >= t_in && t <= t_in + late,
                "outlet {k} sphere {n}: removed at {t} s, enters at {t_in} s"
            );
        }
        // The rate column: each removal appears as m/Δt in its row, and
        // its integral is the mass.
        let rate = col(&format!("outlet{k}_rate_kg_per_s"));
        let integral: f64 = rows.iter().map(|r| r[rate] * DT).sum();
        assert!(
            (integral - drops.len() as f64 * m).abs() <= 1e-9 * m,
            "outlet {k}: {integral}"
        );
    }
    // The steady rate: over the intervals that start at t ≥ T/2 (T = 80
    // ms), the mean of the interval rates; the entries after 40 ms (by the
    // closed form: A at 45.2 and 55.3 ms, B at 50.5 ms; the others at
    // 31.9 and 37.8 ms, removed before 40 ms by the bound above) give
    // c m/Δt in c of the n intervals, 0 in the others: mean c m/(n Δt),
    // standard error √(var/n) with var the sample variance.
    let half = 0.5 * rows.last().unwrap()[time];
    let n = (1..rows.len())
        .filter(|&i| rows[i - 1][time] >= half)
        .count() as f64;
    for (k, drops) in [(0, &DROPS_A[..]), (1, &DROPS_B[..])] {
        let c = drops
            .iter()
            .filter(|&&d| (2.0 * d / G).sqrt() > 0.04)
            .count() as f64;
        let spike = m / DT;
        let mean = c * spike / n;
        let var = (c * (spike - mean).powi(2) + (n - c) * mean * mean) / (n - 1.0);
        let o = &outlets[k];
        // Relative 1e-6: the spikes are m/Δt' with Δt' the row times'
        // difference (Δt to ~1e-12 relative) and the sums' rounding.
        assert!(
            (number(o, "steady_rate") - mean).abs() <= 1e-6 * mean,
            "outlet {k}: {o} vs {mean}"
        );
        assert!(
            (number(o, "steady_rate_error") - (var / n).sqrt()).abs() <= 1e-6 * (var / n).sqrt(),
            "outlet {k}: {o}"
        );
    }
}

/// The colliding shaft (tests/common/shaft.rs) with the left half of its
/// bottom 3 mm an outlet; what misses it is lost below and deleted.
const SHAFT_OUTLET: &str = r#"
[[outlet]]
region = { box = { lower = [0.0, 0.0, 0.0], upper = [0.005, 0.01, 0.003] } }
"#;

#[test]
fn an_outlet_in_a_colliding_shaft_gives_the_same_bits_on_threads_and_restart() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scene.toml"),
        shaft_scene(dir.path(), SHAFT_OUTLET),
    )
    .unwrap();
    let one = run_json(dir.path(), "1", "one", &[]);
    let deleted = one["deleted_particles"].as_u64().unwrap();
    let through = one["outlets"][0]["count"].as_u64().unwrap();
    // Some went through the outlet, some were lost beside it.
    assert!(through > 10 && through < deleted, "{one}");
    let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 1.25e-10;
    let mass = number(&one["outlets"][0], "mass");
    assert!((mass - through as f64 * m).abs() <= 1e-12 * mass, "{mass}");
    // The balance closes with the outlets' spheres carried out too (1e-9
    // of E₀: the contacts' integration error, as in cli_scene_delete).
    let b = &one["energy_balance"];
    assert!(
        (number(b, "total") - number(b, "total_initial")).abs()
            <= 1e-9 * number(b, "total_initial"),
        "{b}"
    );
    let two = run_json(dir.path(), "2", "two", &[]);
    assert_eq!(one, two);
    for file in ["series.csv", "checkpoint.cbor"] {
        assert!(
            read_output(dir.path(), "one", file) == read_output(dir.path(), "two", file),
            "{file} differs on 2 threads"
        );
    }
    let half = run_json(
        dir.path(),
        "1",
        "half",
        &["--set", "integration.steps=13000"],
    );
    let before = half["outlets"][0]["count"].as_u64().unwrap();
    assert!(before > 0 && before < through, "{before} of {through}");
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
    assert_eq!(again["outlets"][0]["count"], one["outlets"][0]["count"]);
    assert_eq!(again["outlets"][0]["mass"], one["outlets"][0]["mass"]);
}

/// Every rank books every rank's removals with their outlet: the per-outlet
/// counts and masses are the one process's bits on 1, 2 and 3 ranks.
#[cfg(feature = "mpi")]
#[test]
fn one_two_three_ranks_give_the_same_outlet_counts() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("scene.toml"),
        shaft_scene(dir.path(), SHAFT_OUTLET),
    )
    .unwrap();
    let local = run_json(dir.path(), "1", "local", &[]);
    let removed = |j: &serde_json::Value| {
        (
            j["deleted_particles"].clone(),
            j["energy_balance"]["carried_out_energy"].clone(),
            j["outlets"][0]["count"].clone(),
            j["outlets"][0]["mass"].clone(),
        )
    };
    for ranks in [1, 2, 3] {
        let j = common::shaft::mpirun_json(dir.path(), ranks, &format!("r{ranks}"), &[]);
        assert_eq!(removed(&j), removed(&local), "{ranks} ranks");
    }
}

#[test]
fn bad_outlet_boxes_are_refused_naming_the_key() {
    let base = columns();
    let old = "upper = [0.005, 0.01, 0.005] }";
    for (new, key) in [
        ("upper = [0.0, 0.01, 0.005] }", "outlet[0].region.box.upper"),
        (
            "upper = [0.005, nan, 0.005] }",
            "outlet[0].region.box.upper",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let text = base.replacen(old, new, 1);
        assert_ne!(text, base);
        let (code, _, stderr) = scene_text(&text, dir.path(), &["-q"]);
        assert_eq!(code, Some(2), "{new}: {stderr}");
        assert!(stderr.contains(key), "{new}: {stderr}");
    }
    let dir = tempfile::tempdir().unwrap();
    let text = base.replacen(
        "box = { lower = [0.0, 0.0, 0.0],",
        "box = { lower = [0.0, inf, 0.0],",
        1,
    );
    assert_ne!(text, base);
    let (code, _, stderr) = scene_text(&text, dir.path(), &["-q"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("outlet[0].region.box.lower"), "{stderr}");
}
