//! The records of a decomposed run's checkpoint (issue 16): what each
//! rank contributes of its owned bodies and listed pairs
//! ([`DistributedSimulation::checkpoint_records`]), the figures the whole
//! run shares ([`DistributedSimulation::checkpoint_globals`]), and the
//! checkpoint assembled from some ranks' records
//! ([`DistributedSimulation::assemble`]): all of them gathered at rank 0
//! (`super::checkpoint`), or one rank's own part
//! (`super::checkpoint_parts`).

use std::collections::BTreeMap;

use dembound_physics::contact::ContactHistory;

use super::DistributedSimulation;
use crate::comm::pack::{self, Reader, Writer};
use crate::comm::Transport;
use crate::dynamics::collisions::Track;
use crate::dynamics::contacts;
use crate::dynamics::friction::{self, WallShear};
use crate::setup::Scheme;
use crate::simulation::{Checkpoint, ElementRecord, HistoryRecord};
use crate::walls::near::NearEntry;

/// The bodies' records while a checkpoint is assembled, in arrival
/// order (the lists of [`Checkpoint`]'s bodies: as compact as the
/// checkpoint itself).
#[derive(Default)]
struct BodyLists {
    id: Vec<u32>,
    x: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    f: Vec<[f64; 3]>,
    x0: Vec<[f64; 3]>,
    higher: Vec<[[f64; 3]; 4]>,
    angular_higher: Vec<[[f64; 3]; 4]>,
    w: Vec<[f64; 3]>,
    t: Vec<[f64; 3]>,
}

/// `v` in the order `perm` (entries of `v`), one list at a time.
fn permuted<T: Copy>(v: Vec<T>, perm: &[u32]) -> Vec<T> {
    if v.is_empty() {
        return v;
    }
    perm.iter().map(|&k| v[k as usize]).collect()
}

impl<T: Transport> DistributedSimulation<T> {
    /// This rank's owned bodies' records and its listed pairs' (what
    /// [`Self::assemble`] reads). No communication.
    pub(super) fn checkpoint_records(&self) -> Writer {
        let w = &self.sim.world;
        let b = &w.bodies;
        let wc = &w.wall_contacts;
        let elements = w.surfaces.iter().any(|s| s.wall().elements() > 1);
        // Body k's element-0 entries (wall, state) and its other ones.
        let entries = |k: usize| -> Vec<NearEntry> {
            if k < wc.bodies() {
                wc.entries(k)
            } else {
                Vec::new()
            }
        };
        let (spin, gear5) = (w.friction.is_some(), w.scheme == Scheme::Gear5);
        let reference = &self.sim.pipeline.reference;
        let mut out = Writer::default();
        let owned: Vec<usize> = (0..b.len()).filter(|&k| !self.comm.halo[k]).collect();
        out.u32(owned.len() as u32);
        for &k in &owned {
            out.u32(b.id[k]);
            out.vec3(b.position[k]);
            out.vec3(b.velocity[k]);
            out.vec3(b.force[k]);
            out.vec3(reference.get(k).copied().unwrap_or(b.position[k]));
            if gear5 {
                pack::write_higher(&mut out, &b.higher, k);
                if spin {
                    pack::write_angular_higher(&mut out, &b.angular_higher, k);
                }
            }
            if spin {
                out.vec3(b.angular_velocity[k]);
                out.vec3(b.torque.get(k).copied().unwrap_or_default());
                let moved: Vec<(u32, WallShear)> = entries(k)
                    .into_iter()
                    .filter(|e| e.key.element == 0 && e.shear != WallShear::default())
                    .map(|e| (e.key.wall, e.shear))
                    .collect();
                out.u32(moved.len() as u32);
                for (p, s) in &moved {
                    out.u32(*p);
                    pack::write_wall_shear(&mut out, std::slice::from_ref(s), 1, 0);
                }
            }
            if w.tracks.is_some() {
                let planes: Vec<(u32, Track)> = entries(k)
                    .into_iter()
                    .filter(|e| e.key.element == 0 && e.track.is_known())
                    .map(|e| (e.key.wall, e.track))
                    .collect();
                out.blob(&pack::encode(&planes));
            }
            let touching: Vec<(u32, ContactHistory)> = entries(k)
                .into_iter()
                .filter(|e| e.key.element == 0 && e.history != ContactHistory::default())
                .map(|e| (e.key.wall, e.history))
                .collect();
            out.u32(touching.len() as u32);
            for (p, h) in &touching {
                out.u32(*p);
                out.history(h);
            }
            // Elements other than 0 (a cylinder's caps), when a wall has
            // them.
            if !elements {
                continue;
            }
            let others: Vec<ElementRecord> = entries(k)
                .into_iter()
                .filter(|e| {
                    e.key.element != 0
                        && (e.history != ContactHistory::default()
                            || e.shear != WallShear::default()
                            || e.track.is_known())
                })
                .map(|e| ElementRecord {
                    id: b.id[k],
                    key: e.key,
                    history: HistoryRecord::from(e.history),
                    shear: e.shear,
                    track: e.track,
                })
                .collect();
            out.blob(&pack::encode(&others));
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
        if let Some(t) = w.tracks.as_ref() {
            let m: Vec<((u32, u32), Track)> = crate::pipeline::saved_tracks_public(w, t)
                .into_iter()
                .collect();
            out.blob(&pack::encode(&m));
        }
        if spin {
            let springs = friction::active_shear(b, &w.ghosts, &w.list, &w.shear);
            out.u32(springs.len() as u32);
            for (a, c, sp) in &springs {
                out.u32(*a);
                out.u32(*c);
                for x in sp {
                    out.f64(*x);
                }
            }
        }
        out
    }

    /// The checkpoint's figures shared by the whole run (step, Δt, energy,
    /// the moving walls', gates' and removals' books, the collision log at
    /// rank 0), with no bodies yet and no fingerprint lists. Collective.
    pub(super) fn checkpoint_globals(&self) -> Checkpoint {
        let w = &self.sim.world;
        // The collision log so far, merged (collective, on every rank).
        let log = if w.tracks.is_some() {
            self.collisions()
        } else {
            None
        };
        // The moving walls' work and power: each rank's share, summed
        // (collective, on every rank).
        let moving = w.moving.as_ref().map(|m| {
            let s = self.comm.transport.sum(&[m.work, m.power, m.group_power]);
            crate::pipeline::moving_walls::MovingWallsRecord {
                built_step: m.built_step,
                work: s[0],
                power: s[1],
                // The same on every rank (`servo_walls`).
                servos: m.servos.iter().map(|d| d.record()).collect(),
                // The moving groups' power: each rank's share, summed.
                group_power: (!m.groups.is_empty()).then_some(s[2]),
            }
        });
        // The gate energy: each rank's share, summed (collective).
        let gate_energy = w
            .gates
            .as_ref()
            .map(|g| self.comm.transport.sum(&[g.energy])[0]);
        Checkpoint {
            steps_done: w.steps_done,
            dt: w.dt,
            order: Vec::new(),
            position: Vec::new(),
            velocity: Vec::new(),
            force: Vec::new(),
            higher: Vec::new(),
            reference: Vec::new(),
            pair_histories: Vec::new(),
            plane_histories: Vec::new(),
            pair_tracks: Vec::new(),
            plane_tracks: Vec::new(),
            collisions: log.unwrap_or_default(),
            initial_energy: self.sim.initial_energy,
            fingerprint: Default::default(),
            list_builds: w.rebuilds,
            angular_velocity: Vec::new(),
            torque: Vec::new(),
            pair_shear: Vec::new(),
            plane_shear: Vec::new(),
            element_records: Vec::new(),
            moving_walls: moving,
            removed: w.removal.as_ref().map(|r| r.removed),
            outlets: w
                .removal
                .as_ref()
                .map_or_else(Vec::new, |r| r.by_outlet.clone()),
            gate_energy,
            inlets: crate::inlets::record(w),
            angular_higher: Vec::new(),
        }
    }

    /// Puts the bodies and pairs of `parts` ([`Self::checkpoint_records`]
    /// of some ranks) into `c`: bodies in input-id order, each wall and
    /// pair record once, in key order. No communication.
    pub(super) fn assemble(&self, c: &mut Checkpoint, parts: &[Vec<u8>]) {
        let w = &self.sim.world;
        let (spin, gear5) = (w.friction.is_some(), w.scheme == Scheme::Gear5);
        let tracked = w.tracks.is_some();
        let multi = w.surfaces.iter().any(|s| s.wall().elements() > 1);
        let mut bodies = BodyLists::default();
        let mut plane_shear = BTreeMap::new();
        let mut springs = BTreeMap::new();
        let mut plane_tracks = BTreeMap::new();
        let mut pair_tracks = BTreeMap::new();
        let mut planes = BTreeMap::new();
        let mut histories = BTreeMap::new();
        let mut elements = BTreeMap::new();
        for bytes in parts {
            let mut r = Reader::new(bytes);
            for _ in 0..r.u32() {
                let id = r.u32();
                bodies.id.push(id);
                bodies.x.push(r.vec3());
                bodies.v.push(r.vec3());
                bodies.f.push(r.vec3());
                bodies.x0.push(r.vec3());
                if gear5 {
                    let mut h = Vec::with_capacity(1);
                    pack::read_higher(&mut r, &mut h);
                    bodies.higher.push(h.first().copied().unwrap_or_default());
                    if spin {
                        let mut h = Vec::with_capacity(1);
                        pack::read_angular_higher(&mut r, &mut h);
                        bodies
                            .angular_higher
                            .push(h.first().copied().unwrap_or_default());
                    }
                }
                if tracked {
                    let planes: Vec<(u32, Track)> = pack::decode(r.blob()).unwrap_or_default();
                    for (p, tr) in planes {
                        plane_tracks.insert((id, p), tr);
                    }
                }
                if spin {
                    bodies.w.push(r.vec3());
                    bodies.t.push(r.vec3());
                    for _ in 0..r.u32() {
                        let p = r.u32();
                        let mut s = Vec::with_capacity(1);
                        pack::read_wall_shear(&mut r, &mut s, 1);
                        if let Some(s) = s.first() {
                            plane_shear.insert((id, p), *s);
                        }
                    }
                }
                for _ in 0..r.u32() {
                    let (p, h) = (r.u32(), r.history());
                    planes.insert((id, p), h);
                }
                if multi {
                    let others: Vec<ElementRecord> = pack::decode(r.blob()).unwrap_or_default();
                    for e in others {
                        elements.insert((e.id, e.key), e);
                    }
                }
            }
            for _ in 0..r.u32() {
                let (a, b, h) = (r.u32(), r.u32(), r.history());
                histories.insert((a, b), h);
            }
            if tracked {
                let m: Vec<((u32, u32), Track)> = pack::decode(r.blob()).unwrap_or_default();
                pair_tracks.extend(m);
            }
            if spin {
                for _ in 0..r.u32() {
                    let (a, b) = (r.u32(), r.u32());
                    let mut sp = [0.0; 6];
                    for x in &mut sp {
                        *x = r.f64();
                    }
                    springs.insert((a, b), sp);
                }
            }
        }
        // Input-id order (each body is owned by one rank: once).
        let mut perm: Vec<u32> = (0..bodies.id.len() as u32).collect();
        perm.sort_unstable_by_key(|&k| bodies.id[k as usize]);
        let b = bodies;
        c.order = permuted(b.id, &perm);
        c.position = permuted(b.x, &perm);
        c.velocity = permuted(b.v, &perm);
        c.force = permuted(b.f, &perm);
        c.reference = permuted(b.x0, &perm);
        c.higher = permuted(b.higher, &perm);
        c.angular_velocity = permuted(b.w, &perm);
        c.torque = permuted(b.t, &perm);
        c.angular_higher = permuted(b.angular_higher, &perm);
        c.pair_shear = springs.into_iter().map(|((a, b), s)| (a, b, s)).collect();
        c.pair_tracks = pair_tracks
            .into_iter()
            .map(|((a, b), t)| (a, b, t))
            .collect();
        c.plane_tracks = plane_tracks
            .into_iter()
            .map(|((id, p), t)| (id, p, t))
            .collect();
        c.plane_shear = plane_shear
            .into_iter()
            .map(|((id, p), s)| (id, p, s))
            .collect();
        c.element_records = elements.into_values().collect();
        c.plane_histories = planes
            .into_iter()
            .map(|((id, p), h)| (id, p, HistoryRecord::from(h)))
            .collect();
        c.pair_histories = histories
            .into_iter()
            .map(|((a, b), h)| (a, b, HistoryRecord::from(h)))
            .collect();
    }
}
