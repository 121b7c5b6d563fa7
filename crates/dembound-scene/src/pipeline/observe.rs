//! Stage "observe" for the global observables: energies, contact counts,
//! wall loads, as one [`Observation`]. Computed once here; what a process
//! counts of the contacts, how the walls' loads are summed over the
//! processes (`wall_loads`) and the sum over processes are its
//! [`ObserveHooks`] (one process: everything, no sum; a rank of a
//! decomposed scene: `comm::distributed`).

use crate::dynamics::entry_tally::EntryTally;
use crate::dynamics::friction::PairTally;
use crate::dynamics::friction_observables::{self, ContactObservables};
use crate::dynamics::{contacts, spring_energy, walls};
use crate::parallel::Workers;
use crate::walls::WallLoad;
use crate::Observation;

use super::{wall_loads, Local, World};

/// What differs between one process and one rank when observing.
pub(crate) trait ObserveHooks {
    /// The observables of the contacts this process counts (each contact
    /// counted by one process), summed in the order this kind of run fixes.
    fn contacts(&self, world: &World, workers: &Workers) -> ContactObservables;
    /// The load on each wall (file order), over every process: the walls
    /// of `World::surfaces` from the force stage's records in an order
    /// that does not depend on the processes (`wall_loads`), the
    /// boundary-particle walls from their spheres.
    fn wall_loads(&self, world: &World, workers: &Workers) -> Vec<WallLoad>;
    /// Element-wise sums over the processes.
    fn sum(&self, values: Vec<f64>) -> Vec<f64>;
    /// This process's kinetic and potential energy ([`body_energies`]).
    fn body_energies(&self, world: &World, workers: &Workers) -> (f64, f64) {
        body_energies(world, workers)
    }
}

impl ObserveHooks for Local {
    fn contacts(&self, world: &World, workers: &Workers) -> ContactObservables {
        let none = Tallied {
            friction: None,
            plain: None,
            walls: None,
            energies: None,
            entries: None,
        };
        local_contacts(world, workers, &none)
    }

    fn wall_loads(&self, world: &World, workers: &Workers) -> Vec<WallLoad> {
        let records = wall_loads::surface_load_records_on(world, workers);
        let mut loads = wall_loads::sum_records(&records, world.walls.len());
        for (load, particles) in loads.iter_mut().zip(wall_loads::particle_wall_loads(world)) {
            if let Some(p) = particles {
                *load = p;
            }
        }
        loads
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        values
    }
}

/// One process's observation with what the last pair pass tallied of the
/// pairs at this state (`Pipeline::pair_tally`), when it did: the pairs
/// are not visited again.
pub(crate) struct Tallied<'a> {
    /// With friction (`friction::add_pair_forces_tallied`).
    pub friction: Option<&'a [PairTally]>,
    /// Without (`contacts::add_pair_forces_tallied`).
    pub plain: Option<&'a [contacts::PairTally]>,
    /// Without friction, each wall entry's elastic energy where touching,
    /// by the last body pass (`walls::add_wall_forces_tallied`).
    pub walls: Option<&'a [f64]>,
    /// The kinetic and potential energy summed by the last half kick
    /// ([`kick_then_energies`](super::closing_kick::kick_then_energies)).
    pub energies: Option<(f64, f64)>,
    /// Each main entry's terms, by the pass that made `friction` or
    /// `plain`, when a rank asked for them (`Pipeline::entry_tally`).
    pub entries: Option<&'a EntryTally>,
}

impl Tallied<'_> {
    /// Whether there is a tally of this state.
    #[cfg(test)]
    pub(crate) fn is_some(&self) -> bool {
        self.friction.is_some()
            || self.plain.is_some()
            || self.walls.is_some()
            || self.energies.is_some()
    }
}

impl ObserveHooks for Tallied<'_> {
    fn contacts(&self, world: &World, workers: &Workers) -> ContactObservables {
        local_contacts(world, workers, self)
    }

    fn wall_loads(&self, world: &World, workers: &Workers) -> Vec<WallLoad> {
        Local.wall_loads(world, workers)
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        values
    }

    fn body_energies(&self, world: &World, workers: &Workers) -> (f64, f64) {
        self.energies
            .unwrap_or_else(|| body_energies(world, workers))
    }
}

/// The contacts' observables on one process: with friction one pass (the
/// pairs from `tally` when given), with the same bits as the separate
/// passes (`friction_observables`).
fn local_contacts(world: &World, workers: &Workers, tally: &Tallied) -> ContactObservables {
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
                tally.friction,
            )
        })
        .unwrap_or_else(|| contact_passes(world, workers, tally.plain, tally.walls))
}

/// Every global observable at the current state; `initial_energy`: the
/// mechanical energy at the start, J (the dissipated energy's reference).
pub(crate) fn observation(
    world: &World,
    workers: &Workers,
    initial_energy: f64,
    hooks: &impl ObserveHooks,
) -> Observation {
    let (kinetic, potential) = hooks.body_energies(world, workers);
    let c = hooks.contacts(world, workers);
    // Counts as f64: exact far beyond any scene's.
    let mut v = vec![
        kinetic,
        potential,
        c.pair_energy + c.plane_energy + c.spring_energy,
        c.particle_contacts as f64,
        (c.boundary_contacts + c.plane_contacts) as f64,
    ];
    // The moving walls' work, each process's share (`moving_walls`).
    if let Some(m) = world.moving.as_ref() {
        v.push(m.work);
    }
    // The gate energy G, each process's share (`walls::gate`), last.
    if let Some(g) = world.gates.as_ref() {
        v.push(g.energy);
    }
    // The springs' energy, for D_c (`dissipation`), last.
    if world.dissipation.is_some() {
        v.push(c.spring_energy);
    }
    let s = hooks.sum(v);
    // The moving groups' loads: each process's share (its copies of the
    // groups' spheres took the forces of the pairs it lists, each pair
    // listed on one process), summed over the processes.
    let mut group_motions = world.group_motion_states();
    if !group_motions.is_empty() {
        let shares: Vec<f64> = group_motions
            .iter()
            .flat_map(|g| g.force.into_iter().chain(g.torque))
            .collect();
        let total = hooks.sum(shares);
        for (g, t) in group_motions.iter_mut().zip(total.chunks_exact(6)) {
            g.force = [t[0], t[1], t[2]];
            g.torque = [t[3], t[4], t[5]];
        }
    }
    let work = world.moving.as_ref().map(|_| s[5]);
    let gate = world
        .gates
        .as_ref()
        .map(|_| s[5 + usize::from(work.is_some())]);
    let dissipated_by_contacts = world
        .dissipation
        .as_ref()
        .and_then(|d| s.last().map(|&springs| d.total(springs)));
    // What the run removed (`crate::removal`): every process books every
    // removal (no sum).
    let removed = world.removal.as_ref().map(|r| r.removed);
    // What came in minus what is there and what left: D = E₀ + W − C − (K + E + P).
    // What the inlets brought in (`crate::inlets`), I: D gains it.
    let inlets = world
        .inlets
        .as_ref()
        .map_or_else(Vec::new, |i| i.inserted());
    let brought = (!inlets.is_empty()).then(|| inlets.iter().map(|i| i.energy).sum::<f64>());
    let carried = |d: f64| {
        let d = match removed {
            None => d,
            Some(r) => d - r.energy,
        };
        match brought {
            None => d,
            Some(i) => d + i,
        }
    };
    // … and what the gates took out: D = E₀ + W − C − G − (K + E + P).
    let carried = |d: f64| match gate {
        None => carried(d),
        Some(g) => carried(d) - g,
    };
    let loads = hooks.wall_loads(world, workers);
    Observation {
        step: world.steps_done,
        time: world.time(),
        kinetic_energy: s[0],
        elastic_energy: s[2],
        potential_energy: s[1],
        dissipated_energy: match work {
            None => carried(initial_energy) - (s[0] + s[2] + s[1]),
            // What came in minus what is there: D = E₀ + W − (K + E + P).
            Some(w) => carried(initial_energy + w) - (s[0] + s[2] + s[1]),
        },
        particle_contacts: s[3].round() as usize,
        wall_contacts: s[4].round() as usize,
        wall_forces: loads.iter().map(|l| l.force).collect(),
        wall_torques: loads.iter().map(|l| l.torque).collect(),
        work_by_walls: work,
        removed,
        wall_motions: world.wall_motion_states(),
        group_motions,
        outlets: world
            .removal
            .as_ref()
            .map_or_else(Vec::new, |r| r.by_outlet.clone()),
        gate_energy: gate,
        inlets,
        dissipated_by_contacts,
        wall_force_means: None,
    }
}

/// The torque point of each wall (file order), m: what
/// [`Observation::wall_torques`] are about.
pub(crate) fn wall_torque_points(world: &World) -> Vec<[f64; 3]> {
    wall_loads::torque_points(world)
}

/// [`kinetic_energy`] and [`potential_energy`] in one pass over the
/// bodies, J: each sum in its own accumulator with the same chunks and
/// order (`Workers::sum` adds element-wise), so the same bits as the two
/// passes.
pub(crate) fn body_energies(world: &World, workers: &Workers) -> (f64, f64) {
    let b = &world.bodies;
    let spin = world.friction.is_some();
    let g = world.gravity;
    let [kinetic, potential] = workers.sum(b.len(), |k| {
        if b.fixed[k] {
            return [0.0, 0.0];
        }
        let v = b.velocity[k];
        let mut e = 0.5 * b.mass[k] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if spin {
            let w = b.angular_velocity[k];
            e += 0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) / b.inverse_inertia[k];
        }
        let x = b.position[k];
        [e, -b.mass[k] * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2])]
    });
    (kinetic, potential)
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

/// The contact observables pass by pass: pair counts and energy, wall
/// contact counts and energy, spring energy; the main pairs' sums from
/// `tally` and the walls' from `walls_tally` when given (frictionless).
pub(crate) fn contact_passes(
    world: &World,
    workers: &Workers,
    tally: Option<&[contacts::PairTally]>,
    walls_tally: Option<&[f64]>,
) -> ContactObservables {
    let w = world;
    let (pc, wc, pe) = contacts::pair_observables(
        &w.bodies,
        &w.ghosts,
        &w.list,
        &w.histories,
        &w.laws,
        workers,
        tally,
    );
    let (plane_contacts, plane_energy) = walls_tally
        .and_then(|e| {
            walls::plane_observables_tallied(&w.bodies, &w.surfaces, &w.wall_contacts, workers, e)
        })
        .unwrap_or_else(|| {
            walls::plane_observables(&w.bodies, &w.surfaces, &w.wall_contacts, &w.laws, workers)
        });
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
        plane_contacts,
        plane_energy,
        spring_energy: springs,
    }
}

#[cfg(test)]
mod tests {
    use crate::dynamics::friction_observables::tests::scene;
    use crate::Simulation;

    /// An observation after steps asked to tally it (`will_observe`) uses
    /// the tally (pairs, energies) and gives the observation that visits
    /// every pair and body again bit for bit (the reference), at the end
    /// of stretches of several lengths, on 1 and 2 threads, with friction
    /// and without, with and without fixed spheres (their wall entries are
    /// skipped by both); a stretch not asked leaves no tally.
    #[test]
    fn tallied_observation_equals_the_pairs_visited_again() {
        let cases = [
            (1, true, false),
            (2, true, false),
            (1, false, false),
            (2, false, false),
            (1, false, true),
            (2, false, true),
        ];
        for (threads, friction, fixed) in cases {
            let mut setup = scene();
            if !friction {
                setup.friction = None;
            }
            if fixed {
                // Every fifth sphere held: spread over the chunks, the
                // lowest layer's beside the floor's entries.
                for sphere in setup.spheres.iter_mut().step_by(5) {
                    sphere.fixed = true;
                }
            }
            let mut sim = Simulation::new(setup.clone(), threads).unwrap();
            // The same run not asked to tally: the state's reference.
            let mut plain = Simulation::new(setup, threads).unwrap();
            let mut loaded = 0;
            for k in 0..20 {
                sim.will_observe();
                sim.step(1 + 37 * (k % 3));
                plain.step(1 + 37 * (k % 3));
                let bits = |s: &Simulation| -> Vec<u64> {
                    let b = &s.world.bodies;
                    [&b.position, &b.velocity, &b.angular_velocity, &b.force]
                        .iter()
                        .flat_map(|v| v.iter().flatten().map(|x| x.to_bits()))
                        .collect()
                };
                assert!(bits(&sim) == bits(&plain));
                let tally = sim.pipeline.pair_tally(&sim.world);
                assert_eq!(tally.friction.is_some(), friction);
                assert_eq!(tally.plain.is_some(), !friction);
                // Without friction the walls' part from the body pass.
                assert_eq!(tally.walls.is_some(), !friction);
                assert!(tally.energies.is_some());
                // The state check passed in the kick's pass.
                assert!(sim.pipeline.sound(&sim.world) && sim.check_finite().is_ok());
                let tallied = sim.observe();
                let again = super::observation(
                    &sim.world,
                    &sim.workers,
                    sim.initial_energy,
                    &crate::pipeline::Local,
                );
                // Debug prints each number's shortest exact decimal.
                assert_eq!(format!("{tallied:?}"), format!("{again:?}"));
                assert_eq!(
                    tallied.elastic_energy.to_bits(),
                    again.elastic_energy.to_bits()
                );
                assert_eq!(
                    tallied.kinetic_energy.to_bits(),
                    again.kinetic_energy.to_bits()
                );
                if tallied.particle_contacts > 0 {
                    loaded += 1;
                }
                sim.step(3);
                plain.step(3);
                assert!(!sim.pipeline.pair_tally(&sim.world).is_some());
            }
            assert!(loaded > 10, "{loaded}");
        }
    }

    /// The fused pass gives the two passes' sums bit for bit (the expected
    /// values are the separate passes', an independent computation of the
    /// same sums), along a run with spins, on 1 and 2 threads.
    #[test]
    fn body_energies_equal_the_two_passes_bit_for_bit() {
        for threads in [1, 2] {
            let mut sim = Simulation::new(scene(), threads).unwrap();
            for _ in 0..10 {
                sim.step(50);
                let (kinetic, potential) = super::body_energies(&sim.world, &sim.workers);
                let alone = super::kinetic_energy(&sim.world, &sim.workers);
                assert!(alone > 0.0);
                assert_eq!(kinetic.to_bits(), alone.to_bits());
                let alone = super::potential_energy(&sim.world, &sim.workers);
                assert_eq!(potential.to_bits(), alone.to_bits());
            }
        }
    }
}
