//! `mpirun -np N dembound scene` (feature `mpi`, issue 16): the same
//! lattice drop (also with friction) on 1, 2 and 3 ranks ends in the same
//! state and the same wall forces and torques to the bit,
//! over shared memory and over TCP on loopback (`--mca btl tcp,self`).
//! Needs Open MPI's `mpirun` (Debian: openmpi-bin); run with
//! `cargo test --release --features mpi --test mpi`. Three ranks on a
//! two-core machine: `--oversubscribe`.
#![cfg(feature = "mpi")]

use std::path::Path;
use std::process::Command;

/// A 8 × 8 × 10 lattice drop (640 spheres, the benchmark's spheres and
/// walls in a box 10.2 mm wide), 10⁴ steps of 2 µs.
fn scene_args() -> Vec<String> {
    [
        "--set",
        "particles.0.lattice.counts=[8,8,10]",
        "--set",
        "domain.upper=[0.0102,0.0102,0.03]",
        "--set",
        "wall.1.plane.point=[0.0102,0.0,0.0]",
        "--set",
        "wall.3.plane.point=[0.0,0.0102,0.0]",
        "--set",
        "integration.steps=10000",
        "--quiet",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// `mpirun --oversubscribe -np RANKS [MCA] dembound scene examples/scenes/SCENE`
/// (allowed as root), arguments to follow.
fn mpirun_scene(ranks: usize, mca: &[&str], scene: &str) -> Command {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes")
        .join(scene);
    let mut cmd = Command::new("mpirun");
    cmd.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .args(["--oversubscribe", "-np", &ranks.to_string()])
        .args(mca)
        .arg(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(scene);
    cmd
}

fn mpirun(ranks: usize, mca: &[&str], extra: &[&str], out: &Path) -> serde_json::Value {
    let mut cmd = mpirun_scene(ranks, mca, "lattice_drop.toml");
    cmd.args(scene_args())
        .args(extra)
        .arg("--json")
        .arg("--out")
        .arg(out);
    let o = cmd.output().expect("mpirun runs (Debian: openmpi-bin)");
    assert!(
        o.status.success(),
        "{ranks} ranks: {}\n{}",
        o.status,
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

/// The end state's positions and velocities (columns 1..7 of state.csv,
/// shortest round-trip text: equal text is equal bits).
fn state(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("state.csv")).expect("state.csv");
    text.lines()
        .skip(1)
        .map(|l| l.split(',').take(7).collect::<Vec<_>>().join(","))
        .collect()
}

fn same_run(mca: &[&str]) {
    same_run_with(mca, &[]);
}

/// `same_run` with `more` arguments on every run.
fn same_run_with(mca: &[&str], more: &[&str]) {
    let tmp = tempfile::tempdir().expect("temp dir");
    let d1 = tmp.path().join("r1");
    let j1 = mpirun(1, mca, more, &d1);
    let s1 = state(&d1);
    assert_eq!(s1.len(), 640);
    // The drop has happened: many contacts, spheres on the floor.
    assert!(j1["particle_contacts"].as_u64().unwrap_or(0) > 100, "{j1}");
    for (ranks, extra) in [
        (2, vec![]),
        (3, vec![]),
        (3, vec!["--set", "parallel.grid=[1,3,1]"]),
    ] {
        let d = tmp.path().join(format!("r{ranks}{}", extra.len()));
        let extra: Vec<&str> = extra.into_iter().chain(more.iter().copied()).collect();
        let j = mpirun(ranks, mca, &extra, &d);
        assert_eq!(j["ranks"], ranks);
        let owned: Vec<u64> = j["rank_particles"]
            .as_array()
            .expect("per-rank counts")
            .iter()
            .filter_map(|v| v.as_u64())
            .collect();
        assert_eq!(owned.iter().sum::<u64>(), 640);
        assert!(owned.iter().all(|&k| k > 0), "{owned:?}");
        let s = state(&d);
        for (k, (a, b)) in s.iter().zip(&s1).enumerate() {
            assert_eq!(a, b, "{ranks} ranks {extra:?}: body {k}");
        }
        // Integers exactly; the energies are sums over ranks in another
        // order: 1e-12 relative. The walls' forces and torques are summed
        // from the force stage's records in input-id order on every rank
        // count: the same bits (the JSON's shortest round-trip numbers
        // equal).
        assert_eq!(j["particle_contacts"], j1["particle_contacts"]);
        assert_eq!(j["wall_contacts"], j1["wall_contacts"]);
        for key in ["wall_forces", "wall_torques", "wall_torque_points"] {
            assert!(j1[key].as_array().is_some_and(|w| w.len() == 6), "{key}");
            assert_eq!(j[key], j1[key], "{ranks} ranks {extra:?}: {key}");
        }
        for key in ["kinetic_energy", "elastic_energy"] {
            let (a, b) = (
                j[key].as_f64().unwrap_or(0.0),
                j1[key].as_f64().unwrap_or(1.0),
            );
            assert!((a - b).abs() <= 1e-12 * b.abs(), "{key}: {a} vs {b}");
        }
    }
}

#[test]
fn one_two_three_ranks_same_state_shared_memory() {
    same_run(&[]);
}

/// The halo exchange during the interior pairs (`parallel.halo_overlap =
/// true`, `dynamics::halo_split`): the lattice drop on 2 and 3
/// ranks (a bed settled across the cuts: many pairs with halo copies)
/// takes the split path on every rank (the JSON's overlapped steps and
/// deferred pairs) and ends in the same state and wall loads as with
/// `halo_overlap = false` (the exchange before the force stage, as the
/// code was) and as on 1 rank.
#[test]
fn the_halo_overlap_keeps_the_bits_under_mpirun() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let off = ["--set", "parallel.halo_overlap=false"];
    let overlap = ["--set", "parallel.halo_overlap=true"];
    let d1 = tmp.path().join("r1");
    mpirun(1, &[], &off, &d1);
    let s1 = state(&d1);
    let per_rank = |j: &serde_json::Value, key: &str| -> Vec<u64> {
        j[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key} in {j}"))
            .iter()
            .filter_map(|v| v.as_u64())
            .collect()
    };
    for ranks in [2, 3] {
        let (d_on, d_off) = (
            tmp.path().join(format!("on{ranks}")),
            tmp.path().join(format!("off{ranks}")),
        );
        let on = mpirun(ranks, &[], &overlap, &d_on);
        let before = mpirun(ranks, &[], &off, &d_off);
        // 10,000 steps, a series row every 10: 9 in 10 steps are fused
        // (the last of each stretch is not, nor are the list builds').
        let overlapped = per_rank(&on, "rank_overlapped_steps");
        assert_eq!(overlapped.len(), ranks);
        assert!(overlapped.iter().all(|&k| k > 5000), "{on}");
        let deferred = per_rank(&on, "rank_deferred_pairs");
        assert!(deferred.iter().all(|&k| k > 0), "{deferred:?}");
        assert!(per_rank(&before, "rank_overlapped_steps")
            .iter()
            .all(|&k| k == 0));
        let s = state(&d_on);
        assert_eq!(s, state(&d_off), "{ranks} ranks: overlapped against not");
        assert_eq!(s, s1, "{ranks} ranks against 1");
        for key in ["particle_contacts", "wall_forces", "wall_torques"] {
            assert_eq!(on[key], before[key], "{ranks} ranks: {key}");
        }
    }
}

#[test]
fn one_two_three_ranks_same_state_over_tcp() {
    same_run(&["--mca", "pml", "ob1", "--mca", "btl", "tcp,self"]);
}

/// With friction and rolling friction (Mindlin, μ = 0.5, μ_r = 0.05):
/// spins in the halo, springs migrating with their bodies; the same bits
/// on 1, 2 and 3 ranks.
#[test]
fn friction_one_two_three_ranks_same_state() {
    same_run_with(
        &[],
        &[
            "--set",
            "contact.friction=0.5",
            "--set",
            "contact.tangential=\"mindlin\"",
            "--set",
            "contact.rolling_friction=0.05",
        ],
    );
}

/// Gear5 with friction and rolling friction (the spins' Nordsieck
/// vectors migrate with their bodies): the same bits on 1, 2 and 3 ranks
/// (4,000 steps). The energies are summed at the halo copies' predicted
/// state (Gear5's observation under MPI): 1e-7 relative.
#[test]
fn gear5_friction_one_two_three_ranks_same_state() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let more = [
        "--set",
        "integration.scheme=\"gear5\"",
        "--set",
        "integration.steps=4000",
        "--set",
        "contact.friction=0.5",
        "--set",
        "contact.rolling_friction=0.05",
    ];
    let d1 = tmp.path().join("g1");
    let j1 = mpirun(1, &[], &more, &d1);
    let s1 = state(&d1);
    assert_eq!(s1.len(), 640);
    for ranks in [2, 3] {
        let d = tmp.path().join(format!("g{ranks}"));
        let j = mpirun(ranks, &[], &more, &d);
        assert_eq!(state(&d), s1, "{ranks} ranks");
        assert_eq!(j["particle_contacts"], j1["particle_contacts"]);
        for key in ["kinetic_energy", "elastic_energy"] {
            let (a, b) = (
                j[key].as_f64().unwrap_or(0.0),
                j1[key].as_f64().unwrap_or(1.0),
            );
            assert!((a - b).abs() <= 1e-7 * b.abs(), "{key}: {a} vs {b}");
        }
    }
}

/// The collision log through `mpirun`: `collisions.csv` of 2 and 3 ranks
/// is the same text as 1 rank's (shortest round-trip numbers: the same
/// bits), and not empty.
#[test]
fn collision_log_is_the_same_on_one_two_three_ranks() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let extra = [
        "--set",
        "output.collisions=true",
        "--set",
        "integration.steps=3000",
    ];
    let read = |ranks: usize| {
        let d = tmp.path().join(format!("c{ranks}"));
        mpirun(ranks, &[], &extra, &d);
        std::fs::read_to_string(d.join("collisions.csv")).expect("collisions.csv")
    };
    let one = read(1);
    assert!(one.lines().count() > 20, "{one}");
    assert_eq!(read(2), one);
    assert_eq!(read(3), one);
}

/// Bad input on every rank: one message, exit 2, no output directory.
#[test]
fn bad_grid_exits_2_with_one_message() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("never");
    let o = mpirun_scene(2, &[], "lattice_drop.toml")
        .args(["--set", "parallel.grid=[1,1,3]", "--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("mpirun runs");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("error: parallel.grid").count(), 1, "{err}");
    assert!(!out.exists());
}

/// A step far beyond the contact time is refused under MPI before any
/// step, one message naming `integration.dt` (issue 24). A run inside the
/// bound that creates energy (the settling bed under Gear5 with Tsuji
/// e = 0.3 and friction μ = 0.5 at 2 µs, see `cli_scene_guard.rs`) stops on every rank with one
/// message from the energy guard (the ranks see the same summed energies),
/// exit 2, no output directory (instead of NaN energies).
#[test]
fn a_blown_up_run_exits_2_with_one_message() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("never");
    let o = mpirun_scene(2, &[], "bed_particle_floor.toml")
        .args([
            "--set",
            "integration.dt=1e-3",
            "--set",
            "integration.steps=400",
        ])
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("mpirun runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(
        err.matches("error: integration.dt = 1e-3 s is out of range")
            .count(),
        1,
        "{err}"
    );
    assert!(!out.exists());
    let o = mpirun_scene(3, &[], "settling_bed.toml")
        .args(["--set", "integration.scheme=gear5"])
        .args(["--set", "contact.friction=0.5"])
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("mpirun runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.matches("the run created energy").count(), 1, "{err}");
    assert!(err.contains("likely cause: the step"), "{err}");
    assert!(!out.exists());
}

/// `--out` under MPI writes the engine's checkpoint; `--restart` continues
/// it on any number of ranks. The lattice drop with Walton–Braun (every
/// contact's largest overlap is state): 2000 steps on 2 ranks and a
/// checkpoint, then 2000 more on 3 ranks and on 1, end in the same
/// positions and velocities as 4000 steps on 2 ranks in one go, and in a
/// byte-identical checkpoint file (the whole state, every history, the
/// list builds). The one-process engine continues it too.
#[test]
fn checkpoint_on_two_ranks_restarts_on_three_and_one() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let law = [
        "--set",
        "contact.law=walton-braun",
        "--set",
        "contact.restitution=0.5",
    ];
    let with = |steps: &str, more: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = law.iter().map(|s| s.to_string()).collect();
        v.push("--set".into());
        v.push(format!("integration.steps={steps}"));
        v.extend(more.iter().map(|s| s.to_string()));
        v
    };
    let run = |ranks: usize, args: Vec<String>, name: &str| {
        let d = tmp.path().join(name);
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let j = mpirun(ranks, &[], &refs, &d);
        (d, j)
    };
    let (straight, j) = run(2, with("4000", &[]), "straight");
    assert_eq!(j["steps"], 4000);
    let (half, _) = run(2, with("2000", &[]), "half");
    let cp = half.join("checkpoint.cbor");
    let cp_arg = cp.to_string_lossy().to_string();
    let expected = state(&straight);
    let expected_cp = std::fs::read(straight.join("checkpoint.cbor")).expect("checkpoint");
    for ranks in [3, 1] {
        let (d, j) = run(
            ranks,
            with("4000", &["--restart", &cp_arg]),
            &format!("r{ranks}"),
        );
        assert_eq!(j["steps"], 4000);
        assert_eq!(j["steps_this_run"], 2000);
        assert_eq!(state(&d), expected, "{ranks} ranks");
        let got = std::fs::read(d.join("checkpoint.cbor")).expect("checkpoint");
        assert!(got == expected_cp, "{ranks} ranks: checkpoint differs");
    }
    // Without mpirun: the engine reads the same file.
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(&scene)
        .args(scene_args())
        .args(with("4000", &["--restart", &cp_arg, "--json"]))
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(j["steps"], 4000);
}

/// Load re-balancing through `mpirun` (examples/scenes/settling_bed.toml:
/// 360 spheres thrown onto the floor, z cut in three): the JSON reports
/// each rank's free spheres at the start, before the last re-partition
/// and at the end; with re-balancing the end is within the threshold,
/// without it the bed sits in the bottom two sub-domains; the end state is
/// the same bits either way. A threshold ≤ 1 is refused (exit 2, the key
/// named, nothing written).
#[test]
fn settling_bed_rebalances_under_mpirun() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let run = |threshold: &str, name: &str| {
        let out = tmp.path().join(name);
        let o = mpirun_scene(3, &[], "settling_bed.toml")
            .args([
                "--set",
                &format!("parallel.rebalance_threshold={threshold}"),
            ])
            .args(["--quiet", "--json", "--out"])
            .arg(&out)
            .output()
            .expect("mpirun runs");
        (o, out)
    };
    let counts = |j: &serde_json::Value, key: &str| -> Vec<u64> {
        j[key]
            .as_array()
            .expect(key)
            .iter()
            .filter_map(|v| v.as_u64())
            .collect()
    };
    let (o, d_moved) = run("1.2", "moved");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let moved: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let (o, d_still) = run("inf", "still");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let still: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    // Layers 0–2, 3–5 and 6–9 of the cloud (cuts at 5.1 and 9.6 mm).
    assert_eq!(counts(&moved, "rank_free_particles_start"), [108, 108, 144]);
    assert!(moved["rebalances"].as_u64().unwrap_or(0) >= 1, "{moved}");
    let before = counts(&moved, "rank_free_particles_before_rebalance");
    assert_eq!(before.iter().sum::<u64>(), 360);
    let end = counts(&moved, "rank_free_particles");
    assert_eq!(end.iter().sum::<u64>(), 360);
    assert!(moved["imbalance"].as_f64().unwrap_or(9.0) <= 1.2, "{moved}");
    assert_eq!(still["rebalances"], 0);
    assert!(still["imbalance"].as_f64().unwrap_or(0.0) > 2.0, "{still}");
    assert_eq!(state(&d_moved), state(&d_still));
    assert_eq!(moved["particle_contacts"], still["particle_contacts"]);

    let (o, d_bad) = run("1.0", "bad");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        err.matches("invalid value for `parallel.rebalance_threshold`: 1")
            .count(),
        1,
        "{err}"
    );
    assert!(err.contains("> 1"), "{err}");
    assert!(!d_bad.exists());
}

/// Issue 24's refusals hold under MPI (every rank resolves and prepares the
/// whole scene): a floor across a periodic z is refused on 2 ranks with one
/// message naming the wall and `domain.periodic`, exit 2, no output.
#[test]
fn a_wall_across_a_periodic_axis_is_refused_with_one_message() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("never");
    let o = mpirun_scene(2, &[], "lattice_drop.toml")
        .args(["--set", "domain.periodic=[false,false,true]"])
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("mpirun runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.matches("error: ").count(), 1, "{err}");
    assert!(
        err.contains("wall[4].plane.normal") && err.contains("domain.periodic"),
        "{err}"
    );
    assert!(!out.exists());
}

/// A triangle-mesh wall under MPI (issue 26): examples/scenes/mesh_box.toml
/// (the lattice drop's box as one 12-triangle STL; 8 × 8 × 10 spheres in
/// it, 5,000 steps) on 1 and 2 ranks ends in the same state and the same
/// wall load to the bit. Every rank loads the mesh (here 12 triangles, a
/// few kB; about 320 B per triangle, `walls::mesh`).
#[test]
fn a_mesh_wall_one_and_two_ranks_same_state() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let run = |ranks: usize| {
        let d = tmp.path().join(format!("mesh{ranks}"));
        let o = mpirun_scene(ranks, &[], "mesh_box.toml")
            .args([
                "--set",
                "particles.0.lattice.counts=[8,8,10]",
                "--set",
                "integration.steps=5000",
                "--quiet",
                "--json",
                "--out",
            ])
            .arg(&d)
            .output()
            .expect("mpirun runs");
        assert!(
            o.status.success(),
            "{ranks} ranks: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        (state(&d), j)
    };
    let (s1, j1) = run(1);
    let (s2, j2) = run(2);
    assert_eq!(s1.len(), 640);
    assert!(j1["wall_contacts"].as_u64().unwrap_or(0) > 20, "{j1}");
    assert_eq!(j2["ranks"], 2);
    let owned: Vec<u64> = j2["rank_particles"]
        .as_array()
        .expect("per-rank counts")
        .iter()
        .filter_map(|v| v.as_u64())
        .collect();
    assert!(
        owned.len() == 2 && owned.iter().all(|&k| k > 0),
        "{owned:?}"
    );
    assert_eq!(s1, s2);
    for key in [
        "wall_contacts",
        "particle_contacts",
        "wall_forces",
        "wall_torques",
    ] {
        assert_eq!(j1[key], j2[key], "{key}");
    }
    // The per-triangle loads (wall_0_*.vtp, issue 26): rank 0 gathers
    // every rank's records, merges them by input id and sums them as one
    // process does: the same bytes on 1 and 2 ranks, and the same as the
    // one-process CLI run (no mpirun).
    let one = tmp.path().join("mesh1");
    let two = tmp.path().join("mesh2");
    let plain = tmp.path().join("plain");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/mesh_box.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(scene)
        .args([
            "--set",
            "particles.0.lattice.counts=[8,8,10]",
            "--set",
            "integration.steps=5000",
            "--quiet",
            "--out",
        ])
        .arg(&plain)
        .output()
        .expect("dembound runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut walls = 0;
    for entry in std::fs::read_dir(&one).expect("output") {
        let name = entry.expect("entry").file_name();
        let name = name.to_string_lossy().into_owned();
        if name.starts_with("wall_0_") && name.ends_with(".vtp") {
            let a = std::fs::read(one.join(&name)).expect("1 rank");
            let b = std::fs::read(two.join(&name)).expect("2 ranks");
            let c = std::fs::read(plain.join(&name)).expect("one process");
            assert!(a == b, "{name} differs between 1 and 2 ranks");
            assert!(a == c, "{name} differs between mpirun and one process");
            walls += 1;
        }
    }
    assert_eq!(
        walls, 6,
        "one wall file per snapshot (every 1000 steps, 0 to 5000)"
    );
    let pvd = std::fs::read_to_string(two.join("snapshots.pvd")).expect("pvd");
    assert!(
        pvd.contains("part=\"1\" file=\"wall_0_000005.vtp\""),
        "{pvd}"
    );
}

/// Moving walls (issue 27) under MPI: the lattice drop on a floor that
/// moves along x and oscillates vertically, on 1, 2 and 3 ranks: the same
/// end state to the bit (every rank places the walls from the step
/// number alone), the same wall forces and torques; the walls' work is
/// each rank's share summed over the ranks, in another order on another
/// rank count: 1e-12 relative. A checkpoint written on 2 ranks continues
/// on 3 ranks and on one process with the same state.
#[test]
fn a_moving_floor_one_two_three_ranks_and_restart() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let motion = [
        "--set",
        "wall.4.motion.velocity=[0.05,0,0]",
        "--set",
        "wall.4.oscillation={amplitude=[0,0,2e-5],frequency=200}",
    ];
    let run = |ranks: usize, steps: &str, more: &[&str], name: &str| {
        let d = tmp.path().join(name);
        let mut args: Vec<String> = motion.iter().map(|s| s.to_string()).collect();
        args.push("--set".into());
        args.push(format!("integration.steps={steps}"));
        args.extend(more.iter().map(|s| s.to_string()));
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let j = mpirun(ranks, &[], &refs, &d);
        (d, j)
    };
    let work = |j: &serde_json::Value| j["energy_balance"]["work_by_walls"].as_f64().unwrap();
    let (d1, j1) = run(1, "4000", &[], "m1");
    assert!(work(&j1) > 0.0, "{j1}");
    let s1 = state(&d1);
    for ranks in [2, 3] {
        let (d, j) = run(ranks, "4000", &[], &format!("m{ranks}"));
        assert_eq!(state(&d), s1, "{ranks} ranks");
        for key in ["wall_forces", "wall_torques", "wall_contacts"] {
            assert_eq!(j[key], j1[key], "{ranks} ranks: {key}");
        }
        assert!(
            (work(&j) - work(&j1)).abs() <= 1e-12 * work(&j1),
            "{ranks} ranks"
        );
    }
    let (half, _) = run(2, "2000", &[], "half");
    let cp = half.join("checkpoint.cbor").to_string_lossy().to_string();
    for ranks in [3, 1] {
        let (d, j) = run(ranks, "4000", &["--restart", &cp], &format!("r{ranks}"));
        assert_eq!(j["steps_this_run"], 2000);
        assert_eq!(state(&d), s1, "restart on {ranks} ranks");
        assert!(
            (work(&j) - work(&j1)).abs() <= 1e-12 * work(&j1),
            "restart on {ranks}"
        );
    }
}

/// A servo lid (issue 27 item 2) under MPI: the lattice drop with the lid
/// pressing down at F = 0.05 N, on 1, 2 and 3 ranks: every rank sums the
/// lid's load from every rank's records in input-id order after each
/// force evaluation, so the lid moves the same on any rank count: the
/// same end state and the same lid position and speed to the bit; a
/// checkpoint written on 2 ranks mid-press continues on 3 ranks and on
/// one process with the same state.
#[test]
fn a_servo_lid_one_two_three_ranks_and_restart() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let servo = [
        "--set",
        "wall.5.servo={force=0.05,axis=[0,0,-1],max_velocity=3,gain=1}",
    ];
    let run = |ranks: usize, steps: &str, more: &[&str], name: &str| {
        let d = tmp.path().join(name);
        let mut args: Vec<String> = servo.iter().map(|s| s.to_string()).collect();
        args.push("--set".into());
        args.push(format!("integration.steps={steps}"));
        args.extend(more.iter().map(|s| s.to_string()));
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let j = mpirun(ranks, &[], &refs, &d);
        (d, j)
    };
    let (d1, j1) = run(1, "5000", &[], "s1");
    // The lid came down and presses on the spheres.
    let lid = &j1["wall_motions"][0];
    assert_eq!(lid["wall"], 5);
    assert!(j1["wall_forces"][5][2].as_f64().unwrap() > 0.0, "{j1}");
    let s1 = state(&d1);
    for ranks in [2, 3] {
        let (d, j) = run(ranks, "5000", &[], &format!("s{ranks}"));
        assert_eq!(state(&d), s1, "{ranks} ranks");
        for key in ["wall_forces", "wall_motions", "wall_contacts"] {
            assert_eq!(j[key], j1[key], "{ranks} ranks: {key}");
        }
    }
    let (half, _) = run(2, "2500", &[], "half");
    let cp = half.join("checkpoint.cbor").to_string_lossy().to_string();
    for ranks in [3, 1] {
        let (d, j) = run(ranks, "5000", &["--restart", &cp], &format!("r{ranks}"));
        assert_eq!(j["steps_this_run"], 2500);
        assert_eq!(state(&d), s1, "restart on {ranks} ranks");
        assert_eq!(j["wall_motions"], j1["wall_motions"], "restart on {ranks}");
    }
}

/// A gate under MPI (issue 28, `[[wall]] active`): the lattice drop's
/// floor (wall 4, z = 0) vanishes at 10 ms and the bed falls onto a second
/// floor 1 mm below (wall 6), on 1, 2 and 3 ranks: the switch is at the
/// same step on every rank (a function of the step), each rank drops its
/// own spheres' floor contacts, so the end state and the wall loads are
/// the same bits; the gate energy (each rank's share, summed) to 1e-12; a
/// checkpoint written on 2 ranks before the opening and one after continue
/// on 3 ranks and on one process with the same state.
#[test]
fn a_gate_opening_one_two_three_ranks_and_restart() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let scene = tmp.path().join("gate.toml");
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop.toml"),
    )
    .expect("lattice_drop.toml");
    std::fs::write(
        &scene,
        format!(
            "{text}\n[[wall]]\nplane = {{ point = [0.0, 0.0, -0.001], normal = [0.0, 0.0, 1.0] }}\n\
             material = \"grain\"\n"
        ),
    )
    .unwrap();
    let run = |ranks: usize, steps: &str, more: &[&str], name: &str| {
        let d = tmp.path().join(name);
        let mut cmd = mpirun_scene(ranks, &[], scene.to_str().unwrap());
        cmd.args(scene_args())
            .args([
                "--set",
                "domain.lower=[0.0,0.0,-0.001]",
                "--set",
                "wall.4.active={to=0.01}",
                "--set",
                &format!("integration.steps={steps}"),
            ])
            .args(more)
            .arg("--json")
            .arg("--out")
            .arg(&d);
        let o = cmd.output().expect("mpirun runs");
        assert!(
            o.status.success(),
            "{ranks} ranks: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        (d, j)
    };
    let gate = |j: &serde_json::Value| j["energy_balance"]["gate_energy"].as_f64().unwrap();
    // 7,000 steps: the floor let go of the settled bed at step 5,000.
    let (d1, j1) = run(1, "7000", &[], "g1");
    assert!(gate(&j1) > 0.0, "{j1}");
    assert_eq!(j1["wall_forces"][4], serde_json::json!([0.0, 0.0, 0.0]));
    let s1 = state(&d1);
    for ranks in [2, 3] {
        let (d, j) = run(ranks, "7000", &[], &format!("g{ranks}"));
        assert_eq!(state(&d), s1, "{ranks} ranks");
        for key in ["wall_forces", "wall_torques", "wall_contacts"] {
            assert_eq!(j[key], j1[key], "{ranks} ranks: {key}");
        }
        // Each rank's share summed: another order of additions.
        assert!(
            (gate(&j) - gate(&j1)).abs() <= 1e-12 * gate(&j1),
            "{ranks} ranks"
        );
    }
    for cut in ["3000", "6000"] {
        let (half, _) = run(2, cut, &[], &format!("half{cut}"));
        let cp = half.join("checkpoint.cbor").to_string_lossy().to_string();
        for ranks in [3, 1] {
            let (d, j) = run(
                ranks,
                "7000",
                &["--restart", &cp],
                &format!("r{cut}{ranks}"),
            );
            assert_eq!(state(&d), s1, "restart at {cut} on {ranks} ranks");
            assert!(
                (gate(&j) - gate(&j1)).abs() <= 1e-12 * gate(&j1),
                "restart at {cut} on {ranks}"
            );
        }
    }
}

/// `mpirun -np RANKS dembound scene examples/scenes/SCENE ARGS --quiet
/// --json --out OUT` (or, `ranks` 0, the one-process CLI with
/// `--threads 2`): the JSON report.
fn run_scene(ranks: usize, scene: &str, args: &[&str], out: &Path) -> serde_json::Value {
    let mut cmd = if ranks == 0 {
        let mut c = Command::new(env!("CARGO_BIN_EXE_dembound"));
        c.arg("scene")
            .arg(
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("examples/scenes")
                    .join(scene),
            )
            .args(["--threads", "2"]);
        c
    } else {
        mpirun_scene(ranks, &[], scene)
    };
    let o = cmd
        .args(args)
        .args(["--quiet", "--json", "--out"])
        .arg(out)
        .output()
        .expect("dembound runs");
    assert!(
        o.status.success(),
        "{scene} on {ranks} ranks: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

/// The walls' work of a `--json` report, J.
fn work_by_walls(j: &serde_json::Value) -> f64 {
    j["energy_balance"]["work_by_walls"]
        .as_f64()
        .unwrap_or(f64::NAN)
}

/// Turning drums (issue 27) under MPI: the triangle-mesh drum of
/// examples/scenes/drum.toml (4,000 steps) and the cylinder-and-caps drum
/// of examples/scenes/drum_cylinder.toml (3,000 steps, without its
/// contact-by-contact dissipation), each on 1, 2 and 3 ranks: the same
/// end state to the bit (every rank poses the turning wall from the step
/// number), the same wall loads, contacts and wall motions (the loads
/// summed from every rank's records in input-id order); the walls' work
/// is each rank's share summed, in another order on another rank count:
/// 1e-12 relative, as the moving floor's.
#[test]
fn turning_mesh_and_cylinder_drums_one_two_three_ranks() {
    let tmp = tempfile::tempdir().expect("temp dir");
    for (scene, args) in [
        ("drum.toml", vec!["--set", "integration.steps=4000"]),
        (
            "drum_cylinder.toml",
            vec![
                "--set",
                "integration.steps=3000",
                "--set",
                "output.dissipation=false",
            ],
        ),
    ] {
        let d1 = tmp.path().join(format!("{scene}1"));
        let j1 = run_scene(1, scene, &args, &d1);
        // The bed reached the turning wall, which did work on it.
        assert!(j1["wall_contacts"].as_u64().unwrap_or(0) > 0, "{j1}");
        assert!(work_by_walls(&j1) > 0.0, "{j1}");
        let s1 = state(&d1);
        for ranks in [2, 3] {
            let d = tmp.path().join(format!("{scene}{ranks}"));
            let j = run_scene(ranks, scene, &args, &d);
            assert_eq!(state(&d), s1, "{scene} on {ranks} ranks");
            for key in [
                "wall_forces",
                "wall_torques",
                "wall_contacts",
                "particle_contacts",
                "wall_motions",
            ] {
                assert_eq!(j[key], j1[key], "{scene} on {ranks} ranks: {key}");
            }
            let (a, b) = (work_by_walls(&j), work_by_walls(&j1));
            assert!((a - b).abs() <= 1e-12 * b, "{scene} on {ranks}: {a} vs {b}");
        }
    }
}

/// A small lined drum (issue 27, examples/scenes/lined_drum.toml: the 828
/// fixed spheres of its r = 1 lining turning with its caps at
/// 1.8718 rad/s; 112 + 56 free spheres, μ = 0.5, dropped near the
/// bottom), 6,000 steps of 10 µs on 1, 2 and 3 ranks: every rank places
/// its copies of the lining's spheres (owned and halo) from the step, so
/// the end state (free and lining spheres) is the same to the bit and the
/// contacts are the same. The lining's force and torque (`group_motions`)
/// and the walls' work are each rank's share summed over the ranks, in
/// another order on another rank count: equal to 1e-12 of the scale of
/// their terms (the bed's weight M g, M g R and M g R · ωt; a sum of a few
/// hundred terms of that size rounds at ~1e-14 of it). The one-process
/// run on 2 threads sums each body's forces in its own list's order
/// (README, "Threads, MPI ranks and one process"): the same snapshots
/// while the bed falls, the same contacts and the same loads, work and
/// energy to 1e-6 after it landed. A checkpoint written on 2 ranks
/// continues on 3 ranks and on one process with the same state.
#[test]
fn a_lined_drum_one_two_three_ranks_threads_and_restart() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let args = [
        "--set",
        "particles.0.lattice={counts=[8,7,2],spacing=[2.3e-3,2.3e-3,4.6e-3],origin=[-8.05e-3,-7.475e-3,-23e-3],radius=1.1e-3}",
        "--set",
        "particles.1.lattice={counts=[8,7,1],spacing=[2.3e-3,2.3e-3,4.6e-3],origin=[-8.05e-3,-7.475e-3,-20.7e-3],radius=0.9e-3}",
        "--set",
        "output.every=1000",
    ];
    let run = |ranks: usize, steps: &str, more: &[&str], name: &str| {
        let d = tmp.path().join(name);
        let mut a: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        a.push("--set".into());
        a.push(format!("integration.steps={steps}"));
        a.extend(more.iter().map(|s| s.to_string()));
        let refs: Vec<&str> = a.iter().map(|s| s.as_str()).collect();
        let j = run_scene(ranks, "lined_drum.toml", &refs, &d);
        (d, j)
    };
    let (d1, j1) = run(1, "6000", &[], "l1");
    let s1 = state(&d1);
    assert_eq!(s1.len(), 112 + 56 + 828);
    let lining = &j1["group_motions"][0];
    assert_eq!(lining["group"], 2);
    // The bed lies on the lining: it carries the bed's weight, and the
    // turning lining does work on it.
    let free_mass = 2500.0 * 4.0 / 3.0
        * std::f64::consts::PI
        * (112.0 * 1.1e-3f64.powi(3) + 56.0 * 0.9e-3f64.powi(3));
    let weight = free_mass * 9.81;
    assert!(j1["particle_contacts"].as_u64().unwrap_or(0) > 50, "{j1}");
    assert!(work_by_walls(&j1) > 0.0, "{j1}");
    let fz = lining["force"][2].as_f64().unwrap_or(f64::NAN);
    assert!(fz < -0.2 * weight, "lining force {fz} N, weight {weight} N");
    let r = 0.028;
    let scales = [weight, weight * r];
    let near = |a: &serde_json::Value, b: &serde_json::Value, scale: f64, what: &str| {
        for k in 0..3 {
            let (x, y) = (
                a[k].as_f64().unwrap_or(f64::NAN),
                b[k].as_f64().unwrap_or(0.0),
            );
            assert!((x - y).abs() <= 1e-12 * scale, "{what}[{k}]: {x} vs {y}");
        }
    };
    let work_scale = weight * r * 1.8718 * 0.06;
    for ranks in [2, 3] {
        let (d, j) = run(ranks, "6000", &[], &format!("l{ranks}"));
        assert_eq!(state(&d), s1, "{ranks} ranks");
        for key in [
            "particle_contacts",
            "wall_contacts",
            "wall_forces",
            "wall_motions",
        ] {
            assert_eq!(j[key], j1[key], "{ranks} ranks: {key}");
        }
        let g = &j["group_motions"][0];
        for key in [
            "group",
            "position",
            "angle",
            "velocity",
            "angular_velocity",
            "torque_point",
        ] {
            assert_eq!(g[key], lining[key], "{ranks} ranks: {key}");
        }
        for (key, scale) in ["force", "torque"].into_iter().zip(scales) {
            near(
                &g[key],
                &lining[key],
                scale,
                &format!("{ranks} ranks: {key}"),
            );
        }
        let (a, b) = (work_by_walls(&j), work_by_walls(&j1));
        assert!(
            (a - b).abs() <= 1e-12 * work_scale,
            "{ranks} ranks: {a} vs {b}"
        );
    }
    // One process on 2 threads: every snapshot through step 2,000 (the
    // bed in flight) is the same file; after the landing each body's
    // forces are summed in another order (README, "Threads, MPI ranks and
    // one process") and the last-bit differences grow with each
    // collision: the same contacts, and the lining's load, the work and
    // the kinetic energy within 1e-6 of their scales (a missing or
    // doubled rank share would be off by order 1; the README measured
    // 3e-7 m of divergence only after 64 ms of a dense bed).
    let (d0, j0) = run(0, "6000", &[], "threads");
    for k in 0..=2 {
        let name = format!("snapshot_{k:06}.vtp");
        let a = std::fs::read(d0.join(&name)).expect("one-process snapshot");
        let b = std::fs::read(d1.join(&name)).expect("MPI snapshot");
        assert!(a == b, "{name} differs between one process and MPI");
    }
    assert_eq!(j0["particle_contacts"], j1["particle_contacts"]);
    let g0 = &j0["group_motions"][0];
    for (key, scale) in ["force", "torque"].into_iter().zip(scales) {
        for k in 0..3 {
            let (x, y) = (
                g0[key][k].as_f64().unwrap_or(f64::NAN),
                lining[key][k].as_f64().unwrap_or(0.0),
            );
            assert!(
                (x - y).abs() <= 1e-6 * scale,
                "one process {key}[{k}]: {x} vs {y}"
            );
        }
    }
    let (a, b) = (work_by_walls(&j0), work_by_walls(&j1));
    assert!(
        (a - b).abs() <= 1e-6 * work_scale,
        "one process: {a} vs {b}"
    );
    let (a, b) = (
        j0["kinetic_energy"].as_f64().unwrap_or(f64::NAN),
        j1["kinetic_energy"].as_f64().unwrap_or(0.0),
    );
    assert!((a - b).abs() <= 1e-6 * b, "one process: kinetic {a} vs {b}");
    // Restart.
    let (half, _) = run(2, "3000", &[], "half");
    let cp = half.join("checkpoint.cbor").to_string_lossy().to_string();
    for ranks in [3, 1] {
        let (d, j) = run(ranks, "6000", &["--restart", &cp], &format!("r{ranks}"));
        assert_eq!(j["steps_this_run"], 3000);
        assert_eq!(state(&d), s1, "restart on {ranks} ranks");
        let (a, b) = (work_by_walls(&j), work_by_walls(&j1));
        assert!(
            (a - b).abs() <= 1e-12 * work_scale,
            "restart on {ranks}: {a} vs {b}"
        );
    }
}

/// A moving boundary-particle wall under MPI: the particle floor of
/// examples/scenes/bed_particle_floor.toml (its spheres of 50 mm are
/// larger than the cells: each body's pair forces are summed by partner
/// id, `comm::distributed::sums`) sliding at 1 cm/s under the settling
/// bed, 5,000 steps on 1, 2 and 3 ranks: the same end state to the bit,
/// the same contacts and wall motion; the floor's load and the work are
/// each rank's share summed, equal to 1e-12 of the bed's weight M g (and
/// of M g · V t for the work): a sum of a few hundred terms of that size
/// rounds at ~1e-14 of it.
#[test]
fn a_sliding_particle_floor_one_two_three_ranks() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let args = [
        "--set",
        "wall.0.motion.velocity=[0.01,0.0,0.0]",
        "--set",
        "integration.steps=5000",
    ];
    let scene = "bed_particle_floor.toml";
    let d1 = tmp.path().join("f1");
    let j1 = run_scene(1, scene, &args, &d1);
    let s1 = state(&d1);
    // 8 × 8 × 6 spheres of 0.5 mm, 1000 kg/m³.
    let weight = 384.0 * 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.5e-3f64.powi(3) * 9.81;
    let floor =
        |j: &serde_json::Value, a: usize| j["wall_forces"][0][a].as_f64().unwrap_or(f64::NAN);
    // The bed lies on the floor (the floor holds most of its weight).
    assert!(floor(&j1, 2) < -0.5 * weight, "{j1}");
    assert_eq!(j1["wall_motions"][0]["wall"], 0);
    let work_scale = weight * 0.01 * 0.01;
    for ranks in [2, 3] {
        let d = tmp.path().join(format!("f{ranks}"));
        let j = run_scene(ranks, scene, &args, &d);
        assert_eq!(state(&d), s1, "{ranks} ranks");
        for key in ["particle_contacts", "wall_contacts", "wall_motions"] {
            assert_eq!(j[key], j1[key], "{ranks} ranks: {key}");
        }
        for a in 0..3 {
            let (x, y) = (floor(&j, a), floor(&j1, a));
            assert!(
                (x - y).abs() <= 1e-12 * weight,
                "{ranks} ranks: floor force {a}: {x} vs {y}"
            );
        }
        let (a, b) = (work_by_walls(&j), work_by_walls(&j1));
        assert!(
            (a - b).abs() <= 1e-12 * work_scale,
            "{ranks} ranks: {a} vs {b}"
        );
    }
}

/// Inlets under MPI (issue 28): examples/scenes/pour.toml at 0.05 kg/s
/// for 0.08 s (367 spheres of R uniform in 0.8–1.2 mm poured onto the
/// floor, friction 0.4), run to 0.12 s on 1, 2 and 3 ranks and in one
/// process. Every rank places the same spheres (the same obstacles, the
/// same draws), so:
/// - 1, 2 and 3 ranks end in the same state to the bit (ids, positions,
///   velocities: equal shortest round-trip text), the same inlet counts,
///   masses and brought-in energy, and the series' inlet columns equal;
/// - one process and MPI insert the same spheres: the inlet report and the
///   series' inlet columns equal in every row, and every snapshot up to
///   t = 0.06 s (snapshot 10 of 20: the spheres in flight and the first
///   landings) is the same file. Later the one process sums some
///   sphere's three or more contact forces in another order than the
///   ranks (README, "ranks") and round-off grows; measured identical
///   through snapshot 18 (0.108 s) on this machine, so 10 is a margin.
#[test]
fn an_inlet_pours_the_same_spheres_on_one_two_three_ranks() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let args = [
        "--set",
        "inlet.0.rate.mass=0.05",
        "--set",
        "inlet.0.end=0.08",
        "--set",
        "integration.duration=0.12",
        "--quiet",
        "--json",
        "--out",
    ];
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/pour.toml");
    let check = |o: std::process::Output, what: &str| -> serde_json::Value {
        assert!(
            o.status.success(),
            "{what}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        serde_json::from_slice(&o.stdout).expect("JSON")
    };
    let d0 = tmp.path().join("one");
    let j0 = check(
        Command::new(env!("CARGO_BIN_EXE_dembound"))
            .arg("scene")
            .arg(&scene)
            .args(args)
            .arg(&d0)
            .output()
            .expect("dembound runs"),
        "one process",
    );
    let inlet_columns = |dir: &Path| -> Vec<String> {
        let text = std::fs::read_to_string(dir.join("series.csv")).expect("series.csv");
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().expect("header").split(',').collect();
        let cols: Vec<usize> = ["inlet0_inserted", "inlet0_mass_kg", "brought_in_energy_J"]
            .iter()
            .map(|c| header.iter().position(|h| h == c).expect(c))
            .collect();
        lines
            .map(|l| {
                let cells: Vec<&str> = l.split(',').collect();
                cols.iter().map(|&c| cells[c]).collect::<Vec<_>>().join(",")
            })
            .collect()
    };
    let series0 = inlet_columns(&d0);
    let inserted = j0["inlets"][0]["inserted"].as_u64().expect("inserted");
    // round(0.05 kg/s · 0.08 s / m̄), m̄ = ρ 4/3 π E[R³] with E[R³] =
    // (b⁴ − a⁴)/(4(b − a)) for R uniform in [a, b] = [0.8, 1.2] mm:
    // 0.004 kg / (2500 · 4/3 π · 1.04e-9 m³) = 367.3.
    let mean_cube = (1.2e-3f64.powi(4) - 0.8e-3f64.powi(4)) / (4.0 * 0.4e-3);
    let expected = (0.004 / (2500.0 * 4.0 / 3.0 * std::f64::consts::PI * mean_cube)).round();
    assert_eq!(inserted as f64, expected, "{j0}");
    assert_eq!(j0["inlets"][0]["not_placed"], 0);
    let mut s1 = Vec::new();
    for ranks in [1, 2, 3] {
        let d = tmp.path().join(format!("r{ranks}"));
        let mut cmd = mpirun_scene(ranks, &[], scene.to_str().expect("path"));
        let j = check(
            cmd.args(args).arg(&d).output().expect("mpirun runs"),
            &format!("{ranks} ranks"),
        );
        assert_eq!(j["inlets"], j0["inlets"], "{ranks} ranks");
        assert_eq!(j["particles"], j0["particles"], "{ranks} ranks");
        let owned: u64 = j["rank_particles"]
            .as_array()
            .expect("per-rank counts")
            .iter()
            .filter_map(|v| v.as_u64())
            .sum();
        assert_eq!(owned, inserted, "{ranks} ranks");
        assert_eq!(
            j["energy_balance"]["brought_in_energy"], j0["energy_balance"]["brought_in_energy"],
            "{ranks} ranks"
        );
        assert_eq!(inlet_columns(&d), series0, "{ranks} ranks");
        for k in 0..=10 {
            let name = format!("snapshot_{k:06}.vtp");
            let a = std::fs::read(d0.join(&name)).expect("one-process snapshot");
            let b = std::fs::read(d.join(&name)).expect("MPI snapshot");
            assert!(a == b, "{ranks} ranks: {name} differs from one process");
        }
        let s = state(&d);
        assert_eq!(s.len() as u64, inserted);
        if ranks == 1 {
            s1 = s;
        } else {
            assert_eq!(s, s1, "{ranks} ranks");
        }
    }
}

/// The 8 × 8 × 10 lattice of `scene_args` by make_lattice.py's formula
/// (`x = 0.6 mm + i · 1.2 mm + s`, `s = 0.6 mm` on odd layers, `z = 0.505
/// mm + k · 0.54 mm`; k outer, then j, then i), independent of the
/// program's lattice source.
fn lattice_sites() -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for k in 0..10 {
        let s = 0.5 * 1.2e-3 * (k % 2) as f64;
        for j in 0..8 {
            for i in 0..8 {
                out.push([
                    0.6e-3 + i as f64 * 1.2e-3 + s,
                    0.6e-3 + j as f64 * 1.2e-3 + s,
                    0.505e-3 + k as f64 * 0.54e-3,
                ]);
            }
        }
    }
    out
}

/// The box and walls of `scene_args`, 5,000 steps (the first contacts
/// after ~1,600).
const BOX_ARGS: [&str; 10] = [
    "--set",
    "domain.upper=[0.0102,0.0102,0.03]",
    "--set",
    "wall.1.plane.point=[0.0102,0.0,0.0]",
    "--set",
    "wall.3.plane.point=[0.0,0.0102,0.0]",
    "--set",
    "integration.steps=5000",
    "--quiet",
    "--json",
];

/// Runs `scene` (a path) on `ranks` with `args`, output into `out`.
fn run_path(ranks: usize, scene: &Path, args: &[&str], out: &Path) -> serde_json::Value {
    let mut cmd = Command::new("mpirun");
    cmd.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .args(["--oversubscribe", "-np", &ranks.to_string()])
        .arg(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(scene)
        .args(BOX_ARGS)
        .args(args)
        .arg("--out")
        .arg(out);
    let o = cmd.output().expect("mpirun runs");
    assert!(
        o.status.success(),
        "{ranks} ranks: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

/// A make_lattice.py data file of `sites` (its format; coordinates in
/// shortest round-trip text), atom ids from `first`.
fn data_file(sites: &[[f64; 3]], first: usize) -> String {
    let mut s = format!(
        "lattice-drop benchmark\n\n{} atoms\n1 atom types\n\n0 0.0102 xlo xhi\n0 0.0102 ylo yhi\n\
         0 0.03 zlo zhi\n\nAtoms # sphere\n\n",
        sites.len()
    );
    for (k, x) in sites.iter().enumerate() {
        s += &format!(
            "{} 1 0.001 1000.0 {:?} {:?} {:?}\n",
            first + k,
            x[0],
            x[1],
            x[2]
        );
    }
    s
}

/// Issue 31 item 5: a lattice made per rank and a data file read per rank
/// (`input_in_parts`) end in the same bits as the same spheres read whole
/// by every rank (today's input: a CSV of the lattice's sites, and the
/// data file with ids 2..N+1, which the part-wise reader leaves to the
/// whole-file one; both keep the input order), on 1, 2 and 3 ranks.
#[test]
fn lattice_and_data_file_in_parts_same_bits_as_read_whole() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let sites = lattice_sites();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    // The lattice scene, and the same with the sites from a CSV file.
    let lattice_toml = examples.join("lattice_drop.toml");
    let text = std::fs::read_to_string(&lattice_toml).expect("lattice_drop.toml");
    let csv_toml = tmp.path().join("csv.toml");
    let csv_text: String = text
        .lines()
        .map(|l| {
            if l.starts_with("lattice = ") {
                "csv = \"sites.csv\"".to_string()
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    std::fs::write(&csv_toml, csv_text).expect("csv scene");
    let mut csv = String::from("x,y,z,radius\n");
    for x in &sites {
        csv += &format!("{:?},{:?},{:?},0.0005\n", x[0], x[1], x[2]);
    }
    std::fs::write(tmp.path().join("sites.csv"), csv).expect("csv");
    let counts = ["--set", "particles.0.lattice.counts=[8,8,10]"];
    // The data file, ids 1..N (read in parts) and 2..N+1 (read whole).
    let data_toml = examples.join("lattice_drop_data.toml");
    let parts_data = tmp.path().join("parts.data");
    let whole_data = tmp.path().join("whole.data");
    std::fs::write(&parts_data, data_file(&sites, 1)).expect("data");
    std::fs::write(&whole_data, data_file(&sites, 2)).expect("data");
    let set = |p: &Path| format!("particles.0.lammps_data={}", p.display());
    let (parts_set, whole_set) = (set(&parts_data), set(&whole_data));
    type Case<'a> = (&'a Path, Vec<&'a str>, bool);
    let sources: [(&str, Case, Case); 2] = [
        (
            "lattice",
            (&lattice_toml, counts.to_vec(), true),
            (&csv_toml, vec![], false),
        ),
        (
            "data file",
            (&data_toml, vec!["--set", &parts_set], true),
            (&data_toml, vec!["--set", &whole_set], false),
        ),
    ];
    for (name, parts, whole) in sources {
        let d0 = tmp.path().join(format!("{name} whole 1"));
        let j0 = run_path(1, whole.0, &whole.1, &d0);
        assert_eq!(j0["input_in_parts"], false, "{name}");
        let reference = state(&d0);
        assert_eq!(reference.len(), 640);
        assert!(j0["particle_contacts"].as_u64().unwrap_or(0) > 100, "{j0}");
        for (ranks, case) in [(1, &parts), (2, &parts), (3, &parts), (3, &whole)] {
            let d = tmp.path().join(format!("{name} {ranks} {}", case.2));
            let j = run_path(ranks, case.0, &case.1, &d);
            assert_eq!(j["input_in_parts"], case.2, "{name} on {ranks}");
            assert_eq!(j["particles"], 640);
            assert_eq!(state(&d), reference, "{name} on {ranks}, parts {}", case.2);
            assert_eq!(j["particle_contacts"], j0["particle_contacts"]);
        }
    }
}

/// A data file read in parts refuses a repeated atom id and a wrong atom
/// count with the whole-file reader's message (the same line), once, exit 2.
#[test]
fn data_file_errors_in_parts_are_the_whole_readers() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let sites = lattice_sites();
    let good = data_file(&sites, 1);
    // Atom 600's line says 17: a repeat of atom 17 (line 12 + 599 = 611).
    let repeated = good.replace("\n600 1 ", "\n17 1 ");
    // One atom fewer than announced.
    let short = good.replacen("640 atoms", "641 atoms", 1);
    let data_toml =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop_data.toml");
    for (name, text, expected) in [
        ("repeated", repeated, "line 611: atom id 17 appears twice"),
        (
            "short",
            short,
            "line 651: the header announces 641 atoms, the Atoms section has 640",
        ),
    ] {
        let path = tmp.path().join(format!("{name}.data"));
        std::fs::write(&path, text).expect("data");
        let set = format!("particles.0.lammps_data={}", path.display());
        // One process (no mpirun): the whole-file reader's message.
        let one = Command::new(env!("CARGO_BIN_EXE_dembound"))
            .arg("scene")
            .arg(&data_toml)
            .args(["--set", &set, "--quiet"])
            .output()
            .expect("runs");
        let one_err = String::from_utf8_lossy(&one.stderr).to_string();
        assert_eq!(one.status.code(), Some(2), "{one_err}");
        assert!(one_err.contains(expected), "{one_err}");
        for ranks in [2, 3] {
            let o = mpirun_scene(ranks, &[], "lattice_drop_data.toml")
                .args(["--set", &set, "--quiet"])
                .output()
                .expect("mpirun runs");
            let err = String::from_utf8_lossy(&o.stderr).to_string();
            assert_eq!(o.status.code(), Some(2), "{name} on {ranks}: {err}");
            let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
            assert_eq!(lines.len(), 1, "{name} on {ranks}: {err}");
            assert!(
                one_err.contains(lines[0]),
                "{name} on {ranks}: {err} vs {one_err}"
            );
        }
    }
}

/// Sparse spheres of 0.5 mm radius in the 24.6 mm data-file box, none
/// touching another (centres 2.4 mm apart across, 2 mm up): x, y = 1.2 +
/// 2.4 i mm (i = 0..3), z = 1 + 2 k mm (k = 0..6). The centres' extent
/// along z is 1 to 13 mm, which a grid of [1, 1, R] cuts at 1 + 12 j / R
/// mm (`Decomposition::new`: evenly across the extent).
fn sparse_sites() -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for k in 0..7 {
        for j in 0..4 {
            for i in 0..4 {
                out.push([
                    1.2e-3 + 2.4e-3 * i as f64,
                    1.2e-3 + 2.4e-3 * j as f64,
                    1e-3 + 2e-3 * k as f64,
                ]);
            }
        }
    }
    out
}

/// Issue 31 item 5: the part-wise input checks each rank's spheres
/// against the other ranks' that may touch them. One pair, 0.6 mm apart
/// (an overlap of 0.4 mm, 80 % of the radius, above the 50 % refusal), on
/// either side of the cut between ranks 0 and 1 (x = y = 2.4 mm, between
/// the sparse columns: 1.7 mm from the nearest), is refused on 2 and 3
/// ranks with one process's message, once, exit 2; the same pair 1 mm
/// apart (touching) runs, and its reported cuts lie between the two.
#[test]
fn an_overlap_across_a_cut_is_refused_as_on_one_process() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let data_toml =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop_data.toml");
    for ranks in [2usize, 3] {
        // The first inner cut along z (m), from the extent of the centres.
        let cut = 1e-3 + 12e-3 / ranks as f64;
        let make = |gap: f64, name: &str| -> (std::path::PathBuf, [f64; 2]) {
            let mut sites = sparse_sites();
            let z = [cut - 0.5 * gap, cut + 0.5 * gap];
            sites.insert(40, [2.4e-3, 2.4e-3, z[0]]);
            sites.push([2.4e-3, 2.4e-3, z[1]]);
            let path = tmp.path().join(format!("{name}_{ranks}.data"));
            std::fs::write(&path, data_file(&sites, 1)).expect("data");
            (path, z)
        };
        let set = |p: &Path| format!("particles.0.lammps_data={}", p.display());
        let grid = format!("parallel.grid=[1,1,{ranks}]");
        let common = [
            "--set",
            &grid,
            "--set",
            "parallel.rebalance_threshold=inf",
            "--set",
            "integration.steps=200",
            "--quiet",
        ];
        // Refused: the pair is sphere 40 and the last (input indices).
        let (overlapping, _) = make(0.6e-3, "overlapping");
        let set_overlapping = set(&overlapping);
        let one = Command::new(env!("CARGO_BIN_EXE_dembound"))
            .arg("scene")
            .arg(&data_toml)
            .args(["--set", &set_overlapping])
            .args(common)
            .output()
            .expect("runs");
        let one_err = String::from_utf8_lossy(&one.stderr).to_string();
        assert_eq!(one.status.code(), Some(2), "{one_err}");
        let last = sparse_sites().len() + 1;
        for named in [
            "`particles[0].lammps_data` sphere 40 (input index 40)".to_string(),
            format!("`particles[0].lammps_data` sphere {last} (input index {last})"),
            "allowed: at most 50 % of the smaller radius".to_string(),
        ] {
            assert!(one_err.contains(&named), "{named}: {one_err}");
        }
        let o = mpirun_scene(ranks, &[], "lattice_drop_data.toml")
            .args(["--set", &set_overlapping])
            .args(common)
            .output()
            .expect("mpirun runs");
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert_eq!(o.status.code(), Some(2), "{ranks} ranks: {err}");
        let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(lines.len(), 1, "{ranks} ranks: {err}");
        assert!(
            one_err.lines().any(|l| l == lines[0]),
            "{ranks} ranks: {err} vs one process: {one_err}"
        );
        // Accepted: touching, read in parts, the pair across the cut.
        let (touching, z) = make(1e-3, "touching");
        let set_touching = set(&touching);
        let o = mpirun_scene(ranks, &[], "lattice_drop_data.toml")
            .args(["--set", &set_touching])
            .args(common)
            .arg("--json")
            .output()
            .expect("mpirun runs");
        assert!(
            o.status.success(),
            "{ranks} ranks: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        assert_eq!(j["input_in_parts"], true);
        assert_eq!(j["rebalances"], 0);
        let cuts: Vec<f64> = j["cuts"][2]
            .as_array()
            .expect("cuts along z")
            .iter()
            .filter_map(|c| c.as_f64())
            .collect();
        assert_eq!(cuts.len(), ranks + 1, "{cuts:?}");
        assert!(z[0] < cuts[1] && cuts[1] < z[1], "{z:?} {cuts:?}");
    }
}

/// The initial-overlap warnings of the part-wise input are one process's,
/// printed once. Added to the sparse spheres (0.5 mm radius): a pair
/// 0.9 mm apart across the first cut along z (an overlap of 0.1 mm, 20 %
/// of the radius: above the 1 % warning, below the 50 % refusal), the
/// upper one first in the file; a pair 0.95 mm apart (10 %) inside rank
/// 0; and a sphere 0.45 mm from the plane x = 0 (10 %) 0.1 mm above the
/// cut, so a halo copy on the rank below. One process warns of 2 pairs,
/// the largest the pair across the cut, and of 1 sphere on a plane; on 2
/// and 3 ranks stderr's warning lines are the same, each once (a pair or
/// a sphere counted on both sides of the cut would make 3 pairs or 2
/// spheres).
#[test]
fn overlap_warnings_in_parts_are_one_process_s() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let data_toml =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop_data.toml");
    for ranks in [2usize, 3] {
        // The first inner cut along z (m), from the extent of the centres
        // (1 to 13 mm, which the added spheres stay within).
        let cut = 1e-3 + 12e-3 / ranks as f64;
        let mut sites = sparse_sites();
        // 1.7 mm across from the nearest column (x, y = 1.2 + 2.4 i mm).
        sites.insert(5, [2.4e-3, 2.4e-3, cut + 0.45e-3]);
        sites.insert(20, [2.4e-3, 2.4e-3, 2.0e-3]);
        sites.push([2.4e-3, 2.4e-3, 2.95e-3]);
        sites.push([2.4e-3, 2.4e-3, cut - 0.45e-3]);
        // 1.4 mm across from the nearest column (x = 1.2, y = 3.6 mm).
        sites.push([0.45e-3, 4.8e-3, cut + 0.1e-3]);
        let n = sites.len();
        let path = tmp.path().join(format!("warned_{ranks}.data"));
        std::fs::write(&path, data_file(&sites, 1)).expect("data");
        let set = format!("particles.0.lammps_data={}", path.display());
        let grid = format!("parallel.grid=[1,1,{ranks}]");
        let common = [
            "--set",
            &set,
            "--set",
            &grid,
            "--set",
            "parallel.rebalance_threshold=inf",
            "--set",
            "integration.steps=20",
            "--quiet",
        ];
        let warnings = |stderr: &[u8]| -> Vec<String> {
            String::from_utf8_lossy(stderr)
                .lines()
                .filter(|l| l.starts_with("warning:"))
                .map(str::to_string)
                .collect()
        };
        let one = Command::new(env!("CARGO_BIN_EXE_dembound"))
            .arg("scene")
            .arg(&data_toml)
            .args(common)
            .output()
            .expect("runs");
        let one_err = String::from_utf8_lossy(&one.stderr).to_string();
        assert!(one.status.success(), "{one_err}");
        let expected = warnings(&one.stderr);
        // The counts and the largest from the construction above (input
        // index k is atom k + 1's, sphere k of the data file).
        let label = |k: usize| format!("`particles[0].lammps_data` sphere {k} (input index {k})");
        let pair = expected
            .iter()
            .find(|l| l.contains("sphere pair(s)"))
            .unwrap_or_else(|| panic!("no pair warning: {one_err}"));
        assert!(pair.starts_with("warning: 2 sphere pair(s)"), "{pair}");
        // Share printed to 3 decimals: 20 % within 5e-6 %.
        assert!(
            pair.contains(&format!("largest: {} and {}, ", label(5), label(n - 2)))
                && pair.contains("(20 %)"),
            "{pair}"
        );
        let plane = expected
            .iter()
            .find(|l| l.contains("plane wall"))
            .unwrap_or_else(|| panic!("no plane warning: {one_err}"));
        assert!(
            plane.starts_with("warning: 1 free sphere(s)")
                && plane.contains(&format!("largest: {} and `wall[0].plane`", label(n - 1)))
                && plane.contains("(10 %)"),
            "{plane}"
        );
        assert_eq!(expected.len(), 2, "{one_err}");
        let o = mpirun_scene(ranks, &[], "lattice_drop_data.toml")
            .args(common)
            .arg("--json")
            .output()
            .expect("mpirun runs");
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success(), "{ranks} ranks: {err}");
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
        assert_eq!(j["input_in_parts"], true);
        assert_eq!(warnings(&o.stderr), expected, "{ranks} ranks: {err}");
    }
}

/// The point arrays of a `.vtp` file read with an XML parser: name →
/// the values' bytes (base64 after an 8-byte length, as VTK reads them).
fn vtp_arrays(path: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    use base64::Engine;
    let text = std::fs::read_to_string(path).expect("vtp");
    let doc = roxmltree::Document::parse(&text).expect("valid XML");
    let piece = doc
        .descendants()
        .find(|n| n.has_tag_name("Piece"))
        .expect("a Piece");
    let mut out = std::collections::BTreeMap::new();
    for n in piece.descendants().filter(|n| n.has_tag_name("DataArray")) {
        let name = n.attribute("Name").expect("Name").to_string();
        let block = base64::engine::general_purpose::STANDARD
            .decode(n.text().unwrap_or("").trim())
            .expect("base64");
        let len = u64::from_le_bytes(block[..8].try_into().expect("8 bytes")) as usize;
        assert_eq!(len, block.len() - 8, "{name}");
        out.insert(name, block[8..].to_vec());
    }
    out
}

/// Sphere id → array name → that sphere's bytes in the array.
type Spheres = std::collections::BTreeMap<i64, std::collections::BTreeMap<String, Vec<u8>>>;

/// Sphere id → every point array's bytes of that sphere (connectivity and
/// offsets, local numbers, left out), from `.vtp` files.
fn spheres_by_id(files: &[std::path::PathBuf]) -> Spheres {
    let mut out = std::collections::BTreeMap::new();
    for f in files {
        let arrays = vtp_arrays(f);
        let ids: Vec<i64> = arrays["id"]
            .chunks(8)
            .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        let n = ids.len();
        for (k, id) in ids.iter().enumerate() {
            let values: std::collections::BTreeMap<String, Vec<u8>> = arrays
                .iter()
                .filter(|(name, _)| !["connectivity", "offsets"].contains(&name.as_str()))
                .map(|(name, bytes)| {
                    let size = bytes.len() / n;
                    (name.clone(), bytes[k * size..(k + 1) * size].to_vec())
                })
                .collect();
            assert!(out.insert(*id, values).is_none(), "id {id} twice");
        }
    }
    out
}

/// Issue 31 item 5: `[parallel] vtk_per_rank` writes each snapshot as
/// one piece per rank and a `.pvtp` index, with no gather: on 2 and 3
/// ranks the pieces together hold every sphere of the one-process
/// snapshot once, every array the same bits (by id); the index lists
/// every rank's piece and declares the pieces' arrays; `snapshots.pvd`
/// lists the indices; every file parses as XML. 3000 steps of the 640
/// spheres (contacts from about step 1,600), snapshots every 1000.
#[test]
fn per_rank_vtk_pieces_hold_the_one_process_snapshot() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop.toml");
    // The lattice and box of `scene_args` (its first four settings).
    let mut args: Vec<String> = scene_args().into_iter().take(8).collect();
    args.extend(
        [
            "--set",
            "integration.steps=3000",
            "--set",
            "output.every=1000",
            "--quiet",
        ]
        .map(String::from),
    );
    let d0 = tmp.path().join("one");
    let o = Command::new(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(&scene)
        .args(&args)
        .arg("--out")
        .arg(&d0)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for ranks in [2usize, 3] {
        let d = tmp.path().join(format!("r{ranks}"));
        let o = mpirun_scene(ranks, &[], "lattice_drop.toml")
            .args(&args)
            .args(["--set", "parallel.vtk_per_rank=true", "--out"])
            .arg(&d)
            .output()
            .expect("mpirun runs");
        assert!(
            o.status.success(),
            "{ranks} ranks: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let pvd = std::fs::read_to_string(d.join("snapshots.pvd")).expect("pvd");
        let pvd = roxmltree::Document::parse(&pvd).expect("valid XML");
        let listed: Vec<&str> = pvd
            .descendants()
            .filter(|n| n.has_tag_name("DataSet"))
            .filter_map(|n| n.attribute("file"))
            .collect();
        let expected: Vec<String> = (0..=3).map(|k| format!("snapshot_{k:06}.pvtp")).collect();
        assert_eq!(listed, expected, "{ranks} ranks");
        for (k, index_name) in expected.iter().enumerate() {
            // No gathered snapshot.
            assert!(!d.join(format!("snapshot_{k:06}.vtp")).exists());
            let index = std::fs::read_to_string(d.join(index_name)).expect("pvtp");
            let index = roxmltree::Document::parse(&index).expect("valid XML");
            assert_eq!(
                index.root_element().attribute("type"),
                Some("PPolyData"),
                "{ranks} ranks"
            );
            let sources: Vec<&str> = index
                .descendants()
                .filter(|n| n.has_tag_name("Piece"))
                .filter_map(|n| n.attribute("Source"))
                .collect();
            let names: Vec<String> = (0..ranks)
                .map(|r| format!("snapshot_{k:06}_rank_{r}.vtp"))
                .collect();
            assert_eq!(sources, names, "{ranks} ranks, snapshot {k}");
            let declared: Vec<&str> = index
                .descendants()
                .filter(|n| n.has_tag_name("PDataArray"))
                .filter_map(|n| n.attribute("Name"))
                .collect();
            let pieces: Vec<std::path::PathBuf> = names.iter().map(|n| d.join(n)).collect();
            for p in &pieces {
                let arrays = vtp_arrays(p);
                let mut in_piece: Vec<&str> = arrays
                    .keys()
                    .map(String::as_str)
                    .filter(|n| !["TIME", "STEP", "connectivity", "offsets"].contains(n))
                    .collect();
                in_piece.sort_unstable();
                let mut want = declared.clone();
                want.sort_unstable();
                assert_eq!(in_piece, want, "{}", p.display());
                // Every rank owns spheres of the lattice.
                assert!(!arrays["id"].is_empty(), "{}", p.display());
            }
            let whole = spheres_by_id(&[d0.join(format!("snapshot_{k:06}.vtp"))]);
            assert_eq!(whole.len(), 640);
            if k == 3 {
                // The end state, each rank's own spheres, not gathered.
                assert!(!d.join("state.csv").exists());
                let mut seen = 0;
                for r in 0..ranks {
                    let text = std::fs::read_to_string(d.join(format!("state_rank_{r}.csv")))
                        .expect("state_rank_R.csv");
                    for line in text.lines().skip(1) {
                        let cells: Vec<&str> = line.split(',').collect();
                        let id: i64 = cells[0].parse().expect("id");
                        assert_eq!(cells[12], r.to_string(), "{line}");
                        // Position and velocity: shortest round-trip text,
                        // the snapshot's bits.
                        let bits: Vec<u8> = cells[1..7]
                            .iter()
                            .flat_map(|c| c.parse::<f64>().expect("number").to_le_bytes())
                            .collect();
                        let sphere = &whole[&id];
                        let (position, velocity) = (&sphere["position"], &sphere["velocity"]);
                        assert_eq!(bits[..24], position[..], "{ranks} ranks: {line}");
                        assert_eq!(bits[24..], velocity[..], "{ranks} ranks: {line}");
                        seen += 1;
                    }
                }
                assert_eq!(seen, 640, "{ranks} ranks");
            }
            let union = spheres_by_id(&pieces);
            assert_eq!(union.len(), 640, "{ranks} ranks, snapshot {k}");
            for (id, values) in &whole {
                assert_eq!(
                    union.get(id),
                    Some(values),
                    "{ranks} ranks, snapshot {k}: sphere {id}"
                );
            }
        }
    }
}

/// Issue 31 item 5: `[parallel] checkpoint_per_rank` writes each rank's
/// part of the checkpoint (`checkpoint_rank_R.cbor`) and the index
/// `checkpoint.cbor`, no gather. The lattice drop with Walton–Braun (every
/// contact's largest overlap is state; contacts from about step 1,600):
/// 2000 steps on 2 and on 3 ranks, checkpointed in parts, then 2000 more
/// from the parts on the same count and on the other one end in the state
/// (`state.csv` by id) and the gathered checkpoint file, byte for byte, of
/// 4000 steps in one go on the writing rank count (the decomposed
/// trajectory does not depend on the rank count, test above; the initial
/// energy in the checkpoint is a sum over the ranks). The one-process engine merges
/// the parts and continues. A damaged part is refused by name (exit 2,
/// nothing written).
#[test]
fn checkpoint_in_parts_restarts_per_rank_bit_for_bit() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let with = |steps: &str, more: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = [
            "--set",
            "contact.law=walton-braun",
            "--set",
            "contact.restitution=0.5",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        v.push("--set".into());
        v.push(format!("integration.steps={steps}"));
        v.extend(more.iter().map(|s| s.to_string()));
        v
    };
    let run = |ranks: usize, args: Vec<String>, name: &str| {
        let d = tmp.path().join(name);
        let refs: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
        let j = mpirun(ranks, &[], &refs, &d);
        (d, j)
    };
    let per_rank = ["--set", "parallel.checkpoint_per_rank=true"];
    for (written, other) in [(2usize, 3usize), (3, 2)] {
        // The reference: the same rank count in one go (the initial
        // energy, a sum over the ranks, is in the checkpoint).
        let (straight, _) = run(written, with("4000", &[]), &format!("straight{written}"));
        let expected = state(&straight);
        let expected_cp = std::fs::read(straight.join("checkpoint.cbor")).expect("checkpoint");
        let (half, _) = run(written, with("2000", &per_rank), &format!("half{written}"));
        // The parts and the index; every part holds some spheres, the
        // index none (it is small).
        for r in 0..written {
            let part = half.join(format!("checkpoint_rank_{r}.cbor"));
            let len = std::fs::metadata(&part).expect("part").len();
            assert!(len > 10_000, "{}: {len} bytes", part.display());
        }
        assert!(!half
            .join(format!("checkpoint_rank_{written}.cbor"))
            .exists());
        let index = half.join("checkpoint.cbor");
        assert!(std::fs::metadata(&index).expect("index").len() < 10_000);
        let cp = index.to_string_lossy().to_string();
        for ranks in [written, other] {
            let name = format!("w{written}r{ranks}");
            let (d, j) = run(ranks, with("4000", &["--restart", &cp]), &name);
            assert_eq!(j["steps_this_run"], 2000);
            // Each rank made only its part of the lattice.
            assert_eq!(j["input_in_parts"], true, "restarted on {ranks}");
            assert_eq!(
                state(&d),
                expected,
                "written on {written}, restarted on {ranks}"
            );
            let got = std::fs::read(d.join("checkpoint.cbor")).expect("checkpoint");
            assert!(
                got == expected_cp,
                "written on {written}, restarted on {ranks}: checkpoint differs"
            );
        }
    }
    // Without mpirun: the parts merged.
    let cp = tmp.path().join("half2/checkpoint.cbor");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lattice_drop.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(&scene)
        .args(scene_args())
        .args(with(
            "4000",
            &["--restart", &cp.to_string_lossy(), "--json"],
        ))
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(j["steps"], 4000);
    // A checkpoint of another scene, on 2 and 3 ranks: refused with one
    // message (exit 2, every rank ends, nothing written): a sphere's
    // radius (found where its record arrives), fewer spheres (a part's ids
    // out of range, found before the build).
    for (other, named) in [
        (
            "particles.0.lattice.radius=0.5005e-3",
            "(input order): radius differs: the checkpoint's 0.0005 m, the scene's 0.0005005 m",
        ),
        (
            "particles.0.lattice.counts=[8,8,9]",
            "body order has a bad or repeated id",
        ),
    ] {
        for ranks in [2usize, 3] {
            let out = tmp.path().join(format!("other{ranks}"));
            let o = mpirun_scene(ranks, &[], "lattice_drop.toml")
                .args(scene_args())
                .args(with("4000", &["--restart", &cp.to_string_lossy()]))
                .args(["--set", other, "--out"])
                .arg(&out)
                .output()
                .expect("mpirun runs");
            let err = String::from_utf8_lossy(&o.stderr);
            assert_eq!(o.status.code(), Some(2), "{other}, {ranks} ranks: {err}");
            assert_eq!(err.matches("error:").count(), 1, "{other}: {err}");
            assert!(err.contains(named), "{other}, {ranks} ranks: {err}");
            assert!(!out.exists(), "{other}, {ranks} ranks");
        }
    }
    // A part damaged (one byte changed): refused, named, nothing written.
    let part = tmp.path().join("half2/checkpoint_rank_1.cbor");
    let mut bytes = std::fs::read(&part).expect("part");
    let mid = bytes.len() / 2;
    bytes[mid] ^= 1;
    std::fs::write(&part, bytes).expect("written");
    let out = tmp.path().join("refused");
    let o = mpirun_scene(2, &[], "lattice_drop.toml")
        .args(scene_args())
        .args(with("4000", &["--restart", &cp.to_string_lossy()]))
        .arg("--out")
        .arg(&out)
        .output()
        .expect("mpirun runs");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("checkpoint_rank_1.cbor") && err.contains("SHA-256"),
        "{err}"
    );
    assert!(!out.exists());
}

/// The arrays of the `FieldData` of a `.vtp` file (`TIME`, `STEP`): name
/// → the values' bytes.
fn field_data(path: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    use base64::Engine;
    let text = std::fs::read_to_string(path).expect("vtp");
    let doc = roxmltree::Document::parse(&text).expect("valid XML");
    let fields = doc
        .descendants()
        .find(|n| n.has_tag_name("FieldData"))
        .expect("FieldData");
    fields
        .children()
        .filter(|n| n.has_tag_name("DataArray"))
        .map(|n| {
            let block = base64::engine::general_purpose::STANDARD
                .decode(n.text().unwrap_or("").trim())
                .expect("base64");
            (n.attribute("Name").expect("Name").to_string(), block)
        })
        .collect()
}

/// Triangle id → (each cell array's bytes of that triangle, its three
/// corners' position bytes through the connectivity), from mesh-wall
/// `.vtp` files (a piece's points numbered in the piece).
type Triangles =
    std::collections::BTreeMap<i32, (std::collections::BTreeMap<String, Vec<u8>>, [Vec<u8>; 3])>;

fn triangles_by_id(files: &[std::path::PathBuf]) -> Triangles {
    let mut out = Triangles::new();
    for f in files {
        let arrays = vtp_arrays(f);
        let ids: Vec<i32> = arrays["triangle_id"]
            .chunks(4)
            .map(|c| i32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect();
        let corners: Vec<usize> = arrays["connectivity"]
            .chunks(8)
            .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")) as usize)
            .collect();
        let offsets: Vec<i64> = arrays["offsets"]
            .chunks(8)
            .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        let n = ids.len();
        assert_eq!(corners.len(), 3 * n, "{}", f.display());
        assert_eq!(
            offsets,
            (1..=n as i64).map(|i| 3 * i).collect::<Vec<_>>(),
            "{}",
            f.display()
        );
        let position = &arrays["position"];
        for (k, id) in ids.iter().enumerate() {
            let cells = ["force", "pressure", "shear", "area", "triangle_id"]
                .iter()
                .map(|name| {
                    let bytes = &arrays[*name];
                    let size = bytes.len() / n;
                    (name.to_string(), bytes[k * size..(k + 1) * size].to_vec())
                })
                .collect();
            let at =
                |c: usize| position[24 * corners[3 * k + c]..24 * corners[3 * k + c] + 24].to_vec();
            assert!(
                out.insert(*id, (cells, [at(0), at(1), at(2)])).is_none(),
                "triangle {id} twice"
            );
        }
    }
    out
}

/// Issue 31 item 5: under `[parallel] vtk_per_rank` the mesh walls' files
/// are written in pieces too, with no gather: examples/scenes/mesh_box.toml
/// (its box a 12-triangle mesh; 8 × 8 × 10 spheres; 3000 steps, files
/// every 1000) on 2 and 3 ranks writes `wall_0_NNNNNN.pvtp` indices
/// listing every rank's piece (`snapshots.pvd` lists them as part 1), the
/// pieces together hold every triangle of the one-process run's
/// `wall_0_NNNNNN.vtp` once, its force, pressure, shear, area and id the
/// same bytes and its corners at the same positions (the reference: the
/// one process's file, whose sums the gathered file's equal, test
/// above), and the same time and step. Every file parses as XML.
#[test]
fn per_rank_mesh_wall_pieces_hold_the_one_process_file() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let args = [
        "--set",
        "particles.0.lattice.counts=[8,8,10]",
        "--set",
        "integration.steps=3000",
        "--set",
        "output.every=1000",
        "--quiet",
    ];
    let plain = tmp.path().join("plain");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/mesh_box.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_dembound"))
        .arg("scene")
        .arg(&scene)
        .args(args)
        .arg("--out")
        .arg(&plain)
        .output()
        .expect("dembound runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for ranks in [2usize, 3] {
        let d = tmp.path().join(format!("r{ranks}"));
        let o = mpirun_scene(ranks, &[], "mesh_box.toml")
            .args(args)
            .args(["--set", "parallel.vtk_per_rank=true", "--out"])
            .arg(&d)
            .output()
            .expect("mpirun runs");
        assert!(
            o.status.success(),
            "{ranks} ranks: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let pvd = std::fs::read_to_string(d.join("snapshots.pvd")).expect("pvd");
        let pvd = roxmltree::Document::parse(&pvd).expect("valid XML");
        let walls: Vec<(&str, &str)> = pvd
            .descendants()
            .filter(|n| n.has_tag_name("DataSet") && n.attribute("part") == Some("1"))
            .filter_map(|n| Some((n.attribute("file")?, n.attribute("timestep")?)))
            .collect();
        let expected: Vec<String> = (0..=3).map(|k| format!("wall_0_{k:06}.pvtp")).collect();
        assert_eq!(
            walls.iter().map(|w| w.0).collect::<Vec<_>>(),
            expected,
            "{ranks} ranks"
        );
        let mut loaded = 0;
        for (k, index_name) in expected.iter().enumerate() {
            // No gathered file.
            assert!(!d.join(format!("wall_0_{k:06}.vtp")).exists());
            let index = std::fs::read_to_string(d.join(index_name)).expect("pvtp");
            let index = roxmltree::Document::parse(&index).expect("valid XML");
            assert_eq!(index.root_element().attribute("type"), Some("PPolyData"));
            let sources: Vec<&str> = index
                .descendants()
                .filter(|n| n.has_tag_name("Piece"))
                .filter_map(|n| n.attribute("Source"))
                .collect();
            let names: Vec<String> = (0..ranks)
                .map(|r| format!("wall_0_{k:06}_rank_{r}.vtp"))
                .collect();
            assert_eq!(sources, names, "{ranks} ranks, file {k}");
            let mut declared: Vec<&str> = index
                .descendants()
                .filter(|n| n.has_tag_name("PDataArray"))
                .filter_map(|n| n.attribute("Name"))
                .collect();
            declared.sort_unstable();
            let whole_file = plain.join(format!("wall_0_{k:06}.vtp"));
            let pieces: Vec<std::path::PathBuf> = names.iter().map(|n| d.join(n)).collect();
            for p in &pieces {
                let mut in_piece: Vec<String> = vtp_arrays(p)
                    .into_keys()
                    .filter(|n| !["connectivity", "offsets"].contains(&n.as_str()))
                    .collect();
                in_piece.sort_unstable();
                assert_eq!(in_piece, declared, "{}", p.display());
                assert_eq!(field_data(p), field_data(&whole_file), "{}", p.display());
            }
            let whole = triangles_by_id(&[whole_file]);
            assert_eq!(whole.len(), 12);
            let union = triangles_by_id(&pieces);
            assert_eq!(union, whole, "{ranks} ranks, file {k}");
            loaded += whole
                .values()
                .filter(|(cells, _)| cells["force"].iter().any(|&b| b != 0))
                .count();
        }
        // Some triangles carry the spheres (the floor from the first
        // contacts on).
        assert!(loaded >= 2, "{ranks} ranks: {loaded} loaded triangles");
    }
}

/// `output.wall_force_mean` sums each step's wall forces on one process; a
/// rank holds only its share of them, so under mpirun the key is refused
/// before any step: exit 2, one message naming the key and what is
/// allowed, no output directory.
#[test]
fn the_averaged_wall_force_columns_are_refused_under_mpi() {
    let tmp = tempfile::tempdir().expect("temp dir");
    let out = tmp.path().join("never");
    let o = mpirun_scene(2, &[], "lattice_drop.toml")
        .args(["--set", "output.wall_force_mean=true", "--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("mpirun runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(
        err.matches("error: output.wall_force_mean = true is not available under mpirun")
            .count(),
        1,
        "{err}"
    );
    assert!(err.contains("allowed here is false"), "{err}");
    assert!(!out.exists());
}
