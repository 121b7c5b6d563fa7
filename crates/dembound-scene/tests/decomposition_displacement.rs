//! The list builds of a decomposed run follow the largest displacement
//! over every rank, also when it travels with the halo messages (two
//! ranks: each trades halo state with the other every step) instead of a
//! collective of its own. Ranks as threads (`comm::threads`).

mod common;

use dembound_scene::comm::threads::ThreadTransport;
use dembound_scene::comm::DistributedSimulation;
use dembound_scene::Simulation;

/// The lattice without gravity, at rest but for the spheres right of the
/// cut (x > 3.9 mm, the 2 × 1 × 1 grid's), which rise at 0.2 m/s: half
/// the skin (50 µm) in about 125 steps of 2 µs. Only the rank that owns
/// them sees a displacement at first; the other's spheres move only when
/// pushed across the cut.
fn one_side_moving(steps: u64) -> dembound_scene::SceneSetup {
    let mut s = common::lattice_drop(6, 8, 2.0e-6, steps);
    s.gravity = [0.0; 3];
    let cut = 0.5 * (6.0 * 1.2e-3 + 0.5 * 1.2e-3);
    for sphere in &mut s.spheres {
        if sphere.position[0] > cut {
            sphere.velocity = [0.0, 0.0, 0.2];
        }
    }
    s
}

/// 2 ranks: the displacement rides with the halo; the list builds happen
/// at the one process's steps (the moving rank's displacement reaches the
/// resting one) and the end state is the one process's to the bit.
#[test]
fn list_builds_follow_the_displacement_on_either_rank() {
    let steps = 1000;
    let setup = one_side_moving(steps);
    let mut one = Simulation::new(setup.clone(), 1).expect("valid scene");
    one.step(steps);
    // The one process's list builds (its own displacement, no exchange):
    // the expected count. Several, so that the test means something: the
    // rising spheres go 0.4 mm in the run, 8 times half the skin.
    let builds = one.list_builds();
    assert!(builds >= 4, "{builds} list builds");
    let handles: Vec<_> = ThreadTransport::group(2)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            std::thread::spawn(move || {
                let mut d =
                    DistributedSimulation::new(&setup, 1, Some([2, 1, 1]), t).expect("valid");
                let in_halo = d.displacement_in_halo();
                d.step(steps);
                (
                    d.gather_state(),
                    d.local().list_builds(),
                    in_halo,
                    d.owned(),
                )
            })
        })
        .collect();
    let mut state = None;
    for h in handles {
        let (s, b, in_halo, owned) = h.join().expect("rank");
        assert!(in_halo, "two ranks carry the displacement in the halo");
        assert!(owned > 0, "each rank owns spheres");
        assert_eq!(b, builds, "list builds on a rank");
        if s.is_some() {
            state = s;
        }
    }
    let s = state.expect("rank 0 gathers");
    let (x1, v1) = (one.positions(), one.velocities());
    for k in 0..x1.len() {
        for a in 0..3 {
            assert_eq!(s.position[k][a].to_bits(), x1[k][a].to_bits(), "body {k}");
            assert_eq!(s.velocity[k][a].to_bits(), v1[k][a].to_bits(), "body {k}");
        }
    }
}
