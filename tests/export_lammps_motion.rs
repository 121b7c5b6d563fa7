//! `dembound export lammps SCENE.toml` with moving groups of fixed spheres
//! (`fix move rotate | linear | wiggle`) and a sliding plane (`fix
//! wall/gran … shear`), issue 27: Debian's LAMMPS (`lmp`) runs the deck
//! and the scene engine runs the same file, same Δt and steps; the deck's
//! `particles.dump` (every sphere's position and velocity at the series
//! cadence, the moving fixed spheres included, so the pose of the group
//! is checked too) against `Simulation::positions()`/`velocities()` at
//! the same steps.
//!
//! Without `lmp` on PATH the tests fail under CI (the CI image installs
//! it) and skip elsewhere, saying so.
//!
//! Why 1e-9: the two codes integrate the same velocity Verlet with the
//! same frictionless Hertz–Tsuji pair forces (the sliding plane: Mindlin
//! against a plane, where both put the torque arm at R), and place the
//! moving spheres by the same closed forms of t, in another
//! floating-point order (LAMMPS's A cos + B sin against Rodrigues' matrix,
//! k a δ against E √R h^(3/2)): ~1e-16 relative per step. Over these runs
//! (a few thousand steps, a few contacts each) that stays many decades
//! below 1e-9, while a pose or surface velocity wrong by a quarter period,
//! a missing spin or a time origin one step off moves the spheres by far
//! more (the sums are printed).

mod common;

use common::peer::{export_lammps, missing, run_lmp};
use dembound_scene::io::{config, resolve::resolve};
use dembound_scene::Simulation;
use std::collections::BTreeMap;
use std::path::Path;

/// True when `lmp` can run; under CI its absence fails the test.
fn have_lmp() -> bool {
    !missing("lmp", "lammps", "the export of moving groups and walls")
}

/// Four free spheres of 1 mm dropped from just above a plate of 4 × 4
/// fixed spheres (`[[particles]]` group 1) with `group` in its entry, over
/// a boundary-particle floor (wall 0) with `floor` in its entry; contact
/// `contact`; `steps` steps of 1 µs, a dump row every 500.
fn scene(contact: &str, group: &str, floor: &str, steps: u64) -> String {
    let mut plate = String::new();
    for i in 0..4 {
        for j in 0..4 {
            let (x, y) = (-3e-3 + 2e-3 * i as f64, -3e-3 + 2e-3 * j as f64);
            plate.push_str(&format!(
                "{{ position = [{x:e}, {y:e}, 0.0], radius = 1e-3 }}, "
            ));
        }
    }
    format!(
        r#"
[domain]
lower = [-0.012, -0.012, -0.012]
upper = [0.012, 0.012, 0.012]

[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
{contact}

[[particles]]
spheres = [{{ position = [-1.1e-3, -0.9e-3, 2.2e-3], radius = 1e-3 }}, {{ position = [1.0e-3, 1.2e-3, 2.4e-3], radius = 1e-3 }}, {{ position = [1.3e-3, -1.0e-3, 2.1e-3], radius = 0.9e-3 }}, {{ position = [-0.8e-3, 1.1e-3, 2.3e-3], radius = 0.8e-3 }}]
material = "grain"

[[particles]]
spheres = [{plate}]
material = "grain"
fixed = true
{group}

[[wall]]
boundary_particles = {{ point = [0.0, 0.0, -0.009], normal = [0.0, 0.0, 1.0], radius_ratio = 1.0, modulus_ratio = 10.0 }}
material = "grain"
{floor}

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
dt = 1.0e-6
steps = {steps}

[output]
series_every = 500
"#
    )
}

const FRICTIONLESS: &str = "law = \"hertz\"\ndamping = \"tsuji\"\nrestitution = 0.5";

/// `particles.dump`: step → every sphere's (x, v) in id order.
fn read_dump(path: &Path) -> BTreeMap<u64, Vec<[f64; 6]>> {
    let text = std::fs::read_to_string(path).expect("particles.dump");
    let mut rows = BTreeMap::new();
    let mut lines = text.lines();
    while let Some(l) = lines.next() {
        if l.starts_with("ITEM: TIMESTEP") {
            let step: u64 = lines
                .next()
                .expect("a step")
                .trim()
                .parse()
                .expect("a step");
            lines.next();
            let n: usize = lines
                .next()
                .expect("a count")
                .trim()
                .parse()
                .expect("a count");
            for _ in 0..5 {
                lines.next();
            }
            let state = (0..n)
                .map(|_| {
                    let w: Vec<f64> = lines
                        .next()
                        .expect("an atom")
                        .split_whitespace()
                        .map(|x| x.parse().expect("a number"))
                        .collect();
                    [w[1], w[2], w[3], w[4], w[5], w[6]]
                })
                .collect();
            rows.insert(step, state);
        }
    }
    rows
}

/// What the comparison of the two runs found.
struct Agreement {
    /// max over rows and spheres of |x_L − x_d| / max |x_d| (m/m).
    position: f64,
    /// max over rows of max_i |v_L − v_d| / max_i |v_d|, free spheres.
    velocity: f64,
    /// The largest distance a fixed sphere moved from its start, m.
    group_travel: f64,
    /// The largest x displacement of a free sphere, m.
    free_drift: f64,
    /// Particle and wall contacts summed over the rows.
    contacts: usize,
}

/// Writes `text`, exports it to LAMMPS (the deck must contain each of
/// `expect`), runs `lmp` and the engine; the agreement.
fn compare(text: &str, expect: &[&str]) -> Agreement {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("moving.toml");
    std::fs::write(&scene, text).expect("written");
    let deck = dir.path().join("deck");
    export_lammps::<&str>(&scene, &[], &deck, "moving");
    let input = std::fs::read_to_string(deck.join("in.lammps")).expect("in.lammps");
    for e in expect {
        assert!(input.contains(e), "the deck lacks `{e}`:\n{input}");
    }
    run_lmp(&deck, "moving");
    let dump = read_dump(&deck.join("particles.dump"));
    let file = config::load(text, "moving", &[]).expect("a valid scene");
    let resolved = resolve(&file, dir.path()).expect("resolves");
    let mut sim = Simulation::new(resolved.setup.clone(), 1).expect("runs");
    let start = sim.positions();
    let fixed = sim.fixed();
    let mut a = Agreement {
        position: 0.0,
        velocity: 0.0,
        group_travel: 0.0,
        free_drift: 0.0,
        contacts: 0,
    };
    for (&step, state) in &dump {
        sim.step(step - sim.steps_done());
        let (x, v) = (sim.positions(), sim.velocities());
        assert_eq!(state.len(), x.len());
        let norm = |b: [f64; 3]| (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
        let dist = |a: &[f64], b: [f64; 3]| norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
        let xmax = x.iter().map(|p| norm(*p)).fold(0.0, f64::max);
        let (mut dv, mut vmax) = (0.0f64, 0.0f64);
        for i in 0..x.len() {
            a.position = a.position.max(dist(&state[i][0..3], x[i]) / xmax);
            if fixed[i] {
                a.group_travel = a.group_travel.max(dist(&start[i], x[i]));
            } else {
                a.free_drift = a.free_drift.max(x[i][0] - start[i][0]);
                dv = dv.max(dist(&state[i][3..6], v[i]));
                vmax = vmax.max(norm(v[i]));
            }
        }
        if vmax > 0.0 {
            a.velocity = a.velocity.max(dv / vmax);
        }
        a.contacts += sim.particle_contacts() + sim.wall_contacts();
    }
    eprintln!(
        "rows {}, position {:.2e}, velocity {:.2e} (relative), group moved up to {:.3e} m, free spheres up to {:.3e} m along x, contacts summed over rows {}",
        dump.len(),
        a.position,
        a.velocity,
        a.group_travel,
        a.free_drift,
        a.contacts
    );
    a
}

/// The checks every case makes: the runs agree to 1e-9 (module doc), the
/// group moved (`travel` m at least) and the spheres touched it.
fn agrees(a: &Agreement, travel: f64) {
    assert!(a.position < 1e-9, "positions differ by {:e}", a.position);
    assert!(a.velocity < 1e-9, "velocities differ by {:e}", a.velocity);
    assert!(
        a.group_travel >= travel,
        "the group moved {:e} m",
        a.group_travel
    );
    assert!(a.contacts > 0, "no contact");
}

/// The plate turning at 20 rad/s about the vertical axis through (0.5,
/// 0, 0) mm: `fix move rotate`. The free spheres land on the moving bumps
/// (the surface velocity ω × (p − c) in their normal damping) and are
/// thrown sideways.
#[test]
fn turning_group_agrees() {
    if !have_lmp() {
        return;
    }
    let text = scene(
        FRICTIONLESS,
        "motion = { angular_velocity = [0.0, 0.0, 20.0], center = [0.5e-3, 0.0, 0.0] }",
        "",
        20000,
    );
    let a = compare(&text, &["move rotate"]);
    // 20 rad/s × 20 ms = 0.4 rad on a radius up to 4.3 mm: > 1 mm.
    agrees(&a, 1e-3);
}

/// The plate rising at 0.05 m/s and drifting sideways at 0.01 m/s into
/// the falling spheres (`fix move linear`).
#[test]
fn translating_group_agrees() {
    if !have_lmp() {
        return;
    }
    let text = scene(
        FRICTIONLESS,
        "motion = { velocity = [0.01, 0.0, 0.05] }",
        "",
        20000,
    );
    let a = compare(&text, &["move linear"]);
    // 0.05 m/s × 20 ms = 1 mm up, 0.2 mm sideways.
    agrees(&a, 1e-3);
}

/// The plate shaken vertically, 0.3 mm at 50 Hz (`fix move wiggle`), and
/// the boundary-particle floor rising at 0.1 m/s (`fix move linear` on
/// the wall's spheres).
#[test]
fn oscillating_group_and_moving_particle_wall_agree() {
    if !have_lmp() {
        return;
    }
    let text = scene(
        FRICTIONLESS,
        "oscillation = { amplitude = [0.0, 0.0, 0.3e-3], frequency = 50.0 }",
        "motion = { velocity = [0.0, 0.0, 0.1] }",
        20000,
    );
    let a = compare(&text, &["move wiggle", "move linear"]);
    // The floor rose 0.1 m/s × 20 ms = 2 mm.
    agrees(&a, 2e-3 * (1.0 - 1e-9));
}

/// Four spheres (μ = 0.5, Hertz–Mindlin, Tsuji normal damping, no
/// tangential dashpot: the export's rule with friction) dropped 0.1 mm
/// onto a floor plane sliding along x at 0.05 m/s, a conveyor (`fix
/// wall/gran … shear x 0.05`): friction drags them along, spinning them.
/// Only sphere–plane contacts (the spheres 3 mm apart), where both codes
/// put the tangential torque at R.
#[test]
fn conveyor_plane_agrees() {
    if !have_lmp() {
        return;
    }
    let text = r#"
[domain]
lower = [-0.01, -0.01, 0.0]
upper = [0.01, 0.01, 0.01]

[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3

[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.5
tangential = "mindlin"
friction = 0.5
tangential_damping = false

[[particles]]
spheres = [{ position = [-3e-3, -3e-3, 1.1e-3], radius = 1e-3 }, { position = [0.0, 0.0, 1.1e-3], radius = 1e-3 }, { position = [3e-3, 0.0, 1.0e-3], radius = 0.9e-3 }, { position = [0.0, 3e-3, 1.2e-3], radius = 1.1e-3 }]
material = "grain"

[[wall]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0] }
material = "grain"
motion = { velocity = [0.05, 0.0, 0.0] }

[motion]
gravity = [0.0, 0.0, -9.81]

[integration]
dt = 1.0e-6
steps = 20000

[output]
series_every = 500
"#;
    let a = compare(text, &["shear x 5e-2"]);
    assert!(a.position < 1e-9, "positions differ by {:e}", a.position);
    assert!(a.velocity < 1e-9, "velocities differ by {:e}", a.velocity);
    assert!(a.contacts > 0, "no contact");
    // Dragged along: sliding at first, then rolling at 2/7 of 0.05 m/s
    // (a solid sphere's rolling speed on a belt from rest), ~0.2 mm in
    // 20 ms; a plane standing still leaves them where they fell.
    assert!(
        a.free_drift > 5e-5,
        "the spheres moved {:e} m along x",
        a.free_drift
    );
}

/// `dembound export CODE` of `text` (written to a fresh directory): the
/// exit code, stderr and whether the output directory was created.
fn export_refused(code: &str, text: &str) -> (Option<i32>, String, bool) {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let scene = dir.path().join("moving.toml");
    std::fs::write(&scene, text).expect("written");
    let deck = dir.path().join("deck");
    let o = common::dembound()
        .args(["export", code])
        .arg(&scene)
        .arg("--out")
        .arg(&deck)
        .output()
        .expect("dembound runs");
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
        deck.exists(),
    )
}

/// What the decks do not move the same way is refused with exit 2, the
/// key named, nothing written: a group that turns and slides (LAMMPS: one
/// fix move style per group), a motion starting late, a plane shaken
/// along its normal (LAMMPS's wiggle is A (1 − cos ωt)), and any moving
/// group in the LIGGGHTS and Yade decks (they would hold it still).
#[test]
fn motions_not_written_are_refused_naming_the_key() {
    let cases = [
        (
            "lammps",
            scene(
                FRICTIONLESS,
                "motion = { velocity = [0.0, 0.0, 0.05], angular_velocity = [0.0, 0.0, 1.0] }",
                "",
                10,
            ),
            "particles[1].motion",
        ),
        (
            "lammps",
            scene(
                FRICTIONLESS,
                "",
                "motion = { velocity = [0.0, 0.0, 0.05], start = 1e-3 }",
                10,
            ),
            "wall[0].motion",
        ),
        (
            "lammps",
            scene(FRICTIONLESS, "", "", 10).replace(
                "boundary_particles = { point = [0.0, 0.0, -0.009], normal = [0.0, 0.0, 1.0], radius_ratio = 1.0, modulus_ratio = 10.0 }",
                "plane = { point = [0.0, 0.0, -0.009], normal = [0.0, 0.0, 1.0] }\noscillation = { amplitude = [0.0, 0.0, 1e-4], frequency = 50.0 }",
            ),
            "wall[0].oscillation",
        ),
        (
            "liggghts",
            scene(FRICTIONLESS, "motion = { velocity = [0.0, 0.0, 0.05] }", "", 10),
            "particles[1].motion",
        ),
        (
            "yade",
            scene(FRICTIONLESS, "motion = { velocity = [0.0, 0.0, 0.05] }", "", 10),
            "particles[1].motion",
        ),
    ];
    for (code, text, key) in cases {
        let (status, stderr, written) = export_refused(code, &text);
        assert_eq!(status, Some(2), "{code} {key}: {stderr}");
        assert!(stderr.contains(key), "{code}: `{key}` not named: {stderr}");
        assert!(!written, "{code} {key}: a deck was written");
    }
}
