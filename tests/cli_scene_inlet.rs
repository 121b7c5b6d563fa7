//! `[[inlet]]` (issue 28): spheres inserted during the run. The count and
//! mass inserted against rate × time (cumulative rounding, number and mass
//! rates), the energy they bring in booked so the balance closes, the same
//! bits on 1 and 2 threads, refusals naming the key (exit 2), and the
//! same counts under MPI. The non-overlap of every insertion is checked over
//! 10⁵ insertions by the unit tests of `dembound_scene::inlets`.

mod common;

use common::scene_text;
use common::shaft::{number, parse_json, read_output, run_json};
use std::f64::consts::PI;

const RHO: f64 = 2500.0;
const R: f64 = 1e-3;

/// A tall box (0.5 m) with two inlets at its top: inlet 0 at 2500
/// spheres/s, inlet 1 at 0.01 kg/s, both of R = 1 mm, ending at 0.05 s,
/// events every 500 steps of 2 µs (1 ms). The regions are one layer thin
/// (2.2 mm: centres within 0.2 mm in height) and the spheres start at
/// 0.5 m/s downwards, so each has left the centres' layer (by ≥ 0.5 mm)
/// before the next event: every earlier sphere is below every later one
/// and faster, and none touches anything in the 0.06 s run (they fall
/// ≤ 48 mm; the floor is 0.45 m below).
fn falling_scene(extra: &str) -> String {
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.1, 0.1, 0.5]
[[material]]
name = "glass"
density = {RHO:e}
youngs_modulus = 1e8
poisson_ratio = 0.25
[contact]
law = "hertz"
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "rigid"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
dt = 2e-6
duration = 0.06
[[inlet]]
region = {{ box = {{ lower = [0.0, 0.0, 0.4978], upper = [0.05, 0.1, 0.5] }} }}
rate = {{ number = 2500.0 }}
size = {{ fixed = {R:e} }}
material = "glass"
velocity = [0.0, 0.0, -0.5]
end = 0.05
every = 500
seed = 1
[[inlet]]
region = {{ cylinder = {{ center = [0.075, 0.05, 0.4989], axis = [0.0, 0.0, 1.0], radius = 0.02, length = 0.0022 }} }}
rate = {{ mass = 0.01 }}
size = {{ fixed = {R:e} }}
material = "glass"
velocity = [0.0, 0.0, -0.5]
end = 0.05
every = 500
seed = 2
{extra}
"#
    )
}

/// Counts and masses: inlet 0 inserts round(2500 · 0.05) = 125 spheres
/// (events k = 0..49 at steps 1 + 500 k, each bringing the spheres due by
/// the end of its 1 ms interval), inlet 1 round(0.01 kg/s · 0.05 s / m) =
/// round(47.746…) = 48, m = 4/3 π ρ R³; all placed (the regions hold
/// thousands). Masses exact to the rounding of 125 additions (1e-12).
/// The energy: falling freely, the spheres keep the K + P they brought
/// in (Verlet is exact for a constant force), so D = 0 to rounding: 1e-9
/// of the energy brought in.
#[test]
fn counts_masses_and_energy_follow_the_rates() {
    let dir = tempfile::tempdir().unwrap();
    let (code, out, err) = scene_text(&falling_scene(""), dir.path(), &["--json", "-q"]);
    assert_eq!(code, Some(0), "{err}");
    let j = parse_json(&out);
    let m = 4.0 / 3.0 * PI * RHO * R * R * R;
    let inlets = j["inlets"].as_array().expect("inlets");
    assert_eq!(inlets.len(), 2);
    let expect = [125u64, (0.01 * 0.05 / m).round() as u64];
    assert_eq!(expect[1], 48);
    for (k, &n) in expect.iter().enumerate() {
        assert_eq!(inlets[k]["inserted"].as_u64(), Some(n), "inlet {k}");
        assert_eq!(inlets[k]["not_placed"].as_u64(), Some(0), "inlet {k}");
        let mass = number(&inlets[k], "mass");
        assert!(
            (mass - n as f64 * m).abs() <= 1e-12 * mass,
            "inlet {k}: {mass}"
        );
    }
    assert_eq!(number(&j, "particles") as u64, 125 + 48);
    assert_eq!(j["particle_contacts"].as_u64(), Some(0));
    assert_eq!(j["wall_contacts"].as_u64(), Some(0));
    let b = &j["energy_balance"];
    let brought = number(b, "brought_in_energy");
    // Each sphere brings m g z ≈ 1e-5 kg · 9.81 · 0.47 m ≈ 5e-5 J.
    assert!(brought > 173.0 * m * 9.81 * 0.45, "{brought}");
    let d = number(&j, "dissipated_energy");
    assert!(d.abs() <= 1e-9 * brought, "D = {d} J of {brought} J");
    let total = number(b, "total") - number(b, "total_initial");
    assert!(total.abs() <= 1e-9 * brought, "{total}");
}

/// A Gear5 scene that starts with no sphere takes the inlets' spheres
/// (found by a random sweep of keys, session 34: the scene's start made
/// Gear5's vectors for its zero bodies, the inlets added none, and the
/// predictor read past them: a segmentation fault). The counts of
/// `counts_masses_and_energy_follow_the_rates`, with and without friction
/// (its rotational vectors too); free flight under constant gravity is a
/// polynomial Gear5 integrates exactly, so D = 0 to rounding (1e-9 of the
/// energy brought in, as for Verlet there).
#[test]
fn a_gear5_scene_that_starts_empty_takes_the_inlets_spheres() {
    for friction in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let mut args = vec!["--json", "-q", "--set", "integration.scheme=gear5"];
        if friction {
            args.extend(["--set", "contact.friction=0.5"]);
        }
        let (code, out, err) = scene_text(&falling_scene(""), dir.path(), &args);
        assert_eq!(code, Some(0), "friction {friction}: {err}");
        let j = parse_json(&out);
        assert_eq!(
            number(&j, "particles") as u64,
            125 + 48,
            "friction {friction}"
        );
        let brought = number(&j["energy_balance"], "brought_in_energy");
        let d = number(&j, "dissipated_energy");
        assert!(
            d.abs() <= 1e-9 * brought,
            "friction {friction}: D = {d} J of {brought} J"
        );
    }
}

/// The text summary names what the inlets did and the balance's terms:
/// the header counts the 125 + 48 inserted spheres (the closed-form counts
/// of `counts_masses_and_energy_follow_the_rates`) apart from the free
/// spheres at the start (none), each inlet's line gives its count, and the
/// balance line says that its total subtracts what was brought in (a
/// total of K + E + P + D alone would not be the initial energy).
#[test]
fn the_summary_names_the_inserted_spheres_and_the_balance_terms() {
    let dir = tempfile::tempdir().unwrap();
    let (code, out, err) = scene_text(&falling_scene(""), dir.path(), &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("173 spheres (0 free at the start, 0 fixed, 173 inserted by inlets)"),
        "{out}"
    );
    assert!(out.contains("inlet 0: 125 spheres inserted"), "{out}");
    assert!(out.contains("inlet 1: 48 spheres inserted"), "{out}");
    assert!(
        out.contains("energy balance: kinetic + elastic + potential + dissipated − brought in = "),
        "{out}"
    );
}

/// The series has the inlets' columns (and only with inlets): spheres and
/// mass so far, and the energy brought in; the last row's counts are the
/// JSON's.
#[test]
fn the_series_has_the_inlet_columns() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), falling_scene("")).unwrap();
    let j = run_json(dir.path(), "1", "a", &[]);
    let text = String::from_utf8(read_output(dir.path(), "a", "series.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for col in [
        "inlet0_inserted",
        "inlet0_mass_kg",
        "inlet1_inserted",
        "inlet1_mass_kg",
        "brought_in_energy_J",
    ] {
        assert!(header.contains(&col), "{col} in {header:?}");
    }
    let last: Vec<&str> = text.lines().last().unwrap().split(',').collect();
    let at = |c: &str| last[header.iter().position(|h| *h == c).unwrap()];
    assert_eq!(at("inlet0_inserted"), "125");
    assert_eq!(
        at("inlet1_inserted"),
        j["inlets"][1]["inserted"].to_string()
    );
}

/// A pour onto the floor of a box periodic in x and y (contacts, images, a size distribution, spheres of an
/// inlet landing on earlier ones): the same bits on 1 and 2 threads.
#[test]
fn threads_give_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    let scene = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.03, 0.03, 0.06]
periodic = [true, true, false]
[[material]]
name = "glass"
density = 2500.0
youngs_modulus = 1e8
poisson_ratio = 0.25
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
friction = 0.3
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "rigid"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
dt = 2e-6
duration = 0.03
[[inlet]]
region = { box = { lower = [0.0, 0.0, 0.03], upper = [0.03, 0.03, 0.06] } }
rate = { number = 15000.0 }
size = { normal = { mean = 1e-3, std = 2e-4, min = 6e-4, max = 1.4e-3 } }
material = "glass"
velocity = [0.0, 0.0, -1.0]
"#;
    std::fs::write(dir.path().join("scene.toml"), scene).unwrap();
    let a = run_json(dir.path(), "1", "t1", &[]);
    let b = run_json(dir.path(), "2", "t2", &[]);
    assert_eq!(a, b);
    assert!(a["inlets"][0]["inserted"].as_u64().unwrap() > 400);
    // Damped collisions happened: they alone dissipate (D > 0; free
    // flight keeps D at rounding, 1e-15 J here).
    assert!(number(&a, "dissipated_energy") > 1e-6, "{a}");
    for file in ["series.csv", "checkpoint.cbor"] {
        assert!(
            read_output(dir.path(), "t1", file) == read_output(dir.path(), "t2", file),
            "{file} differs"
        );
    }
}

/// Bad input exits 2 naming the key, with no output.
#[test]
fn bad_inlets_are_refused_naming_the_key() {
    let cases = [
        (
            "size = { fixed = 1e-3 }",
            "size = { fixed = -1e-3 }",
            "inlet[0].size.fixed",
        ),
        (
            "size = { fixed = 1e-3 }",
            "size = { uniform = [2e-3, 1e-3] }",
            "inlet[0].size.uniform",
        ),
        (
            "rate = { number = 2500.0 }",
            "rate = { number = 0.0 }",
            "inlet[0].rate.number",
        ),
        // 1e9 spheres/s of 4.2e-9 m³ each over 500 steps of 2 µs: 4.2 m³
        // per event in a 2.5e-4 m³ region.
        (
            "rate = { number = 2500.0 }",
            "rate = { number = 1e9 }",
            "inlet[0].rate.number",
        ),
        (
            "material = \"glass\"\nvelocity",
            "material = \"sand\"\nvelocity",
            "inlet[0].material",
        ),
        (
            "upper = [0.05, 0.1, 0.5] }",
            "upper = [0.05, 0.1, 0.6] }",
            "inlet[0].region",
        ),
        (
            "end = 0.05\nevery = 500\nseed = 1",
            "end = -1.0\nevery = 500\nseed = 1",
            "inlet[0].end",
        ),
        (
            "every = 500\nseed = 1",
            "every = 0\nseed = 1",
            "inlet[0].every",
        ),
    ];
    for (from, to, key) in cases {
        let text = falling_scene("");
        assert!(text.contains(from), "{from}");
        let text = text.replacen(from, to, 1);
        let dir = tempfile::tempdir().unwrap();
        let (code, out, err) = scene_text(&text, dir.path(), &["--json", "-q"]);
        assert_eq!(code, Some(2), "{to}: {err}");
        assert!(out.is_empty());
        assert!(err.contains(key), "{to}: {err}");
    }
}

/// Under MPI (2 ranks, each owning some of the inserted spheres) the
/// inlets insert what one process does: inlet 0 round(2500 · 0.05) = 125
/// spheres, inlet 1 round(0.01 · 0.05 / m) = 48 (as
/// `counts_masses_and_energy_follow_the_rates`), the same report to the
/// bit (every rank places the same spheres: tests/mpi.rs checks the
/// states).
#[cfg(feature = "mpi")]
#[test]
fn mpi_inserts_what_one_process_does() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, falling_scene("")).unwrap();
    let o = std::process::Command::new("mpirun")
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .args(["--oversubscribe", "-np", "2"])
        .arg(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(&scene)
        .args(["--json", "-q"])
        .output()
        .expect("mpirun runs (Debian: openmpi-bin)");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let (code, out, err) = scene_text(&falling_scene(""), dir.path(), &["--json", "-q"]);
    assert_eq!(code, Some(0), "{err}");
    let one: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let owned: Vec<u64> = j["rank_particles"]
        .as_array()
        .expect("per-rank counts")
        .iter()
        .filter_map(|v| v.as_u64())
        .collect();
    assert!(
        owned.len() == 2 && owned.iter().all(|&k| k > 0),
        "{owned:?}"
    );
    assert_eq!(j["inlets"][0]["inserted"], 125);
    assert_eq!(j["inlets"][1]["inserted"], 48);
    assert_eq!(j["inlets"], one["inlets"]);
    assert_eq!(j["particles"], one["particles"]);
    assert_eq!(
        j["energy_balance"]["brought_in_energy"],
        one["energy_balance"]["brought_in_energy"]
    );
}

/// A pour restarted mid-way goes on as the uninterrupted run:
/// examples/scenes/pour.toml at 0.05 kg/s until 0.08 s (events every 500
/// steps, given: the default interval depends on the run's length), run
/// to 0.12 s in one go, and 25,000 steps (0.05 s, 234 spheres in) then restarted
/// from its checkpoint to 0.12 s. The restarted run's final checkpoint is
/// the same file (every body's state, the inserted spheres and the inlet
/// counts), its JSON the same but for timing, steps_this_run and the
/// energy guard's scale (the largest |P − P₀| seen, P₀ taken at a run's
/// first check: not the same reference after a restart), and its series
/// rows the uninterrupted run's at every step both have.
#[test]
fn a_pour_restarted_mid_way_goes_on_as_the_uninterrupted_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/pour.toml");
    let run = |name: &str, more: &[&str]| -> (std::path::PathBuf, serde_json::Value) {
        let out = dir.path().join(name);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_dembound"))
            .arg("scene")
            .arg(&scene)
            .args([
                "--set",
                "inlet.0.rate.mass=0.05",
                "--set",
                "inlet.0.end=0.08",
                "--set",
                "inlet.0.every=500",
                "--set",
                "output.series_every=100",
                "--json",
                "-q",
            ])
            .args(more)
            .arg("--out")
            .arg(&out)
            .output()
            .expect("dembound runs");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{name}: {err}");
        (out, serde_json::from_slice(&o.stdout).expect("JSON"))
    };
    let full = ["--set", "integration.duration=0.12"];
    let (a, ja) = run("whole", &full);
    let (b, jb) = run("half", &["--set", "integration.steps=25000"]);
    // Mid-pour: some spheres in, more to come.
    let half = jb["inlets"][0]["inserted"].as_u64().unwrap();
    let all = ja["inlets"][0]["inserted"].as_u64().unwrap();
    assert!(half > 0 && half < all, "{half} of {all}");
    let cp = b.join("checkpoint.cbor");
    let restart = [&full[..], &["--restart", cp.to_str().unwrap()]].concat();
    let (c, jc) = run("restarted", &restart);
    let bytes = |d: &std::path::Path| std::fs::read(d.join("checkpoint.cbor")).unwrap();
    assert!(bytes(&a) == bytes(&c), "final checkpoints differ");
    let strip = |j: &serde_json::Value| {
        let mut j = j.clone();
        let o = j.as_object_mut().unwrap();
        o.retain(|k, _| !k.contains("clock") && !k.contains("per_second") && k != "steps_this_run");
        if let Some(b) = o.get_mut("energy_balance").and_then(|b| b.as_object_mut()) {
            b.remove("scale");
        }
        j
    };
    assert_eq!(strip(&ja), strip(&jc));
    let rows = |d: &std::path::Path| -> Vec<String> {
        std::fs::read_to_string(d.join("series.csv"))
            .unwrap()
            .lines()
            .map(str::to_string)
            .collect()
    };
    let (ra, rc) = (rows(&a), rows(&c));
    assert_eq!(ra[0], rc[0]);
    let by_step: std::collections::HashMap<&str, &String> = ra[1..]
        .iter()
        .map(|l| (l.split(',').next().unwrap(), l))
        .collect();
    let mut common = 0;
    for l in &rc[1..] {
        if let Some(w) = by_step.get(l.split(',').next().unwrap()) {
            assert_eq!(*w, l);
            common += 1;
        }
    }
    // 0.05 s to 0.12 s every 100 steps of 2 µs: 351 rows.
    assert_eq!(common, 351);
}
