//! Checkpoint and restart of a decomposed run (issue 16), in the engine's
//! own checkpoint format ([`Checkpoint`], `io::checkpoint`), so that a
//! checkpoint written on any number of ranks, or by the one-process
//! engine, continues on any number of ranks.
//!
//! - [`DistributedSimulation::checkpoint`] gathers every rank's owned
//!   bodies at rank 0, in input-id order: position, velocity, force,
//!   position at the last list build, plane-wall histories; the pair
//!   histories keyed by input ids (a pair across a cut is held by both its
//!   ranks with the same bits: kept once); the step count, the list
//!   builds and the initial energy.
//! - [`DistributedSimulation::restore`] starts as a new run would (every
//!   rank reads the scene and the whole checkpoint), then puts every body
//!   at its position of the last list build and rebuilds there: bodies go
//!   to their owners under the *new* rank count, the halo and the lists
//!   are those the run had, and the next rebuild falls on the same step.
//!   Then the histories by input ids, and the positions, velocities and
//!   forces of the checkpointed step.
//!
//! Because each body's force is summed in partner-id order, the decomposed
//! trajectory does not depend on the decomposition: k steps on 2 ranks, a
//! checkpoint, and k more on 3 ranks (or 1) end in the same bits as 2k
//! steps in one go (tests/decomposition_checkpoint.rs).

use std::collections::{BTreeMap, HashMap};

use dembound_physics::contact::ContactHistory;

use super::DistributedSimulation;
use crate::comm::pack::{Reader, Writer};
use crate::comm::Transport;
use crate::dynamics::contacts::{self, extended};
use crate::setup::SceneSetup;
use crate::simulation::{Checkpoint, HistoryRecord};
use crate::SceneError;

/// What decomposed runs cannot checkpoint yet (the same answer on every
/// rank: it depends on the scene only).
fn refuse_checkpoint(friction: bool) -> Result<(), SceneError> {
    if friction {
        return Err(SceneError::input(
            "a checkpoint under MPI holds no tangential springs or spins yet: \
             run scenes with friction without mpirun to checkpoint them",
        ));
    }
    Ok(())
}

/// Checks a checkpoint against the scene before anything is exchanged
/// (every rank reads the same file: every rank gives the same answer).
fn check(c: &Checkpoint, n: usize) -> Result<Vec<usize>, SceneError> {
    let lens = [
        c.order.len(),
        c.position.len(),
        c.velocity.len(),
        c.force.len(),
        c.reference.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(SceneError::Checkpoint(format!(
            "it holds {} bodies, the scene {n}",
            c.order.len()
        )));
    }
    if !c.higher.is_empty() {
        return Err(SceneError::Checkpoint(
            "it was written by a Gear5 run; runs under MPI are Verlet".into(),
        ));
    }
    if !c.angular_velocity.is_empty() || !c.pair_shear.is_empty() || !c.plane_shear.is_empty() {
        return Err(SceneError::Checkpoint(
            "it was written by a run with friction, which is not decomposed yet".into(),
        ));
    }
    // slot[id]: the checkpoint's entry of input body id.
    let mut slot = vec![usize::MAX; n];
    for (k, &id) in c.order.iter().enumerate() {
        match slot.get_mut(id as usize) {
            Some(s) if *s == usize::MAX => *s = k,
            _ => {
                return Err(SceneError::Checkpoint(format!(
                    "body order has a bad or repeated id {id}"
                )))
            }
        }
    }
    for &(a, b, _) in &c.pair_histories {
        if a as usize >= n || b as usize >= n {
            return Err(SceneError::Checkpoint(format!(
                "pair history of bodies {a}, {b} out of range"
            )));
        }
    }
    Ok(slot)
}

impl<T: Transport> DistributedSimulation<T> {
    /// The whole state at rank 0 in the engine's checkpoint format, bodies
    /// in input order (`Ok(None)` on the other ranks). Collective.
    pub fn checkpoint(&self) -> Result<Option<Checkpoint>, SceneError> {
        let w = &self.sim.world;
        refuse_checkpoint(w.friction.is_some())?;
        let b = &w.bodies;
        let np = w.planes.len();
        let reference = &self.sim.pipeline.reference;
        let mut out = Writer::default();
        let owned: Vec<usize> = (0..b.len()).filter(|&k| !self.halo[k]).collect();
        out.u32(owned.len() as u32);
        for &k in &owned {
            out.u32(b.id[k]);
            out.vec3(b.position[k]);
            out.vec3(b.velocity[k]);
            out.vec3(b.force[k]);
            out.vec3(reference.get(k).copied().unwrap_or(b.position[k]));
            let touching: Vec<(u32, ContactHistory)> = (0..np)
                .filter_map(|p| {
                    let h = w.wall_contacts.history.get(k * np + p).copied()?;
                    (h != ContactHistory::default()).then_some((p as u32, h))
                })
                .collect();
            out.u32(touching.len() as u32);
            for (p, h) in &touching {
                out.u32(*p);
                out.history(h);
            }
        }
        // Every listed pair has an owned body: a pair across a cut comes
        // from both its ranks, the same bits.
        let pairs = contacts::active_histories(b, &w.ghosts, &w.list, &w.histories);
        out.u32(pairs.len() as u32);
        for (a, c, h) in &pairs {
            out.u32(*a);
            out.u32(*c);
            out.history(h);
        }
        let Some(parts) = self.transport.gather(out.0) else {
            return Ok(None);
        };
        let n = self.fixed_by_id.len();
        let mut c = Checkpoint {
            steps_done: w.steps_done,
            dt: w.dt,
            order: (0..n as u32).collect(),
            position: vec![[0.0; 3]; n],
            velocity: vec![[0.0; 3]; n],
            force: vec![[0.0; 3]; n],
            higher: Vec::new(),
            reference: vec![[0.0; 3]; n],
            pair_histories: Vec::new(),
            plane_histories: Vec::new(),
            pair_tracks: Vec::new(),
            plane_tracks: Vec::new(),
            collisions: Vec::new(),
            initial_energy: self.sim.initial_energy,
            list_builds: w.rebuilds,
            angular_velocity: Vec::new(),
            torque: Vec::new(),
            pair_shear: Vec::new(),
            plane_shear: Vec::new(),
        };
        let mut seen = vec![false; n];
        let mut planes = BTreeMap::new();
        let mut histories = BTreeMap::new();
        for bytes in &parts {
            let mut r = Reader::new(bytes);
            for _ in 0..r.u32() {
                let id = r.u32() as usize;
                let (x, v, f, x0) = (r.vec3(), r.vec3(), r.vec3(), r.vec3());
                for _ in 0..r.u32() {
                    let (p, h) = (r.u32(), r.history());
                    planes.insert((id as u32, p), h);
                }
                if let Some(s) = seen.get_mut(id) {
                    *s = true;
                    c.position[id] = x;
                    c.velocity[id] = v;
                    c.force[id] = f;
                    c.reference[id] = x0;
                }
            }
            for _ in 0..r.u32() {
                let (a, b, h) = (r.u32(), r.u32(), r.history());
                histories.insert((a, b), h);
            }
        }
        if let Some(id) = seen.iter().position(|s| !s) {
            return Err(SceneError::input(format!(
                "checkpoint: body {id} is owned by no rank (a bug)"
            )));
        }
        c.plane_histories = planes
            .into_iter()
            .map(|((id, p), h)| (id, p, HistoryRecord::from(h)))
            .collect();
        c.pair_histories = histories
            .into_iter()
            .map(|((a, b), h)| (a, b, HistoryRecord::from(h)))
            .collect();
        Ok(Some(c))
    }

    /// Continues checkpoint `c` (written on any number of ranks, or by the
    /// one-process engine) of the same `setup` on this transport's ranks.
    /// Every rank passes the same checkpoint. Collective.
    pub fn restore(
        setup: &SceneSetup,
        c: &Checkpoint,
        threads: usize,
        grid: Option<[usize; 3]>,
        transport: T,
    ) -> Result<Self, SceneError> {
        let n = setup.spheres.len();
        let slot = check(c, n)?;
        let mut me = Self::new(setup, threads, grid, transport)?;
        if c.dt.to_bits() != me.sim.world.dt.to_bits() {
            return Err(SceneError::Checkpoint(format!(
                "its Δt is {} s, the scene's {} s",
                c.dt, me.sim.world.dt
            )));
        }
        let np = me.sim.world.planes.len();
        if let Some(&(id, p, _)) = c
            .plane_histories
            .iter()
            .find(|(id, p, _)| *id as usize >= n || *p as usize >= np)
        {
            return Err(SceneError::Checkpoint(format!(
                "wall history of body {id}, plane {p} out of range"
            )));
        }
        // Every body at its position of the last list build, its plane
        // histories as saved, no pair history (set after the build).
        {
            let w = &mut me.sim.world;
            let b = &mut w.bodies;
            let entries: Vec<usize> = b.id.iter().map(|&id| slot[id as usize]).collect();
            b.position = entries.iter().map(|&s| c.reference[s]).collect();
            b.velocity = entries.iter().map(|&s| c.velocity[s]).collect();
            b.force = entries.iter().map(|&s| c.force[s]).collect();
            let wc = &mut w.wall_contacts;
            wc.history.fill(ContactHistory::default());
            wc.touching.fill(0);
            let mut local = vec![usize::MAX; n];
            for (k, &id) in b.id.iter().enumerate() {
                local[id as usize] = k;
            }
            for &(id, p, h) in &c.plane_histories {
                let k = local[id as usize];
                if k == usize::MAX {
                    continue;
                }
                if let Some(slot) = wc.history.get_mut(k * np + p as usize) {
                    *slot = h.into();
                    wc.touching[k] |= 1u64 << p;
                }
            }
            w.histories.main.fill(ContactHistory::default());
            w.histories.extra.fill(ContactHistory::default());
        }
        // Owners under this rank count, the halo and the lists as built
        // (the re-balancing counts start here).
        me.balance = super::balance::Balance::default();
        me.rebuild();
        let w = &mut me.sim.world;
        if w.laws.history {
            let pairs: HashMap<(u32, u32), ContactHistory> = c
                .pair_histories
                .iter()
                .map(|&(a, b, h)| ((a, b), h.into()))
                .collect();
            let b = &w.bodies;
            let key = |i: usize, j: usize| {
                let (_, _, owner) = extended(b, &w.ghosts, j);
                let (x, y) = (b.id[i], b.id[owner]);
                (x.min(y), x.max(y))
            };
            for (i, k) in w.list.entries() {
                if let Some(h) = pairs.get(&key(i, w.list.j[k] as usize)) {
                    w.histories.main[k] = *h;
                }
            }
            for (q, &(i, j)) in w.list.extra.iter().enumerate() {
                if let Some(h) = pairs.get(&key(i as usize, j as usize)) {
                    w.histories.extra[q] = *h;
                }
            }
        }
        // The checkpointed step itself (halo copies too: every rank has
        // the whole checkpoint).
        let b = &mut w.bodies;
        let entries: Vec<usize> = b.id.iter().map(|&id| slot[id as usize]).collect();
        b.position = entries.iter().map(|&s| c.position[s]).collect();
        b.velocity = entries.iter().map(|&s| c.velocity[s]).collect();
        b.force = entries.iter().map(|&s| c.force[s]).collect();
        me.sim.pipeline.ghosts(w);
        w.steps_done = c.steps_done;
        w.rebuilds = c.list_builds;
        me.sim.initial_energy = c.initial_energy;
        // The boundary-particle walls' force for the observation at the
        // restart step: a pass of the pair stage whose effects are undone
        // (the forces and histories are the checkpoint's). Its damping
        // terms see the step's velocities, not the half-step ones the run
        // saw: that one observation differs by them.
        let saved = (
            me.sim.world.bodies.force.clone(),
            me.sim.world.histories.clone(),
        );
        me.pair_forces();
        me.sim.world.bodies.force = saved.0;
        me.sim.world.histories = saved.1;
        me.bytes_sent = 0;
        me.rebuild_bytes = 0;
        me.migrated = 0;
        me.steps_run = 0;
        me.stepping = 0.0;
        Ok(me)
    }
}
