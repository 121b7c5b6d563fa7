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
//!
//! The scene the records arrive in is set up either from the whole sphere
//! list on every rank ([`DistributedSimulation::restore_parts`]) or with
//! each rank making only its part of the spheres
//! ([`DistributedSimulation::restore_parts_in_parts`], through
//! `comm::distributed::input`: the same bodies in the same places): then
//! no rank holds the whole scene either. Each record is checked where it
//! arrives against the scene's sphere held there (radius, material,
//! fixedness), so no rank needs the scene's other spheres.

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};

use super::{DistributedSimulation, RankComm, PEER_REFUSED};
use crate::comm::pack::{self, Reader, Writer};
use crate::comm::Transport;
use crate::dynamics::collisions::Track;
use crate::dynamics::friction::WallShear;
use crate::fingerprint::Fingerprint;
use crate::setup::{SceneSetup, Scheme};
use crate::simulation::{Checkpoint, ElementRecord, HistoryRecord};
use crate::SceneError;

/// A body's wall records (round 1; most bodies have none).
#[derive(Default, Serialize, Deserialize)]
struct WallRecords {
    histories: Vec<(u32, HistoryRecord)>,
    shear: Vec<(u32, WallShear)>,
    tracks: Vec<(u32, Track)>,
    elements: Vec<ElementRecord>,
}

/// The tags of the records after the list build (round 2).
const STEP: u8 = 0;
const HISTORY: u8 = 1;
const TRACK: u8 = 2;
const SPRINGS: u8 = 3;

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

/// Appends to `out` (by the directory rank of each id, `to`) the record
/// of each body of `c` (round 1): id, radius, material, fixedness,
/// position of the last list build, velocity, force (96 bytes), Gear5's
/// derivatives, the spin and its derivatives where the run has them, and
/// its wall records (CBOR, an empty blob for none).
fn body_records(c: &Checkpoint, to: &dyn Fn(u32) -> usize, out: &mut BTreeMap<usize, Writer>) {
    let mut walls: HashMap<u32, WallRecords> = HashMap::new();
    for &(id, p, h) in &c.plane_histories {
        walls.entry(id).or_default().histories.push((p, h));
    }
    for &(id, p, sh) in &c.plane_shear {
        walls.entry(id).or_default().shear.push((p, sh));
    }
    for &(id, p, t) in &c.plane_tracks {
        walls.entry(id).or_default().tracks.push((p, t));
    }
    for r in &c.element_records {
        walls.entry(r.id).or_default().elements.push(*r);
    }
    let f = &c.fingerprint;
    for (k, &id) in c.order.iter().enumerate() {
        let w = &mut Writer::default();
        w.u32(id);
        w.f64(f.radius[k]);
        w.u32(f.material[k]);
        w.u8(u8::from(f.fixed[k]));
        w.vec3(c.reference[k]);
        w.vec3(c.velocity[k]);
        w.vec3(c.force[k]);
        if !c.higher.is_empty() {
            pack::write_higher(w, &c.higher, k);
        }
        if let Some(a) = c.angular_velocity.get(k) {
            w.vec3(*a);
        }
        if !c.angular_higher.is_empty() {
            pack::write_higher(w, &c.angular_higher, k);
        }
        match walls.get(&id) {
            Some(r) => w.blob(&pack::encode(r)),
            None => w.u32(0),
        }
        put(out, to, id, &w.0);
    }
}

/// Appends body `id`'s record `rec` to the message for its directory rank
/// (`to`).
fn put(out: &mut BTreeMap<usize, Writer>, to: &dyn Fn(u32) -> usize, id: u32, rec: &[u8]) {
    let w = out.entry(to(id)).or_default();
    w.u32(id);
    w.blob(rec);
}

/// Reads one record of [`body_records`] into the lists of `c` (`gear5`,
/// `spin`: the run's); returns the id, radius, material and fixedness.
fn read_body_record(
    r: &mut Reader,
    c: &mut Checkpoint,
    gear5: bool,
    spin: bool,
) -> (u32, f64, u32, bool) {
    let (id, radius, material, fixed) = (r.u32(), r.f64(), r.u32(), r.u8() != 0);
    c.order.push(id);
    c.reference.push(r.vec3());
    c.velocity.push(r.vec3());
    c.force.push(r.vec3());
    if gear5 {
        pack::read_higher(r, &mut c.higher);
    }
    if spin {
        c.angular_velocity.push(r.vec3());
    }
    if gear5 && spin {
        pack::read_higher(r, &mut c.angular_higher);
    }
    let walls = r.blob();
    if !walls.is_empty() {
        let w: WallRecords = pack::decode(walls).unwrap_or_default();
        c.plane_histories
            .extend(w.histories.iter().map(|&(p, h)| (id, p, h)));
        c.plane_shear
            .extend(w.shear.iter().map(|&(p, s)| (id, p, s)));
        c.plane_tracks
            .extend(w.tracks.iter().map(|&(p, t)| (id, p, t)));
        c.element_records.extend(w.elements);
    }
    (id, radius, material, fixed)
}

/// Appends to `out` the records of `c` after the build (round 2): each
/// body's state at the checkpointed step by its id, each pair's history,
/// track and springs by both its ids.
fn after_build_records(
    c: &Checkpoint,
    to: &dyn Fn(u32) -> usize,
    out: &mut BTreeMap<usize, Writer>,
) {
    for (k, &id) in c.order.iter().enumerate() {
        let w = &mut Writer::default();
        w.u8(STEP);
        w.vec3(c.position[k]);
        w.vec3(c.velocity[k]);
        w.vec3(c.force[k]);
        if let Some(t) = c.torque.get(k) {
            w.vec3(*t);
        }
        put(out, to, id, &w.0);
    }
    let mut pair = |a: u32, b: u32, write: &dyn Fn(&mut Writer)| {
        let w = &mut Writer::default();
        write(w);
        put(out, to, a, &w.0);
        if a != b {
            put(out, to, b, &w.0);
        }
    };
    for &(a, b, h) in &c.pair_histories {
        pair(a, b, &|w| {
            w.u8(HISTORY);
            w.u32(a);
            w.u32(b);
            w.history(&h.into());
        });
    }
    for &(a, b, t) in &c.pair_tracks {
        let bytes = pack::encode(&t);
        pair(a, b, &|w| {
            w.u8(TRACK);
            w.u32(a);
            w.u32(b);
            w.blob(&bytes);
        });
    }
    for &(a, b, sp) in &c.pair_shear {
        pair(a, b, &|w| {
            w.u8(SPRINGS);
            w.u32(a);
            w.u32(b);
            for x in sp {
                w.f64(x);
            }
        });
    }
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
    /// Every rank builds the scene from `setup`'s whole sphere list first
    /// ([`Self::new`]); [`Self::restore_parts_in_parts`] builds only each
    /// rank's part. Collective.
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
        let (parts, change) = check_parts(setup, all, index, parts, &transport)?;
        let me = Self::new(setup, threads, grid, transport)?;
        me.continue_parts(index, parts, all, &change)
    }

    /// [`Self::restore_parts`] with each rank making or reading only its
    /// part of the scene's spheres ([`Self::new_parts`]: `setup.spheres`
    /// empty, the spheres described by `groups`, `label` naming them):
    /// no rank holds the scene's whole sphere list. The same checks in the
    /// same order, the same bodies in the same places before the records
    /// arrive ([`Self::new_parts`] starts as [`Self::new`] to the bit), so
    /// the same bits after. Returns with the simulation the overlap
    /// warnings one process prints, at rank 0. `Ok(None)`: the scene is to
    /// be read whole ([`Self::new_parts`]; every rank agrees, `parts` spent:
    /// read them again). Collective.
    #[allow(clippy::too_many_arguments)]
    pub fn restore_parts_in_parts(
        setup: &SceneSetup,
        groups: &[crate::io::resolve::PartGroup],
        label: crate::setup_checks::Label<'_>,
        index: &Checkpoint,
        parts: Vec<Checkpoint>,
        threads: usize,
        grid: Option<[usize; 3]>,
        transport: T,
    ) -> Result<Option<(Self, Vec<String>)>, SceneError> {
        crate::inlets::refuse_restart_under_mpi(&setup.inlets)?;
        let all = groups.last().map_or(0, |g| g.ids.end);
        let (parts, change) = check_parts(setup, all, index, parts, &transport)?;
        let Some((me, warnings)) = Self::new_parts(setup, groups, label, threads, grid, transport)?
        else {
            return Ok(None);
        };
        Ok(Some((
            me.continue_parts(index, parts, all, &change)?,
            warnings,
        )))
    }

    /// The restart from the parts once the scene is built (its bodies as
    /// set up, `all` of them): each record to the ranks holding its body,
    /// checked against the scene's sphere there, in the two rounds of the
    /// module's description. Collective.
    fn continue_parts(
        mut self,
        index: &Checkpoint,
        parts: Vec<Checkpoint>,
        all: usize,
        change: &crate::restart_walls::WallChange,
    ) -> Result<Self, SceneError> {
        let me = &mut self;
        me.check_dt(index)?;
        let removed = index.removed.map_or(0, |r| r.particles as usize);
        let gear5 = me.sim.world.scheme == Scheme::Gear5;
        let spin = me.sim.world.friction.is_some();
        // Round 1: each body's record to the ranks holding it now.
        let to = me.comm.directory();
        let mut out = BTreeMap::new();
        for p in &parts {
            body_records(p, &to, &mut out);
        }
        let held = me.sim.world.bodies.id.clone();
        let got = me.comm.route(&held, out);
        let mut c = shared(index);
        // Body id → the local body (the scene's sphere of that id here).
        let mut local = vec![u32::MAX; all];
        for (k, &id) in held.iter().enumerate() {
            if let Some(l) = local.get_mut(id as usize) {
                *l = k as u32;
            }
        }
        let mut refused = Ok(());
        for bytes in &got {
            let mut r = Reader::new(bytes);
            while !r.done() && refused.is_ok() {
                let _ = r.u32();
                let mut record = Reader::new(r.blob());
                let (id, radius, material, fixed) =
                    read_body_record(&mut record, &mut c, gear5, spin);
                refused = me.check_sphere(&local, id, radius, material, fixed);
            }
        }
        drop(got);
        drop(local);
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
        let mut out = BTreeMap::new();
        for p in &parts {
            after_build_records(p, &to, &mut out);
        }
        drop(parts);
        let held = me.sim.world.bodies.id.clone();
        let got = me.comm.route(&held, out);
        let mut c = shared(index);
        let mut histories = BTreeMap::new();
        let mut tracks = BTreeMap::new();
        let mut springs = BTreeMap::new();
        for bytes in &got {
            let mut r = Reader::new(bytes);
            while !r.done() {
                let id = r.u32();
                let mut record = Reader::new(r.blob());
                match record.u8() {
                    STEP => {
                        c.order.push(id);
                        c.position.push(record.vec3());
                        c.velocity.push(record.vec3());
                        c.force.push(record.vec3());
                        if spin {
                            c.torque.push(record.vec3());
                        }
                    }
                    tag => {
                        let (a, b) = (record.u32(), record.u32());
                        match tag {
                            HISTORY => {
                                histories.insert((a, b), HistoryRecord::from(record.history()));
                            }
                            TRACK => {
                                if let Some(t) = pack::decode::<Track>(record.blob()) {
                                    tracks.insert((a, b), t);
                                }
                            }
                            _ => {
                                let mut sp = [0.0; 6];
                                for x in &mut sp {
                                    *x = record.f64();
                                }
                                springs.insert((a, b), sp);
                            }
                        }
                    }
                }
            }
        }
        drop(got);
        c.pair_histories = histories.into_iter().map(|((a, b), h)| (a, b, h)).collect();
        c.pair_tracks = tracks.into_iter().map(|((a, b), t)| (a, b, t)).collect();
        c.pair_shear = springs.into_iter().map(|((a, b), s)| (a, b, s)).collect();
        let slot = slots(&c, all);
        me.restore_after_rebuild(&c, &slot, change);
        Ok(self)
    }

    /// Refuses a body whose radius, material or fixedness in the
    /// checkpoint is not the scene's (as `Fingerprint::check` names it):
    /// the scene's sphere is the body held here (`local[id]`: its local
    /// index), as set up; its fixedness the scene's (`fixed_by_id`: a
    /// halo copy is flagged fixed here).
    fn check_sphere(
        &self,
        local: &[u32],
        id: u32,
        radius: f64,
        material: u32,
        fixed: bool,
    ) -> Result<(), SceneError> {
        let b = &self.sim.world.bodies;
        let (Some(&k), Some(&scene_fixed)) = (
            local.get(id as usize),
            self.comm.fixed_by_id.get(id as usize),
        ) else {
            return Err(SceneError::Checkpoint(format!("body {id} out of range")));
        };
        // The records go to the ranks holding the body only.
        let k = k as usize;
        let (Some(&scene_radius), Some(&scene_material)) = (b.radius.get(k), b.material.get(k))
        else {
            return Ok(());
        };
        let at = format!("sphere {id} (input order)");
        if radius.to_bits() != scene_radius.to_bits() {
            return Err(SceneError::Checkpoint(format!(
                "{at}: radius differs: the checkpoint's {radius:?} m, the scene's {scene_radius:?} m"
            )));
        }
        if material != scene_material {
            return Err(SceneError::Checkpoint(format!(
                "{at}: material differs: the checkpoint's {material}, the scene's {scene_material}"
            )));
        }
        if fixed != scene_fixed {
            let kind = |f: bool| if f { "fixed" } else { "free" };
            return Err(SceneError::Checkpoint(format!(
                "{at}: the checkpoint's is {}, the scene's {}",
                kind(fixed),
                kind(scene_fixed)
            )));
        }
        Ok(())
    }
}

/// The checks of the parts before the scene is built (the same answer on
/// every rank): the settings the scene's (`setup`, `all` spheres), each
/// part read here whole ([`check_part`]), every body in some part, the
/// checkpoint's walls matched with the scene's (the parts remapped where
/// they changed). Collective.
fn check_parts<T: Transport>(
    setup: &SceneSetup,
    all: usize,
    index: &Checkpoint,
    parts: Vec<Checkpoint>,
    transport: &T,
) -> Result<(Vec<Checkpoint>, crate::restart_walls::WallChange), SceneError> {
    let gear5 = setup.integration.scheme == Scheme::Gear5;
    let friction = setup.friction.is_some();
    // The settings here (they do not depend on the spheres); each body's
    // radius, material and fixedness where its record arrives.
    let settings = |f: &Fingerprint| Fingerprint {
        settings: f.settings.clone(),
        ..Fingerprint::default()
    };
    let scene = settings(&Fingerprint::of(setup));
    settings(&index.fingerprint).check(&scene)?;
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
    agree(transport, checked)?;
    let removed = index.removed.map_or(0, |r| r.particles as usize);
    let bodies = counts[surfaces] as usize;
    if bodies + removed != all {
        return Err(SceneError::Checkpoint(format!(
            "its parts hold {bodies} bodies, the scene {all} less the {removed} it removed"
        )));
    }
    let touching = |s: u32| counts.get(s as usize).copied().unwrap_or(0.0) as usize;
    let change = crate::restart_walls::match_walls_counted(index, &scene, &touching)?;
    let parts = if change.unchanged() {
        parts
    } else {
        parts
            .iter()
            .map(|p| crate::restart_walls::remap(p, &change))
            .collect()
    };
    Ok((parts, change))
}

impl<T: Transport> RankComm<T> {
    /// The directory rank of each input id: ⌊id·P/N⌋.
    fn directory(&self) -> impl Fn(u32) -> usize {
        let size = self.transport.size();
        let all = self.fixed_by_id.len().max(1) as u64;
        move |id: u32| ((u64::from(id) * size as u64 / all) as usize).min(size - 1)
    }

    /// Delivers each record of `out` (by directory rank, [`Self::directory`]:
    /// entries of an id and a blob) to every rank holding a body of that id
    /// (`held`: the input ids of this rank's bodies, halo copies too)
    /// through the directory rank of the id: three exchanges, no rank
    /// holding more than its share of the ids. Returns the messages for
    /// this rank's bodies, entries as sent (a record for a body nobody
    /// holds is dropped). Collective.
    fn route(&mut self, held: &[u32], out: BTreeMap<usize, Writer>) -> Vec<Vec<u8>> {
        let to = self.directory();
        // 1. Which ranks hold each id, at its directory rank.
        let mut ids: BTreeMap<usize, Writer> = BTreeMap::new();
        for &id in held {
            ids.entry(to(id)).or_default().u32(id);
        }
        let mut holders: HashMap<u32, Vec<u32>> = HashMap::new();
        for (from, bytes) in self.send_or_keep(ids) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                holders.entry(r.u32()).or_default().push(from as u32);
            }
        }
        // 2. The records to the directory ranks of their ids, 3. from there
        // to every rank holding the body.
        let mut forward: BTreeMap<usize, Writer> = BTreeMap::new();
        for (_, bytes) in self.send_or_keep(out) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                let (id, record) = (r.u32(), r.blob());
                for &h in holders.get(&id).map_or(&[][..], |v| &v[..]) {
                    let w = forward.entry(h as usize).or_default();
                    w.u32(id);
                    w.blob(record);
                }
            }
        }
        drop(holders);
        self.send_or_keep(forward)
            .into_iter()
            .map(|(_, b)| b)
            .collect()
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
