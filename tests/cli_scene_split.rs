//! `dembound scene --threads 1|2|3|4` on a frictional lattice large
//! enough to split (4,608 spheres, ≥ 9 force blocks of ≥ 512 bodies):
//! every output file (series, collision log, snapshots, checkpoint, the
//! resolved scene) is the same to the byte, and the same scene through
//! the engine API shows that each of 4 workers holds force blocks.
//! (`crates/dembound-scene/tests/thread_split.rs` compares the per-body
//! state under Verlet and Gear5 in the same way.)

mod common;

use common::{lattice_drop, scene_summary};
use dembound_scene::io::config;
use dembound_scene::io::resolve::resolve;
use dembound_scene::Simulation;
use serde_json::Value;
use std::ffi::OsStr;
use std::path::Path;

/// lattice_drop.toml cut to 12 × 12 × 32 spheres in a 15 mm box, with
/// Mindlin μ = 0.5 and rolling friction 0.05 on grains and walls, Δt =
/// 20 µs, 400 steps (the lattice collapses onto the floor), the collision
/// log on, a snapshot every 100 steps.
const SETS: [&str; 11] = [
    "particles.0.lattice.counts=[12,12,32]",
    "domain.upper=[0.015,0.015,0.03]",
    "wall.1.plane.point=[0.015,0.0,0.0]",
    "wall.3.plane.point=[0.0,0.015,0.0]",
    "contact.friction=0.5",
    "contact.rolling_friction=0.05",
    "integration.dt=2e-5",
    "integration.steps=400",
    "output.every=100",
    "output.collisions=true",
    "output.series_every=1",
];

fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("the output directory")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

fn run(threads: usize, out: &Path) -> Value {
    let threads = threads.to_string();
    scene_summary(
        &lattice_drop(),
        &SETS,
        &[OsStr::new("--threads"), OsStr::new(&threads)],
        out,
        &format!("{threads} threads"),
    )
}

#[test]
fn frictional_lattice_files_are_identical_on_1_to_4_threads_with_the_work_split() {
    let root = tempfile::tempdir().expect("a temporary directory");
    let one = root.path().join("1");
    let v = run(1, &one);
    // Not vacuous: the lattice collapsed, touched and turned.
    assert_eq!(v["particles"], 4608);
    assert!(v["particle_contacts"].as_u64().unwrap_or(0) > 100, "{v}");
    assert!(v["wall_contacts"].as_u64().unwrap_or(0) > 10, "{v}");
    let log = std::fs::read_to_string(one.join("collisions.csv")).expect("collisions.csv");
    assert!(log.lines().count() > 100, "too few collisions logged");
    let names = files(&one);
    for name in ["series.csv", "collisions.csv", "checkpoint.cbor"] {
        assert!(names.iter().any(|n| n == name), "{name} missing: {names:?}");
    }
    for threads in 2..=4 {
        let dir = root.path().join(threads.to_string());
        let w = run(threads, &dir);
        assert_eq!(w["threads"], threads);
        assert_eq!(files(&dir), names, "{threads} threads: other files");
        for name in &names {
            let a = std::fs::read(one.join(name)).expect("read");
            let b = std::fs::read(dir.join(name)).expect("read");
            assert!(a == b, "{name} differs between 1 and {threads} threads");
        }
        for key in ["kinetic_energy_exact", "particle_contacts", "wall_forces"] {
            assert_eq!(w[key], v[key], "{threads} threads: {key}");
        }
    }

    // The split: the same scene through the engine API on 4 threads;
    // every worker holds force blocks at every sample (25 steps apart),
    // and the run is the binary's (the same kinetic energy to the bit).
    let sets: Vec<String> = SETS.iter().map(|s| s.to_string()).collect();
    let file = config::read(&lattice_drop(), &sets).expect("the scene reads");
    let base = lattice_drop()
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let setup = resolve(&file, &base).expect("the scene resolves").setup;
    let mut sim = Simulation::new(setup, 4).expect("a valid scene");
    // The shares follow measured block times (scheduling only): a worker
    // preempted on a busy machine may lose its blocks for a while, so each
    // must hold a block in at least 3/4 of the samples (measured: all).
    let mut fewest = vec![usize::MAX; 4];
    let mut held = [0usize; 4];
    for _ in 0..16 {
        sim.step(25);
        let shares = sim.worker_shares();
        assert_eq!(shares.len(), 4, "the force loop is shared by 4 workers");
        let blocks: usize = shares.iter().map(|s| s.0).sum();
        assert!(blocks >= 4, "{blocks} force blocks for 4 workers");
        for (t, (blocks, bodies)) in shares.into_iter().enumerate() {
            held[t] += usize::from(blocks >= 1);
            fewest[t] = fewest[t].min(bodies);
        }
    }
    eprintln!(
        "4 threads: fewest bodies held per worker over the run {fewest:?} of 4608; \
         samples with a block {held:?} of 16"
    );
    assert!(
        held.iter().all(|&h| h >= 12),
        "shares {held:?} of 16 samples"
    );
    assert_eq!(
        Some(sim.kinetic_energy().to_bits()),
        v["kinetic_energy_exact"].as_u64(),
        "the API run is not the binary's"
    );
}
