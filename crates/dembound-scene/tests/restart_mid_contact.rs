//! A restart in the middle of contacts continues bit for bit: run A goes
//! N steps straight; run B goes N/2, checkpoints, is restored (on another
//! thread count) and goes to N. Before comparing, the checkpoint is
//! asserted to hold live contacts (pairs and walls in contact, collisions
//! under way) with non-zero tangential and rolling springs on pairs and
//! walls, and under Gear5 the spins' derivatives: a restart before the
//! first contact (as the older tests did) would pass with the springs and
//! histories lost.
//!
//! The same through the binary (`--out`, then `--restart`):
//! `tests/cli_scene_restart.rs` at the workspace root.

mod common;

use common::state;
use dembound_scene::{Checkpoint, SceneSetup, Simulation};

/// Asserts the checkpoint is taken with contacts and springs live.
fn assert_live(sim: &Simulation, cp: &Checkpoint, what: &str) {
    let o = sim.observe();
    assert!(
        o.particle_contacts > 0 && o.wall_contacts > 0,
        "{what}: no live contact at the checkpoint ({} pairs, {} wall)",
        o.particle_contacts,
        o.wall_contacts
    );
    let nonzero = |s: &[f64]| s.iter().any(|x| *x != 0.0);
    let pair_shear = cp.pair_shear.iter().filter(|p| nonzero(&p.2[..3])).count();
    let pair_roll = cp.pair_shear.iter().filter(|p| nonzero(&p.2[3..])).count();
    let wall_shear = cp
        .plane_shear
        .iter()
        .filter(|p| nonzero(&p.2.shear[..3]))
        .count();
    eprintln!(
        "{what} at step {}: {} pair and {} wall contacts; non-zero springs: \
         {pair_shear} pair tangential, {pair_roll} pair rolling, {wall_shear} wall tangential; \
         {} pair and {} wall collisions under way",
        cp.steps_done,
        o.particle_contacts,
        o.wall_contacts,
        cp.pair_tracks.len(),
        cp.plane_tracks.len()
    );
    assert!(
        pair_shear > 0 && pair_roll > 0 && wall_shear > 0,
        "{what}: the springs are not live at the checkpoint"
    );
    assert!(
        !cp.pair_tracks.is_empty() && !cp.plane_tracks.is_empty(),
        "{what}: no collision under way at the checkpoint"
    );
}

/// Runs A (n steps on 1 thread) and B (n/2 on 2 threads, checkpoint,
/// restored on `restore_threads`, to n): the same bits, the same
/// checkpoint at n.
fn assert_restart_exact(setup: SceneSetup, n: u64, restore_threads: usize, what: &str) {
    let mut a = Simulation::new(setup.clone(), 1).expect("a valid scene");
    a.step(n);
    let mut b = Simulation::new(setup.clone(), 2).expect("a valid scene");
    b.step(n / 2);
    let cp = b.checkpoint();
    assert_live(&b, &cp, what);
    let mut c = Simulation::restore(setup, &cp, restore_threads).expect("restored");
    assert_eq!(c.steps_done(), n / 2);
    c.step(n - n / 2);
    assert!(
        a.positions().iter().flatten().all(|x| x.is_finite()),
        "{what}: the run blew up"
    );
    assert!(a.list_builds() > 1, "{what}: no list rebuild");
    assert_eq!(state(&a), state(&c), "{what}: the restarted run differs");
    assert!(
        a.checkpoint() == c.checkpoint(),
        "{what}: the checkpoints at step {n} differ"
    );
}

/// The lattice drop (8 × 8 × 6, E = 1e7 Pa, elastic Hertz) with Mindlin
/// μ = 0.5 and rolling friction 0.05 on the grains and the floor, Δt =
/// 20 µs: the lattice lands from step ~50; the checkpoint at step 500
/// (10 ms) is taken with the bed bouncing on the floor.
#[test]
fn verlet_friction_restart_mid_contact_is_bit_identical() {
    let setup = common::frictional_lattice(8, 6, 2.0e-5);
    assert_restart_exact(setup, 1000, 1, "Verlet + friction");
}

/// The same lattice under Gear5, Hertz + Tsuji e = 0.6, E = 1e8 Pa, Δt =
/// 2 µs, thrown with random velocities (≤ 0.05 m/s per component) so
/// that it collides from the first steps; the checkpoint at step 1,000
/// (2 ms) holds the Gear5 derivatives of positions and spins.
#[test]
fn gear5_friction_restart_mid_contact_is_bit_identical() {
    let setup = common::gear5_frictional_lattice(8, 6, 0.05);
    let mut probe = Simulation::new(setup.clone(), 1).expect("a valid scene");
    probe.step(1000);
    // The run is sound, not only repeatable: the energy balance's guard
    // (no energy created beyond integration error) passes at the checkpoint.
    probe
        .observe_checked()
        .expect("the Gear5 run keeps its energy balance");
    let cp = probe.checkpoint();
    let nonzero = |r: &[[f64; 3]; 4]| r.iter().flatten().any(|x| *x != 0.0);
    assert!(
        cp.higher.iter().any(nonzero) && cp.angular_higher.iter().any(nonzero),
        "Gear5: the derivatives are not live at the checkpoint"
    );
    assert_restart_exact(setup, 2000, 3, "Gear5 + friction");
}
