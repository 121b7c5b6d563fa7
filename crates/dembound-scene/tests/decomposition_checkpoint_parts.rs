//! Checkpoints written in parts, one a rank (`[parallel]
//! checkpoint_per_rank`, issue 31 item 5), with ranks as threads
//! (`comm::threads::ThreadTransport`, the same code as under MPI):
//!
//! - the parts of 2 ranks, through the file format and merged
//!   (`io::checkpoint_parts::merge`), are the gathered checkpoint of the
//!   same step, every field equal (the reference: the gathered
//!   checkpoint, which tests/decomposition_checkpoint.rs shows continues
//!   bit for bit);
//! - restarted from the parts on 2 ranks (each its own part), on 3 and on
//!   1 (parts shared out), 3000 more steps end in the same whole
//!   checkpoint (positions, velocities, forces, every history, spring,
//!   track and the collision log) as 6000 steps in one go.
//!
//! With Walton–Braun (every contact's largest overlap is state), friction
//! (spins, torques, pair and plane springs), Gear5 with friction (the
//! derivatives) and the collision log (tracks, the log so far).

mod common;

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, NormalLaw};
use dembound_scene::comm::threads::ThreadTransport;
use dembound_scene::comm::DistributedSimulation;
use dembound_scene::fingerprint::Fingerprint;
use dembound_scene::io::checkpoint::{self, CheckpointFile};
use dembound_scene::io::{checkpoint_parts, config};
use dembound_scene::setup::{FrictionSetup, Scheme};
use dembound_scene::{Checkpoint, SceneSetup};

/// What the ranks left: the gathered checkpoint (rank 0) and each rank's
/// part, in rank order.
struct End {
    gathered: Checkpoint,
    parts: Vec<Checkpoint>,
}

/// `ranks` thread-ranks on `grid`, from the start or from the parts
/// `from` (each rank those `parts_for_rank` gives it), then `steps` steps.
fn run(
    setup: &SceneSetup,
    ranks: usize,
    grid: Option<[usize; 3]>,
    from: Option<&[Checkpoint]>,
    steps: u64,
) -> End {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .enumerate()
        .map(|(rank, t)| {
            let setup = setup.clone();
            let from: Option<(Checkpoint, Vec<Checkpoint>)> = from.map(|parts| {
                let index = checkpoint_parts::shared_figures(&parts[0]);
                let mine = checkpoint_parts::parts_for_rank(rank, ranks, parts.len());
                (index, parts[mine].to_vec())
            });
            std::thread::spawn(move || {
                let mut d = match from {
                    Some((index, parts)) => {
                        DistributedSimulation::restore_parts(&setup, &index, parts, 1, grid, t)
                    }
                    None => DistributedSimulation::new(&setup, 1, grid, t),
                }
                .expect("valid scene and checkpoint");
                d.step(steps);
                let gathered = d.checkpoint().expect("checkpointed");
                (gathered, d.checkpoint_part())
            })
        })
        .collect();
    let mut gathered = None;
    let mut parts = Vec::new();
    for h in handles {
        let (c, part) = h.join().expect("rank finished");
        gathered = gathered.or(c);
        parts.push(part);
    }
    End {
        gathered: gathered.expect("rank 0 gathers"),
        parts,
    }
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

/// The small lattice drop of tests/decomposition_checkpoint.rs: Walton–
/// Braun, random velocities up to 0.3 m/s per axis so that spheres cross
/// the cuts while in contact.
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

fn friction() -> Option<FrictionSetup> {
    Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.5,
        rolling_friction: 0.05,
    }))
}

/// The module's claims for `setup`; returns the straight run's end.
fn parts_restart_bit_for_bit(setup: &SceneSetup) -> Checkpoint {
    let straight = run(setup, 2, Some([2, 1, 1]), None, 6000);
    let half = run(setup, 2, Some([2, 1, 1]), None, 3000);
    let parts: Vec<Checkpoint> = half.parts.iter().map(through_file).collect();
    let n = setup.spheres.len();
    // Each part holds some of the bodies, together all of them once.
    let counts: Vec<usize> = parts.iter().map(|p| p.order.len()).collect();
    assert!(counts.iter().all(|&k| k > 0 && k < n), "{counts:?}");
    assert_eq!(counts.iter().sum::<usize>(), n);
    // Merged, the parts are the gathered checkpoint.
    let index = checkpoint_parts::shared_figures(&parts[0]);
    let merged = checkpoint_parts::merge(&index, parts.clone(), &Fingerprint::of(setup));
    assert_eq!(merged, half.gathered, "merged parts against the gathered");
    let s = &straight.gathered;
    for (ranks, grid) in [(2, Some([2, 1, 1])), (3, Some([1, 3, 1])), (1, None)] {
        let resumed = run(setup, ranks, grid, Some(&parts), 3000);
        let r = &resumed.gathered;
        assert_eq!(r.steps_done, 6000);
        for k in 0..s.position.len() {
            assert_eq!(r.order[k], s.order[k]);
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
            }
        }
        assert_eq!(r.pair_histories, s.pair_histories, "{ranks} ranks");
        assert_eq!(r, s, "{ranks} ranks: the whole checkpoint");
    }
    straight.gathered
}

#[test]
fn walton_braun_parts_restart_on_two_three_and_one_bit_for_bit() {
    let c = parts_restart_bit_for_bit(&scene());
    // Histories are in play, with the pairs and the walls.
    assert!(c.pair_histories.len() > 10, "{}", c.pair_histories.len());
    assert!(!c.plane_histories.is_empty());
}

#[test]
fn friction_parts_restart_bit_for_bit() {
    let mut setup = scene();
    setup.friction = friction();
    let c = parts_restart_bit_for_bit(&setup);
    assert!(c.pair_shear.len() > 10, "{}", c.pair_shear.len());
    assert!(!c.plane_shear.is_empty());
}

#[test]
fn gear5_friction_parts_restart_bit_for_bit() {
    let mut setup = scene();
    setup.contact = ContactModel::elastic(NormalLaw::Hertz);
    setup.integration.scheme = Scheme::Gear5;
    setup.friction = friction();
    let c = parts_restart_bit_for_bit(&setup);
    assert_eq!(c.angular_higher.len(), c.position.len());
    assert!(c.higher.iter().any(|r| r != &[[0.0; 3]; 4]));
}

#[test]
fn collision_log_parts_restart_bit_for_bit() {
    let mut setup = scene();
    setup.collisions = true;
    let c = parts_restart_bit_for_bit(&setup);
    assert!(c.collisions.len() > 50, "{}", c.collisions.len());
    assert!(!c.pair_tracks.is_empty());
}

/// A part of another scene is refused by the rank reading it, named, on
/// every rank (no rank hangs): a sphere's radius differs.
#[test]
fn a_part_of_another_scene_is_refused_on_every_rank() {
    let setup = scene();
    let half = run(&setup, 2, Some([2, 1, 1]), None, 100);
    let mut other = setup.clone();
    let last = other.spheres.len() - 1;
    other
        .spheres
        .get_mut(last)
        .expect("the scene has spheres")
        .radius *= 1.01;
    let index = checkpoint_parts::shared_figures(&half.parts[0]);
    let handles: Vec<_> = ThreadTransport::group(2)
        .into_iter()
        .enumerate()
        .map(|(rank, t)| {
            let (other, index) = (other.clone(), index.clone());
            let parts = vec![half.parts[rank].clone()];
            std::thread::spawn(move || {
                DistributedSimulation::restore_parts(&other, &index, parts, 1, Some([2, 1, 1]), t)
                    .err()
                    .map(|e| e.to_string())
            })
        })
        .collect();
    let errors: Vec<String> = handles
        .into_iter()
        .map(|h| h.join().expect("rank finished").expect("refused"))
        .collect();
    let named = format!("sphere {last} (input order): radius differs");
    assert!(errors.iter().any(|e| e.contains(&named)), "{errors:?}");
}

/// The lattice drop of examples/scenes/lattice_drop.toml, 8 × 8 × 10
/// spheres in a 10.2 mm box, Walton–Braun, the lattice moving at
/// (0.2, 0.1, −0.3) m/s so that spheres cross the cuts while in contact,
/// with `more` settings: (the scene resolved whole, the same resolved in
/// parts for `ranks`).
fn lattice_scene(
    more: &[&str],
    ranks: usize,
) -> (
    dembound_scene::io::resolve::ResolvedScene,
    (
        dembound_scene::io::resolve::ResolvedScene,
        Vec<dembound_scene::io::resolve::PartGroup>,
    ),
) {
    use dembound_scene::io::resolve;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/scenes/lattice_drop.toml");
    let sets: Vec<String> = [
        "particles.0.lattice.counts=[8,8,10]",
        "particles.0.lattice.velocity=[0.2,0.1,-0.3]",
        "domain.upper=[0.0102,0.0102,0.03]",
        "wall.1.plane.point=[0.0102,0.0,0.0]",
        "wall.3.plane.point=[0.0,0.0102,0.0]",
        "contact.law=\"walton-braun\"",
        "contact.restitution=0.5",
        "integration.steps=3000",
    ]
    .iter()
    .chain(more)
    .map(|s| s.to_string())
    .collect();
    let file = config::read(&path, &sets).expect("the example scene reads");
    let base = path.parent().expect("a directory");
    let whole = resolve::resolve(&file, base).expect("resolves");
    let parts = resolve::resolve_parts(&file, base, ranks)
        .expect("resolves")
        .expect("lattice and planes: made in parts");
    (whole, parts)
}

/// `ranks` thread-ranks continue the parts `from` (each rank those
/// `parts_for_rank` gives it) of the scene `more` describes, built whole
/// (every rank the whole sphere list, [`DistributedSimulation::restore_parts`])
/// or in parts ([`DistributedSimulation::restore_parts_in_parts`]), then
/// run `steps` steps: the gathered checkpoint, or each rank's refusal.
fn continue_lattice(
    more: &[&str],
    ranks: usize,
    grid: [usize; 3],
    from: &[Checkpoint],
    in_parts: bool,
    steps: u64,
) -> Result<Checkpoint, Vec<String>> {
    let handles: Vec<_> = ThreadTransport::group(ranks)
        .into_iter()
        .enumerate()
        .map(|(rank, t)| {
            let more: Vec<String> = more.iter().map(|s| s.to_string()).collect();
            let index = checkpoint_parts::shared_figures(&from[0]);
            let parts = from[checkpoint_parts::parts_for_rank(rank, ranks, from.len())].to_vec();
            std::thread::spawn(move || {
                let more: Vec<&str> = more.iter().map(String::as_str).collect();
                let (whole, (resolved, groups)) = lattice_scene(&more, ranks);
                let grid = Some(grid);
                let built = if in_parts {
                    let label = dembound_scene::io::labels::label(
                        &resolved.file,
                        &resolved.groups,
                        &resolved.wall_bodies,
                    );
                    DistributedSimulation::restore_parts_in_parts(
                        &resolved.setup,
                        &groups,
                        &label,
                        &index,
                        parts,
                        1,
                        grid,
                        t,
                    )
                    .map(|made| made.expect("covered by the part-wise input").0)
                } else {
                    DistributedSimulation::restore_parts(&whole.setup, &index, parts, 1, grid, t)
                };
                let mut d = built.map_err(|e| e.to_string())?;
                d.step(steps);
                Ok(d.checkpoint().expect("checkpointed"))
            })
        })
        .collect();
    let mut gathered = None;
    let mut errors = Vec::new();
    for h in handles {
        match h.join().expect("rank finished") {
            Ok(c) => gathered = gathered.or(c),
            Err(e) => errors.push(e),
        }
    }
    match gathered {
        Some(c) if errors.is_empty() => Ok(c),
        _ => Err(errors),
    }
}

/// Issue 31 item 5: continuing parts with each rank making only its part
/// of the scene's spheres (`restore_parts_in_parts`: no rank holds the
/// whole sphere list) ends, 1000 steps after a checkpoint at step 2000
/// (contacts from the first steps on: the lattice moves into the walls), in the same gathered checkpoint, every
/// field, as continuing them with the whole sphere list on every rank
/// (`restore_parts`, which the tests above show continues bit for bit),
/// on the writing rank count and on another. A checkpoint of another
/// scene is refused on every rank with the same errors, rank by rank, as
/// with the whole list: a sphere's radius differs (found where its record
/// arrives), fewer spheres (a part's ids out of range, found before the
/// build).
#[test]
fn parts_restart_in_parts_is_the_whole_lists_restart() {
    let (whole, _) = lattice_scene(&[], 2);
    let half = run(&whole.setup, 2, Some([2, 1, 1]), None, 2000);
    let parts: Vec<Checkpoint> = half.parts.iter().map(through_file).collect();
    assert!(half.gathered.pair_histories.len() > 10);
    for (ranks, grid) in [(2, [2, 1, 1]), (3, [1, 3, 1])] {
        let in_whole = continue_lattice(&[], ranks, grid, &parts, false, 1000).expect("continues");
        let in_parts = continue_lattice(&[], ranks, grid, &parts, true, 1000).expect("continues");
        assert_eq!(in_whole.steps_done, 3000);
        assert_eq!(in_parts, in_whole, "{ranks} ranks: the whole checkpoint");
    }
    for (other, named) in [
        (
            "particles.0.lattice.radius=0.5005e-3",
            "(input order): radius differs",
        ),
        (
            "particles.0.lattice.counts=[8,8,9]",
            "body order has a bad or repeated id",
        ),
    ] {
        for ranks in [2, 3] {
            let grid = if ranks == 2 { [2, 1, 1] } else { [1, 3, 1] };
            let refused = |in_parts| {
                continue_lattice(&[other], ranks, grid, &parts, in_parts, 10).expect_err("refused")
            };
            let (in_whole, in_parts) = (refused(false), refused(true));
            assert_eq!(in_whole.len(), ranks, "{other}: every rank refuses");
            assert!(
                in_whole.iter().any(|e| e.contains(named)),
                "{other}: {in_whole:?}"
            );
            assert_eq!(in_parts, in_whole, "{other}, {ranks} ranks");
        }
    }
}
