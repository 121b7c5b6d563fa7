//! Checkpoint and restore of one process's run: the whole state in
//! input order (the engine's format, which a decomposed run reads and
//! writes too), restored bit for bit.

use std::collections::HashMap;

use dembound_physics::contact::ContactHistory;
use serde::{Deserialize, Serialize};

use super::Simulation;
use crate::dynamics::collisions::{Collision, Track};
use crate::dynamics::contacts::{self, PairHistories};
use crate::dynamics::friction::{self, WallShear};
use crate::error::SceneError;
use crate::fingerprint::Fingerprint;
use crate::pipeline::World;
use crate::setup::{SceneSetup, Scheme};
use crate::walls::WallElement;

impl Simulation {
    /// The full state, enough to continue bit for bit.
    pub fn checkpoint(&self) -> Checkpoint {
        let w = &self.world;
        let b = &w.bodies;
        let pairs = contacts::active_histories(b, &w.ghosts, &w.list, &w.histories)
            .into_iter()
            .map(|(a, c, h)| (a, c, HistoryRecord::from(h)))
            .collect();
        // Wall state by (input id, wall), bodies in the engine's order,
        // walls ascending: element 0 in the plane records, other elements
        // in `element_records`.
        let wc = &w.wall_contacts;
        let mut plane_histories = Vec::new();
        let mut plane_tracks = Vec::new();
        let mut plane_shear = Vec::new();
        let mut element_records = Vec::new();
        if wc.bodies() == b.len() {
            for i in 0..b.len() {
                for k in wc.range(i) {
                    let e = wc.entry(k);
                    let (id, p) = (b.id[i], e.key.wall);
                    if e.key.element != 0 {
                        if e.history != ContactHistory::default()
                            || e.shear != WallShear::default()
                            || e.track != Track::default()
                        {
                            element_records.push(ElementRecord {
                                id,
                                key: e.key,
                                history: HistoryRecord::from(e.history),
                                shear: e.shear,
                                track: e.track,
                            });
                        }
                        continue;
                    }
                    if e.history != ContactHistory::default() {
                        plane_histories.push((id, p, HistoryRecord::from(e.history)));
                    }
                    if e.track != Track::default() {
                        plane_tracks.push((id, p, e.track));
                    }
                    if e.shear != WallShear::default() {
                        plane_shear.push((id, p, e.shear));
                    }
                }
            }
        }
        let mut pair_tracks = Vec::new();
        if let Some(t) = &w.tracks {
            let mut m: Vec<_> = crate::pipeline::saved_tracks_public(w, t)
                .into_iter()
                .collect();
            m.sort_by_key(|(k, _)| *k);
            pair_tracks = m.into_iter().map(|((a, c), t)| (a, c, t)).collect();
        }
        Checkpoint {
            steps_done: w.steps_done,
            dt: w.dt,
            order: b.id.clone(),
            position: b.position.clone(),
            velocity: b.velocity.clone(),
            force: b.force.clone(),
            higher: b.higher.clone(),
            reference: self.pipeline.reference.clone(),
            pair_histories: pairs,
            plane_histories,
            pair_tracks,
            plane_tracks,
            collisions: w.collisions.clone(),
            initial_energy: self.initial_energy,
            fingerprint: self.fingerprint.clone(),
            list_builds: w.rebuilds,
            angular_velocity: if w.friction.is_some() {
                b.angular_velocity.clone()
            } else {
                Vec::new()
            },
            angular_higher: b.angular_higher.clone(),
            torque: if w.friction.is_some() {
                b.torque.clone()
            } else {
                Vec::new()
            },
            pair_shear: if w.friction.is_some() {
                friction::active_shear(b, &w.ghosts, &w.list, &w.shear)
            } else {
                Vec::new()
            },
            plane_shear,
            element_records,
            moving_walls: w.moving.as_ref().map(|m| m.record()),
            removed: w.removal.as_ref().map(|r| r.removed),
            outlets: w
                .removal
                .as_ref()
                .map_or_else(Vec::new, |r| r.by_outlet.clone()),
            gate_energy: w.gates.as_ref().map(|g| g.energy),
            inlets: crate::inlets::record(w),
        }
    }

    /// Continues a checkpointed run of the same `setup`.
    pub fn restore(
        setup: SceneSetup,
        checkpoint: &Checkpoint,
        threads: usize,
    ) -> Result<Self, SceneError> {
        let mut sim = Self::prepare(&setup, threads)?;
        checkpoint.fingerprint.check(&sim.fingerprint)?;
        // The checkpoint's walls on the scene's (`crate::restart_walls`).
        let change = crate::restart_walls::match_walls(checkpoint, &sim.fingerprint)?;
        let remapped;
        let c = if change.unchanged() {
            checkpoint
        } else {
            remapped = crate::restart_walls::remap(checkpoint, &change);
            &remapped
        };
        // The spheres the inlets inserted join the scene's (ids after
        // them; `crate::inlets`).
        crate::inlets::restore(&mut sim.world, c.inlets.as_ref())?;
        // The scene's bodies (input order), less those the run removed.
        let all = sim.world.bodies.len();
        let removed = match (c.removed, sim.world.removal.as_deref_mut()) {
            (Some(r), Some(removal)) => {
                removal.removed = r;
                if c.outlets.len() == removal.by_outlet.len() {
                    removal.by_outlet.clone_from(&c.outlets);
                }
                r.particles
            }
            _ => 0,
        };
        let n = usize::try_from(removed)
            .ok()
            .and_then(|r| all.checked_sub(r))
            .unwrap_or(usize::MAX);
        let same_len = |len: usize| len == n;
        if !(same_len(c.order.len())
            && same_len(c.position.len())
            && same_len(c.velocity.len())
            && same_len(c.force.len())
            && same_len(c.reference.len())
            && (c.higher.is_empty() || same_len(c.higher.len())))
        {
            return Err(SceneError::Checkpoint(format!(
                "it holds {} bodies, the scene {all} less the {removed} it removed",
                c.order.len()
            )));
        }
        if c.dt.to_bits() != sim.world.dt.to_bits() {
            return Err(SceneError::Checkpoint(format!(
                "its Δt is {} s, the scene's {} s",
                c.dt, sim.world.dt
            )));
        }
        let mut seen = vec![false; all];
        for &id in &c.order {
            if id as usize >= all || seen[id as usize] {
                return Err(SceneError::Checkpoint(format!(
                    "body order has a bad or repeated id {id}"
                )));
            }
            seen[id as usize] = true;
        }
        if sim.world.scheme == Scheme::Gear5 && c.higher.is_empty() {
            return Err(SceneError::Checkpoint(
                "it was written by a Verlet run, the scene uses Gear5".into(),
            ));
        }
        let w = &mut sim.world;
        w.bodies.permute(&c.order);
        w.wall_contacts.permute(&c.order);
        // The lists as they were built: from the positions of the last build
        // (already sorted, so the stable sort keeps this order).
        w.bodies.position.clone_from(&c.reference);
        w.bodies.velocity.clone_from(&c.velocity);
        if w.friction.is_some() {
            if !(same_len(c.angular_velocity.len()) && same_len(c.torque.len())) {
                return Err(SceneError::Checkpoint(
                    "it holds no spins: it was written by a run without friction".into(),
                ));
            }
            w.bodies.angular_velocity.clone_from(&c.angular_velocity);
            w.bodies.torque.clone_from(&c.torque);
            if w.scheme == Scheme::Gear5 {
                if !same_len(c.angular_higher.len()) {
                    return Err(SceneError::Checkpoint(
                        "it holds no Gear5 spin derivatives: it was written by a run \
                         without friction or with Verlet"
                            .into(),
                    ));
                }
                w.bodies.angular_higher.clone_from(&c.angular_higher);
            }
        }
        // The walls that act at the checkpoint's step, and G so far
        // (`walls::gate`).
        w.set_gates_at(c.steps_done);
        if let (Some(g), Some(e)) = (w.gates.as_deref_mut(), c.gate_energy) {
            g.energy = e;
        }
        // The walls where the lists were built from these positions.
        let moving = c.moving_walls.clone().filter(|_| w.moving.is_some());
        if let Some(m) = &moving {
            w.restore_servos(&m.servos, true, m.built_step);
            w.place_walls(m.built_step);
        }
        sim.pipeline.neighbours(w, &sim.workers);
        // The build sorts the bodies by cell: a checkpoint written in the
        // engine's order is already sorted (the order stays), one in
        // another order (a decomposed run's, input order) is not; the
        // arrays not moved with the bodies are taken by id.
        let mut entry = vec![0usize; all];
        for (k, &id) in c.order.iter().enumerate() {
            entry[id as usize] = k;
        }
        let by_id = |k: usize| entry[w.bodies.id[k] as usize];
        w.bodies.position = (0..n).map(|k| c.position[by_id(k)]).collect();
        w.bodies.force = (0..n).map(|k| c.force[by_id(k)]).collect();
        w.bodies.higher = if c.higher.is_empty() {
            Vec::new()
        } else {
            (0..n).map(|k| c.higher[by_id(k)]).collect()
        };
        w.ghosts.update(&w.bodies.position, &w.bodies.velocity);
        w.steps_done = c.steps_done;
        w.rebuilds = c.list_builds;
        w.collisions.clone_from(&c.collisions);
        if let Some(m) = &moving {
            w.restore_servos(&m.servos, false, c.steps_done);
        }
        w.place_walls(c.steps_done);
        if let (Some(r), Some(m)) = (moving, w.moving.as_mut()) {
            m.work = r.work;
            m.power = r.power;
            m.group_power = r.group_power.unwrap_or(0.0);
        }
        sim.initial_energy = c.initial_energy;
        // Histories and tracks by input ids.
        let pairs: HashMap<(u32, u32), ContactHistory> = c
            .pair_histories
            .iter()
            .map(|&(a, b, h)| ((a, b), h.into()))
            .collect();
        let tracks: HashMap<(u32, u32), Track> =
            c.pair_tracks.iter().map(|&(a, b, t)| ((a, b), t)).collect();
        let key_of = |w: &World, i: usize, j: usize| {
            let (_, _, owner) = contacts::extended(&w.bodies, &w.ghosts, j);
            let (a, b) = (w.bodies.id[i], w.bodies.id[owner]);
            (a.min(b), a.max(b))
        };
        let keep = w.laws.history;
        let mut main = vec![ContactHistory::default(); if keep { w.list.j.len() } else { 0 }];
        let mut extra = vec![ContactHistory::default(); if keep { w.list.extra.len() } else { 0 }];
        let mut tmain = vec![Track::default(); w.list.j.len()];
        let mut textra = vec![Track::default(); w.list.extra.len()];
        for (i, k) in w.list.entries() {
            let key = key_of(w, i, w.list.j[k] as usize);
            if let (Some(h), Some(slot)) = (pairs.get(&key), main.get_mut(k)) {
                *slot = *h;
            }
            if let Some(t) = tracks.get(&key) {
                tmain[k] = *t;
            }
        }
        for (k, &(i, j)) in w.list.extra.iter().enumerate() {
            let key = key_of(w, i as usize, j as usize);
            if let (Some(h), Some(slot)) = (pairs.get(&key), extra.get_mut(k)) {
                *slot = *h;
            }
            if let Some(t) = tracks.get(&key) {
                textra[k] = *t;
            }
        }
        w.histories = PairHistories { main, extra };
        if w.friction.is_some() {
            let saved: HashMap<(u32, u32), friction::Springs> =
                c.pair_shear.iter().map(|&(a, b, s)| ((a, b), s)).collect();
            let rolling = w.friction.as_ref().is_some_and(|t| t.rolling());
            w.shear = friction::restore_shear(&w.bodies, &w.ghosts, &w.list, &saved, rolling);
        }
        if let Some(t) = w.tracks.as_mut() {
            t.main = tmain;
            t.extra = textra;
        }
        let at: Vec<usize> = w
            .bodies
            .index_of_ids()
            .into_iter()
            .map(|k| {
                if k == crate::bodies::REMOVED {
                    usize::MAX
                } else {
                    k as usize
                }
            })
            .collect();
        restore_wall_records(w, c, &at)?;
        if !change.unchanged() {
            crate::restart_walls::book_added(w, &change, c.gate_energy, true);
            sim.restart_notes = change.notes;
        }
        // The wall loads are not in the checkpoint.
        sim.pipeline.record_wall_loads(&mut sim.world, &sim.workers);
        // D_c (`output.dissipation`) goes on from the residual D at the
        // checkpoint: the balance error before it is not in the checkpoint.
        if sim.world.dissipation.is_some() {
            sim.world.start_dissipation();
            let o = sim.observe();
            if let (Some(d), Some(dc)) = (sim.world.dissipation.as_mut(), o.dissipated_by_contacts)
            {
                d.offset = o.dissipated_energy - dc;
            }
        }
        Ok(sim)
    }
}

/// Puts a checkpoint's wall records (histories, springs, tracks by input
/// id and wall) into the lists just built; `local[id]`: the body's index
/// here (`usize::MAX`: held by another rank, its records skipped).
pub(crate) fn restore_wall_records(
    w: &mut World,
    c: &Checkpoint,
    local: &[usize],
) -> Result<(), SceneError> {
    let np = w.surfaces.len() as u32;
    let tracked = w.tracks.is_some();
    let plane = |p: u32| WallElement {
        wall: p,
        element: 0,
    };
    type Record = (
        u32,
        WallElement,
        Option<HistoryRecord>,
        Option<WallShear>,
        Option<Track>,
    );
    let mut records: Vec<(Record, &str)> = Vec::new();
    for &(id, p, h) in &c.plane_histories {
        records.push(((id, plane(p), Some(h), None, None), "history"));
    }
    for &(id, p, sh) in &c.plane_shear {
        records.push(((id, plane(p), None, Some(sh), None), "displacement"));
    }
    if tracked {
        for &(id, p, tr) in &c.plane_tracks {
            records.push(((id, plane(p), None, None, Some(tr)), "track"));
        }
    }
    for r in &c.element_records {
        let history =
            (ContactHistory::from(r.history) != ContactHistory::default()).then_some(r.history);
        let shear = (r.shear != WallShear::default()).then_some(r.shear);
        let track = (tracked && r.track != Track::default()).then_some(r.track);
        records.push(((r.id, r.key, history, shear, track), "record"));
    }
    // A wall that does not act at this step has no entries (`walls::gate`:
    // a record of one, from a restart that changed its window, is dropped).
    let acts = |p: u32| {
        w.gates
            .as_deref()
            .is_none_or(|g| g.active.get(p as usize).copied().unwrap_or(true))
    };
    let acting: Vec<bool> = (0..np).map(acts).collect();
    let wc = &mut w.wall_contacts;
    // Every entry first (an insertion moves the later ones), then the state.
    for ((id, key, ..), what) in &records {
        let (id, key) = (*id, *key);
        let Some(&i) = local.get(id as usize).filter(|_| key.wall < np) else {
            return Err(SceneError::Checkpoint(format!(
                "wall {what} of body {id}, plane {} out of range",
                key.wall
            )));
        };
        if i != usize::MAX && acting[key.wall as usize] {
            wc.insert(i, key);
        }
    }
    for ((id, key, h, sh, tr), _) in records {
        let i = local[id as usize];
        let Some(k) = (i != usize::MAX).then(|| wc.find(i, key)).flatten() else {
            continue;
        };
        if let Some(h) = h {
            if let Some(slot) = wc.history.get_mut(k) {
                *slot = h.into();
                wc.touching[k] = true;
            }
        }
        if let Some(sh) = sh {
            if let Some(slot) = wc.shear.get_mut(k) {
                *slot = sh;
                wc.touching[k] = true;
            }
        }
        if let Some(tr) = tr {
            if let Some(slot) = wc.track.get_mut(k) {
                *slot = tr;
            }
        }
    }
    Ok(())
}

/// A wall element's state other than a plane's (element > 0) as stored in
/// a checkpoint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ElementRecord {
    /// Input id of the body.
    pub id: u32,
    pub key: WallElement,
    pub history: HistoryRecord,
    pub shear: WallShear,
    pub track: Track,
}

/// A contact history as stored in a checkpoint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HistoryRecord {
    /// m.
    pub max_overlap: f64,
    /// On the unloading branch (hysteretic laws).
    #[serde(default)]
    pub unloading: bool,
}

impl From<ContactHistory> for HistoryRecord {
    fn from(h: ContactHistory) -> Self {
        Self {
            max_overlap: h.max_overlap,
            unloading: h.unloading,
        }
    }
}

impl From<HistoryRecord> for ContactHistory {
    fn from(h: HistoryRecord) -> Self {
        ContactHistory {
            max_overlap: h.max_overlap,
            unloading: h.unloading,
        }
    }
}

/// Everything needed to continue a run bit for bit. Per-body arrays are in
/// the engine's order at the time (`order` gives each entry's input index).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    pub steps_done: u64,
    /// s.
    pub dt: f64,
    pub order: Vec<u32>,
    pub position: Vec<[f64; 3]>,
    pub velocity: Vec<[f64; 3]>,
    pub force: Vec<[f64; 3]>,
    /// Gear5's scaled derivatives (empty for Verlet).
    pub higher: Vec<[[f64; 3]; 4]>,
    /// Positions at the last list build.
    pub reference: Vec<[f64; 3]>,
    /// (input id a < b, history) of pairs in contact.
    pub pair_histories: Vec<(u32, u32, HistoryRecord)>,
    /// (input id, plane index, history).
    pub plane_histories: Vec<(u32, u32, HistoryRecord)>,
    /// The collision log's tracks of pairs (input ids a < b) and of
    /// plane walls (input id, plane index), in columns (format 4; formats
    /// 2 and 3's list of triples still read: `keyed_columns`).
    #[serde(with = "super::keyed_columns")]
    pub pair_tracks: Vec<(u32, u32, Track)>,
    #[serde(with = "super::keyed_columns")]
    pub plane_tracks: Vec<(u32, u32, Track)>,
    /// The completed contacts (the collision log so far), stored in
    /// columns of fixed-width values (format 3; format 2's list of rows is
    /// still read: `collision_columns`).
    #[serde(with = "super::collision_columns")]
    pub collisions: Vec<Collision>,
    /// J.
    pub initial_energy: f64,
    /// The scene that wrote it: a restart refuses another.
    pub fingerprint: Fingerprint,
    pub list_builds: u64,
    /// rad/s, engine order (friction only).
    #[serde(default)]
    pub angular_velocity: Vec<[f64; 3]>,
    /// N m, engine order (friction only).
    #[serde(default)]
    pub torque: Vec<[f64; 3]>,
    /// (input id a < b, springs seen from a: tangential displacement of
    /// a relative to b, m, and rolling torque on a, N m).
    #[serde(default)]
    pub pair_shear: Vec<(u32, u32, friction::Springs)>,
    /// (input id, plane index, displacement record).
    #[serde(default)]
    pub plane_shear: Vec<(u32, u32, WallShear)>,
    /// Gear5 with friction: the spins' scaled derivatives r₁..r₄, rad/s,
    /// engine order (empty otherwise; `dynamics::gear5_rotation`).
    #[serde(default)]
    pub angular_higher: Vec<[[f64; 3]; 4]>,
    /// The state of wall elements other than element 0 (a cylinder's
    /// caps), in the engine's body order, walls and elements ascending
    /// (absent from the file when empty: scenes of planes keep their
    /// bytes).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub element_records: Vec<ElementRecord>,
    /// The moving walls' list-build step, work and power (issue 27;
    /// absent when every wall is fixed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moving_walls: Option<crate::pipeline::moving_walls::MovingWallsRecord>,
    /// The spheres removed so far, their mass and the energy they carried
    /// out (`crate::removal`; absent when the scene removes none). The
    /// removed spheres are those whose input index `order` lacks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub removed: Option<crate::removal::Removed>,
    /// What each outlet removed so far (file order; absent without
    /// outlets).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outlets: Vec<crate::removal::OutletRemoved>,
    /// The gate energy G booked so far, J (`walls::gate`; absent when
    /// every wall acts always).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gate_energy: Option<f64>,
    /// The spheres the inlets inserted and each inlet's counts
    /// (`crate::inlets`; absent without inlets).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inlets: Option<crate::inlets::InletsRecord>,
}
