//! A run continued from a checkpoint is bit-identical to the run that was
//! never stopped (Verlet and Gear5, with contacts, walls, ghosts and the
//! collision log).

mod common;

use dembound_physics::contact::{ContactModel, NormalLaw};
use dembound_scene::setup::Scheme;
use dembound_scene::{SceneSetup, Simulation};

fn state(sim: &Simulation) -> String {
    format!(
        "{:?} {:?} {:?} {:?} {:?}",
        sim.positions(),
        sim.velocities(),
        sim.forces(),
        sim.observe(),
        sim.collisions()
    )
}

fn check(setup: SceneSetup, first: u64, second: u64) {
    let mut straight = Simulation::new(setup.clone(), 1).unwrap();
    straight.step(first + second);
    let mut a = Simulation::new(setup.clone(), 2).unwrap();
    a.step(first);
    let cp = a.checkpoint();
    let mut b = Simulation::restore(setup, &cp, 1).unwrap();
    assert_eq!(b.steps_done(), first);
    b.step(second);
    assert_eq!(state(&straight), state(&b));
}

#[test]
fn restart_continues_bit_for_bit() {
    let mut lattice = common::lattice_drop(8, 10, 2.0e-5, 0);
    lattice.collisions = true;
    check(lattice.clone(), 350, 250);
    lattice.integration.scheme = Scheme::Gear5;
    check(lattice, 350, 250);
    let mut gas = common::periodic_gas(4, 0.05, 0.5, 3);
    gas.collisions = true;
    check(gas.clone(), 500, 500);
    // A hysteretic law: per-pair histories stored, carried over list
    // rebuilds and through the checkpoint.
    gas.contact = ContactModel::elastic(NormalLaw::WaltonBraun { restitution: 0.5 });
    check(gas, 500, 500);
}

#[test]
fn checkpoint_of_another_scene_is_refused() {
    let a = common::lattice_drop(4, 4, 2.0e-5, 0);
    let b = common::lattice_drop(4, 5, 2.0e-5, 0);
    let cp = Simulation::new(a, 1).unwrap().checkpoint();
    assert!(Simulation::restore(b, &cp, 1).is_err());
}
