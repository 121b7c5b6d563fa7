//! Domain decomposition (issue 16) with ranks as threads
//! (`comm::threads::ThreadTransport`): the same code as under MPI, only the
//! transport differs. The MPI runs themselves: tests/mpi.rs at the root
//! (feature `mpi`) and tests/mpi/run.sh.

mod common;

use dembound_scene::comm::threads::ThreadTransport;
use dembound_scene::comm::DistributedSimulation;
use dembound_scene::setup::{BoundaryParticles, Plane};
use dembound_scene::{Observation, SceneSetup, Simulation};

/// Positions, velocities, the final observation, bodies per rank.
type Run = (Vec<[f64; 3]>, Vec<[f64; 3]>, Observation, Vec<usize>);

/// Runs `setup` on `ranks` thread-ranks with `grid` for `steps` steps;
/// returns rank 0's gathered positions and velocities (input order), the
/// final observation and the bodies each rank owns.
fn run(setup: &SceneSetup, ranks: usize, grid: Option<[usize; 3]>, steps: u64) -> Run {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            std::thread::spawn(move || {
                let mut d = DistributedSimulation::new(&setup, 1, grid, t).expect("valid scene");
                d.step(steps);
                let o = d.observe();
                let reports = d.rank_reports();
                let state = d.gather_state();
                (state, o, reports)
            })
        })
        .collect();
    let mut out = None;
    for h in handles {
        let (state, o, reports) = h.join().expect("rank finished");
        if let Some(s) = state {
            out = Some((
                s.position,
                s.velocity,
                o,
                reports.iter().map(|r| r.owned).collect(),
            ));
        }
    }
    out.expect("rank 0 gathers")
}

/// 1, 2 and 3 ranks (and a 2 × 2 × 1 grid), 4,000 steps of a small
/// lattice drop: the same positions and velocities to the bit, because
/// each body's force is summed in an order fixed by the whole scene (its
/// partners' cells of the whole scene's grid, then their ids).
/// The contact count is an integer; the energies are sums over the ranks
/// in a rank-dependent order, so they agree to round-off (1e-12
/// relative: a few ulps times the number of ranks); the walls' forces and
/// torques are summed in input-id order: the same bits.
#[test]
fn positions_are_bit_identical_on_1_2_3_ranks() {
    let setup = common::lattice_drop(6, 8, 2.0e-6, 4000);
    let (x1, v1, o1, owned1) = run(&setup, 1, None, 4000);
    assert_eq!(owned1, vec![288]);
    // The spheres have fallen and touch (the test means something).
    assert!(o1.particle_contacts > 100, "{o1:?}");
    // The spheres sit in the bottom 5 mm of a 30 mm box: the grids cut x
    // and y (the default, least surface, would cut z above them all).
    for (ranks, grid) in [
        (2, Some([2, 1, 1])),
        (3, Some([1, 3, 1])),
        (4, Some([2, 2, 1])),
    ] {
        let (x, v, o, owned) = run(&setup, ranks, grid, 4000);
        assert_eq!(owned.iter().sum::<usize>(), 288);
        assert!(owned.iter().all(|&k| k > 0), "{owned:?}");
        for k in 0..x1.len() {
            for a in 0..3 {
                assert_eq!(
                    x[k][a].to_bits(),
                    x1[k][a].to_bits(),
                    "{ranks} ranks, body {k}"
                );
                assert_eq!(
                    v[k][a].to_bits(),
                    v1[k][a].to_bits(),
                    "{ranks} ranks, body {k}"
                );
            }
        }
        assert_eq!(o.particle_contacts, o1.particle_contacts);
        assert_eq!(o.wall_contacts, o1.wall_contacts);
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
        assert!(rel(o.kinetic_energy, o1.kinetic_energy) < 1e-12);
        assert!(rel(o.elastic_energy, o1.elastic_energy) < 1e-12);
        assert_same_wall_loads(&o, &o1, ranks);
    }
}

/// Each rank, ranks as threads: (gathered state at rank 0, observation,
/// whether every rank summed in cell order).
fn run_states(
    setup: &SceneSetup,
    ranks: usize,
    grid: Option<[usize; 3]>,
    steps: u64,
) -> (
    dembound_scene::comm::distributed::GatheredState,
    Observation,
    bool,
) {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            std::thread::spawn(move || {
                let mut d = DistributedSimulation::new(&setup, 1, grid, t).expect("valid scene");
                // In pieces, as the CLI observes: the last step of each is
                // not fused.
                let mut done = 0;
                while done < steps {
                    let n = (steps - done).min(700);
                    d.step(n);
                    done += n;
                }
                let cell_order = d.sums_in_cell_order();
                (d.gather_state(), d.observe(), cell_order)
            })
        })
        .collect();
    let mut out = None;
    let mut all_cell_order = true;
    for h in handles {
        let (state, o, cell_order) = h.join().expect("rank finished");
        all_cell_order &= cell_order;
        if let Some(s) = state {
            out = Some((s, o));
        }
    }
    let (s, o) = out.expect("rank 0 gathers");
    (s, o, all_cell_order)
}

/// Random velocities of up to 0.3 m/s per axis (seeded): spheres cross
/// the cuts while in contact and contacts begin and end throughout.
fn shake(setup: &mut SceneSetup, seed: u64) {
    let mut rng = common::Rng(seed);
    for s in &mut setup.spheres {
        s.velocity = [
            0.3 * rng.symmetric(),
            0.3 * rng.symmetric(),
            0.3 * rng.symmetric(),
        ];
    }
}

/// The same positions and velocities to the bit.
fn assert_same_bits(
    s: &dembound_scene::comm::distributed::GatheredState,
    s1: &dembound_scene::comm::distributed::GatheredState,
    ranks: usize,
) {
    assert_eq!(s.position.len(), s1.position.len());
    for k in 0..s1.position.len() {
        for a in 0..3 {
            assert_eq!(
                s.position[k][a].to_bits(),
                s1.position[k][a].to_bits(),
                "{ranks}: {k}"
            );
            assert_eq!(
                s.velocity[k][a].to_bits(),
                s1.velocity[k][a].to_bits(),
                "{ranks}: {k}"
            );
        }
    }
}

/// Enough bodies that each rank's force loop has several blocks (of at
/// least 512 bodies): the rows run in order, the sums are the whole
/// scene's, and the end state is the same bits on 1, 2 and 3 ranks.
#[test]
fn many_blocks_are_bit_identical_on_1_2_3_ranks() {
    let setup = common::lattice_drop(16, 8, 2.0e-6, 2100);
    let (s1, o1, c1) = run_states(&setup, 1, None, 2100);
    assert!(c1, "summed in cell order");
    assert!(o1.particle_contacts > 500, "{o1:?}");
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        let (s, o, c) = run_states(&setup, ranks, grid, 2100);
        assert!(c);
        assert_same_bits(&s, &s1, ranks);
        assert_eq!(o.particle_contacts, o1.particle_contacts);
    }
}

/// Each rank with the halo exchange during the interior pairs or before
/// the force stage (`set_halo_overlap`), stepped in pieces as the CLI
/// observes: the gathered state at rank 0 and every rank's report.
fn run_overlap(
    setup: &SceneSetup,
    ranks: usize,
    grid: Option<[usize; 3]>,
    steps: u64,
    overlap: bool,
) -> (
    dembound_scene::comm::distributed::GatheredState,
    Vec<dembound_scene::comm::RankReport>,
) {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            std::thread::spawn(move || {
                let mut d = DistributedSimulation::new(&setup, 1, grid, t).expect("valid scene");
                d.set_halo_overlap(overlap);
                let mut done = 0;
                while done < steps {
                    let n = (steps - done).min(700);
                    d.step(n);
                    done += n;
                }
                (d.gather_state(), d.rank_reports())
            })
        })
        .collect();
    let mut out = None;
    for h in handles {
        let (state, reports) = h.join().expect("rank finished");
        if let Some(s) = state {
            out = Some((s, reports));
        }
    }
    out.expect("rank 0 gathers")
}

/// The halo exchange overlapped with the interior pairs
/// (`dynamics::halo_split`): a shaken drop (spheres crossing the cuts in
/// contact, contacts beginning and ending) on 2 and 3 ranks. Every rank
/// takes the split path (most steps overlapped; pairs with halo copies
/// deferred), and the end state (positions, velocities and forces) is the
/// same bits as with the exchange before the force stage (the loop as it
/// was) and as on 1 rank: the split only reorders when pairs are
/// computed, not the additions into any body.
#[test]
fn the_halo_overlapped_with_the_interior_pairs_changes_no_bit() {
    let mut setup = common::lattice_drop(16, 8, 2.0e-6, 2100);
    shake(&mut setup, 7);
    let steps = 2100;
    let (s1, r1) = run_overlap(&setup, 1, None, steps, false);
    assert_eq!(r1[0].overlapped_steps, 0);
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        let (before, rb) = run_overlap(&setup, ranks, grid, steps, false);
        let (s, r) = run_overlap(&setup, ranks, grid, steps, true);
        assert!(rb.iter().all(|x| x.overlapped_steps == 0), "{rb:?}");
        for x in &r {
            // Every step but the list builds' and the last of each piece
            // (not fused: the exchange comes first there).
            assert!(x.overlapped_steps > steps / 2, "{ranks} ranks: {r:?}");
            assert!(x.deferred_pairs > 0, "{ranks} ranks: {r:?}");
        }
        assert_same_bits(&s, &before, ranks);
        assert_same_bits(&s, &s1, ranks);
        for k in 0..s1.force.len() {
            for a in 0..3 {
                assert_eq!(
                    s.force[k][a].to_bits(),
                    before.force[k][a].to_bits(),
                    "{ranks} ranks: force of {k}"
                );
            }
        }
    }
}

/// A floor of boundary particles (fixed spheres of the grains' size, a
/// touching square layer under the lattice drop, instead of the plane
/// floor), Tsuji-damped: the floor force, summed over the ranks from the
/// forces the floor particles got, balances the grains' momentum: force
/// on the floor = N m g − Σ (force on each grain), the grains' pair
/// forces cancelling (round-off of the ~1e-3 N sums: 1e-9 of N m g is
/// far above it, and far below a missed or double-counted contact, which
/// carries ~1e-6 N). The same on 1, 2 and 3 ranks to round-off of the
/// rank sums (1e-12 relative; the floor's torque too, each rank summing
/// its share of the particles: not the same bits), and the state to the
/// bit.
#[test]
fn a_boundary_particle_floor_carries_the_grains_on_any_ranks() {
    let mut setup = common::lattice_drop(8, 4, 2.0e-6, 4000);
    setup.contact = dembound_physics::contact::ContactModel::damped(
        dembound_physics::contact::NormalLaw::Hertz,
        dembound_physics::contact::Damping::new(
            dembound_physics::contact::DampingKind::Tsuji,
            dembound_physics::contact::Dissipation::Restitution(0.3),
        ),
    );
    // Walls: x−, x+, y−, y+, z−, z+ planes; the z− plane goes.
    let upper = match &setup.walls[5] {
        dembound_scene::setup::WallSetup::Plane(Plane { point, .. }) => *point,
        _ => unreachable!("lattice_drop's walls are planes"),
    };
    setup.walls.remove(4);
    let grains = setup.spheres.len();
    let r = 0.5e-3;
    let per_side = ((upper[0] - 2.0 * r) / (2.0 * r)).floor() as usize + 1;
    let wall = setup.walls.len();
    for j in 0..per_side {
        for i in 0..per_side {
            setup.spheres.push(dembound_scene::setup::SphereInit {
                position: [r + 2.0 * r * i as f64, r + 2.0 * r * j as f64, -r],
                velocity: [0.0; 3],
                radius: r,
                material: 0,
                fixed: true,
                group: Some(wall),
            });
        }
    }
    setup
        .walls
        .push(dembound_scene::setup::WallSetup::BoundaryParticles(
            BoundaryParticles {
                first_body: grains,
                count: per_side * per_side,
            },
        ));
    let steps = 4000;
    let (s1, o1, c1) = run_states(&setup, 1, None, steps);
    assert!(c1, "summed in cell order");
    assert!(
        o1.wall_contacts > 50,
        "the first layer sits on the floor: {o1:?}"
    );
    let mass = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let weight = grains as f64 * mass * 9.81;
    let grain_force: f64 = (0..grains).map(|k| s1.force[k][2]).sum();
    let floor = o1.wall_forces[wall][2];
    // Force on the floor (downward, negative) = −N m g − Σ f_z.
    assert!(
        (floor - (-weight - grain_force)).abs() < 1e-9 * weight,
        "floor {floor} N, weight {weight} N, grains' net {grain_force} N"
    );
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        let (s, o, c) = run_states(&setup, ranks, grid, steps);
        assert!(c);
        for k in 0..s1.position.len() {
            for a in 0..3 {
                assert_eq!(
                    s.position[k][a].to_bits(),
                    s1.position[k][a].to_bits(),
                    "{ranks}: {k}"
                );
            }
        }
        assert_eq!(o.wall_contacts, o1.wall_contacts);
        let f = o.wall_forces[wall];
        let t = o.wall_torques[wall];
        for a in 0..3 {
            let g = o1.wall_forces[wall][a];
            assert!(
                (f[a] - g).abs() <= 1e-12 * weight,
                "{ranks}: {f:?} {:?}",
                o1.wall_forces[wall]
            );
            // Torques about the floor's centre: lever arms up to the
            // box's half-width.
            let g = o1.wall_torques[wall][a];
            assert!(
                (t[a] - g).abs() <= 1e-12 * weight * upper[0],
                "{ranks}: {t:?} {:?}",
                o1.wall_torques[wall]
            );
        }
    }
}

/// One rank against the engine itself: the same physics, the force sums
/// in another order. After 300 steps (before the drop's contacts become
/// chaotic) positions agree to 1e-12 m (round-off of 1e-16 relative
/// amplified by the contacts; a missing pair or a wrong sign would move a
/// sphere by its overlap, ~1e-6 m).
#[test]
fn one_rank_matches_the_engine() {
    let setup = common::lattice_drop(6, 8, 2.0e-6, 2000);
    let mut sim = Simulation::new(setup.clone(), 1).expect("valid scene");
    sim.step(2000);
    let (x, _, o, _) = run(&setup, 1, None, 2000);
    let (x2, _, o2, owned) = run(&setup, 2, Some([2, 1, 1]), 2000);
    assert_eq!(owned, vec![144, 144]);
    let xs = sim.positions();
    let mut worst = 0.0f64;
    for k in 0..xs.len() {
        for a in 0..3 {
            worst = worst.max((x[k][a] - xs[k][a]).abs());
            assert_eq!(x2[k][a].to_bits(), x[k][a].to_bits());
        }
    }
    assert!(worst < 1e-12, "{worst}");
    assert_eq!(o.particle_contacts, sim.particle_contacts());
    assert_eq!(o2.wall_contacts, sim.wall_contacts());
    assert!((o.kinetic_energy - sim.kinetic_energy()).abs() < 1e-9 * sim.kinetic_energy());
}

/// A grid that does not match the ranks is refused with the key named;
/// friction with a periodic axis too (its images' pairs would be summed
/// without torques).
#[test]
fn bad_grid_and_periodic_friction_are_refused() {
    let setup = common::lattice_drop(4, 4, 2.0e-6, 10);
    let t = ThreadTransport::group(1).pop().expect("one rank");
    let e = DistributedSimulation::new(&setup, 1, Some([1, 1, 2]), t)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("parallel.grid"), "{e}");
    let mut f = setup.clone();
    f.friction = Some(friction(0.5, 0.0));
    f.domain.periodic = [true, false, false];
    f.walls.drain(0..2);
    let t = ThreadTransport::group(1).pop().expect("one rank");
    let e = DistributedSimulation::new(&f, 1, None, t)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("contact.friction"), "{e}");
}

fn friction(mu: f64, mu_r: f64) -> dembound_scene::setup::FrictionSetup {
    dembound_scene::setup::FrictionSetup::uniform(
        dembound_physics::contact::tangential::FrictionModel {
            tangential: dembound_physics::contact::tangential::TangentialKind::Mindlin,
            friction: mu,
            rolling_friction: mu_r,
        },
    )
}

/// Friction and rolling friction (Mindlin springs, μ = 0.5, μ_r = 0.05),
/// random velocities and spins so that bodies cross the cuts while in
/// contact (their springs migrate with them, the halo carries the spins),
/// Walton–Braun histories: the end state (positions, velocities, spins:
/// gathered) and the walls' forces and torques are the same bits on 1, 2
/// and 3 ranks; the energies agree to the round-off of the rank sums
/// (1e-12).
#[test]
fn friction_is_bit_identical_on_1_2_3_ranks() {
    let mut setup = common::lattice_drop(8, 6, 2.0e-6, 3000);
    setup.contact = dembound_physics::contact::ContactModel::elastic(
        dembound_physics::contact::NormalLaw::WaltonBraun { restitution: 0.5 },
    );
    setup.friction = Some(friction(0.5, 0.05));
    shake(&mut setup, 7);
    let (s1, o1, c1) = run_states(&setup, 1, None, 3000);
    assert!(c1);
    assert!(o1.particle_contacts > 20, "{o1:?}");
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        let (s, o, _) = run_states(&setup, ranks, grid, 3000);
        assert_same_bits(&s, &s1, ranks);
        assert_observables_agree(&o, &o1, 1e-12);
        assert_same_wall_loads(&o, &o1, ranks);
    }
}

/// The decomposed friction run against the engine itself (its sums in
/// another order), 2000 steps of the frictional lattice drop, before the
/// contacts' chaos amplifies round-off: positions to 1e-12 m (a missing
/// torque or spring would move a sphere by ~1e-7 m: the tangential
/// displacement of a 300-step contact), and the observables — kinetic
/// energy with spin, elastic energy with the springs, the plane forces
/// with their tangential part — to 1e-9 relative.
#[test]
fn friction_on_one_and_two_ranks_matches_the_engine() {
    let mut setup = common::lattice_drop(6, 8, 2.0e-6, 2000);
    setup.friction = Some(friction(0.5, 0.05));
    let mut sim = Simulation::new(setup.clone(), 1).expect("valid scene");
    sim.step(2000);
    let e = sim.observe();
    let (s2, o2, _) = run_states(&setup, 2, Some([2, 1, 1]), 2000);
    let xs = sim.positions();
    let mut worst = 0.0f64;
    for (x2, x) in s2.position.iter().zip(&xs) {
        for a in 0..3 {
            worst = worst.max((x2[a] - x[a]).abs());
        }
    }
    assert!(worst < 1e-12, "{worst}");
    assert!(o2.particle_contacts > 100, "{o2:?}");
    assert_observables_agree(&o2, &e, 1e-9);
}

/// A rank's series row from what its last steps tallied (each listed
/// pair's terms written by the pair pass, the bodies' energies by the
/// last half kick) is the row it gets by visiting every pair again: the
/// same pairs counted on one rank only and the same sums in the same
/// order, bit for bit, on 2 and 3 ranks, with and without friction, at
/// several states of a drop (the rows every 150 steps as a run takes
/// them, so that pairs cross the cuts between rows).
#[test]
fn a_rank_row_from_the_tallies_is_the_row_from_every_pair() {
    for with_friction in [false, true] {
        let mut setup = common::lattice_drop(6, 6, 2.0e-6, 1500);
        if with_friction {
            setup.friction = Some(friction(0.5, 0.05));
        }
        shake(&mut setup, 11);
        for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
            let handles: Vec<_> = ThreadTransport::group(ranks)
                .into_iter()
                .map(|t| {
                    let setup = setup.clone();
                    std::thread::spawn(move || {
                        let mut d =
                            DistributedSimulation::new(&setup, 1, grid, t).expect("valid scene");
                        let mut rows = Vec::new();
                        for _ in 0..10 {
                            d.step(149);
                            d.will_observe();
                            d.step(1);
                            rows.push((d.observe(), d.observe_visiting()));
                        }
                        rows
                    })
                })
                .collect();
            for h in handles {
                let rows = h.join().expect("rank finished");
                let touching: usize = rows.iter().map(|(o, _)| o.particle_contacts).sum();
                assert!(
                    touching > 50,
                    "the drop must have pairs in contact: {touching}"
                );
                for (tallied, visited) in rows {
                    // Debug prints each f64's shortest round-trip digits
                    // and −0 apart from +0: equal text, equal bits.
                    assert_eq!(
                        format!("{tallied:?}"),
                        format!("{visited:?}"),
                        "{ranks} ranks, friction {with_friction}"
                    );
                }
            }
        }
    }
}

/// The walls' loads (forces and torques: every wall here is a plane, its
/// load summed from the force stage's records by input id) are the same
/// bits as on one rank.
fn assert_same_wall_loads(o: &Observation, o1: &Observation, ranks: usize) {
    let bits = |v: &[[f64; 3]]| -> Vec<u64> { v.iter().flatten().map(|x| x.to_bits()).collect() };
    assert_eq!(o.wall_forces.len(), o1.wall_forces.len());
    assert_eq!(
        bits(&o.wall_forces),
        bits(&o1.wall_forces),
        "{ranks} ranks: wall forces"
    );
    assert_eq!(
        bits(&o.wall_torques),
        bits(&o1.wall_torques),
        "{ranks} ranks: wall torques"
    );
}

/// Contact counts equal; energies and wall forces (each component, or
/// 1e-9 N where it is smaller) to `tol` relative.
fn assert_observables_agree(o: &Observation, e: &Observation, tol: f64) {
    assert_eq!(o.particle_contacts, e.particle_contacts);
    assert_eq!(o.wall_contacts, e.wall_contacts);
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    assert!(rel(o.kinetic_energy, e.kinetic_energy) < tol, "{o:?} {e:?}");
    assert!(rel(o.elastic_energy, e.elastic_energy) < tol, "{o:?} {e:?}");
    for (f, g) in o.wall_forces.iter().zip(&e.wall_forces) {
        for a in 0..3 {
            assert!(
                (f[a] - g[a]).abs() <= tol * g[a].abs().max(1e-9),
                "{f:?} {g:?}"
            );
        }
    }
}

/// Gear5 (the paper's scheme) with random velocities, so that bodies
/// cross the cuts while in contact (their Nordsieck vectors migrate with
/// them), and contacts begin and end inside steps (the kink corrections,
/// added in list order): the same bits on 1, 2 and 3 ranks; and one rank
/// against the engine after 2000 steps to 1e-12 m (the engine's sums in
/// another order: round-off, amplified by the contacts; a lost
/// derivative or kink would move a sphere by ~1e-9 m or more).
#[test]
fn gear5_is_bit_identical_on_1_2_3_ranks_and_follows_the_engine() {
    let mut setup = common::lattice_drop(8, 6, 2.0e-6, 2000);
    setup.integration.scheme = dembound_scene::setup::Scheme::Gear5;
    shake(&mut setup, 11);
    let (s1, o1, c1) = run_states(&setup, 1, None, 2000);
    assert!(c1);
    // Contacts at the end (16 of them: the spheres fly apart and collide).
    assert!(o1.particle_contacts > 8, "{o1:?}");
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        let (s, o, _) = run_states(&setup, ranks, grid, 2000);
        assert_same_bits(&s, &s1, ranks);
        assert_eq!(o.particle_contacts, o1.particle_contacts);
        assert_same_wall_loads(&o, &o1, ranks);
    }
    let mut sim = Simulation::new(setup.clone(), 1).expect("valid scene");
    sim.step(2000);
    let mut worst = 0.0f64;
    for (x1, x) in s1.position.iter().zip(sim.positions()) {
        for a in 0..3 {
            worst = worst.max((x1[a] - x[a]).abs());
        }
    }
    assert!(worst < 1e-12, "{worst}");
}

/// Gear5 with friction and rolling friction (Mindlin, μ = 0.5,
/// μ_r = 0.05), random velocities: bodies cross the cuts while in contact
/// (their translational and spin Nordsieck vectors and springs migrate
/// with them, the halo carries the predicted spins). The same bits on 1,
/// 2 and 3 ranks; one rank against the engine after 2000 steps to 1e-12 m
/// (its sums in another order: round-off amplified by the contacts; a
/// lost spin derivative or spring would move a sphere by far more, ~1e-9
/// m in 100 steps of a sticking contact).
#[test]
fn gear5_friction_is_bit_identical_on_1_2_3_ranks_and_follows_the_engine() {
    let mut setup = common::lattice_drop(8, 6, 2.0e-6, 2000);
    setup.integration.scheme = dembound_scene::setup::Scheme::Gear5;
    setup.friction = Some(friction(0.5, 0.05));
    shake(&mut setup, 13);
    let (s1, o1, c1) = run_states(&setup, 1, None, 2000);
    assert!(c1);
    assert!(o1.particle_contacts > 8, "{o1:?}");
    assert!(s1.position.iter().flatten().all(|x| x.is_finite()));
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        let (s, o, _) = run_states(&setup, ranks, grid, 2000);
        assert_same_bits(&s, &s1, ranks);
        for (w, w1) in s.angular_velocity.iter().zip(&s1.angular_velocity) {
            for a in 0..3 {
                assert_eq!(w[a].to_bits(), w1[a].to_bits(), "{ranks} ranks: spins");
            }
        }
        // The observation reads the halo copies where the last exchange
        // left them, at Gear5's predicted state (frictionless Gear5 too):
        // the pairs across a cut differ by the corrector's move there,
        // 2.6e-9 relative in the elastic energy here; a lost spring would
        // change it by its whole share (order 1). The walls' loads are
        // the force stage's: the same bits.
        assert_observables_agree(&o, &o1, 1e-7);
        assert_same_wall_loads(&o, &o1, ranks);
    }
    let mut sim = Simulation::new(setup.clone(), 1).expect("valid scene");
    sim.step(2000);
    let mut worst = 0.0f64;
    for (x1, x) in s1.position.iter().zip(sim.positions()) {
        for a in 0..3 {
            worst = worst.max((x1[a] - x[a]).abs());
        }
    }
    eprintln!("Gear5 friction, 1 rank against the engine: {worst:e} m");
    assert!(worst < 1e-12, "{worst}");
}

/// The collision log on 1, 2 and 3 ranks, spheres crossing the cuts
/// while in contact (random velocities): each rank logs the collisions of
/// the spheres it owns, rank 0 merges them in the engine's order; the
/// merged log is the same on any rank count, to the bit. Against the
/// engine itself (its force sums in another order) over 1500 steps, the
/// same collisions in the same order with onsets, ends, peak overlaps and
/// impact speeds to 1e-6 relative (round-off amplified by the colliding
/// spheres: measured up to 3e-9 here; a collision lost at a cut or
/// logged twice changes the list, a partner's stale half-step velocity
/// the impact speed by ~1e-3 relative).
#[test]
fn the_collision_log_is_the_same_on_1_2_3_ranks() {
    let mut setup = common::lattice_drop(6, 8, 2.0e-6, 1500);
    shake(&mut setup, 5);
    setup.collisions = true;
    let log = |ranks: usize, grid: Option<[usize; 3]>| {
        let handles: Vec<_> = ThreadTransport::group(ranks)
            .into_iter()
            .map(|t| {
                let setup = setup.clone();
                std::thread::spawn(move || {
                    let mut d = DistributedSimulation::new(&setup, 1, grid, t).expect("valid");
                    for _ in 0..3 {
                        d.step(500);
                    }
                    d.collisions()
                })
            })
            .collect();
        handles
            .into_iter()
            .filter_map(|h| h.join().expect("rank"))
            .next()
            .expect("rank 0 merges")
    };
    let one = log(1, None);
    assert!(one.len() > 50, "{}", one.len());
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1]))] {
        assert_eq!(log(ranks, grid), one, "{ranks} ranks");
    }
    let mut sim = Simulation::new(setup.clone(), 1).expect("valid scene");
    sim.step(1500);
    let engine = sim.collisions();
    assert_eq!(engine.len(), one.len());
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
    for (c, e) in one.iter().zip(engine) {
        assert_eq!((c.i, c.j), (e.i, e.j));
        assert!(rel(c.t_start, e.t_start) < 1e-6, "{c:?} {e:?}");
        assert!(rel(c.t_end, e.t_end) < 1e-6, "{c:?} {e:?}");
        assert!(rel(c.max_overlap, e.max_overlap) < 1e-6, "{c:?} {e:?}");
        assert!(
            rel(c.impact_normal_velocity, e.impact_normal_velocity) < 1e-6,
            "{c:?} {e:?}"
        );
    }
}

/// The experiment behind the partner-id order: with the engine's own
/// half-list sums, whose order follows each rank's list, 1 and 2 ranks
/// drift apart by round-off that the drop's contacts amplify. Prints the
/// largest relative position difference at a few step counts
/// (`cargo test --release -p dembound-scene --test decomposition plain
/// -- --ignored --nocapture`); asserts only that it is not zero (else the
/// partner-id order would not be needed).
#[test]
#[ignore = "an experiment; prints its figures"]
fn plain_half_list_sums_drift_apart() {
    let setup = common::lattice_drop(8, 10, 2.0e-6, 10_000);
    let run_plain = |ranks: usize, grid: Option<[usize; 3]>, steps: u64| {
        let handles: Vec<_> = ThreadTransport::group(ranks)
            .into_iter()
            .map(|t| {
                let setup = setup.clone();
                std::thread::spawn(move || {
                    let mut d = DistributedSimulation::new(&setup, 1, grid, t).expect("valid");
                    d.use_plain_sums();
                    d.step(steps);
                    d.gather_state()
                })
            })
            .collect();
        handles
            .into_iter()
            .filter_map(|h| h.join().expect("rank"))
            .next()
            .expect("rank 0")
            .position
    };
    let mut last = 0.0;
    for steps in [1000, 2000, 4000, 6000, 8000, 10_000] {
        let a = run_plain(1, None, steps);
        let b = run_plain(2, Some([2, 1, 1]), steps);
        let mut worst = 0.0f64;
        for k in 0..a.len() {
            for c in 0..3 {
                worst = worst.max((a[k][c] - b[k][c]).abs() / a[k][c].abs().max(1e-3));
            }
        }
        println!("plain half lists, 1 vs 2 ranks, {steps} steps: max relative position difference {worst:.3e}");
        last = worst;
    }
    assert!(last > 0.0);
}

/// Migration with pair histories: the grid cuts x in the middle, and the
/// spheres, given random velocities, cross the cut and change rank while
/// in contact; with Walton–Braun (a hysteretic law: each
/// contact's largest overlap and branch travel with it) the end state of
/// 2 ranks is the same bits as 1 rank.
#[test]
fn bodies_migrate_with_their_pair_histories() {
    let mut setup = common::lattice_drop(6, 8, 2.0e-6, 6000);
    setup.contact = dembound_physics::contact::ContactModel::elastic(
        dembound_physics::contact::NormalLaw::WaltonBraun { restitution: 0.5 },
    );
    // Random velocities up to 0.3 m/s per axis: up to 3.6 mm in the run,
    // many spheres cross the cut (at x = 3.9 mm) while in contact.
    shake(&mut setup, 16);
    let (x1, v1, o1, _) = run(&setup, 1, None, 6000);
    let handles: Vec<_> = ThreadTransport::group(2)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            std::thread::spawn(move || {
                let mut d =
                    DistributedSimulation::new(&setup, 1, Some([2, 1, 1]), t).expect("valid");
                d.step(6000);
                let moved = d.migrated();
                (d.gather_state(), d.observe(), moved)
            })
        })
        .collect();
    let mut moved = Vec::new();
    let mut state = None;
    let mut o2 = None;
    for h in handles {
        let (s, o, m) = h.join().expect("rank");
        moved.push(m);
        if s.is_some() {
            state = s;
            o2 = Some(o);
        }
    }
    // Bodies went both ways.
    assert!(moved.iter().all(|&m| m >= 5), "{moved:?}");
    let s = state.expect("rank 0");
    for k in 0..x1.len() {
        for a in 0..3 {
            assert_eq!(s.position[k][a].to_bits(), x1[k][a].to_bits(), "body {k}");
            assert_eq!(s.velocity[k][a].to_bits(), v1[k][a].to_bits(), "body {k}");
        }
    }
    let o2 = o2.expect("rank 0");
    assert_eq!(o2.particle_contacts, o1.particle_contacts);
    // Energy was lost in the hysteresis loops: histories were in play.
    assert!(
        o1.dissipated_energy > 1e-3 * o1.kinetic_energy.max(1e-12),
        "{o1:?}"
    );
}
