//! The LIGGGHTS and Yade scene decks' `walls_mean.txt` (issue 32): each
//! wall's force averaged over every step since the previous row, run in
//! LIGGGHTS and in Yade and checked against the momentum balance of the
//! same run (docs/export-liggghts.md and docs/export-yade.md, "Output").
//!
//! One free sphere bounces on a boundary-particle floor and against a
//! plane side wall, with friction and damping; nothing else acts on it but
//! gravity g, so the walls' forces W_i (the force the sphere exerts on
//! them, summed over the walls) are −m (a_i − g). Velocity Verlet (LIGGGHTS)
//! and the leapfrog with the deck's synchronised velocity (Yade) both give
//! v_K − v_J = Δt [Σ_{i=J+1..K} a_i − (a_K − a_J)/2], hence the mean over
//! the steps J+1 … K (N of them) written at the row K:
//!
//!   mean W = m g − m (v_K − v_J)/(N Δt) + (W_K − W_J)/(2N),
//!
//! from the dump's velocities and walls.txt's forces at the two rows only:
//! numbers the deck writes without averaging anything.
//!
//! Skips (saying so on stderr) when the code is not on PATH, except under
//! CI, where a missing code fails (tests/common/peer.rs).

mod common;

use common::dembound;
use common::peer::{missing, read_dump, read_liggghts_dump, run_liggghts, run_yade};
use dembound_export::scene_dump::parse_walls;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// Steps between rows.
const EVERY: u64 = 50;
/// Δt (s).
const DT: f64 = 2e-6;
/// The free sphere's mass: ρ 4/3 π R³ with ρ = 1000 kg/m³, R = 0.5 mm.
fn mass() -> f64 {
    1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.5e-3_f64.powi(3)
}
const G: [f64; 3] = [0.0, 0.0, -9.81];

/// Scene A's materials and contact (examples/compare/bed.toml) with one
/// sphere thrown down and towards the plane wall at x = 10.2 mm, above
/// A's boundary-particle floor: it bounces on the floor and hits the
/// wall within the 10,000 steps.
const SCENE: &str = r#"
[domain]
lower = [0.0, 0.0, 0.0]
upper = [0.0102, 0.0102, 0.02]
[[material]]
name = "grain"
density = 1000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz"
damping = "tsuji"
restitution = 0.3
friction = 0.5
tangential_damping = false
torque_arm = "contact_point"
[[particles]]
material = "grain"
spheres = [{ position = [0.0093, 0.0051, 0.0008], radius = 0.5e-3, velocity = [0.15, 0.02, -0.2] }]
[[wall]]
boundary_particles = { point = [0.0051, 0.0051, 0.0], normal = [0.0, 0.0, 1.0], radius_ratio = 4.0, modulus_ratio = 10.0, tiling = "hexagonal" }
material = "grain"
[[wall]]
plane = { point = [0.0102, 0.0, 0.0], normal = [-1.0, 0.0, 0.0] }
material = "grain"
[motion]
gravity = [0.0, 0.0, -9.81]
[integration]
scheme = "verlet"
dt = 2.0e-6
steps = 10000
[output]
series_every = 50
"#;

/// Step → a force (N) per row of a walls file.
type Rows<T> = BTreeMap<u64, T>;

/// walls.txt or walls_mean.txt of `deck`: step → the force summed over
/// the walls, and step → each wall's force.
fn walls(deck: &Path, name: &str) -> (Rows<[f64; 3]>, Rows<Vec<[f64; 3]>>) {
    let text = std::fs::read_to_string(deck.join(name)).expect(name);
    let rows = parse_walls(&text).expect("the walls file reads");
    let mut sum = BTreeMap::new();
    let mut each = BTreeMap::new();
    for (step, f) in rows {
        assert_eq!(f.len(), 6, "two walls, three components: {name} at {step}");
        let w: Vec<[f64; 3]> = f.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        sum.insert(step, [0, 1, 2].map(|a| w[0][a] + w[1][a]));
        each.insert(step, w);
    }
    (sum, each)
}

/// Checks the deck's walls_mean.txt against the momentum balance
/// (module doc) at every row whose interval starts at a row of walls.txt,
/// given the free sphere's velocity at each row.
fn check_means(deck: &Path, velocity: &BTreeMap<u64, [f64; 3]>, code: &str) {
    let (at_row, _) = walls(deck, "walls.txt");
    let (mean, each) = walls(deck, "walls_mean.txt");
    let m = mass();
    let n = EVERY as f64;
    let peak = at_row
        .values()
        .chain(mean.values())
        .flat_map(|f| f.iter().map(|x| x.abs()))
        .fold(0.0, f64::max);
    assert!(
        peak > 1e-4,
        "{code}: the sphere must hit the walls (peak {peak} N)"
    );
    assert!(!mean.contains_key(&0), "{code}: no mean at step 0");
    let (mut checked, mut sampled_off, mut wall_hit) = (0, 0, [false; 2]);
    for (&k, got) in &mean {
        let j = k - EVERY;
        let (Some(vk), Some(vj), Some(wk), Some(wj)) = (
            velocity.get(&k),
            velocity.get(&j),
            at_row.get(&k),
            at_row.get(&j),
        ) else {
            continue;
        };
        for a in 0..3 {
            let want = m * G[a] - m * (vk[a] - vj[a]) / (n * DT) + (wk[a] - wj[a]) / (2.0 * n);
            // 1e-9 of the largest force: the files' text (15 significant
            // digits in LIGGGHTS, 17 in Yade) and the N-term sums round at
            // ~1e-14 of it; a mean over other steps (one step sampled, the
            // interval shifted by one) is off by 1e-3 of it or more at
            // the impacts (counted below).
            assert!(
                (got[a] - want).abs() <= 1e-9 * peak,
                "{code}: row {k}, component {a}: walls_mean.txt {} against the momentum balance {want} (peak {peak} N)",
                got[a]
            );
            if (got[a] - wk[a]).abs() > 1e-3 * peak {
                sampled_off += 1;
            }
        }
        for (w, f) in each[&k].iter().enumerate() {
            wall_hit[w] |= f.iter().any(|x| x.abs() > 1e-3 * peak);
        }
        checked += 1;
    }
    assert!(checked >= 190, "{code}: {checked} rows checked of 200");
    // The test can tell an average from a sample: at the impacts the row's
    // own force is far from the interval's mean.
    assert!(
        sampled_off >= 5,
        "{code}: only {sampled_off} components differ from walls.txt"
    );
    assert_eq!(wall_hit, [true; 2], "{code}: both walls carry a force");
}

/// `dembound compare` reads walls_mean.txt on both sides.
fn compare_reads_the_means(deck: &Path, code: &str) {
    let out = dembound()
        .args(["compare", "--json"])
        .arg(deck)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        report["wall_forces"], "mean_over_row_interval",
        "{code}: {}",
        report["wall_forces"]
    );
}

fn write_scene(dir: &Path) -> std::path::PathBuf {
    let scene = dir.join("scene_in.toml");
    std::fs::write(&scene, SCENE).expect("written");
    scene
}

#[test]
fn liggghts_averages_every_step_of_each_row() {
    if missing("liggghts", "LIGGGHTS", "the LIGGGHTS wall-force means") {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let deck = dir.path().join("deck");
    run_liggghts(&write_scene(dir.path()), &deck);
    // id type radius x y z vx vy vz …: the free sphere is id 1.
    let velocity: BTreeMap<u64, [f64; 3]> = read_liggghts_dump(&deck)
        .into_iter()
        .map(|(step, rows)| {
            let s = &rows[0];
            assert_eq!((s[0], s[2]), (1.0, 0.5e-3), "the free sphere");
            (step, [s[6], s[7], s[8]])
        })
        .collect();
    check_means(&deck, &velocity, "LIGGGHTS");
    compare_reads_the_means(&deck, "LIGGGHTS");
}

#[test]
fn yade_averages_every_step_of_each_row() {
    if missing("yade", "Yade", "the Yade wall-force means") {
        return;
    }
    let dir = tempfile::tempdir().expect("a temporary directory");
    let deck = dir.path().join("deck");
    run_yade(&write_scene(dir.path()), &deck);
    // The free sphere is body 0 (id 1): x y z vx vy vz ωx ωy ωz.
    let velocity: BTreeMap<u64, [f64; 3]> = read_dump(&deck.join("particles.dump"))
        .into_iter()
        .map(|(step, s)| (step, [s[0][3], s[0][4], s[0][5]]))
        .collect();
    check_means(&deck, &velocity, "Yade");
    compare_reads_the_means(&deck, "Yade");
}
