//! Checkpoint and restart of a decomposed run (issue 16), in the engine's
//! own checkpoint format ([`Checkpoint`], `io::checkpoint`), so that a
//! checkpoint written on any number of ranks, or by the one-process
//! engine, continues on any number of ranks.
//!
//! - [`DistributedSimulation::checkpoint`] gathers every rank's owned
//!   bodies at rank 0, in input-id order: position, velocity, force,
//!   position at the last list build, plane-wall histories (and spins,
//!   torques, plane springs, Gear5 derivatives); the pair
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
//! Friction runs carry their spins, torques and pair and plane springs,
//! Gear5 runs their derivatives r₂..r₅.
//!
//! Because each body's force is summed in an order the whole scene fixes
//! (the cells of the last list build, then ids: the restart rebuilds at
//! the same positions), the decomposed trajectory does not depend on the
//! decomposition: k steps on 2 ranks, a checkpoint, and k more on 3 ranks
//! (or 1) end in the same bits as 2k steps in one go
//! (tests/decomposition_checkpoint.rs).

use std::collections::HashMap;

use dembound_physics::contact::ContactHistory;

use super::DistributedSimulation;
use crate::comm::Transport;
use crate::dynamics::collisions::Track;
use crate::dynamics::contacts::extended;
use crate::dynamics::friction;
use crate::fingerprint::Fingerprint;
use crate::setup::{SceneSetup, Scheme};
use crate::simulation::Checkpoint;
use crate::SceneError;

/// Checks a checkpoint against the scene before anything is exchanged
/// (every rank reads the same file: every rank gives the same answer).
fn check(
    c: &Checkpoint,
    all: usize,
    gear5: bool,
    friction: bool,
) -> Result<Vec<usize>, SceneError> {
    // The scene's bodies less those the run removed (`crate::removal`).
    let removed = c.removed.map_or(0, |r| r.particles);
    let n = usize::try_from(removed)
        .ok()
        .and_then(|r| all.checked_sub(r))
        .unwrap_or(usize::MAX);
    check_bodies(c, n, all, gear5, friction)
}

/// [`check`] for `n` bodies of the scene's `all` (a part of a checkpoint
/// written per rank holds some of them: [`super::checkpoint_parts`]).
pub(super) fn check_bodies(
    c: &Checkpoint,
    n: usize,
    all: usize,
    gear5: bool,
    friction: bool,
) -> Result<Vec<usize>, SceneError> {
    let removed = c.removed.map_or(0, |r| r.particles);
    let lens = [
        c.order.len(),
        c.position.len(),
        c.velocity.len(),
        c.force.len(),
        c.reference.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(SceneError::Checkpoint(format!(
            "it holds {} bodies, the scene {all} less the {removed} it removed",
            c.order.len()
        )));
    }
    if gear5 == c.higher.is_empty() || (gear5 && c.higher.len() != n) {
        return Err(SceneError::Checkpoint(if gear5 {
            "it holds no Gear5 derivatives: it was written by a Verlet run".into()
        } else {
            "it was written by a Gear5 run; the scene is Verlet".into()
        }));
    }
    let spins = c.angular_velocity.len() == n && c.torque.len() == n;
    if friction && !spins {
        return Err(SceneError::Checkpoint(
            "it holds no spins: it was written by a run without friction".into(),
        ));
    }
    if gear5 && friction && c.angular_higher.len() != n {
        return Err(SceneError::Checkpoint(
            "it holds no Gear5 spin derivatives: it was written by a run without friction \
             or with Verlet"
                .into(),
        ));
    }
    if !friction && (!c.angular_velocity.is_empty() || !c.pair_shear.is_empty()) {
        return Err(SceneError::Checkpoint(
            "it was written by a run with friction; the scene has none".into(),
        ));
    }
    // slot[id]: the checkpoint's entry of input body id (MAX: removed).
    let mut slot = vec![usize::MAX; all];
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
        if a as usize >= all || b as usize >= all {
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
        let out = self.checkpoint_records();
        let mut c = self.checkpoint_globals();
        // A run whose ranks made their own parts of the spheres holds no
        // list of them: the fingerprint's is gathered (collective).
        let n = self.comm.fixed_by_id.len();
        let gathered = (self.sim.fingerprint.radius.len() != n)
            .then(|| self.gather_state())
            .flatten();
        let Some(parts) = self.comm.transport.gather(out.0) else {
            return Ok(None);
        };
        c.fingerprint = match gathered {
            Some(g) => {
                let mut f = self.sim.fingerprint.clone();
                f.radius = g.radius;
                f.material = g.material;
                f.fixed = g.fixed;
                f
            }
            None => self.sim.fingerprint.clone(),
        };
        self.assemble(&mut c, &parts);
        // The removed spheres are owned by no rank (`crate::removal`): the
        // checkpoint lists the others.
        let removed = c.removed.map_or(0, |r| r.particles as usize);
        if c.order.len() + removed != n {
            let mut seen = vec![false; n];
            for &id in &c.order {
                if let Some(s) = seen.get_mut(id as usize) {
                    *s = true;
                }
            }
            if let Some(id) = seen.iter().position(|s| !s) {
                return Err(SceneError::input(format!(
                    "checkpoint: body {id} is owned by no rank (a bug)"
                )));
            }
        }
        Ok(Some(c))
    }

    /// This rank's part of the checkpoint (`[parallel] checkpoint_per_rank`,
    /// [`super::checkpoint_parts`]): the bodies it owns in input order, its
    /// listed pairs' histories and springs (a pair across a cut is in both
    /// ranks' parts, the same bits), and the run's shared figures (the
    /// collision log merged at rank 0 only). The fingerprint's per-body
    /// lists are those of the bodies here. Collective (the log, the
    /// moving walls' and gates' sums); no body crosses ranks.
    pub fn checkpoint_part(&self) -> Checkpoint {
        let out = self.checkpoint_records();
        let mut c = self.checkpoint_globals();
        self.assemble(&mut c, &[out.0]);
        if self.comm.transport.rank() != 0 {
            c.collisions.clear();
        }
        // The owned bodies' radii, materials and fixedness, in id order.
        let b = &self.sim.world.bodies;
        let mut own: Vec<usize> = (0..b.len()).filter(|&k| !self.comm.halo[k]).collect();
        own.sort_unstable_by_key(|&k| b.id[k]);
        c.fingerprint = crate::fingerprint::Fingerprint {
            settings: self.sim.fingerprint.settings.clone(),
            radius: own.iter().map(|&k| b.radius[k]).collect(),
            material: own.iter().map(|&k| b.material[k]).collect(),
            fixed: own.iter().map(|&k| b.fixed[k]).collect(),
        };
        c
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
        crate::inlets::refuse_restart_under_mpi(&setup.inlets)?;
        let n = setup.spheres.len();
        let gear5 = setup.integration.scheme == Scheme::Gear5;
        let scene = Fingerprint::of(setup);
        c.fingerprint.check(&scene)?;
        // The checkpoint's walls on the scene's (`crate::restart_walls`).
        let change = crate::restart_walls::match_walls(c, &scene)?;
        let remapped;
        let c = if change.unchanged() {
            c
        } else {
            remapped = crate::restart_walls::remap(c, &change);
            &remapped
        };
        let slot = check(c, n, gear5, setup.friction.is_some())?;
        let mut me = Self::new(setup, threads, grid, transport)?;
        me.check_dt(c)?;
        me.restore_bodies(c, &slot)?;
        me.restore_after_rebuild(c, &slot, &change);
        Ok(me)
    }

    /// Refuses a checkpoint whose Δt is not the scene's (the same answer
    /// on every rank: every rank has the same figures).
    pub(super) fn check_dt(&self, c: &Checkpoint) -> Result<(), SceneError> {
        if c.dt.to_bits() != self.sim.world.dt.to_bits() {
            return Err(SceneError::Checkpoint(format!(
                "its Δt is {} s, the scene's {} s",
                c.dt, self.sim.world.dt
            )));
        }
        Ok(())
    }

    /// The restart up to the list build: every body held here at its
    /// position of the last list build with its velocity, force,
    /// derivatives, spins and wall records from `c` (`slot[id]`: its entry
    /// in `c`, `usize::MAX`: none), the removed spheres dropped, then the
    /// bodies to their owners, the halo and the lists as the run had
    /// them. `c` holds at least every body held here. Collective.
    pub(super) fn restore_bodies(
        &mut self,
        c: &Checkpoint,
        slot: &[usize],
    ) -> Result<(), SceneError> {
        let me = self;
        let n = slot.len();
        let np = me.sim.world.surfaces.len();
        if let Some(&(id, p, _)) = c
            .plane_histories
            .iter()
            .find(|(id, p, _)| *id as usize >= n || *p as usize >= np)
        {
            return Err(SceneError::Checkpoint(format!(
                "wall history of body {id}, plane {p} out of range"
            )));
        }
        // The spheres the run removed leave (`crate::removal`), with the
        // lists built for them.
        if let (Some(r), Some(removal)) = (c.removed, me.sim.world.removal.as_deref_mut()) {
            removal.removed = r;
            if c.outlets.len() == removal.by_outlet.len() {
                removal.by_outlet.clone_from(&c.outlets);
            }
            let w = &mut me.sim.world;
            let keep: Vec<u32> = (0..w.bodies.len() as u32)
                .filter(|&k| slot[w.bodies.id[k as usize] as usize] != usize::MAX)
                .collect();
            if keep.len() != w.bodies.len() {
                super::select(w, &keep);
                me.comm.halo = keep.iter().map(|&k| me.comm.halo[k as usize]).collect();
                w.list = Default::default();
                w.histories = Default::default();
                w.shear = Default::default();
                if let Some(t) = w.tracks.as_mut() {
                    *t = Default::default();
                }
            }
        }
        // Every body at its position of the last list build, its plane
        // histories as saved, no pair history (set after the build).
        {
            let w = &mut me.sim.world;
            let b = &mut w.bodies;
            for k in 0..b.len() {
                let s = slot[b.id[k] as usize];
                let (Some(x0), Some(v), Some(f)) =
                    (c.reference.get(s), c.velocity.get(s), c.force.get(s))
                else {
                    continue;
                };
                (b.position[k], b.velocity[k], b.force[k]) = (*x0, *v, *f);
                // Derivatives and spins travel with the bodies.
                if let (Some(h), Some(ch)) = (b.higher.get_mut(k), c.higher.get(s)) {
                    *h = *ch;
                }
                if let (Some(a), Some(ca)) =
                    (b.angular_velocity.get_mut(k), c.angular_velocity.get(s))
                {
                    *a = *ca;
                }
                if let (Some(a), Some(ca)) = (b.angular_higher.get_mut(k), c.angular_higher.get(s))
                {
                    *a = *ca;
                }
            }
            // Body id → local body; each body's wall records as saved
            // (they migrate with it).
            let mut local = vec![usize::MAX; n];
            for (k, &id) in b.id.iter().enumerate() {
                local[id as usize] = k;
            }
            // The walls that act at the checkpoint's step (`walls::gate`);
            // G so far at rank 0, the others' shares from zero.
            w.set_gates_at(c.steps_done);
            let first = me.comm.transport.rank() == 0;
            if let Some(g) = w.gates.as_deref_mut() {
                g.energy = if first {
                    c.gate_energy.unwrap_or(0.0)
                } else {
                    0.0
                };
            }
            w.wall_contacts.relax();
            crate::simulation::restore_wall_records(w, c, &local)?;
            w.histories.main.fill(ContactHistory::default());
            w.histories.extra.fill(ContactHistory::default());
        }
        // Owners under this rank count, the halo and the lists as built
        // (the re-balancing counts start here).
        me.comm.balance = super::balance::Balance::default();
        // The walls where the lists were built (`Simulation::restore`).
        let moving = c
            .moving_walls
            .clone()
            .filter(|_| me.sim.world.moving.is_some());
        if let Some(m) = &moving {
            me.sim.world.restore_servos(&m.servos, true, m.built_step);
            me.sim.world.place_walls(m.built_step);
        }
        me.rebuild();
        Ok(())
    }

    /// The restart after the list build: the pair histories, tracks and
    /// springs of `c` by input ids, the checkpointed step's positions,
    /// velocities, forces and torques of every body held here (halo
    /// copies too; `slot` as [`Self::restore_bodies`]), the run's books,
    /// and the walls' loads of the restart step. Collective.
    pub(super) fn restore_after_rebuild(
        &mut self,
        c: &Checkpoint,
        slot: &[usize],
        change: &crate::restart_walls::WallChange,
    ) {
        let me = self;
        let moving = c
            .moving_walls
            .clone()
            .filter(|_| me.sim.world.moving.is_some());
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
        if let Some(t) = w.tracks.as_mut() {
            let saved: HashMap<(u32, u32), Track> =
                c.pair_tracks.iter().map(|&(a, b, t)| ((a, b), t)).collect();
            let b = &w.bodies;
            let key = |i: usize, j: usize| {
                let (_, _, owner) = extended(b, &w.ghosts, j);
                let (x, y) = (b.id[i], b.id[owner]);
                (x.min(y), x.max(y))
            };
            t.main = vec![Track::default(); w.list.j.len()];
            t.extra = vec![Track::default(); w.list.extra.len()];
            for (i, k) in w.list.entries() {
                if let Some(tr) = saved.get(&key(i, w.list.j[k] as usize)) {
                    t.main[k] = *tr;
                }
            }
            for (q, &(i, j)) in w.list.extra.iter().enumerate() {
                if let Some(tr) = saved.get(&key(i as usize, j as usize)) {
                    t.extra[q] = *tr;
                }
            }
            // The log so far, once: at rank 0.
            if me.comm.transport.rank() == 0 {
                w.collisions.clone_from(&c.collisions);
                me.comm.collision_steps = vec![c.steps_done; c.collisions.len()];
                me.comm.restored_collisions = c.collisions.len();
            }
        }
        if let Some(table) = w.friction.as_ref() {
            let springs: HashMap<(u32, u32), friction::Springs> =
                c.pair_shear.iter().map(|&(a, b, s)| ((a, b), s)).collect();
            w.shear =
                friction::restore_shear(&w.bodies, &w.ghosts, &w.list, &springs, table.rolling());
        }
        // The checkpointed step itself (halo copies too: `c` holds every
        // body held here).
        let b = &mut w.bodies;
        for k in 0..b.len() {
            let s = slot[b.id[k] as usize];
            let (Some(x), Some(v), Some(f)) =
                (c.position.get(s), c.velocity.get(s), c.force.get(s))
            else {
                continue;
            };
            (b.position[k], b.velocity[k], b.force[k]) = (*x, *v, *f);
            if let (Some(t), Some(ct)) = (b.torque.get_mut(k), c.torque.get(s)) {
                *t = *ct;
            }
        }
        me.sim.pipeline.ghosts(w);
        w.steps_done = c.steps_done;
        w.rebuilds = c.list_builds;
        me.sim.initial_energy = c.initial_energy;
        if let Some(m) = &moving {
            w.restore_servos(&m.servos, false, c.steps_done);
        }
        w.place_walls(c.steps_done);
        // The work so far and the last power at rank 0, the others' shares
        // start from zero (the observation sums them).
        let first = me.comm.transport.rank() == 0;
        if let (Some(r), Some(m)) = (moving, w.moving.as_mut()) {
            (m.work, m.power) = if first { (r.work, r.power) } else { (0.0, 0.0) };
            m.group_power = match r.group_power {
                Some(p) if first => p,
                _ => 0.0,
            };
        }
        // The boundary-particle walls' force for the observation at the
        // restart step: a pass of the pair stage whose effects are undone
        // (the forces and histories are the checkpoint's). Its damping
        // terms see the step's velocities, not the half-step ones the run
        // saw: that one observation differs by them.
        let w = &mut me.sim.world;
        let saved = (
            w.bodies.force.clone(),
            w.histories.clone(),
            w.bodies.torque.clone(),
            w.shear.clone(),
        );
        // The pair stage adds onto the forces: the boundary particles'
        // start from zero, as in a step.
        for k in 0..w.bodies.len() {
            if w.bodies.fixed[k] {
                w.bodies.force[k] = [0.0; 3];
                if w.in_moving_group(w.bodies.id[k]) {
                    if let Some(t) = w.bodies.torque.get_mut(k) {
                        *t = [0.0; 3];
                    }
                }
            }
        }
        me.pair_forces();
        let w = &mut me.sim.world;
        // A moving group's copies keep what this pass gave them: this
        // rank's share of their load (`pipeline::moving_groups`; the
        // checkpoint holds one copy's per sphere).
        let mut force = saved.0;
        let mut torque = saved.2;
        for (k, f) in force.iter_mut().enumerate() {
            if w.bodies.fixed[k] && w.in_moving_group(w.bodies.id[k]) {
                *f = w.bodies.force[k];
                if let (Some(t), Some(now)) = (torque.get_mut(k), w.bodies.torque.get(k)) {
                    *t = *now;
                }
            }
        }
        w.bodies.force = force;
        w.histories = saved.1;
        w.bodies.torque = torque;
        w.shear = saved.3;
        if !change.unchanged() {
            let first = me.comm.transport.rank() == 0;
            crate::restart_walls::book_added(&mut me.sim.world, change, c.gate_energy, first);
            me.sim.restart_notes.clone_from(&change.notes);
        }
        // The walls' loads (not in the checkpoint), as the note above.
        me.sim
            .pipeline
            .record_wall_loads(&mut me.sim.world, &me.sim.workers);
        me.comm.bytes_sent = 0;
        me.comm.rebuild_bytes = 0;
        me.comm.migrated = 0;
        me.steps_run = 0;
        me.stepping = 0.0;
    }
}
