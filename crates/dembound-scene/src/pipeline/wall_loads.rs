//! Stage "observe", the wall loads: the force (N) and torque (N m) each
//! wall takes from the spheres, one [`WallLoad`] per wall in file order.
//!
//! Walls of `World::surfaces` (planes, cylinders): the force pass records,
//! per touching near entry, what the wall took from that contact
//! (`WallContacts::load`, [`WallLoad::of_contact`]): the force and torque
//! it applied, with the velocities it saw (Verlet's half-step ones), so
//! the loads balance the forces that moved the spheres. Summed here per
//! wall, bodies by input id, each body's entries in (wall, element)
//! order, one running sum per wall: the bits depend on the recorded
//! values only, not on how many threads or ranks hold the bodies (a rank
//! sends its records to every rank, which all sum the merged list:
//! `comm::distributed::observe`). Torques about the wall's
//! `Wall::torque_point`.
//!
//! Walls of boundary particles (fixed spheres of one group): the force
//! is the sum of the forces on their spheres, the torque
//! Σ (x_k − c) × f_k + τ_k (f_k, τ_k the force and torque the sphere took
//! in the last force stage), about the centroid c of its spheres'
//! initial positions ([`WallKind::Particles`]); spheres in input order on
//! one process, each rank's share summed over the ranks under MPI.

use crate::bodies::NO_GROUP;
use crate::walls::WallLoad;

use super::{Pipeline, WallKind, World};
use crate::parallel::{Workers, BODY_CHUNK};

/// One touching wall contact's recorded load, as the sums take it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LoadRecord {
    /// Input id of the sphere.
    pub id: u32,
    /// The wall, file order.
    pub wall: u32,
    pub load: WallLoad,
}

/// The recorded loads of the touching wall contacts of the free bodies
/// this process holds: bodies ascending by input id, a body's entries in
/// (wall, element) order.
pub(crate) fn surface_load_records(world: &World) -> Vec<LoadRecord> {
    surface_load_records_on(world, &Workers::serial())
}

/// [`surface_load_records`], the bodies scanned by `workers` in chunks of
/// [`BODY_CHUNK`], each chunk's records sorted by (input id, entry), the
/// runs merged at the end: the keys are all distinct, so the result does
/// not depend on the chunks or the threads.
pub(crate) fn surface_load_records_on(world: &World, workers: &Workers) -> Vec<LoadRecord> {
    let (b, wc) = (&world.bodies, &world.wall_contacts);
    let n = b.len();
    if wc.bodies() != n || wc.load.len() != wc.key.len() {
        return Vec::new();
    }
    // The touching entries, each as its key (body's input id, entry),
    // packed in one u64 (id above, entry below: entries are u32) so that
    // the integer order is the key order. A chunk's entries entry by
    // entry: body i's entries are start[i]..start[i + 1] and the ranges
    // ascend with the body, so a touching entry's body is found by walking
    // the bodies forward from the last one's (eight at a time while the
    // eighth next starts at or before it); a fixed body (a halo copy) is
    // not forced: its flags are not this step's.
    let (start, fixed, touching, id) = (&wc.start[..], &b.fixed[..], &wc.touching[..], &b.id[..]);
    let parts = workers.map_bodies(n, BODY_CHUNK, |c| {
        let mut keys: Vec<u64> = Vec::new();
        let (mut i, end) = (c * BODY_CHUNK, ((c + 1) * BODY_CHUNK).min(n));
        let (lo, hi) = (start[i] as usize, start[end] as usize);
        for (k, &t) in touching[lo..hi].iter().enumerate() {
            if !t {
                continue;
            }
            let k = lo + k;
            // Body i: start[i] ≤ k < start[i + 1] (i < end: k < start[end]).
            while i + 8 < end && start[i + 8] as usize <= k {
                i += 8;
            }
            while start[i + 1] as usize <= k {
                i += 1;
            }
            if !fixed[i] {
                keys.push(u64::from(id[i]) << 32 | k as u64);
            }
        }
        keys.sort_unstable();
        keys
    });
    // The chunks' sorted runs merged (a stable sort merges runs it finds
    // sorted; the keys are distinct: one order).
    let mut keys: Vec<u64> = parts.concat();
    keys.sort();
    keys.into_iter()
        .map(|key| {
            let k = (key & u64::from(u32::MAX)) as usize;
            LoadRecord {
                id: (key >> 32) as u32,
                wall: world.surfaces[wc.key[k].wall as usize].file_index() as u32,
                load: wc.load[k],
            }
        })
        .collect()
}

/// The loads of `walls` walls (file order) from `records` in the order
/// given (ascending by id, a body's in entry order): one running sum per
/// wall. Records of a wall outside `walls` are skipped.
pub(crate) fn sum_records(records: &[LoadRecord], walls: usize) -> Vec<WallLoad> {
    let mut out = vec![WallLoad::default(); walls];
    for r in records {
        if let Some(w) = out.get_mut(r.wall as usize) {
            w.add(&r.load);
        }
    }
    out
}

/// The centroid (m) of a boundary-particle wall's spheres `positions`,
/// its torque point: the mean in the order given.
pub fn particle_wall_torque_point(positions: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for x in positions {
        for a in 0..3 {
            c[a] += x[a];
        }
    }
    let n = positions.len().max(1) as f64;
    c.map(|s| s / n)
}

/// The torque point of each wall (file order), m.
pub(crate) fn torque_points(world: &World) -> Vec<[f64; 3]> {
    world
        .walls
        .iter()
        .map(|kind| match kind {
            WallKind::Surface(p) => world
                .surfaces
                .get(*p)
                .map_or([0.0; 3], |s| s.torque_point()),
            WallKind::Particles { torque_point } => *torque_point,
        })
        .collect()
}

/// Adds what a boundary particle at `x` that took force `f` and torque
/// `tau` (N, N m) gives its wall about `c`: f, and (x − c) × f + τ.
#[inline]
pub(crate) fn add_particle_load(
    load: &mut WallLoad,
    x: [f64; 3],
    c: [f64; 3],
    f: [f64; 3],
    tau: [f64; 3],
) {
    let d = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
    let t = [
        d[1] * f[2] - d[2] * f[1],
        d[2] * f[0] - d[0] * f[2],
        d[0] * f[1] - d[1] * f[0],
    ];
    for a in 0..3 {
        load.force[a] += f[a];
        load.torque[a] += t[a] + tau[a];
    }
}

/// The loads of the boundary-particle walls from the spheres this process
/// holds (`Some` entries; the others `None`), spheres in input order.
pub(crate) fn particle_wall_loads(world: &World) -> Vec<Option<WallLoad>> {
    let mut out: Vec<Option<WallLoad>> = world
        .walls
        .iter()
        .map(|k| matches!(k, WallKind::Particles { .. }).then(WallLoad::default))
        .collect();
    if out.iter().all(Option::is_none) {
        return out;
    }
    let points = torque_points(world);
    let b = &world.bodies;
    for i in b.index_of_ids() {
        if i == crate::bodies::REMOVED {
            continue;
        }
        let i = i as usize;
        let g = b.group[i];
        if g == NO_GROUP {
            continue;
        }
        if let Some(Some(load)) = out.get_mut(g as usize) {
            let tau = b.torque.get(i).copied().unwrap_or([0.0; 3]);
            add_particle_load(load, b.position[i], points[g as usize], b.force[i], tau);
        }
    }
    out
}

impl Pipeline {
    /// Records the wall loads of the state as it is, changing nothing
    /// else: the per-body force stage run on copies of what it writes
    /// (springs not moved), only its loads kept. For a restored
    /// checkpoint, which does not carry them: its first observation's
    /// loads are the end-of-step state's, not those of the force pass that
    /// ended the step (it saw Verlet's half-step velocities); from the
    /// first step on they are the force pass's again.
    pub(crate) fn record_wall_loads(&mut self, world: &mut World, workers: &Workers) {
        let saved = (
            world.wall_contacts.clone(),
            world.bodies.force.clone(),
            world.bodies.torque.clone(),
        );
        world.wall_contacts.load.fill(WallLoad::default());
        self.body_forces(world, workers, 0.0);
        let load = std::mem::take(&mut world.wall_contacts.load);
        world.wall_contacts = saved.0;
        world.wall_contacts.load = load;
        world.bodies.force = saved.1;
        world.bodies.torque = saved.2;
    }
}

#[cfg(test)]
mod tests {
    use super::{surface_load_records_on, LoadRecord};
    use crate::dynamics::friction_observables::tests::scene;
    use crate::pipeline::World;
    use crate::Simulation;

    /// The records straight from their definition: every touching entry
    /// of every body that is not fixed, body by body, sorted by (input
    /// id, entry).
    fn by_definition(world: &World) -> Vec<LoadRecord> {
        let (b, wc) = (&world.bodies, &world.wall_contacts);
        let mut keys = Vec::new();
        for i in 0..b.len() {
            if b.fixed[i] {
                continue;
            }
            for k in wc.range(i) {
                if wc.touching[k] {
                    keys.push((b.id[i], k));
                }
            }
        }
        keys.sort();
        keys.into_iter()
            .map(|(id, k)| LoadRecord {
                id,
                wall: world.surfaces[wc.key[k].wall as usize].file_index() as u32,
                load: wc.load[k],
            })
            .collect()
    }

    /// The chunks' entry walk gives the records of the definition (the
    /// reference, body by body), on 1 and 2 threads, along a run with
    /// bodies on the walls, with and without fixed bodies among them
    /// (their entries left out).
    #[test]
    fn load_records_are_the_touching_entries_of_the_free_bodies() {
        for threads in [1, 2] {
            let mut sim = Simulation::new(scene(), threads).unwrap();
            let (mut seen, mut dropped) = (0, 0);
            for round in 0..8 {
                sim.step(40);
                let expected = by_definition(&sim.world);
                assert_eq!(surface_load_records_on(&sim.world, &sim.workers), expected);
                seen += expected.len();
                if round % 2 == 1 {
                    // Every third body with near walls fixed, then freed.
                    let n = sim.world.bodies.len();
                    let walled: Vec<usize> = (0..n)
                        .filter(|&i| !sim.world.wall_contacts.range(i).is_empty())
                        .step_by(3)
                        .collect();
                    for &i in &walled {
                        sim.world.bodies.fixed[i] = true;
                    }
                    let fewer = by_definition(&sim.world);
                    dropped += expected.len() - fewer.len();
                    assert_eq!(surface_load_records_on(&sim.world, &sim.workers), fewer);
                    for &i in &walled {
                        sim.world.bodies.fixed[i] = false;
                    }
                }
            }
            // Touching entries were there, of free and of fixed bodies.
            assert!(seen > 100 && dropped > 10, "{seen} {dropped}");
        }
    }
}
