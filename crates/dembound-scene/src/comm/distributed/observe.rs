//! What a rank counts when the scene is observed (`pipeline::observe`
//! computes the observation): each contact on one rank, the boundary
//! particles' forces from its pair stage, the sums over the ranks.

use dembound_physics::contact::ContactHistory;

use super::RankComm;
use crate::bodies::NO_GROUP;
use crate::comm::Transport;
use crate::dynamics::contacts::{extended, touching};
use crate::dynamics::friction;
use crate::dynamics::friction_observables::ContactObservables;
use crate::dynamics::{spring_energy, walls};
use crate::parallel::Workers;
use crate::pipeline::observe::ObserveHooks;
use crate::pipeline::World;

impl<T: Transport> ObserveHooks for RankComm<T> {
    /// A pair is counted on the rank owning its free body of lower id (a
    /// pair across a cut is listed on both); summed pair by pair in list
    /// order.
    fn contacts(&self, w: &World, workers: &Workers) -> ContactObservables {
        let b = &w.bodies;
        let (plane_forces, plane_contacts, plane_energy) =
            walls::plane_observables(b, &w.surfaces, &w.wall_contacts, &w.laws, workers);
        // A pair is counted on the rank owning its free body of lower id.
        let (fixed_by_id, halo) = (&self.fixed_by_id, &self.halo);
        let counted_here = |i: usize, j: usize| {
            let (a, c) = (b.id[i], b.id[j]);
            let lead = match (fixed_by_id[a as usize], fixed_by_id[c as usize]) {
                (false, false) => {
                    if a < c {
                        i
                    } else {
                        j
                    }
                }
                (false, true) => i,
                _ => j,
            };
            !halo[lead]
        };
        let (mut pc, mut wc, mut energy) = (0.0, 0.0, 0.0);
        let mut visit = |i: usize, xj: [f64; 3], owner: usize, h: &ContactHistory| {
            // The contact test first: most listed pairs are apart.
            let Some(g) = touching(
                b.position[i],
                [0.0; 3],
                b.radius[i],
                xj,
                [0.0; 3],
                b.radius[owner],
            ) else {
                return;
            };
            if !counted_here(i, owner) {
                return;
            }
            if b.group[i] != NO_GROUP || b.group[owner] != NO_GROUP {
                wc += 1.0;
            } else {
                pc += 1.0;
            }
            energy += w
                .laws
                .elastic_energy(&w.laws.pair(b, i, owner), g.overlap, h);
        };
        let list = &w.list;
        for i in 0..b.len() {
            for k in list.start[i] as usize..list.start[i + 1] as usize {
                let j = list.j[k] as usize;
                visit(i, b.position[j], j, w.histories.main(k));
            }
        }
        for (q, &(i, j)) in list.extra.iter().enumerate() {
            let (xj, _, owner) = extended(b, &w.ghosts, j as usize);
            visit(i as usize, xj, owner, w.histories.extra(q));
        }
        // The friction springs' energy and the planes' tangential forces
        // (halo copies are fixed: they touch no plane here).
        let (springs, tangential) = match &w.friction {
            Some(table) => (
                spring_energy::spring_energy_counted(
                    b,
                    &w.ghosts,
                    &w.list,
                    &w.laws,
                    table,
                    &w.shear,
                    &w.surfaces,
                    &w.wall_contacts,
                    workers,
                    counted_here,
                ),
                friction::plane_tangential_forces(b, &w.surfaces, &w.laws, table, &w.wall_contacts),
            ),
            None => (0.0, Vec::new()),
        };
        ContactObservables {
            particle_contacts: pc as usize,
            boundary_contacts: wc as usize,
            pair_energy: energy,
            plane_forces,
            plane_contacts,
            plane_energy,
            plane_tangential: tangential,
            spring_energy: springs,
        }
    }

    /// From this rank's pair stage: each pair of a free body with a
    /// boundary particle counted on one rank.
    fn particle_wall_forces(&self, _world: &World) -> Vec<[f64; 3]> {
        self.particle_wall_force.clone()
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        self.transport.sum(&values)
    }
}
