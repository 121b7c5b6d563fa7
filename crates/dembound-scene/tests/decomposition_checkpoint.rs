//! Checkpoint and restart of decomposed runs (issue 16) with ranks as
//! threads (`comm::threads::ThreadTransport`, the same code as under MPI):
//! a checkpoint written on 2 ranks continues on 3 ranks and on 1 rank in
//! the same bits as the run that never stopped, and a checkpoint of the
//! one-process engine continues under the decomposition (and back).

mod common;

use dembound_physics::contact::{ContactModel, NormalLaw};
use dembound_scene::comm::threads::ThreadTransport;
use dembound_scene::comm::DistributedSimulation;
use dembound_scene::io::checkpoint::{self, CheckpointFile};
use dembound_scene::io::config;
use dembound_scene::{Checkpoint, SceneSetup, Simulation};

/// What a run leaves: rank 0's checkpoint (the whole state, input order)
/// and the neighbour-list builds.
struct End {
    checkpoint: Checkpoint,
    list_builds: u64,
    particle_contacts: usize,
}

/// `ranks` thread-ranks on `grid`: from the start, or from `from`; then
/// `steps` steps.
fn run(
    setup: &SceneSetup,
    ranks: usize,
    grid: Option<[usize; 3]>,
    from: Option<&Checkpoint>,
    steps: u64,
) -> End {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .map(|t| {
            let setup = setup.clone();
            let from = from.cloned();
            std::thread::spawn(move || {
                let mut d = match &from {
                    Some(c) => DistributedSimulation::restore(&setup, c, 1, grid, t),
                    None => DistributedSimulation::new(&setup, 1, grid, t),
                }
                .expect("valid scene and checkpoint");
                d.step(steps);
                let o = d.observe();
                let builds = d.local().list_builds();
                (d.checkpoint().expect("checkpointed"), builds, o)
            })
        })
        .collect();
    let mut end = None;
    for h in handles {
        let (c, builds, o) = h.join().expect("rank finished");
        if let Some(c) = c {
            end = Some(End {
                checkpoint: c,
                list_builds: builds,
                particle_contacts: o.particle_contacts,
            });
        }
    }
    end.expect("rank 0 gathers")
}

/// Through the file format and back (CBOR keeps every f64 bit).
fn through_file(c: &Checkpoint) -> Checkpoint {
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/scenes/lattice_drop.toml");
    let scene = config::read(&scene, &[]).expect("the example scene reads");
    let file = CheckpointFile::new(scene, c.clone());
    let mut bytes = Vec::new();
    checkpoint::write(&mut bytes, &file).expect("written");
    checkpoint::read_from(&bytes[..], "memory")
        .expect("read back")
        .state
}

/// A small lattice drop with Walton–Braun (a hysteretic law: every
/// contact's largest overlap and branch must survive the restart) and
/// random velocities up to 0.3 m/s per axis, so that spheres cross the
/// cuts (x = 3.9 mm for 2 ranks, y = 2.6 and 5.2 mm for 3) while in
/// contact.
fn scene() -> SceneSetup {
    let mut setup = common::lattice_drop(6, 8, 2.0e-6, 6000);
    setup.contact = ContactModel::elastic(NormalLaw::WaltonBraun { restitution: 0.5 });
    let mut rng = common::Rng(16);
    for s in &mut setup.spheres {
        s.velocity = [
            0.3 * rng.symmetric(),
            0.3 * rng.symmetric(),
            0.3 * rng.symmetric(),
        ];
    }
    setup
}

/// The must-show: 3000 steps on 2 ranks and a checkpoint, then 3000 more
/// on 3 ranks (and on 1): the whole end state (positions, velocities,
/// forces, positions of the last list build, every pair and wall
/// history) equals that of 6000 steps on 2 ranks in one go, to the bit,
/// and the lists were rebuilt on the same steps.
#[test]
fn two_ranks_checkpoint_continues_on_three_and_one_bit_for_bit() {
    restarts_bit_for_bit(&scene());
}

/// The same with friction (Mindlin, μ = 0.5, rolling μ_r = 0.05: the
/// spins, torques, pair and plane springs go through the checkpoint) and
/// with Gear5 (its derivatives r₂..r₅ do).
#[test]
fn friction_and_gear5_checkpoints_continue_bit_for_bit() {
    let mut friction = scene();
    friction.friction = Some(dembound_scene::setup::FrictionSetup::uniform(
        dembound_physics::contact::tangential::FrictionModel {
            tangential: dembound_physics::contact::tangential::TangentialKind::Mindlin,
            friction: 0.5,
            rolling_friction: 0.05,
        },
    ));
    let c = restarts_bit_for_bit(&friction);
    assert!(c.pair_shear.len() > 10, "{}", c.pair_shear.len());
    assert!(!c.plane_shear.is_empty());
    let mut gear5 = scene();
    gear5.contact = ContactModel::elastic(NormalLaw::Hertz);
    gear5.integration.scheme = dembound_scene::setup::Scheme::Gear5;
    let c = restarts_bit_for_bit(&gear5);
    assert_eq!(c.higher.len(), c.position.len());
}

/// Gear5 with friction (the spins' derivatives r₁..r₄ migrate with their
/// bodies and go through the checkpoint): the same restarts, to the bit.
#[test]
fn gear5_friction_checkpoints_continue_bit_for_bit() {
    let mut setup = scene();
    setup.contact = ContactModel::elastic(NormalLaw::Hertz);
    setup.integration.scheme = dembound_scene::setup::Scheme::Gear5;
    setup.friction = Some(dembound_scene::setup::FrictionSetup::uniform(
        dembound_physics::contact::tangential::FrictionModel {
            tangential: dembound_physics::contact::tangential::TangentialKind::Mindlin,
            friction: 0.5,
            rolling_friction: 0.05,
        },
    ));
    let c = restarts_bit_for_bit(&setup);
    assert_eq!(c.angular_higher.len(), c.position.len());
    assert!(c.angular_higher.iter().any(|r| r != &[[0.0; 3]; 4]));
    assert!(c.pair_shear.len() > 10, "{}", c.pair_shear.len());
    // Finite to the end (Gear5 with stiff springs at this Δt is stable).
    assert!(c.position.iter().flatten().all(|x| x.is_finite()));
}

/// The same with the collision log on: the tracks of open contacts and
/// the log so far go through the checkpoint, and the continued log equals
/// the uninterrupted one.
#[test]
fn collision_log_checkpoints_continue_bit_for_bit() {
    let mut logged = scene();
    logged.collisions = true;
    let c = restarts_bit_for_bit(&logged);
    assert!(c.collisions.len() > 50, "{}", c.collisions.len());
    assert!(!c.pair_tracks.is_empty());
}

/// The must-show's steps for `setup`; returns the straight run's end.
fn restarts_bit_for_bit(setup: &SceneSetup) -> Checkpoint {
    let setup = setup.clone();
    let straight = run(&setup, 2, Some([2, 1, 1]), None, 6000);
    let half = run(&setup, 2, Some([2, 1, 1]), None, 3000);
    let saved = through_file(&half.checkpoint);
    assert_eq!(saved, half.checkpoint);
    assert_eq!(saved.steps_done, 3000);
    // Histories are in play (a law that keeps them): pair contacts and
    // wall contacts with a largest overlap to remember.
    let s = &straight.checkpoint;
    if matches!(setup.contact.normal, NormalLaw::WaltonBraun { .. }) {
        assert!(
            saved.pair_histories.len() > 10,
            "{}",
            saved.pair_histories.len()
        );
        assert!(!saved.plane_histories.is_empty());
        assert!(s.pair_histories.len() > 10, "{}", s.pair_histories.len());
    }
    for (ranks, grid) in [(3, Some([1, 3, 1])), (1, None), (2, Some([2, 1, 1]))] {
        let resumed = run(&setup, ranks, grid, Some(&saved), 3000);
        let r = &resumed.checkpoint;
        assert_eq!(r.steps_done, 6000);
        for k in 0..s.position.len() {
            for a in 0..3 {
                assert_eq!(
                    r.position[k][a].to_bits(),
                    s.position[k][a].to_bits(),
                    "{ranks} ranks, body {k}"
                );
                assert_eq!(
                    r.velocity[k][a].to_bits(),
                    s.velocity[k][a].to_bits(),
                    "{ranks} ranks, body {k}"
                );
                assert_eq!(
                    r.force[k][a].to_bits(),
                    s.force[k][a].to_bits(),
                    "{ranks} ranks, body {k}"
                );
                assert_eq!(
                    r.reference[k][a].to_bits(),
                    s.reference[k][a].to_bits(),
                    "{ranks} ranks, body {k}"
                );
            }
        }
        assert_eq!(r.pair_histories, s.pair_histories, "{ranks} ranks");
        assert_eq!(r.plane_histories, s.plane_histories, "{ranks} ranks");
        assert_eq!(r.list_builds, s.list_builds, "{ranks} ranks");
        assert_eq!(resumed.list_builds, straight.list_builds);
        assert_eq!(resumed.particle_contacts, straight.particle_contacts);
        assert_eq!(r.pair_tracks, s.pair_tracks, "{ranks} ranks: pair tracks");
        assert_eq!(
            r.plane_tracks, s.plane_tracks,
            "{ranks} ranks: plane tracks"
        );
        assert_eq!(
            r.collisions.len(),
            s.collisions.len(),
            "{ranks} ranks: log length"
        );
        for (k, (a, b)) in r.collisions.iter().zip(&s.collisions).enumerate() {
            assert_eq!(a, b, "{ranks} ranks: collision {k}");
        }
        assert_eq!(r, s, "{ranks} ranks: the whole checkpoint");
    }
    straight.checkpoint
}

/// A checkpoint of the one-process engine loads under the decomposition
/// and the decomposition's checkpoint loads in the engine. The engine
/// sums each body's forces in the order of its own list, the
/// decomposition in whole-scene cell order: the continuations agree to
/// round-off, not to the bit. After 300 steps of this dense, colliding
/// bed, 1e-12 m (round-off of 1e-16 relative amplified by the contacts; a
/// lost history or a wrong position would move a sphere by its overlap,
/// ~1e-6 m). Continuations of the same checkpoint on 1 and 3 ranks are the
/// same bits.
#[test]
fn engine_checkpoints_load_under_the_decomposition_and_back() {
    engine_and_decomposition_checkpoints(scene());
}

/// The same with Gear5 and friction (the spins' derivatives go both ways).
#[test]
fn gear5_friction_engine_checkpoints_load_under_the_decomposition_and_back() {
    let mut setup = scene();
    setup.contact = ContactModel::elastic(NormalLaw::Hertz);
    setup.integration.scheme = dembound_scene::setup::Scheme::Gear5;
    setup.friction = Some(dembound_scene::setup::FrictionSetup::uniform(
        dembound_physics::contact::tangential::FrictionModel {
            tangential: dembound_physics::contact::tangential::TangentialKind::Mindlin,
            friction: 0.5,
            rolling_friction: 0.05,
        },
    ));
    engine_and_decomposition_checkpoints(setup);
}

fn engine_and_decomposition_checkpoints(setup: SceneSetup) {
    let mut sim = Simulation::new(setup.clone(), 1).expect("valid scene");
    sim.step(1500);
    let serial = through_file(&sim.checkpoint());
    sim.step(300);
    let one = run(&setup, 1, None, Some(&serial), 300);
    let three = run(&setup, 3, Some([1, 3, 1]), Some(&serial), 300);
    assert_eq!(one.checkpoint, three.checkpoint);
    let worst = |x: &[[f64; 3]], y: &[[f64; 3]]| {
        x.iter()
            .zip(y)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0f64, f64::max)
    };
    let d = worst(&one.checkpoint.position, &sim.positions());
    assert!(d < 1e-12, "{d}");
    // And back: the decomposition's checkpoint in the engine.
    let mut back = Simulation::restore(setup.clone(), &through_file(&one.checkpoint), 1)
        .expect("the engine loads it");
    assert_eq!(back.steps_done(), 1800);
    back.step(300);
    sim.step(300);
    let d = worst(&back.positions(), &sim.positions());
    assert!(d < 1e-12, "{d}");
}

/// A checkpoint of another scene is refused on every rank with the reason.
#[test]
fn checkpoint_of_another_scene_is_refused() {
    let setup = scene();
    let other = common::lattice_drop(6, 7, 2.0e-6, 10);
    let c = Simulation::new(other, 1).expect("valid").checkpoint();
    let handles: Vec<_> = ThreadTransport::group(2)
        .into_iter()
        .map(|t| {
            let (setup, c) = (setup.clone(), c.clone());
            std::thread::spawn(move || {
                DistributedSimulation::restore(&setup, &c, 1, None, t)
                    .err()
                    .map(|e| e.to_string())
            })
        })
        .collect();
    for h in handles {
        let e = h.join().expect("rank").expect("refused");
        assert!(e.contains("252 bodies, the scene 288"), "{e}");
    }
}
