//! What a rank counts when the scene is observed (`pipeline::observe`
//! computes the observation): each contact on one rank, the walls' loads
//! (every rank sums every rank's records of the force stage in input-id
//! order: the same bits on any number of ranks; the boundary particles'
//! loads from its pair stage, summed over the ranks), the sums over the
//! ranks. After steps asked to tally the row ([`RankTallied`]), the
//! contacts come from what the last pair pass wrote of each listed pair
//! and the bodies' energies from the last half kick, with the same bits
//! as the pass that visits every pair again.

use dembound_physics::contact::ContactHistory;

use super::RankComm;
use crate::bodies::{Bodies, NO_GROUP};
use crate::comm::Transport;
use crate::dynamics::contacts::{extended, touching};
use crate::dynamics::entry_tally::apart;
use crate::dynamics::friction_observables::{self, ContactObservables};
use crate::dynamics::{spring_energy, walls};
use crate::parallel::Workers;
use crate::pipeline::observe::{body_energies, ObserveHooks, Tallied};
use crate::pipeline::wall_loads::{self, LoadRecord};
use crate::pipeline::{WallKind, World};
use crate::walls::WallLoad;

impl<T: Transport> ObserveHooks for RankComm<T> {
    /// A pair is counted on the rank owning its free body of lower id (a
    /// pair across a cut is listed on both); summed pair by pair in list
    /// order.
    fn contacts(&self, w: &World, workers: &Workers) -> ContactObservables {
        let b = &w.bodies;
        let (plane_contacts, plane_energy) =
            walls::plane_observables(b, &w.surfaces, &w.wall_contacts, &w.laws, workers);
        let (fixed_by_id, halo) = (&self.fixed_by_id[..], &self.halo[..]);
        let counted_here = |i: usize, j: usize| counted(fixed_by_id, halo, b, i, j);
        let (mut pc, mut wc, mut energy) = (0.0, 0.0, 0.0);
        let mut visit = |i: usize, xj: [f64; 3], owner: usize, h: &ContactHistory| {
            if let Some((walled, e)) = self.pair_terms(w, i, xj, owner, h) {
                if walled {
                    wc += 1.0;
                } else {
                    pc += 1.0;
                }
                energy += e;
            }
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
        // The friction springs' energy (halo copies are fixed: they
        // touch no wall here).
        let springs = match &w.friction {
            Some(table) => spring_energy::spring_energy_counted(
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
            None => 0.0,
        };
        ContactObservables {
            particle_contacts: pc as usize,
            boundary_contacts: wc as usize,
            pair_energy: energy,
            plane_contacts,
            plane_energy,
            spring_energy: springs,
        }
    }

    /// The walls of `World::surfaces`: every rank's records (its owned
    /// bodies' touching entries) sent to every rank, merged by input id
    /// (a body's records come from its one owner, in entry order) and
    /// summed as on one process. The boundary-particle walls: this rank's
    /// share from its pair stage (each pair of a free body with a
    /// boundary particle counted on one rank), summed over the ranks.
    /// Collective.
    fn wall_loads(&self, world: &World, workers: &Workers) -> Vec<WallLoad> {
        let walls = world.walls.len();
        let mut records = wall_loads::surface_load_records_on(world, workers);
        if !world.surfaces.is_empty() {
            records = self.merge_records(records);
        }
        let mut loads = wall_loads::sum_records(&records, walls);
        let particles: Vec<usize> = (0..walls)
            .filter(|&k| matches!(world.walls[k], WallKind::Particles { .. }))
            .collect();
        if !particles.is_empty() {
            let mut v = Vec::with_capacity(6 * particles.len());
            for &k in &particles {
                let l = self.particle_wall_load.get(k).copied().unwrap_or_default();
                v.extend_from_slice(&l.force);
                v.extend_from_slice(&l.torque);
            }
            let s = self.transport.sum(&v);
            for (q, &k) in particles.iter().enumerate() {
                let at = |a: usize| s[6 * q + a];
                loads[k] = WallLoad {
                    force: [at(0), at(1), at(2)],
                    torque: [at(3), at(4), at(5)],
                };
            }
        }
        loads
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        self.transport.sum(&values)
    }
}

/// Whether a rank counts the pair of its local bodies i and j: the rank
/// owning its free body of lower id (a pair across a cut is listed on
/// both ranks; of a free and a fixed body, the free one's). `fixed_by_id`:
/// each input id's fixed flag; `halo`: each local body's.
#[inline(always)]
fn counted(fixed_by_id: &[bool], halo: &[bool], b: &Bodies, i: usize, j: usize) -> bool {
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
}

/// A rank's observation after steps asked to tally it
/// (`DistributedSimulation::will_observe`): [`RankComm`]'s hooks, with the
/// contacts from `tally` (each listed pair's terms as the last pair pass
/// wrote them, [`RankComm::tallied_contacts`]) and the bodies' energies
/// from the last half kick, when they describe this state; else as
/// [`RankComm`] observes.
pub(crate) struct RankTallied<'a, T: Transport> {
    pub comm: &'a RankComm<T>,
    pub tally: Tallied<'a>,
}

impl<T: Transport> ObserveHooks for RankTallied<'_, T> {
    fn contacts(&self, w: &World, workers: &Workers) -> ContactObservables {
        self.comm
            .tallied_contacts(w, workers, &self.tally)
            .unwrap_or_else(|| self.comm.contacts(w, workers))
    }

    fn wall_loads(&self, world: &World, workers: &Workers) -> Vec<WallLoad> {
        self.comm.wall_loads(world, workers)
    }

    fn sum(&self, values: Vec<f64>) -> Vec<f64> {
        self.comm.sum(values)
    }

    /// The last half kick's sums: [`body_energies`]' bits.
    fn body_energies(&self, world: &World, workers: &Workers) -> (f64, f64) {
        self.tally
            .energies
            .unwrap_or_else(|| body_energies(world, workers))
    }
}

impl<T: Transport> RankComm<T> {
    /// [`counted`] on this rank.
    #[inline(always)]
    fn counted_here(&self, w: &World, i: usize, j: usize) -> bool {
        counted(&self.fixed_by_id, &self.halo, &w.bodies, i, j)
    }

    /// Body i's pair with the body or halo copy at `xj` (its owner
    /// `owner`, history `h`) in the row: whether a wall's boundary
    /// particle is in it, and its elastic energy (J), when it touches and
    /// is counted on this rank.
    fn pair_terms(
        &self,
        w: &World,
        i: usize,
        xj: [f64; 3],
        owner: usize,
        h: &ContactHistory,
    ) -> Option<(bool, f64)> {
        let b = &w.bodies;
        // The contact test first: most listed pairs are apart.
        let g = touching(
            b.position[i],
            [0.0; 3],
            b.radius[i],
            xj,
            [0.0; 3],
            b.radius[owner],
        )?;
        if !self.counted_here(w, i, owner) {
            return None;
        }
        let walled = b.group[i] != NO_GROUP || b.group[owner] != NO_GROUP;
        let energy = w
            .laws
            .elastic_energy(&w.laws.pair(b, i, owner), g.overlap, h);
        Some((walled, energy))
    }

    /// [`ObserveHooks::contacts`] from what the last pair pass wrote of
    /// each main entry (`tally.entries`): the same counted pairs, their
    /// energies added one by one in list order into one sum (the extra
    /// pairs then visited as there), so the same bits; with friction each
    /// body's springs are its counted entries' springs in row order, then
    /// its planes' (`friction_observables`, with the planes and the sums'
    /// chunks of `walls::plane_observables` and
    /// `spring_energy::spring_energy_counted`); without, the planes from
    /// the body pass's tally when there is one. `None` when there is no
    /// tally of this state (then [`ObserveHooks::contacts`] visits the
    /// pairs).
    pub(crate) fn tallied_contacts(
        &self,
        w: &World,
        workers: &Workers,
        tally: &Tallied,
    ) -> Option<ContactObservables> {
        let entries = tally.entries?;
        let b = &w.bodies;
        let list = &w.list;
        let n = b.len();
        let friction = w.friction.as_ref();
        // The rows' tally of the same pass: with friction it carries
        // the springs' lane the planes are added to.
        let mut rows = match friction {
            Some(_) => Some(tally.friction?.to_vec()),
            None => {
                tally.plain?;
                None
            }
        };
        if list.start.len() != n + 1 || !entries.fits(list.j.len(), friction.is_some()) {
            return None;
        }
        let (mut pc, mut wc, mut energy) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let mut springs = 0.0;
            for k in list.start[i] as usize..list.start[i + 1] as usize {
                let e = entries.energy[k];
                if apart(e) {
                    continue;
                }
                let j = list.j[k] as usize;
                if !self.counted_here(w, i, j) {
                    continue;
                }
                if b.group[i] != NO_GROUP || b.group[j] != NO_GROUP {
                    wc += 1.0;
                } else {
                    pc += 1.0;
                }
                energy += e;
                if rows.is_some() {
                    springs += entries.spring[k];
                }
            }
            if let Some(rows) = rows.as_mut() {
                rows[i][3] = springs;
            }
        }
        // The extra pairs (none with friction's tally), as `contacts`.
        for (q, &(i, j)) in list.extra.iter().enumerate() {
            let (xj, _, owner) = extended(b, &w.ghosts, j as usize);
            let h = w.histories.extra(q);
            if let Some((walled, e)) = self.pair_terms(w, i as usize, xj, owner, h) {
                if walled {
                    wc += 1.0;
                } else {
                    pc += 1.0;
                }
                energy += e;
            }
        }
        let (plane_contacts, plane_energy, spring_energy) = match (friction, rows) {
            (Some(table), Some(rows)) => {
                let c = friction_observables::observe(
                    b,
                    list,
                    &w.histories,
                    table,
                    &w.shear,
                    &w.surfaces,
                    &w.wall_contacts,
                    workers,
                    Some(&rows),
                )?;
                (c.plane_contacts, c.plane_energy, c.spring_energy)
            }
            _ => {
                let (c, e) = tally
                    .walls
                    .and_then(|e| {
                        walls::plane_observables_tallied(
                            b,
                            &w.surfaces,
                            &w.wall_contacts,
                            workers,
                            e,
                        )
                    })
                    .unwrap_or_else(|| {
                        walls::plane_observables(b, &w.surfaces, &w.wall_contacts, &w.laws, workers)
                    });
                (c, e, 0.0)
            }
        };
        Some(ContactObservables {
            particle_contacts: pc as usize,
            boundary_contacts: wc as usize,
            pair_energy: energy,
            plane_contacts,
            plane_energy,
            spring_energy,
        })
    }

    /// This rank's load records and every other rank's, merged by input
    /// id (a body's records come from its one owner, in entry order).
    /// Collective.
    pub(crate) fn merge_records(&self, mut records: Vec<LoadRecord>) -> Vec<LoadRecord> {
        let me = self.transport.rank();
        let others: Vec<usize> = (0..self.transport.size()).filter(|&r| r != me).collect();
        let bytes = encode(&records);
        let sends: Vec<(usize, Vec<u8>)> = others.iter().map(|&r| (r, bytes.clone())).collect();
        for got in self.transport.exchange(&sends, &others) {
            records.extend(decode(&got));
        }
        // Stable: a body's records keep their entry order.
        records.sort_by_key(|r| r.id);
        records
    }
}

/// Records as bytes: id, wall (u32 each), force and torque (f64 each),
/// little-endian.
fn encode(records: &[LoadRecord]) -> Vec<u8> {
    let mut out = Vec::with_capacity(56 * records.len());
    for r in records {
        out.extend_from_slice(&r.id.to_le_bytes());
        out.extend_from_slice(&r.wall.to_le_bytes());
        for x in r.load.force.iter().chain(&r.load.torque) {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    out
}

/// [`encode`]'s records (a short tail is ignored).
fn decode(bytes: &[u8]) -> Vec<LoadRecord> {
    let u32_at = |c: &[u8], k: usize| u32::from_le_bytes([c[k], c[k + 1], c[k + 2], c[k + 3]]);
    let f64_at = |c: &[u8], k: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&c[k..k + 8]);
        f64::from_le_bytes(b)
    };
    bytes
        .chunks_exact(56)
        .map(|c| {
            let v = |a: usize| f64_at(c, 8 + 8 * a);
            LoadRecord {
                id: u32_at(c, 0),
                wall: u32_at(c, 4),
                load: WallLoad {
                    force: [v(0), v(1), v(2)],
                    torque: [v(3), v(4), v(5)],
                },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Records survive the byte form bit for bit.
    #[test]
    fn records_round_trip() {
        let r = vec![
            LoadRecord {
                id: 7,
                wall: 2,
                load: WallLoad {
                    force: [1.5, -0.0, f64::MIN_POSITIVE],
                    torque: [1e-300, -3.25, 1e300],
                },
            },
            LoadRecord {
                id: u32::MAX,
                wall: 0,
                load: WallLoad::default(),
            },
        ];
        assert_eq!(decode(&encode(&r)), r);
    }
}
