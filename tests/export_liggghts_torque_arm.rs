//! `contact.torque_arm = "half_overlap"` runs LIGGGHTS 3.8's frictional
//! model (issue 32): LIGGGHTS's `surface_model_default.h` and
//! `tangential_model_history.h` take the lever arm R − δ/2 from each
//! centre, in the slip velocity and in the torque of the tangential force,
//! in sphere pairs and against walls alike, with no other scaling. Scenes
//! exported to LIGGGHTS, run there and in dembound, compared at every
//! dumped step (`particles.dump`, every number at `%.17g`, i.e. the
//! double itself). Under `"half_overlap"`: against a plane wall the same
//! state to 1e-9 (round-off); in a sphere pair the one difference left is
//! the tangential spring's length when the pair's normal turns (dembound
//! keeps it by default, LIGGGHTS projects the spring and shortens it by θ²/2 a step),
//! so the state agrees within twice that term summed over the contact
//! (2e-8 measured). Under
//! `"contact_point"` (LAMMPS's arm) and `"overlap_middle"` (Yade's) the
//! runs part by a hundred times more, so the test can fail. Under
//! `"half_overlap"` with `contact.spring_rotation = "project"` (session
//! 36: the spring projected as LIGGGHTS projects it) the pair too is the
//! same state to 1e-9: the model is LIGGGHTS's.
//!
//! Without `liggghts` on PATH the test fails under CI (the CI image
//! installs it) and skips elsewhere, saying so.

mod common;

use common::peer::{missing, read_liggghts_dump, run_liggghts};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::Simulation;

/// The domain, the material and the law of both scenes (`ARM` replaced
/// by each arm, `ROTATION` by each spring rotation): ρ = 1000 kg/m³,
/// E = 1e7 Pa, ν = 0.3; Hertz, Tsuji damping
/// for e = 0.3 without the tangential dashpot (the one damping the
/// LIGGGHTS export takes with friction), μ = 0.5.
const LAW: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
periodic = [false, false, false]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.3
friction = 0.5
tangential_damping = false
torque_arm = "ARM"
spring_rotation = "ROTATION"
"#;

/// Two free spheres (R = 0.5 and 0.4 mm, ρ = 1000 kg/m³, E = 1e7 Pa,
/// ν = 0.3), no gravity, no wall: sphere 1 at 0.1 m/s along x meets
/// sphere 2 coming back at 0.05 m/s and rising at 0.02 m/s, their centres
/// 0.3 mm apart in y and 0.1 mm in z (an impact 20° off the line of
/// centres). Hertz, Tsuji damping for e = 0.3 without the tangential
/// dashpot (the one damping the LIGGGHTS export takes with friction),
/// μ = 0.5; Δt = 2 µs, 3000 steps. The contact (56 steps) spins both
/// spheres up from rest (to 128 rad/s), and the slip it sees carries that
/// spin at the lever arm.
const PAIR: &str = r#"
[[particles]]
material = "grain"
spheres = [
  { position = [0.004, 0.005, 0.005], radius = 0.5e-3, velocity = [0.1, 0.0, 0.0] },
  { position = [0.0052, 0.0053, 0.0051], radius = 0.4e-3, velocity = [-0.05, 0.0, 0.02] },
]
[integration]
scheme = "verlet"
dt = 2e-6
steps = 3000
[output]
series_every = 10
"#;

/// A sphere (R = 0.5 mm) thrown at (0.15, 0, −0.05) m/s onto a
/// frictional plane floor (the same material) under gravity: it bounces,
/// slides and rolls, spun up by the floor, into a sphere of R = 0.4 mm
/// standing on the floor 0.2 mm off its path; both then roll, slide and
/// meet the floor again. The law of `PAIR`; 8000 steps of 2 µs (the pair
/// touches for 78 steps; spins up to 218 rad/s).
const ROLL: &str = r#"
[[particles]]
material = "grain"
spheres = [
  { position = [0.002, 0.005, 0.00052], radius = 0.5e-3, velocity = [0.15, 0.0, -0.05] },
  { position = [0.0035, 0.0052, 0.0004], radius = 0.4e-3 },
]
[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2e-6
steps = 8000
[output]
series_every = 10
"#;

/// The largest differences between the two runs over every dumped step
/// and sphere: |Δx|/R, |Δv| over the throw speed, |Δω| over the throw
/// speed/R (R the sphere's radius); over the whole run and over the rows
/// before the two spheres first touch (walls only).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Apart {
    whole: f64,
    before_pair: f64,
    /// The largest |ω| dembound reached (rad/s): the scene spins.
    max_spin: f64,
    /// Steps at which the two spheres overlapped (dembound's).
    pair_steps: usize,
    /// Σ θ²/2 over the pair's steps, θ the turn of its normal in a step:
    /// the relative length dembound's spring turn restores and
    /// LIGGGHTS's projection drops, summed (the one difference left).
    length_term: f64,
}

/// `scene` (with `ARM` for the arm, `ROTATION` for the spring's
/// rotation) exported under `"half_overlap"` and `"project"` and run in
/// LIGGGHTS once (the deck's commands depend on neither key: only its
/// header's notes do), then dembound under each of `variants` (arm,
/// rotation) against it, step by step.
fn against_liggghts(scene: &str, speed: f64, variants: &[(&str, &str)]) -> Vec<Apart> {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let file = dir.path().join("scene.toml");
    let text = |arm: &str, rotation: &str| scene.replace("ARM", arm).replace("ROTATION", rotation);
    std::fs::write(&file, text("half_overlap", "project")).expect("written");
    let deck = dir.path().join("deck");
    run_liggghts(&file, &deck);
    let input = std::fs::read_to_string(deck.join("in.liggghts")).expect("in.liggghts");
    assert!(
        input.contains("The lever arm is LIGGGHTS's")
            && input.contains("and so is the spring's rotation")
            && !input.contains("Differences kept: the lever arm")
            && !input.contains("Difference kept"),
        "the deck's header: {input}"
    );
    let dump = read_liggghts_dump(&deck);
    assert!(dump.len() > 100, "{} dumped steps", dump.len());
    variants
        .iter()
        .map(|&(arm, rotation)| {
            let parsed =
                config::load(&text(arm, rotation), "scene.toml", &[]).expect("a valid scene");
            let resolved = resolve(&parsed, dir.path()).expect("resolves");
            let radii: Vec<f64> = resolved.setup.spheres.iter().map(|s| s.radius).collect();
            let mut sim = Simulation::new(resolved.setup, 1).expect("builds");
            let mut apart = Apart {
                whole: 0.0,
                before_pair: 0.0,
                max_spin: 0.0,
                pair_steps: 0,
                length_term: 0.0,
            };
            let mut normal: Option<[f64; 3]> = None;
            for (step, rows) in &dump {
                while sim.steps_done() < *step {
                    sim.step(1);
                    let x = sim.positions();
                    let d: Vec<f64> = (0..3).map(|a| x[1][a] - x[0][a]).collect();
                    let norm = d.iter().map(|c| c * c).sum::<f64>().sqrt();
                    if norm < radii[0] + radii[1] {
                        apart.pair_steps += 1;
                        let n = [d[0] / norm, d[1] / norm, d[2] / norm];
                        if let Some(p) = normal {
                            let turn: f64 = (0..3).map(|a| (n[a] - p[a]).powi(2)).sum();
                            apart.length_term += 0.5 * turn;
                        }
                        normal = Some(n);
                    } else {
                        normal = None;
                    }
                }
                let (x, v, w) = (sim.positions(), sim.velocities(), sim.angular_velocities());
                assert_eq!(rows.len(), x.len(), "step {step}");
                let mut worst = 0.0f64;
                for (i, row) in rows.iter().enumerate() {
                    assert_eq!(row[0] as usize, i + 1, "ids in dembound's order");
                    let r = radii[i];
                    for a in 0..3 {
                        worst = worst
                            .max((row[3 + a] - x[i][a]).abs() / r)
                            .max((row[6 + a] - v[i][a]).abs() / speed)
                            .max((row[9 + a] - w[i][a]).abs() * r / speed);
                        apart.max_spin = apart.max_spin.max(w[i][a].abs());
                    }
                }
                apart.whole = apart.whole.max(worst);
                if apart.pair_steps == 0 {
                    apart.before_pair = apart.before_pair.max(worst);
                }
            }
            eprintln!("{arm}, {rotation}: {apart:?}");
            apart
        })
        .collect()
}

/// The same state within this, relative (of R, of the throw speed, of
/// the throw speed/R), where the two codes have the same law. They do the
/// same arithmetic in other orders (e.g. LIGGGHTS's `(cri ω_i + crj ω_j)
/// / r` then × `delta`, dembound's (c₁ ω₁ + c₂ ω₂) × n; LIGGGHTS projects
/// the spring after adding the step's slip v_t Δt, dembound before, the
/// same in exact arithmetic as v_t ⟂ n), so they differ by round-off,
/// 1e-16 per operation, grown by the contacts over a few thousand steps;
/// the dump prints the doubles themselves (`%.17g`). 1e-9 is the issue's
/// bar for the same model.
const SAME: f64 = 1e-9;

/// Another arm parts by more than this (δ/(2R) ~ 1e-3 at the largest
/// overlaps, in the spin terms).
const PARTED: f64 = 1e-5;

/// A sphere pair whose normal turns while the spring is loaded is not the
/// same law in the two codes: dembound turns the spring into the new
/// tangent plane keeping its length (`FrictionPair::turn_spring`),
/// LIGGGHTS 3.8 projects it (`tangential_model_history.h`: `shear −=
/// (shear·n) n`, no rescale), shorter by θ²/2 per step, θ the turn. Over
/// the contact the springs part by at most `length_term` = Σ θ²/2 of the
/// spring, whose impulse is at most the contact's tangential impulse, of
/// the order of the throw's momentum: the states part by about that
/// fraction of it (measured 0.10 `length_term` on `PAIR`, 0.43 on `ROLL`),
/// and by round-off only with the spring's length dropped as LIGGGHTS
/// drops it (`contact.spring_rotation = "project"`: measured 2.3e-16 on
/// `PAIR`, 8.5e-14 on `ROLL`; session 35 saw the same with the rescale
/// removed by hand). Bounded here at twice `length_term` (2.1e-7 and
/// 1.9e-7 here).
fn spring_length_bound(a: &Apart) -> f64 {
    2.0 * a.length_term
}

#[test]
fn half_overlap_is_liggghts_in_an_oblique_sphere_pair() {
    if missing(
        "liggghts",
        "liggghts",
        "contact.torque_arm against LIGGGHTS",
    ) {
        return;
    }
    let got = against_liggghts(
        &format!("{LAW}{PAIR}"),
        0.1,
        &[
            ("half_overlap", "rescale"),
            ("contact_point", "rescale"),
            ("overlap_middle", "rescale"),
            ("half_overlap", "project"),
        ],
    );
    let [half, point, middle, projected] = [got[0], got[1], got[2], got[3]];
    // The spheres met, and the contact spun them.
    assert!(half.pair_steps >= 20 && half.max_spin > 10.0, "{half:?}");
    // LIGGGHTS's arm and LIGGGHTS's rotation: LIGGGHTS's state to
    // round-off, where the rescale parts by the spring's length.
    assert!(
        projected.whole <= SAME,
        "half_overlap + project parts from LIGGGHTS: {projected:?}"
    );
    assert!(half.whole > 10.0 * SAME, "{half:?}");
    // The spring's length is the only difference left, and it is small.
    let bound = spring_length_bound(&half);
    assert!(
        half.whole <= bound,
        "half_overlap parts from LIGGGHTS: {half:?}"
    );
    // The other arms part by a hundred times the length term at least.
    assert!(bound < PARTED, "{half:?}");
    assert!(
        point.whole > 100.0 * bound,
        "contact_point did not part: {point:?}"
    );
    assert!(
        middle.whole > 100.0 * bound,
        "overlap_middle did not part: {middle:?}"
    );
}

#[test]
fn half_overlap_is_liggghts_on_a_frictional_floor_and_into_a_sphere() {
    if missing(
        "liggghts",
        "liggghts",
        "contact.torque_arm against LIGGGHTS",
    ) {
        return;
    }
    let got = against_liggghts(
        &format!("{LAW}{ROLL}"),
        0.15,
        &[
            ("half_overlap", "rescale"),
            ("contact_point", "rescale"),
            ("overlap_middle", "rescale"),
            ("half_overlap", "project"),
        ],
    );
    let [half, point, middle, projected] = [got[0], got[1], got[2], got[3]];
    assert!(half.pair_steps >= 20 && half.max_spin > 100.0, "{half:?}");
    // LIGGGHTS's arm and rotation: the floor and the pair, LIGGGHTS's
    // state to round-off; on the flat floor the rotations are one (the
    // same bits before the pair meets: δ·n = 0 exactly there).
    assert!(
        projected.whole <= SAME,
        "half_overlap + project parts from LIGGGHTS: {projected:?}"
    );
    assert_eq!(projected.before_pair, half.before_pair, "{projected:?}");
    assert!(half.whole > 10.0 * SAME, "{half:?}");
    // Until the spheres touch only the floor acts, whose normal never
    // turns: the same law, the same state to round-off.
    assert!(
        half.before_pair <= SAME,
        "half_overlap parts at the floor: {half:?}"
    );
    // At a wall Yade's arm is LIGGGHTS's, bit for bit; contact_point keeps
    // R there and parts at the first bounce.
    assert_eq!(middle.before_pair, half.before_pair, "{middle:?}");
    assert!(
        point.before_pair > PARTED,
        "contact_point did not part: {point:?}"
    );
    // Then the pair: the spring's length only.
    let bound = spring_length_bound(&half);
    assert!(
        half.whole <= bound,
        "half_overlap parts from LIGGGHTS: {half:?}"
    );
    assert!(bound < PARTED, "{half:?}");
    // Yade's α in the pair's slip parts it there.
    assert!(
        middle.whole > 100.0 * bound,
        "overlap_middle did not part: {middle:?}"
    );
}

/// `dembound export liggghts` notes the arm for a frictional scene under
/// any arm but `"half_overlap"` (naming it, and `contact.spring_rotation
/// = "project"` too under the default rotation), and under
/// `"half_overlap"` notes the rotation alone unless it is `"project"`
/// (then nothing); the deck's header calls the lever arm a difference
/// kept under the other arms and LIGGGHTS's own under `"half_overlap"`,
/// and the spring's length a difference kept unless the rotation is
/// `"project"`. No LIGGGHTS needed.
#[test]
fn export_notes_every_arm_but_half_overlap() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("pair.toml");
    let pair = format!("{LAW}{PAIR}")
        .replace("torque_arm = \"ARM\"\n", "")
        .replace("spring_rotation = \"ROTATION\"\n", "");
    std::fs::write(&scene, pair).expect("written");
    for rotation in ["rescale", "project"] {
        let project = rotation == "project";
        for arm in ["radius", "contact_point", "overlap_middle", "half_overlap"] {
            let deck = dir.path().join(format!("{arm}-{rotation}"));
            let mut sets = vec!["--set".to_string(), format!("contact.torque_arm={arm}")];
            if project {
                sets.extend(["--set".into(), "contact.spring_rotation=project".into()]);
            }
            let out = common::dembound()
                .args(["export", "liggghts"])
                .arg(&scene)
                .args(&sets)
                .arg("--out")
                .arg(&deck)
                .output()
                .expect("dembound runs");
            let note = String::from_utf8_lossy(&out.stderr);
            assert!(out.status.success(), "{arm}, {rotation}: {note}");
            let input = std::fs::read_to_string(deck.join("in.liggghts")).expect("in.liggghts");
            let length_kept = input.contains("the spring's length on a turning normal");
            assert_eq!(length_kept, !project, "{arm}, {rotation}: {input}");
            assert_eq!(
                input.contains("contact.spring_rotation = \"project\""),
                project,
                "{arm}, {rotation}: {input}"
            );
            if arm == "half_overlap" {
                assert!(!note.contains("torque_arm"), "{arm}: {note}");
                assert!(input.contains("The lever arm is LIGGGHTS's"), "{input}");
                assert!(!input.contains("kept: the lever arm"), "{input}");
                if project {
                    assert!(!note.contains("note:"), "{arm}, {rotation}: {note}");
                } else {
                    assert!(
                        note.contains("note: contact.spring_rotation = \"rescale\"")
                            && note.contains("set contact.spring_rotation = \"project\""),
                        "{arm}, {rotation}: {note}"
                    );
                }
            } else {
                assert!(
                    note.contains(&format!("note: contact.torque_arm = \"{arm}\""))
                        && note.contains("contact.torque_arm = \"half_overlap\""),
                    "{arm}: {note}"
                );
                assert!(!note.contains("note: contact.spring_rotation"), "{note}");
                assert_eq!(
                    note.contains("and contact.spring_rotation = \"project\""),
                    !project,
                    "{arm}, {rotation}: {note}"
                );
                let kept = if project {
                    "Difference kept: the lever arm"
                } else {
                    "Differences kept: the lever arm"
                };
                assert!(input.contains(kept), "{input}");
            }
        }
    }
}
