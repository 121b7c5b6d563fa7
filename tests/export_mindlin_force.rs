//! The incremental Hertz–Mindlin spring (`contact.tangential =
//! "mindlin_force"`, issue 32) in the exports: LAMMPS writes its
//! `tangential mindlin/force` with k_t = 8 G* per type pair (and runs the
//! deck), LIGGGHTS refuses it (its `tangential history` is the total
//! spring, dembound's "mindlin") naming the key and the code, Yade accepts
//! it (its Mindlin law increments the shear force) and says so in the deck.
//! Side by side with LAMMPS: spheres thrown obliquely at a plane, through
//! sticking, sliding and unloading, are the same state in both codes.

mod common;

use common::peer::{export_lammps, lattice_bed, missing, run_lmp, STEEL_PLANE_FLOOR};
use common::{dembound, numbers, quantity};
use dembound_export::agreement::IDENTICAL;
use serde_json::Value;
use std::path::Path;

/// `lattice_bed` with undamped Hertz, μ = 0.5 and the tangential spring
/// `tangential`, thrown sideways at a steel plane, 200 steps.
fn bed(tangential: &str) -> String {
    bed_on(tangential, STEEL_PLANE_FLOOR)
}

/// `bed` on the floor body `floor` (Yade: a floor of the grain, since a
/// much stiffer plane has no Yade stand-in material).
fn bed_on(tangential: &str, floor: &str) -> String {
    lattice_bed(
        &format!(
            "law = \"hertz\"\ndamping = \"none\"\ntangential = \"{tangential}\"\nfriction = 0.5"
        ),
        "[0.03, 0.02, -0.1]",
        floor,
        200,
        "",
    )
}

/// G* = 1/((2 − ν₁)/G₁ + (2 − ν₂)/G₂), G = E/(2(1 + ν)) (Mindlin 1949),
/// written from the formula, not through the program's code.
fn shear_modulus_star(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    let g1 = e1 / (2.0 * (1.0 + nu1));
    let g2 = e2 / (2.0 * (1.0 + nu2));
    1.0 / ((2.0 - nu1) / g1 + (2.0 - nu2) / g2)
}

/// The numbers after `tangential mindlin/force` on each line that has it.
fn mindlin_force_args(input: &str) -> Vec<[f64; 3]> {
    input
        .lines()
        .filter_map(|l| l.split("tangential mindlin/force ").nth(1))
        .map(|rest| {
            let v: Vec<f64> = rest
                .split_whitespace()
                .take(3)
                .map(|x| x.parse().expect("a number"))
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// Runs `dembound export CODE scene --out out`; (exit code, stderr).
fn export(code: &str, scene: &Path, out: &Path) -> (Option<i32>, String) {
    let o = dembound()
        .args(["export", code])
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .expect("dembound runs");
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// LAMMPS: every pair is `tangential mindlin/force 8G* 0.0 0.5`, with
/// G* of the pair's materials (grain–grain and grain–steel both appear:
/// the spheres, the side walls, the steel floor); the `mindlin` scene
/// writes no `mindlin/force`. k_t within 1e-12 relative: the deck prints
/// the number in full (shortest round trip), the formula here and the
/// program's differ in their order of operations by a few ulp. The deck
/// runs in `lmp` when installed.
#[test]
fn lammps_writes_mindlin_force_with_eight_g_star() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("bed.toml");
    std::fs::write(&scene, bed("mindlin_force")).expect("written");
    let deck = dir.path().join("deck");
    export_lammps(&scene, &[] as &[&str], &deck, "mindlin_force");
    let input = std::fs::read_to_string(deck.join("in.lammps")).expect("in.lammps");
    let args = mindlin_force_args(&input);
    assert!(!args.is_empty(), "no mindlin/force in\n{input}");
    let grain = 8.0 * shear_modulus_star(1.0e7, 0.3, 1.0e7, 0.3);
    let steel = 8.0 * shear_modulus_star(1.0e7, 0.3, 2.0e11, 0.3);
    let mut seen = [false; 2];
    for [k, gamma, mu] in &args {
        assert_eq!((*gamma, *mu), (0.0, 0.5), "{input}");
        let near = |x: f64| ((k - x) / x).abs() < 1e-12;
        assert!(
            near(grain) || near(steel),
            "k_t {k} is neither {grain} nor {steel}"
        );
        seen[0] |= near(grain);
        seen[1] |= near(steel);
    }
    assert_eq!(seen, [true, true], "{input}");
    assert!(!input.contains("tangential mindlin "), "{input}");

    let total = dir.path().join("total.toml");
    std::fs::write(&total, bed("mindlin")).expect("written");
    let total_deck = dir.path().join("total_deck");
    export_lammps(&total, &[] as &[&str], &total_deck, "mindlin");
    let total_input = std::fs::read_to_string(total_deck.join("in.lammps")).expect("in.lammps");
    assert!(
        !total_input.contains("mindlin/force") && total_input.contains("tangential mindlin "),
        "{total_input}"
    );

    if !missing("lmp", "lammps", "the mindlin/force deck") {
        run_lmp(&deck, "mindlin_force");
    }
}

/// LIGGGHTS: exit 2 naming the key and the code, and no deck; the same
/// scene with `mindlin` exports.
#[test]
fn liggghts_refuses_mindlin_force_naming_the_key() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("bed.toml");
    std::fs::write(&scene, bed("mindlin_force")).expect("written");
    let out = dir.path().join("deck");
    let (code, err) = export("liggghts", &scene, &out);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("contact.tangential")
            && err.contains("mindlin_force")
            && err.contains("LIGGGHTS"),
        "{err}"
    );
    assert!(!out.join("in.liggghts").exists(), "no deck written");

    let total = dir.path().join("total.toml");
    std::fs::write(&total, bed("mindlin")).expect("written");
    let (code, err) = export("liggghts", &total, &dir.path().join("total_deck"));
    assert_eq!(code, Some(0), "{err}");
}

/// Yade: the deck is written, and says that its Mindlin law is the
/// `mindlin_force` spring; the `mindlin` deck says that the two differ.
#[test]
fn yade_accepts_mindlin_force_and_says_it_is_its_law() {
    let floor =
        "plane = { point = [0.0051, 0.0051, 0.0], normal = [0.0, 0.0, 1.0] }\nmaterial = \"grain\"";
    let dir = tempfile::tempdir().expect("a temporary directory");
    let text = |deck: &Path| -> String {
        std::fs::read_dir(deck)
            .expect("a deck folder")
            .map(|e| e.expect("an entry").path())
            .filter(|p| p.extension().is_some_and(|x| x == "py"))
            .map(|p| std::fs::read_to_string(p).expect("readable"))
            .collect()
    };
    let scene = dir.path().join("bed.toml");
    std::fs::write(&scene, bed_on("mindlin_force", floor)).expect("written");
    let deck = dir.path().join("deck");
    let (code, err) = export("yade", &scene, &deck);
    assert_eq!(code, Some(0), "{err}");
    let py = text(&deck);
    assert!(
        py.contains("contact.tangential = \"mindlin_force\": the same spring"),
        "{py}"
    );

    let total = dir.path().join("total.toml");
    std::fs::write(&total, bed_on("mindlin", floor)).expect("written");
    let total_deck = dir.path().join("total_deck");
    let (code, err) = export("yade", &total, &total_deck);
    assert_eq!(code, Some(0), "{err}");
    let py = text(&total_deck);
    assert!(
        py.contains("the two differ when the overlap changes under a loaded spring"),
        "{py}"
    );
}

/// Four spheres (R = 0.5 mm, the grain) 0.5 µm above a grain plane,
/// thrown at it with tangential-to-normal speed ratios 0.3, 0.6, 1.0
/// (with a y part) and 3.0: undamped Hertz, μ = 0.5, the incremental
/// spring; Δt = 0.1 µs, 2000 steps (each impact lasts about 1300), rows
/// every 20. With k_t/k_n = 4 G*/E* ≈ 0.82 for ν = 0.3, an impact with
/// v_t/v_n = 0.3 sticks while it loads (0.82 · 0.3 < μ), then slides as the
/// normal force falls, then leaves the plane; at 3.0 it slides throughout;
/// the others slide, stick, then slide again (seen in LAMMPS's per-sphere
/// forces when this test was written).
fn oblique_impacts(tangential: &str) -> String {
    format!(
        r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.02, 0.005, 0.01]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "none"
tangential = "{tangential}"
friction = 0.5
[[particles]]
material = "grain"
spheres = [
  {{ position = [0.002, 0.0025, 0.0005005], radius = 5e-4, velocity = [0.03, 0.0, -0.1] }},
  {{ position = [0.007, 0.0025, 0.0005005], radius = 5e-4, velocity = [0.06, 0.0, -0.1] }},
  {{ position = [0.012, 0.0025, 0.0005005], radius = 5e-4, velocity = [0.1, 0.01, -0.1] }},
  {{ position = [0.016, 0.0025, 0.0005005], radius = 5e-4, velocity = [0.3, 0.0, -0.1] }},
]
[[wall]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }}
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 1.0e-7
steps = 2000
[output]
series_every = 20
"#
    )
}

/// `dembound compare DECK --json`, expecting success.
fn compare(deck: &Path) -> Value {
    let out = dembound()
        .arg("compare")
        .arg(deck)
        .arg("--json")
        .output()
        .expect("dembound runs");
    assert!(
        out.status.success(),
        "compare failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

/// The largest relative difference of a quantity over the rows.
fn worst(report: &Value, name: &str) -> f64 {
    numbers(&quantity(report, name)["relative_difference"])
        .into_iter()
        .fold(0.0, f64::max)
}

/// LAMMPS's `mindlin/force` and dembound's `mindlin_force` are the same
/// model, so the oblique impacts are the same state to 1e-9 (`compare`'s
/// "identical") at every row in every quantity: the runs differ only in
/// round-off (measured 3e-16 in the forces and spins when written), and
/// four spheres that never touch each other have no collisions to
/// amplify it. Not vacuous: the plane pushes (its force > 0 at some row)
/// and friction spins the spheres (rotational energy > 0 at the end). And
/// the comparison sees the spring: the same LAMMPS run against dembound's
/// total spring (`mindlin`, the deck's scene.toml changed) differs by more
/// than 1e-3 in the rotational energy (measured 5e-2 when written: the two
/// springs' forces part by a fraction of themselves as the overlap
/// changes; 1e-3 is far above round-off and far below that).
#[test]
fn lammps_mindlin_force_is_the_same_state_through_stick_slip_and_unloading() {
    if missing("lmp", "lammps", "mindlin/force side by side") {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("impacts.toml");
    std::fs::write(&scene, oblique_impacts("mindlin_force")).expect("written");
    let deck = dir.path().join("deck");
    export_lammps(&scene, &[] as &[&str], &deck, "oblique impacts");
    run_lmp(&deck, "oblique impacts");
    let report = compare(&deck);
    assert_eq!(report["code"], "LAMMPS");
    assert_eq!(report["rows"], 101);
    for q in report["quantities"].as_array().expect("quantities") {
        let name = q["name"].as_str().expect("a name");
        let w = worst(&report, name);
        assert!(w <= IDENTICAL, "{name}: {w:e}");
    }
    let floor = numbers(&quantity(&report, "wall[0] force |F|")["code"]);
    assert!(floor.iter().any(|f| *f > 0.0), "{floor:?}");
    let spin = numbers(&quantity(&report, "rotational energy")["code"]);
    assert!(spin[spin.len() - 1] > 0.0, "{spin:?}");

    std::fs::write(deck.join("scene.toml"), oblique_impacts("mindlin")).expect("written");
    let total = compare(&deck);
    let w = worst(&total, "rotational energy");
    assert!(w > 1e-3, "the total spring's spins differ by only {w:e}");
}
