//! Tests of the pair loop with friction ([`super::add_pair_forces`]):
//! the batched kernels against the row-by-row loop, and the force pass's
//! tallies against the observation pass.

use std::sync::atomic::Ordering;

use dembound_physics::contact::{ContactHistory, ContactModel, NormalLaw};

use super::super::row_laws::{HertzMindlin, OneLaw};
use super::{add_pair_forces, add_pair_forces_tallied, PairForceInput, ROW_BY_ROW};
use crate::dynamics::friction::PairShear;
use crate::dynamics::friction_observables::observe;
use crate::dynamics::friction_observables::tests::scene;
use crate::setup::{SceneSetup, TimeStep};
use crate::Simulation;

/// Held by the tests that set [`ROW_BY_ROW`] (a global flag, and the
/// harness runs tests on parallel threads): one test's row-by-row run
/// must not switch the other's batched run, or its stepping, to rows.
static ROW_BY_ROW_USERS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The scenes the batched loop is checked on: `friction_observables`'s
/// settling bed (two radii, so two body classes: the class table; Tsuji
/// damping; rolling springs); the same with Walton–Braun's law (contact
/// histories); and the bed of one radius with undamped Hertz (one class:
/// the kernel without per-contact dispatch, `row_laws::OneLaw`), with and
/// without rolling springs. Returns the scene and whether it takes the
/// one-law kernel.
fn settings() -> Vec<(&'static str, SceneSetup, bool)> {
    let tsuji = scene();
    let mut walton_braun = scene();
    // Walton–Braun's linear spring is soft: a step well inside its
    // contact time (~50 µs).
    walton_braun.contact = ContactModel::elastic(NormalLaw::WaltonBraun { restitution: 0.5 });
    walton_braun.integration.time_step = TimeStep::Fixed(2.0e-6);
    let mut one = scene();
    for s in &mut one.spheres {
        s.radius = 0.5e-3;
    }
    one.contact = ContactModel::elastic(NormalLaw::Hertz);
    // Undamped: a step well inside the Hertz contact time of these
    // impacts (~0.1 ms at 5 cm/s).
    one.integration.time_step = TimeStep::Fixed(5.0e-6);
    let mut one_sliding = one.clone();
    let friction = one_sliding.friction.as_mut().unwrap();
    friction.model.rolling_friction = 0.0;
    friction.walls = vec![Some((0.5, 0.0)); 6];
    vec![
        ("tsuji, two classes", tsuji, false),
        ("walton-braun", walton_braun, false),
        ("hertz, one class, rolling", one, true),
        ("hertz, one class", one_sliding, true),
    ]
}

/// Whether the simulation's pair loop takes the one-law kernel (the
/// conditions of `add_pair_forces_then`).
fn one_law(sim: &Simulation) -> bool {
    let w = &sim.world;
    let friction = w.friction.as_ref().unwrap();
    friction.classes == 1
        && !w.laws.history
        && OneLaw::<HertzMindlin>::new(&friction.pairs[0]).is_some()
}

/// What one pair loop leaves: forces and torques by body, the springs,
/// the contact histories by main entry.
type LoopResult = (Vec<[f64; 3]>, Vec<[f64; 3]>, PairShear, Vec<ContactHistory>);

/// The pair loop with friction once on `sim`'s state, batched or (`rows`)
/// row by row, from copies of its springs and histories: the forces,
/// torques, springs and contact histories it leaves. Hold
/// [`ROW_BY_ROW_USERS`] while calling it.
fn pair_loop(sim: &Simulation, rows: bool) -> LoopResult {
    let w = &sim.world;
    let n = w.bodies.len();
    let input = PairForceInput {
        bodies: &w.bodies,
        ghosts: &w.ghosts,
        list: &w.list,
        laws: &w.laws,
        friction: w.friction.as_ref().unwrap(),
        dt: sim.dt(),
    };
    let (mut histories, mut shear) = (w.histories.clone(), w.shear.clone());
    let (mut force, mut torque) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
    ROW_BY_ROW.store(rows, Ordering::Relaxed);
    add_pair_forces(
        &input,
        &mut histories,
        &mut shear,
        &mut force,
        &mut torque,
        &sim.workers,
    );
    ROW_BY_ROW.store(false, Ordering::Relaxed);
    (force, torque, shear, histories.main)
}

/// The batched pair loop (two passes, stages) gives the row-by-row
/// loop's forces, torques, springs and histories bit for bit (the
/// row-by-row loop is the reference: each contact evaluated whole, in
/// list order, its law read from the class table and dispatched on its
/// variants), along a run of impacts, sliding and sticking, with and
/// without rolling springs and contact histories, through the class
/// table and through the one-law kernel.
#[test]
fn batched_pairs_equal_row_by_row_bit_for_bit() {
    let _flag = ROW_BY_ROW_USERS.lock().unwrap_or_else(|e| e.into_inner());
    for (setting, setup, one) in settings() {
        let mut sim = Simulation::new(setup, 1).unwrap();
        assert_eq!(one_law(&sim), one, "{setting}");
        let mut touching = 0;
        for _ in 0..30 {
            sim.step(100);
            let run = |rows: bool| {
                let (force, torque, shear, histories) = pair_loop(&sim, rows);
                let bits = |v: &[[f64; 3]]| -> Vec<u64> {
                    v.iter().flatten().map(|x| x.to_bits()).collect()
                };
                (
                    bits(&force),
                    bits(&torque),
                    bits(&shear.main),
                    bits(&shear.roll_main),
                    histories,
                )
            };
            let (batched, rows) = (run(false), run(true));
            assert!(batched == rows, "{setting}");
            touching += batched.2.iter().filter(|&&x| x != 0).count();
        }
        // Loaded springs were compared: the settling bed has hundreds
        // of loaded components per check by the end (Walton–Braun's
        // shorter run, tens; 833 in all when written).
        assert!(touching > 500, "{setting}: {touching}");
    }
}

/// The force pass's tally, summed by the observation pass, gives what
/// the observation pass computes from the pairs itself, bit for bit
/// (the reference visits every listed pair again at the state the
/// force pass left: the springs and histories it moved), batched and
/// row by row, with and without contact histories, through the class
/// table and the one-law kernel, on 1 and 2 threads.
#[test]
fn tally_equals_the_observation_pass_bit_for_bit() {
    let _flag = ROW_BY_ROW_USERS.lock().unwrap_or_else(|e| e.into_inner());
    let all = settings();
    let runs = all
        .iter()
        .map(|s| (s, 1))
        .chain([(&all[0], 2), (&all[3], 2)]);
    for ((setting, setup, _), threads) in runs {
        let mut sim = Simulation::new(setup.clone(), threads).unwrap();
        let mut compared = 0;
        for _ in 0..30 {
            sim.step(100);
            let w = &sim.world;
            let n = w.bodies.len();
            let friction = w.friction.as_ref().unwrap();
            let input = PairForceInput {
                bodies: &w.bodies,
                ghosts: &w.ghosts,
                list: &w.list,
                laws: &w.laws,
                friction,
                dt: sim.dt(),
            };
            for rows in [false, true] {
                let (mut histories, mut shear) = (w.histories.clone(), w.shear.clone());
                let (mut force, mut torque) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
                let mut tally = Vec::new();
                ROW_BY_ROW.store(rows, Ordering::Relaxed);
                let made = add_pair_forces_tallied(
                    &input,
                    &mut histories,
                    &mut shear,
                    &mut force,
                    &mut torque,
                    &sim.workers,
                    &mut tally,
                    None,
                );
                ROW_BY_ROW.store(false, Ordering::Relaxed);
                assert!(made && tally.len() == n);
                let observe = |tally| {
                    observe(
                        &w.bodies,
                        &w.list,
                        &histories,
                        friction,
                        &shear,
                        &w.surfaces,
                        &w.wall_contacts,
                        &sim.workers,
                        tally,
                    )
                    .expect("the fast path applies: class table, no extra pairs")
                };
                let (tallied, passes) = (observe(Some(&tally)), observe(None));
                assert_eq!(
                    (tallied.particle_contacts, tallied.boundary_contacts),
                    (passes.particle_contacts, passes.boundary_contacts)
                );
                assert_eq!(tallied.pair_energy.to_bits(), passes.pair_energy.to_bits());
                assert_eq!(
                    tallied.spring_energy.to_bits(),
                    passes.spring_energy.to_bits()
                );
                if passes.particle_contacts > 0 && passes.spring_energy > 0.0 {
                    compared += 1;
                }
            }
        }
        // States with touching pairs and loaded springs were compared
        // (of 60 a setting: 38 in Walton–Braun's shorter run when
        // written, more in the others).
        assert!(compared > 20, "{setting}, {threads} threads: {compared}");
    }
}

/// Pairs with coincident centres (r = 0: no direction to push along,
/// not touching for `touching_lazy`) in the batched pass, whose first
/// pass takes every entry's root and division (r = 0, 1/r = ∞) and masks
/// them after: the batched loop gives the row-by-row loop's forces,
/// torques, springs and histories bit for bit, all finite, with the
/// coincident pairs' springs relaxed to +0 (as a pair apart's), through
/// the class table and the one-law kernel. Partners are put on their
/// row's body (first, fourth and last entries of the rows of 4 or more:
/// within the four-lane groups of the spring pass and after them).
#[test]
fn coincident_centres_in_a_batch_give_no_force() {
    let _flag = ROW_BY_ROW_USERS.lock().unwrap_or_else(|e| e.into_inner());
    for (setting, setup, _) in settings() {
        let mut sim = Simulation::new(setup, 1).unwrap();
        sim.step(300);
        let w = &mut sim.world;
        let n = w.bodies.len();
        let (mut placed, mut moved) = (Vec::new(), vec![false; n]);
        for i in 0..n {
            let (s, e) = (w.list.start[i] as usize, w.list.start[i + 1] as usize);
            if e - s < 4 || moved[i] {
                continue;
            }
            for k in [s, s + 3, e - 1] {
                let j = w.list.j[k] as usize;
                if !moved[j] {
                    w.bodies.position[j] = w.bodies.position[i];
                    moved[j] = true;
                    moved[i] = true;
                    placed.push(k);
                }
            }
        }
        assert!(placed.len() > 10, "{setting}: {}", placed.len());
        let (batched, rows) = (pair_loop(&sim, false), pair_loop(&sim, true));
        let bits =
            |v: &[[f64; 3]]| -> Vec<u64> { v.iter().flatten().map(|x| x.to_bits()).collect() };
        assert!(bits(&batched.0) == bits(&rows.0), "{setting}: forces");
        assert!(bits(&batched.1) == bits(&rows.1), "{setting}: torques");
        assert!(
            bits(&batched.2.main) == bits(&rows.2.main),
            "{setting}: springs"
        );
        assert!(batched.3 == rows.3, "{setting}: histories");
        let finite = |v: &[[f64; 3]]| v.iter().flatten().all(|x| x.is_finite());
        assert!(finite(&batched.0) && finite(&batched.1) && finite(&batched.2.main));
        for &k in &placed {
            assert_eq!(
                batched.2.main[k].map(f64::to_bits),
                [0; 3],
                "{setting}: entry {k}"
            );
        }
    }
}

/// Under `contact.spring_rotation = "project"` the pair loop projects
/// every spring (LIGGGHTS's rotation): the batched kernels turn springs
/// by the rescale only, so such a scene runs row by row, each contact
/// through `FrictionPair::rotate_spring`. Checked on the settling beds of
/// [`settings`] (the class table and the one-law scene): the loop gives
/// the row-by-row loop's forces, torques and springs bit for bit (a
/// batch that rescaled would not: the beds' normals turn), and the bed's
/// state after the run is not the rescaled bed's (the rotation was
/// applied). How far apart is not asserted: the two rotations differ by
/// θ²/2 of the spring a step (θ the normal's turn, second order), but the
/// settling bed is chaotic and grows any difference (measured 4.9e-5 m on
/// the two-class bed after 3000 steps).
#[test]
fn projected_springs_run_row_by_row_and_change_the_bed() {
    use dembound_physics::contact::tangential::SpringRotation;
    let _flag = ROW_BY_ROW_USERS.lock().unwrap_or_else(|e| e.into_inner());
    for (setting, setup, _) in [&settings()[0], &settings()[2]] {
        let mut projected = setup.clone();
        projected.friction.as_mut().unwrap().spring_rotation = SpringRotation::Project;
        let mut sim = Simulation::new(projected, 1).unwrap();
        let mut rescaled = Simulation::new(setup.clone(), 1).unwrap();
        let mut loaded = 0;
        for _ in 0..30 {
            sim.step(100);
            rescaled.step(100);
            let bits = |r: &LoopResult| -> Vec<u64> {
                r.0.iter()
                    .chain(&r.1)
                    .chain(&r.2.main)
                    .flatten()
                    .map(|x| x.to_bits())
                    .collect()
            };
            let (batched, rows) = (pair_loop(&sim, false), pair_loop(&sim, true));
            assert!(bits(&batched) == bits(&rows), "{setting}");
            loaded += batched
                .2
                .main
                .iter()
                .flatten()
                .filter(|&&x| x != 0.0)
                .count();
        }
        assert!(loaded > 500, "{setting}: {loaded}");
        // The states part.
        let (a, b) = (sim.positions(), rescaled.positions());
        let apart = a
            .iter()
            .zip(&b)
            .flat_map(|(p, q)| (0..3).map(move |k| (p[k] - q[k]).abs()))
            .fold(0.0f64, f64::max);
        assert!(apart > 0.0, "{setting}: {apart}");
    }
}
