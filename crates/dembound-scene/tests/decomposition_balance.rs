//! Load re-balancing of decomposed runs (issue 16) with ranks as threads
//! (`comm::threads::ThreadTransport`, the same code as under MPI): a
//! settling bed cut along z ends with every particle in the bottom
//! sub-domain unless the cuts move; with re-balancing they follow the
//! bed, and the trajectory stays the same bits.

mod common;

use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::comm::distributed::balance::{imbalance, BalanceReport};
use dembound_scene::comm::threads::ThreadTransport;
use dembound_scene::comm::DistributedSimulation;
use dembound_scene::SceneSetup;

/// Rank 0's gathered positions and velocities, the ranks' free bodies at
/// the end, the re-balancing report.
type Run = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<usize>, BalanceReport);

fn run(setup: &SceneSetup, ranks: usize, grid: [usize; 3], threshold: f64, steps: u64) -> Run {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            std::thread::spawn(move || {
                let mut d = DistributedSimulation::new(&setup, 1, Some(grid), t).expect("valid");
                d.set_rebalance_threshold(threshold);
                d.step(steps);
                let free = d.free_counts();
                (d.gather_state(), free, d.balance_report())
            })
        })
        .collect();
    let mut out = None;
    for h in handles {
        let (s, free, report) = h.join().expect("rank finished");
        if let Some(s) = s {
            out = Some((s.position, s.velocity, free, report));
        }
    }
    out.expect("rank 0 gathers")
}

/// 6 × 6 × 10 spheres (R = 0.5 mm) 1.5 mm apart in z, thrown down at
/// 1 m/s onto the floor of the lattice-drop box, damped (Tsuji, e = 0.3):
/// after 10000 steps of 2 µs (16 ms: the top sphere has fallen 14 mm at
/// ≥ 1 m/s) they lie in the bottom 4 mm.
fn falling_bed() -> SceneSetup {
    let mut s = common::lattice_drop(6, 1, 2.0e-6, 10000);
    s.contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
    );
    s.spheres.clear();
    for k in 0..10 {
        let shift = 0.6e-3 * (k % 2) as f64;
        for j in 0..6 {
            for i in 0..6 {
                s.spheres.push(dembound_scene::setup::SphereInit {
                    position: [
                        0.6e-3 + 1.2e-3 * i as f64 + shift,
                        0.6e-3 + 1.2e-3 * j as f64 + shift,
                        0.6e-3 + 1.5e-3 * k as f64,
                    ],
                    velocity: [0.0, 0.0, -1.0],
                    radius: 0.5e-3,
                    material: 0,
                    fixed: false,
                    group: None,
                });
            }
        }
    }
    s
}

/// Three sub-domains along z, cut evenly over the cloud at the start
/// (cuts at 5.1 and 9.6 mm: layers 0–2, 3–5 and 6–9, 108, 108 and 144
/// spheres). Without re-balancing the bed ends in the bottom two
/// (imbalance > 2); with the threshold 1.2 the cuts follow it
/// (imbalance ≤ 1.2 at the end: the bed is at rest, no rebuild since the
/// last re-partition could have moved a body across a cut), and the
/// positions and velocities are the same bits as without, and as on one
/// rank (the forces are summed in partner-id order).
#[test]
fn settling_bed_rebalances_with_the_same_bits() {
    let setup = falling_bed();
    let (x1, v1, _, _) = run(&setup, 1, [1, 1, 1], f64::INFINITY, 10000);
    // The bed has come down: every sphere below 8 mm (the top layer
    // started at 14.1 mm), the mean height below 3.5 mm (a pile of 360
    // spheres of 1 mm on 7.8 × 7.8 mm², packing fraction ~0.55: ~6 mm
    // high, its centre of mass near 3 mm).
    let top = x1.iter().map(|x| x[2]).fold(0.0, f64::max);
    let mean = x1.iter().map(|x| x[2]).sum::<f64>() / x1.len() as f64;
    assert!(
        top < 8e-3 && mean < 3.5e-3,
        "not down: top {top} m, mean {mean} m"
    );
    let (xs, vs, still, r_still) = run(&setup, 3, [1, 1, 3], f64::INFINITY, 10000);
    let (xb, vb, moved, r_moved) = run(&setup, 3, [1, 1, 3], 1.2, 10000);
    assert_eq!(r_still.free_at_start, vec![108, 108, 144]);
    assert_eq!(r_moved.free_at_start, vec![108, 108, 144]);
    assert_eq!(r_still.rebalances, 0);
    assert!(imbalance(&still) > 2.0, "{still:?}");
    assert!(r_moved.rebalances >= 1, "{r_moved:?}");
    assert!(imbalance(&r_moved.free_before_last) > 1.2, "{r_moved:?}");
    assert!(imbalance(&moved) <= 1.2, "{moved:?} {r_moved:?}");
    assert_eq!(moved.iter().sum::<usize>(), 360);
    // The cuts came down into the bed.
    assert!(r_moved.cuts[2][2] < 5e-3, "{:?}", r_moved.cuts);
    println!("free bodies per rank: start {:?}, before the last of {} re-partitions {:?}, end {:?} (without: {still:?}); cuts {:?}", r_moved.free_at_start, r_moved.rebalances, r_moved.free_before_last, moved, r_moved.cuts[2]);
    for k in 0..x1.len() {
        for a in 0..3 {
            assert_eq!(xb[k][a].to_bits(), x1[k][a].to_bits(), "body {k}");
            assert_eq!(vb[k][a].to_bits(), v1[k][a].to_bits(), "body {k}");
            assert_eq!(xs[k][a].to_bits(), x1[k][a].to_bits(), "body {k}");
            assert_eq!(vs[k][a].to_bits(), v1[k][a].to_bits(), "body {k}");
        }
    }
}
