//! The incremental Hertz–Mindlin spring (`contact.tangential =
//! "mindlin_force"`, issue 32) in the exports: LAMMPS writes its
//! `tangential mindlin/force` with k_t = 8 G* per type pair (and runs the
//! deck), LIGGGHTS refuses it (its `tangential history` is the total
//! spring, dembound's "mindlin") naming the key and the code, Yade accepts
//! it (its Mindlin law increments the shear force) and says so in the deck.

mod common;

use common::dembound;
use common::peer::{export_lammps, lattice_bed, missing, run_lmp, STEEL_PLANE_FLOOR};
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
