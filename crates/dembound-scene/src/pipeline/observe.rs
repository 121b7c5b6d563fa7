//! Stage "observe" for the global observables: energies, contact counts,
//! wall forces, as one [`Observation`]. Computed once here; what a
//! process counts of the contacts, where its boundary-particle walls'
//! forces come from and the sum over processes are its
//! [`ObserveHooks`] (one process: everything, the bodies' forces, no
//! sum; a rank of a decomposed scene: `comm::distributed`).

use crate::bodies::NO_GROUP;
use crate::dynamics::friction_observables::{self, ContactObservables};
use crate::dynamics::{contacts, friction, spring_energy, walls};
use crate::parallel::Workers;
use crate::Observation;

use super::{Local, WallKind, World};

/// What differs between one process and one rank when observing.
pub(crate) trait ObserveHooks {
    /// The observables of the contacts this process counts (each contact
    /// counted by one process), summed in the order this kind of run fixes.
    fn contacts(&self, world: &World, workers: &Workers) -> ContactObservables;
    /// This process's share of the force on each wall of boundary
    /// particles (file order; the planes' entries are not read), N.
    fn particle_wall_forces(&self, world: &World) -> Vec<[f64; 3]>;
    /// Element-wise sums over the processes.
    fn sum(&self, values: Vec<f64>) -> Vec<f64>;
}

impl ObserveHooks for Local {
    fn contacts(&self, world: &World, workers: &Workers) -> ContactObservables {
        // With friction, one pass gives what the passes give, with the
        // same bits (`friction_observables`).
        world
            .friction
            .as_ref()
            .and_then(|table| {
                friction_observables::observe(
                    &world.bodies,
                    &world.list,
                    &world.histories,
                    table,
                    &world.shear,
                    &world.surfaces,
                    &world.wall_contacts,
                    workers,
                )
            })
            .unwrap_or_else(|| contact_passes(world, workers))
    }

    /// The boundary particles' forces, their spheres in input order.
    fn particle_wall_forces(&self, world: &World) -> Vec<[f64; 3]> {
        let mut wall_forces = vec![[0.0; 3]; world.walls.len()];
        if world
            .walls
            .iter()
            .any(|k| !matches!(k, WallKind::Surface(_)))
        {
            let force_in = world.bodies.in_input_order(&world.bodies.force);
            let group_in = world.bodies.in_input_order(&world.bodies.group);
            for (k, g) in group_in.iter().enumerate() {
                if *g != NO_GROUP {
                    let f = &mut wall_forces[*g as usize];
                    for a in 0..3 {
                        f[a] += force_in[k][a];
                    }
                }
            }
        }
        wall_forces
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        values
    }
}

/// Every global observable at the current state; `initial_energy`: the
/// mechanical energy at the start, J (the dissipated energy's reference).
pub(crate) fn observation(
    world: &World,
    workers: &Workers,
    initial_energy: f64,
    hooks: &impl ObserveHooks,
) -> Observation {
    let kinetic = kinetic_energy(world, workers);
    let potential = potential_energy(world, workers);
    let c = hooks.contacts(world, workers);
    let particle_walls = hooks.particle_wall_forces(world);
    // Counts as f64: exact far beyond any scene's.
    let mut v = vec![
        kinetic,
        potential,
        c.pair_energy + c.plane_energy + c.spring_energy,
        c.particle_contacts as f64,
        (c.boundary_contacts + c.plane_contacts) as f64,
    ];
    for (wi, kind) in world.walls.iter().enumerate() {
        let f = match kind {
            WallKind::Surface(p) => {
                let mut f = c.plane_forces[*p];
                if let Some(t) = c.plane_tangential.get(*p) {
                    for a in 0..3 {
                        f[a] += t[a];
                    }
                }
                f
            }
            WallKind::Particles => particle_walls.get(wi).copied().unwrap_or([0.0; 3]),
        };
        v.extend_from_slice(&f);
    }
    let s = hooks.sum(v);
    let wall_forces = (0..world.walls.len())
        .map(|k| [s[5 + 3 * k], s[6 + 3 * k], s[7 + 3 * k]])
        .collect();
    Observation {
        step: world.steps_done,
        time: world.time(),
        kinetic_energy: s[0],
        elastic_energy: s[2],
        potential_energy: s[1],
        dissipated_energy: initial_energy - (s[0] + s[2] + s[1]),
        particle_contacts: s[3].round() as usize,
        wall_contacts: s[4].round() as usize,
        wall_forces,
    }
}

/// Σ ½ m v² over free bodies, plus Σ ½ I ω² with friction, J.
pub(crate) fn kinetic_energy(world: &World, workers: &Workers) -> f64 {
    let b = &world.bodies;
    let spin = world.friction.is_some();
    let [e] = workers.sum(b.len(), |k| {
        if b.fixed[k] {
            return [0.0];
        }
        let v = b.velocity[k];
        let mut e = 0.5 * b.mass[k] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if spin {
            let w = b.angular_velocity[k];
            e += 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / b.inverse_inertia[k];
        }
        [e]
    });
    e
}

/// −Σ m g·x over free bodies, J.
pub(crate) fn potential_energy(world: &World, workers: &Workers) -> f64 {
    let b = &world.bodies;
    let g = world.gravity;
    let [e] = workers.sum(b.len(), |k| {
        if b.fixed[k] {
            return [0.0];
        }
        let x = b.position[k];
        [-b.mass[k] * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])]
    });
    e
}

/// The contact observables pass by pass: pair counts and energy, plane
/// forces, counts and energy, plane tangential forces, spring energy.
pub(crate) fn contact_passes(world: &World, workers: &Workers) -> ContactObservables {
    let w = world;
    let (pc, wc, pe) = contacts::pair_observables(
        &w.bodies,
        &w.ghosts,
        &w.list,
        &w.histories,
        &w.laws,
        workers,
    );
    let (plane_forces, plane_contacts, plane_energy) =
        walls::plane_observables(&w.bodies, &w.surfaces, &w.wall_contacts, &w.laws, workers);
    let tangential = match &w.friction {
        Some(table) => friction::plane_tangential_forces(
            &w.bodies,
            &w.surfaces,
            &w.laws,
            table,
            &w.wall_contacts,
        ),
        None => Vec::new(),
    };
    let springs = match &w.friction {
        Some(table) => spring_energy::spring_energy(
            &w.bodies,
            &w.ghosts,
            &w.list,
            &w.laws,
            table,
            &w.shear,
            &w.surfaces,
            &w.wall_contacts,
            workers,
        ),
        None => 0.0,
    };
    ContactObservables {
        particle_contacts: pc,
        boundary_contacts: wc,
        pair_energy: pe,
        plane_forces,
        plane_contacts,
        plane_energy,
        plane_tangential: tangential,
        spring_energy: springs,
    }
}
