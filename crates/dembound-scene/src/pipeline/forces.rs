//! Stage "forces": gravity and the walls per body (and torques, with
//! friction), then the pair forces, as one process sums them.

use super::{Pipeline, World};
use crate::dynamics::contacts;
use crate::dynamics::friction;
use crate::dynamics::walls;
use crate::parallel::{SharedMut, Workers};

impl Pipeline {
    /// Stage "forces": gravity and plane walls per body, then the pairs.
    /// With friction the tangential springs do not move (LAMMPS's setup):
    /// used at the start only (Gear5 with friction steps with the body
    /// and pair force stages over Δt).
    pub fn forces(&mut self, world: &mut World, workers: &Workers) {
        self.body_forces(world, workers, 0.0);
        self.pair_forces(world, workers, 0.0);
    }

    /// Gravity and plane walls: sets each body's force (and torque, with
    /// friction; the springs move by `dt` s of slip).
    pub(crate) fn body_forces(&mut self, world: &mut World, workers: &Workers, dt: f64) {
        world.bodies.force.resize(world.bodies.len(), [0.0; 3]);
        if world.friction.is_some() {
            self.wall_tally_valid = false;
            self.body_forces_friction(world, workers, dt);
            return;
        }
        let mut force = std::mem::take(&mut world.bodies.force);
        // The series row's tally of the walls, when this pass may be the
        // last before it (`Pipeline::wall_tallying`).
        self.wall_tally_valid = self.wall_tallying;
        walls::start_forces(
            &world.bodies,
            &world.surfaces,
            &mut world.wall_contacts,
            &world.laws,
            world.gravity,
            &mut force,
            workers,
            self.wall_tallying.then_some(&mut self.wall_energy),
        );
        world.bodies.force = force;
    }

    /// [`Self::body_forces`] with friction: forces and torques.
    fn body_forces_friction(&mut self, world: &mut World, workers: &Workers, dt: f64) {
        let n = world.bodies.len();
        world.bodies.torque.resize(n, [0.0; 3]);
        let mut force = std::mem::take(&mut world.bodies.force);
        let mut torque = std::mem::take(&mut world.bodies.torque);
        let (f, t) = (SharedMut::new(&mut force), SharedMut::new(&mut torque));
        let walls = world.wall_contacts.shared();
        if let Some(table) = world.friction.as_ref() {
            let input = friction::BodyForceInput {
                bodies: &world.bodies,
                surfaces: &world.surfaces,
                laws: &world.laws,
                friction: table,
                gravity: world.gravity,
                step: world.steps_done + u64::from(dt > 0.0),
                dt,
            };
            let b = &world.bodies;
            workers.run_bodies(n, crate::parallel::BODY_CHUNK, |c| {
                let chunk = crate::parallel::BODY_CHUNK;
                for i in c * chunk..((c + 1) * chunk).min(n) {
                    // SAFETY: chunks are disjoint ranges of bodies.
                    unsafe {
                        let (fi, ti) = friction::body_force(
                            &input,
                            i,
                            (b.position[i], b.velocity[i], b.angular_velocity[i]),
                            &walls,
                        );
                        *f.at(i) = fi;
                        *t.at(i) = ti;
                    }
                }
            });
        }
        world.bodies.force = force;
        world.bodies.torque = torque;
    }

    /// Adds the pair forces (and torques, with friction; the springs move
    /// by `dt` s of slip).
    pub(crate) fn pair_forces(&mut self, world: &mut World, workers: &Workers, dt: f64) {
        if let Some(table) = world.friction.as_ref() {
            let mut force = std::mem::take(&mut world.bodies.force);
            let mut torque = std::mem::take(&mut world.bodies.torque);
            let input = friction::PairForceInput {
                bodies: &world.bodies,
                ghosts: &world.ghosts,
                list: &world.list,
                laws: &world.laws,
                friction: table,
                dt,
            };
            if std::mem::take(&mut self.tallying) {
                // The observables' tally of this state (`Pipeline::steps`
                // marks the step once the state is complete).
                let made = friction::add_pair_forces_tallied(
                    &input,
                    &mut world.histories,
                    &mut world.shear,
                    &mut force,
                    &mut torque,
                    workers,
                    &mut self.pair_tally,
                    self.entry_tally.as_mut(),
                );
                self.tally_step = made.then_some(world.steps_done);
            } else {
                friction::add_pair_forces(
                    &input,
                    &mut world.histories,
                    &mut world.shear,
                    &mut force,
                    &mut torque,
                    workers,
                );
            }
            world.bodies.force = force;
            world.bodies.torque = torque;
            return;
        }
        let mut force = std::mem::take(&mut world.bodies.force);
        if std::mem::take(&mut self.tallying) {
            let made = contacts::add_pair_forces_tallied(
                &world.bodies,
                &world.ghosts,
                &world.list,
                &mut world.histories,
                &world.laws,
                &mut force,
                workers,
                &mut self.plain_tally,
                self.entry_tally.as_mut(),
            );
            self.tally_step = made.then_some(world.steps_done);
        } else {
            contacts::add_pair_forces(
                &world.bodies,
                &world.ghosts,
                &world.list,
                &mut world.histories,
                &world.laws,
                &mut force,
                workers,
            );
        }
        world.bodies.force = force;
    }
}
