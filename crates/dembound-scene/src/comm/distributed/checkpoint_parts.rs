//! Restart from a checkpoint written in parts, one a rank
//! (`[parallel] checkpoint_per_rank`, issue 31 item 5): no rank reads or
//! holds the whole checkpoint.
//!
//! Each writing rank's part ([`DistributedSimulation::checkpoint_part`])
//! holds the bodies it owned, their wall records, the pairs it listed (a
//! pair across a cut in both parts) and the run's shared figures. On
//! restart each rank reads some of the parts (any assignment: the written
//! and the restarting rank counts may differ, `io::checkpoint_parts`), and
//! every record goes to the ranks that hold its body through a directory
//! by input id (rank ⌊id·P/N⌋ learns which ranks hold id, then forwards
//! the records: [`RankComm::route`]), in two rounds:
//!
//! 1. before the list build, each body's position of the last list build,
//!    velocity, force, derivatives, spins and wall records to the ranks
//!    that hold it as the scene was set up;
//! 2. after the build (bodies at their owners, the halo and the lists as
//!    the run had them), each pair's history, track and springs to the
//!    ranks holding either body, and each body's state of the
//!    checkpointed step to its owner and its halo copies.
//!
//! Then the restart continues as from the gathered checkpoint
//! ([`DistributedSimulation::restore`]) with the same values in the same
//! places: the same bits.

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};

use super::{DistributedSimulation, RankComm, PEER_REFUSED};
use crate::comm::pack::{self, Reader, Writer};
use crate::comm::Transport;
use crate::dynamics::collisions::Track;
use crate::dynamics::friction::{Springs, WallShear};
use crate::fingerprint::Fingerprint;
use crate::setup::{SceneSetup, Scheme};
use crate::simulation::{Checkpoint, ElementRecord, HistoryRecord};
use crate::SceneError;

/// A body's record before the list build (round 1).
#[derive(Serialize, Deserialize)]
struct BodyRecord {
    id: u32,
    radius: f64,
    material: u32,
    fixed: bool,
    reference: [f64; 3],
    velocity: [f64; 3],
    force: [f64; 3],
    higher: Option<[[f64; 3]; 4]>,
    angular_velocity: Option<[f64; 3]>,
    angular_higher: Option<[[f64; 3]; 4]>,
    plane_histories: Vec<(u32, HistoryRecord)>,
    plane_shear: Vec<(u32, WallShear)>,
    plane_tracks: Vec<(u32, Track)>,
    elements: Vec<ElementRecord>,
}

/// A record after the list build (round 2).
#[derive(Serialize, Deserialize)]
enum AfterBuild {
    /// A body's state at the checkpointed step: id, position, velocity,
    /// force, torque.
    Step(u32, [f64; 3], [f64; 3], [f64; 3], Option<[f64; 3]>),
    History(u32, u32, HistoryRecord),
    Track(u32, u32, Track),
    Springs(u32, u32, Springs),
}

/// Checks a part read here against the scene: its lists of one length,
/// each body in range and once, the step the index's.
fn check_part(
    c: &Checkpoint,
    index: &Checkpoint,
    all: usize,
    surfaces: usize,
    gear5: bool,
    friction: bool,
) -> Result<(), SceneError> {
    if c.steps_done != index.steps_done || c.list_builds != index.list_builds {
        return Err(SceneError::Checkpoint(format!(
            "a part is of step {} ({} list builds), the index of step {} ({}): the parts \
             are of another run",
            c.steps_done, c.list_builds, index.steps_done, index.list_builds
        )));
    }
    let n = c.order.len();
    let f = &c.fingerprint;
    if [f.radius.len(), f.material.len(), f.fixed.len()]
        .iter()
        .any(|&l| l != n)
    {
        return Err(SceneError::Checkpoint(format!(
            "a part lists {n} bodies and {} radii: damaged",
            f.radius.len()
        )));
    }
    // A rank may have owned nothing.
    if n > 0 {
        super::checkpoint::check_bodies(c, n, all, gear5, friction)?;
    }
    let ids = c
        .plane_histories
        .iter()
        .map(|r| (r.0, r.1))
        .chain(c.plane_shear.iter().map(|r| (r.0, r.1)))
        .chain(c.plane_tracks.iter().map(|r| (r.0, r.1)))
        .chain(c.element_records.iter().map(|r| (r.id, r.key.wall)));
    for (id, p) in ids {
        if id as usize >= all || p as usize >= surfaces {
            return Err(SceneError::Checkpoint(format!(
                "wall record of body {id}, plane {p} out of range"
            )));
        }
    }
    let pairs = c
        .pair_tracks
        .iter()
        .map(|r| (r.0, r.1))
        .chain(c.pair_shear.iter().map(|r| (r.0, r.1)));
    for (a, b) in pairs {
        if a as usize >= all || b as usize >= all {
            return Err(SceneError::Checkpoint(format!(
                "pair record of bodies {a}, {b} out of range"
            )));
        }
    }
    Ok(())
}

/// `Err` on every rank when any rank's `r` is (its own error where it has
/// one, [`PEER_REFUSED`] elsewhere). Collective.
fn agree<T: Transport>(t: &T, r: Result<(), SceneError>) -> Result<(), SceneError> {
    let failed = t.max(if r.is_err() { 1.0 } else { 0.0 });
    r?;
    if failed > 0.0 {
        return Err(SceneError::input(PEER_REFUSED));
    }
    Ok(())
}

/// The records of `c` for each body of it, by id (round 1).
fn body_records(c: &Checkpoint) -> Vec<(u32, Vec<u8>)> {
    let mut by_body: HashMap<u32, BodyRecord> = HashMap::with_capacity(c.order.len());
    for (k, &id) in c.order.iter().enumerate() {
        let f = &c.fingerprint;
        by_body.insert(
            id,
            BodyRecord {
                id,
                radius: f.radius[k],
                material: f.material[k],
                fixed: f.fixed[k],
                reference: c.reference[k],
                velocity: c.velocity[k],
                force: c.force[k],
                higher: c.higher.get(k).copied(),
                angular_velocity: c.angular_velocity.get(k).copied(),
                angular_higher: c.angular_higher.get(k).copied(),
                plane_histories: Vec::new(),
                plane_shear: Vec::new(),
                plane_tracks: Vec::new(),
                elements: Vec::new(),
            },
        );
    }
    for &(id, p, h) in &c.plane_histories {
        if let Some(b) = by_body.get_mut(&id) {
            b.plane_histories.push((p, h));
        }
    }
    for &(id, p, s) in &c.plane_shear {
        if let Some(b) = by_body.get_mut(&id) {
            b.plane_shear.push((p, s));
        }
    }
    for &(id, p, t) in &c.plane_tracks {
        if let Some(b) = by_body.get_mut(&id) {
            b.plane_tracks.push((p, t));
        }
    }
    for r in &c.element_records {
        if let Some(b) = by_body.get_mut(&r.id) {
            b.elements.push(*r);
        }
    }
    by_body
        .into_values()
        .map(|b| (b.id, pack::encode(&b)))
        .collect()
}

/// The records of `c` after the build (round 2): each body's step state
/// by its id, each pair's by both its ids.
fn after_build_records(c: &Checkpoint) -> Vec<(u32, Vec<u8>)> {
    let mut out = Vec::new();
    for (k, &id) in c.order.iter().enumerate() {
        let r = AfterBuild::Step(
            id,
            c.position[k],
            c.velocity[k],
            c.force[k],
            c.torque.get(k).copied(),
        );
        out.push((id, pack::encode(&r)));
    }
    let pairs = c
        .pair_histories
        .iter()
        .map(|&(a, b, h)| (a, b, AfterBuild::History(a, b, h)))
        .chain(
            c.pair_tracks
                .iter()
                .map(|&(a, b, t)| (a, b, AfterBuild::Track(a, b, t))),
        )
        .chain(
            c.pair_shear
                .iter()
                .map(|&(a, b, s)| (a, b, AfterBuild::Springs(a, b, s))),
        );
    for (a, b, r) in pairs {
        let bytes = pack::encode(&r);
        if a != b {
            out.push((b, bytes.clone()));
        }
        out.push((a, bytes));
    }
    out
}

/// `index` (the run's shared figures) with no bodies: what each round's
/// local checkpoint starts from.
fn shared(index: &Checkpoint) -> Checkpoint {
    Checkpoint {
        fingerprint: Fingerprint::default(),
        ..index.clone()
    }
}

/// `slot[id]`: the entry of body id in `c` (`usize::MAX`: none).
fn slots(c: &Checkpoint, all: usize) -> Vec<usize> {
    let mut slot = vec![usize::MAX; all];
    for (k, &id) in c.order.iter().enumerate() {
        if let Some(s) = slot.get_mut(id as usize) {
            *s = k;
        }
    }
    slot
}

impl<T: Transport> DistributedSimulation<T> {
    /// Continues a checkpoint written in parts (`index`: the run's shared
    /// figures, `parts`: those this rank read; every rank the same
    /// `index`, each part read by one rank) of the same `setup` on this
    /// transport's ranks, as [`Self::restore`] continues a gathered one.
    /// Collective.
    pub fn restore_parts(
        setup: &SceneSetup,
        index: &Checkpoint,
        parts: Vec<Checkpoint>,
        threads: usize,
        grid: Option<[usize; 3]>,
        transport: T,
    ) -> Result<Self, SceneError> {
        crate::inlets::refuse_restart_under_mpi(&setup.inlets)?;
        let all = setup.spheres.len();
        let gear5 = setup.integration.scheme == Scheme::Gear5;
        let friction = setup.friction.is_some();
        let scene = Fingerprint::of(setup);
        // The settings here (the same answer on every rank); each body's
        // radius, material and fixedness where its record arrives.
        let settings = |f: &Fingerprint| Fingerprint {
            settings: f.settings.clone(),
            ..Fingerprint::default()
        };
        settings(&index.fingerprint).check(&settings(&scene))?;
        let surfaces = crate::restart_walls::surface_count(index);
        // The spheres with a record on each of the checkpoint's surfaces,
        // and the parts' bodies, over every rank (collective).
        let mut local: Vec<f64> = (0..surfaces as u32)
            .map(|s| {
                parts
                    .iter()
                    .map(|p| crate::restart_walls::spheres_touching(p, s) as f64)
                    .sum()
            })
            .collect();
        local.push(parts.iter().map(|p| p.order.len() as f64).sum());
        let counts = transport.sum(&local);
        let checked = parts
            .iter()
            .try_for_each(|p| check_part(p, index, all, surfaces, gear5, friction));
        agree(&transport, checked)?;
        let removed = index.removed.map_or(0, |r| r.particles as usize);
        let bodies = counts[surfaces] as usize;
        if bodies + removed != all {
            return Err(SceneError::Checkpoint(format!(
                "its parts hold {bodies} bodies, the scene {all} less the {removed} it removed"
            )));
        }
        let touching = |s: u32| counts.get(s as usize).copied().unwrap_or(0.0) as usize;
        let change = crate::restart_walls::match_walls_counted(index, &scene, &touching)?;
        let parts: Vec<Checkpoint> = if change.unchanged() {
            parts
        } else {
            parts
                .iter()
                .map(|p| crate::restart_walls::remap(p, &change))
                .collect()
        };
        let mut me = Self::new(setup, threads, grid, transport)?;
        me.check_dt(index)?;
        // Round 1: each body's record to the ranks holding it now.
        let records: Vec<(u32, Vec<u8>)> = parts.iter().flat_map(body_records).collect();
        let held = me.sim.world.bodies.id.clone();
        let got = me.comm.route(&held, records);
        let mut c = shared(index);
        let mut bodies: Vec<BodyRecord> = got
            .iter()
            .filter_map(|(_, b)| pack::decode::<BodyRecord>(b))
            .collect();
        bodies.sort_unstable_by_key(|b| b.id);
        bodies.dedup_by_key(|b| b.id);
        let mut refused = Ok(());
        for b in &bodies {
            let Some(s) = setup.spheres.get(b.id as usize) else {
                continue;
            };
            let at = format!("sphere {} (input order)", b.id);
            if b.radius.to_bits() != s.radius.to_bits() {
                refused = Err(SceneError::Checkpoint(format!(
                    "{at}: radius differs: the checkpoint's {:?} m, the scene's {:?} m",
                    b.radius, s.radius
                )));
            } else if b.material as usize != s.material {
                refused = Err(SceneError::Checkpoint(format!(
                    "{at}: material differs: the checkpoint's {}, the scene's {}",
                    b.material, s.material
                )));
            } else if b.fixed != s.fixed {
                let kind = |f: bool| if f { "fixed" } else { "free" };
                refused = Err(SceneError::Checkpoint(format!(
                    "{at}: the checkpoint's is {}, the scene's {}",
                    kind(b.fixed),
                    kind(s.fixed)
                )));
            }
            if refused.is_err() {
                break;
            }
            c.order.push(b.id);
            c.reference.push(b.reference);
            c.velocity.push(b.velocity);
            c.force.push(b.force);
            c.higher.extend(b.higher);
            c.angular_velocity.extend(b.angular_velocity);
            c.angular_higher.extend(b.angular_higher);
            for &(p, h) in &b.plane_histories {
                c.plane_histories.push((b.id, p, h));
            }
            for &(p, sh) in &b.plane_shear {
                c.plane_shear.push((b.id, p, sh));
            }
            for &(p, t) in &b.plane_tracks {
                c.plane_tracks.push((b.id, p, t));
            }
            c.element_records.extend(b.elements.iter().copied());
        }
        drop(bodies);
        let slot = slots(&c, all);
        // With nothing removed, every body held here has its record.
        if refused.is_ok() && removed == 0 {
            if let Some(id) = held.iter().find(|&&id| slot[id as usize] == usize::MAX) {
                refused = Err(SceneError::Checkpoint(format!(
                    "body {id} is in none of its parts"
                )));
            }
        }
        agree(&me.comm.transport, refused)?;
        me.restore_bodies(&c, &slot)?;
        drop(c);
        // Round 2: the pairs and the checkpointed step to the ranks
        // holding their bodies after the build.
        let records: Vec<(u32, Vec<u8>)> = parts.iter().flat_map(after_build_records).collect();
        drop(parts);
        let held = me.sim.world.bodies.id.clone();
        let got = me.comm.route(&held, records);
        let mut c = shared(index);
        let mut steps = Vec::new();
        let mut histories = BTreeMap::new();
        let mut tracks = BTreeMap::new();
        let mut springs = BTreeMap::new();
        for (_, bytes) in &got {
            match pack::decode::<AfterBuild>(bytes) {
                Some(AfterBuild::Step(id, x, v, f, t)) => steps.push((id, x, v, f, t)),
                Some(AfterBuild::History(a, b, h)) => {
                    histories.insert((a, b), h);
                }
                Some(AfterBuild::Track(a, b, t)) => {
                    tracks.insert((a, b), t);
                }
                Some(AfterBuild::Springs(a, b, s)) => {
                    springs.insert((a, b), s);
                }
                None => {}
            }
        }
        drop(got);
        steps.sort_unstable_by_key(|s| s.0);
        steps.dedup_by_key(|s| s.0);
        for (id, x, v, f, t) in steps {
            c.order.push(id);
            c.position.push(x);
            c.velocity.push(v);
            c.force.push(f);
            c.torque.extend(t);
        }
        c.pair_histories = histories.into_iter().map(|((a, b), h)| (a, b, h)).collect();
        c.pair_tracks = tracks.into_iter().map(|((a, b), t)| (a, b, t)).collect();
        c.pair_shear = springs.into_iter().map(|((a, b), s)| (a, b, s)).collect();
        let slot = slots(&c, all);
        me.restore_after_rebuild(&c, &slot, &change);
        Ok(me)
    }
}

impl<T: Transport> RankComm<T> {
    /// Delivers each `(id, bytes)` of `records` to every rank holding a
    /// body `id` (`held`: the input ids of this rank's bodies, halo
    /// copies too), through the directory rank of id (⌊id·P/N⌋): three
    /// exchanges, no rank holding more than its share of the ids.
    /// Returns the records for this rank's bodies (a record for a body
    /// nobody holds is dropped). Collective.
    fn route(&mut self, held: &[u32], records: Vec<(u32, Vec<u8>)>) -> Vec<(u32, Vec<u8>)> {
        let size = self.transport.size();
        let all = self.fixed_by_id.len().max(1) as u64;
        let directory = |id: u32| ((u64::from(id) * size as u64 / all) as usize).min(size - 1);
        // 1. Which ranks hold each id, at its directory rank.
        let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
        for &id in held {
            out.entry(directory(id)).or_default().u32(id);
        }
        let mut holders: HashMap<u32, Vec<u32>> = HashMap::new();
        for (from, bytes) in self.send_or_keep(out) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                holders.entry(r.u32()).or_default().push(from as u32);
            }
        }
        // 2. The records to the directory ranks of their ids.
        let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
        for (id, bytes) in records {
            let w = out.entry(directory(id)).or_default();
            w.u32(id);
            w.blob(&bytes);
        }
        let mut forward: BTreeMap<usize, Writer> = BTreeMap::new();
        for (_, bytes) in self.send_or_keep(out) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                let (id, record) = (r.u32(), r.blob());
                // 3. From there to every rank holding the body.
                for &to in holders.get(&id).map_or(&[][..], |v| &v[..]) {
                    let w = forward.entry(to as usize).or_default();
                    w.u32(id);
                    w.blob(record);
                }
            }
        }
        drop(holders);
        let mut got = Vec::new();
        for (_, bytes) in self.send_or_keep(forward) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                let id = r.u32();
                got.push((id, r.blob().to_vec()));
            }
        }
        got
    }

    /// [`Self::send_records`], this rank's own share kept here (first).
    /// Collective.
    fn send_or_keep(&mut self, mut out: BTreeMap<usize, Writer>) -> Vec<(usize, Vec<u8>)> {
        let rank = self.transport.rank();
        let own = out.remove(&rank).map(|w| (rank, w.0));
        let mut got: Vec<(usize, Vec<u8>)> = own.into_iter().collect();
        got.extend(self.send_records(out));
        got
    }
}
