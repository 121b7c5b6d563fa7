//! `dembound scene --restart` in the middle of contacts, through the
//! binary: run A goes N steps into one directory; run B goes N/2 into
//! another, then `--restart B/checkpoint.cbor` goes on to N into a third.
//! The restarted run's checkpoint, last snapshot, collision log and series
//! rows from N/2 on are A's to the byte, under Verlet and under Gear5,
//! with friction (tangential and rolling springs on pairs and walls).
//!
//! Not vacuous: B's summary at N/2 has pair and wall contacts and B's
//! log completed ones (the checkpoint's collision columns), and the
//! same scene run to N/2 through the engine API (the same bits as the
//! binary: its kinetic energy is B's) has non-zero springs on pairs and
//! walls at that step. Only the commands' behaviour is used, not the
//! checkpoint's layout (which may change).

mod common;

use common::{lattice_drop, scene_summary};
use dembound_scene::io::config;
use dembound_scene::io::resolve::resolve;
use dembound_scene::Simulation;
use serde_json::Value;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

/// lattice_drop.toml cut to 8 × 8 × 6 spheres in a 10.2 mm box, with
/// Mindlin μ = 0.5 and rolling friction 0.05 on grains and walls, the
/// collision log on, a snapshot every `every` steps, series every step.
fn base_sets(every: u64) -> Vec<String> {
    [
        "particles.0.lattice.counts=[8,8,6]",
        "domain.upper=[0.0102,0.0102,0.03]",
        "wall.1.plane.point=[0.0102,0.0,0.0]",
        "wall.3.plane.point=[0.0,0.0102,0.0]",
        "contact.friction=0.5",
        "contact.rolling_friction=0.05",
        "output.collisions=true",
        "output.series_every=1",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([format!("output.every={every}")])
    .collect()
}

/// `dembound scene lattice_drop.toml SETS --set integration.steps=STEPS
/// [--restart CP] --json --out OUT`.
fn run(sets: &[String], steps: u64, restart: Option<&Path>, out: &Path) -> Value {
    let mut sets = sets.to_vec();
    sets.push(format!("integration.steps={steps}"));
    let mut extra: Vec<&OsStr> = Vec::new();
    if let Some(cp) = restart {
        extra.extend([OsStr::new("--restart"), cp.as_os_str()]);
    }
    extra.extend([OsStr::new("--threads"), OsStr::new("1")]);
    scene_summary(
        &lattice_drop(),
        &sets,
        &extra,
        out,
        &format!("{steps} steps"),
    )
}

/// The same scene through the engine API after `steps`: asserts the
/// springs are live (pairs and walls, tangential and rolling) and that
/// the run is the binary's (`summary` of the binary at that step).
fn assert_springs_live(sets: &[String], steps: u64, summary: &Value, what: &str) {
    let file = config::read(&lattice_drop(), sets).expect("the scene reads");
    let base = lattice_drop()
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let setup = resolve(&file, &base).expect("the scene resolves").setup;
    let mut sim = Simulation::new(setup, 1).expect("a valid scene");
    sim.step(steps);
    assert_eq!(
        Some(sim.kinetic_energy().to_bits()),
        summary["kinetic_energy_exact"].as_u64(),
        "{what}: the API run is not the binary's"
    );
    let cp = sim.checkpoint();
    let nonzero = |s: &[f64]| s.iter().any(|x| *x != 0.0);
    let pair_shear = cp.pair_shear.iter().filter(|p| nonzero(&p.2[..3])).count();
    let pair_roll = cp.pair_shear.iter().filter(|p| nonzero(&p.2[3..])).count();
    let wall_shear = cp
        .plane_shear
        .iter()
        .filter(|p| nonzero(&p.2.shear[..3]))
        .count();
    eprintln!(
        "{what} at step {steps}: {} pair and {} wall contacts; non-zero springs: \
         {pair_shear} pair tangential, {pair_roll} pair rolling, {wall_shear} wall tangential",
        summary["particle_contacts"], summary["wall_contacts"]
    );
    assert!(
        pair_shear > 0 && pair_roll > 0 && wall_shear > 0,
        "{what}: the springs are not live at step {steps}"
    );
}

/// A, B to N/2, B restarted to N: compares what the restart must keep.
fn assert_restart_mid_contact(sets: Vec<String>, n: u64, every: u64, what: &str) {
    let root = tempfile::tempdir().expect("a temporary directory");
    let (a, b, c) = (
        root.path().join("a"),
        root.path().join("b"),
        root.path().join("c"),
    );
    let va = run(&sets, n, None, &a);
    let vb = run(&sets, n / 2, None, &b);
    assert!(
        vb["particle_contacts"].as_u64().unwrap_or(0) > 0
            && vb["wall_contacts"].as_u64().unwrap_or(0) > 0,
        "{what}: no contact live at the checkpoint: {vb}"
    );
    assert_springs_live(&sets, n / 2, &vb, what);
    // The checkpoint carries completed contacts (its collision columns):
    // B's log has rows before the restart.
    let logged = std::fs::read_to_string(b.join("collisions.csv")).unwrap_or_default();
    assert!(
        logged.lines().count() > 1,
        "{what}: no contact completed before the checkpoint"
    );
    let vc = run(&sets, n, Some(&b.join("checkpoint.cbor")), &c);
    assert_eq!(vc["steps"], n);
    assert_eq!(vc["steps_this_run"], n - n / 2);
    for key in ["kinetic_energy_exact", "particle_contacts", "wall_forces"] {
        assert_eq!(vc[key], va[key], "{what}: {key}");
    }
    let read = |p: PathBuf| std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert!(
        read(a.join("checkpoint.cbor")) == read(c.join("checkpoint.cbor")),
        "{what}: the checkpoints at step {n} differ"
    );
    assert!(
        read(a.join("collisions.csv")) == read(c.join("collisions.csv")),
        "{what}: the collision logs differ"
    );
    let last = |k: u64| format!("snapshot_{k:06}.vtp");
    assert!(
        read(a.join(last(n / every))) == read(c.join(last((n - n / 2) / every))),
        "{what}: the last snapshots differ"
    );
    // The series: B's rows 0..=N/2 then C's rows N/2..=N are A's rows.
    let rows = |d: &Path| -> Vec<String> {
        let text = String::from_utf8(read(d.join("series.csv"))).expect("UTF-8");
        text.lines().map(str::to_string).collect()
    };
    let (ra, rb, rc) = (rows(&a), rows(&b), rows(&c));
    assert_eq!(ra.len() as u64, 2 + n, "{what}: header and N + 1 rows");
    assert_eq!(rb[..], ra[..rb.len()], "{what}: rows to N/2");
    assert_eq!(rc[0], ra[0], "{what}: header");
    // The restart step's row: the walls' loads are the force stage's
    // records, which a checkpoint does not hold; the restarted run
    // evaluates them at the step's end state (README), so that row's wall
    // columns differ by the velocity-dependent terms. Every other column
    // of it, and every later row, the same bits.
    let walls: Vec<usize> = ra[0]
        .split(',')
        .enumerate()
        .filter(|(_, h)| h.starts_with("wall") && (h.contains("_force_") || h.contains("_torque_")))
        .map(|(k, _)| k)
        .collect();
    assert!(!walls.is_empty(), "{what}: wall columns");
    let without_walls = |row: &str| -> Vec<String> {
        row.split(',')
            .enumerate()
            .filter(|(k, _)| !walls.contains(k))
            .map(|(_, v)| v.to_string())
            .collect()
    };
    assert_eq!(
        without_walls(&rc[1]),
        without_walls(&ra[rb.len() - 1]),
        "{what}: the restart step's row"
    );
    assert_eq!(
        rc[2..],
        ra[rb.len()..],
        "{what}: the restarted run's rows after N/2"
    );
}

/// Verlet, elastic Hertz, Δt = 20 µs: the lattice lands from step ~50 and
/// bounces; the checkpoint at step 500 (10 ms) is in the middle of it.
#[test]
fn verlet_friction_restart_mid_contact_through_the_binary() {
    let mut sets = base_sets(250);
    sets.push("integration.dt=2e-5".into());
    assert_restart_mid_contact(sets, 1000, 250, "Verlet + friction");
}

/// Gear5, Hertz + Tsuji e = 0.6, E = 1e8 Pa, Δt = 1 µs, 4,000 steps (at
/// 2 µs, 0.077 of the contact time, the energy guard stops the run at step
/// ~3,400: the tangential dashpot under Gear5, see README "Gear5"): the
/// lattice lands from step ~1,000 (a 5 µm fall); the checkpoint at step
/// 2,000 is taken with the bed on the floor, Gear5's derivatives of the
/// positions and spins live.
#[test]
fn gear5_friction_restart_mid_contact_through_the_binary() {
    let mut sets = base_sets(1000);
    sets.extend(
        [
            "integration.scheme=gear5",
            "integration.dt=1e-6",
            "material.0.youngs_modulus=1e8",
            "contact.damping=tsuji",
            "contact.restitution=0.6",
        ]
        .map(String::from),
    );
    assert_restart_mid_contact(sets, 4000, 1000, "Gear5 + friction");
}
