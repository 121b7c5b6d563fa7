//! The sparse per-body list of near wall elements: for body i, entries
//! `start[i]..start[i + 1]`, ascending by (wall, element) (the order the
//! force sums take, so that their bits do not depend on how the list was
//! built), each with its contact state: whether it touches, its contact
//! history (hysteretic laws), its springs (friction) and its collision
//! track (collision log). Built at each list build from the walls' near
//! tests; an entry that touches or is tracked is kept across builds even
//! when no longer near, so that its state is relaxed by the force pass
//! and its track closed by the log, as for a pair. Permuted with the
//! bodies, sent with them to other ranks, saved by (input id, wall,
//! element) in checkpoints.

use dembound_physics::contact::ContactHistory;
use serde::{Deserialize, Serialize};

use super::{Surface, WallLoad};
use crate::bodies::Bodies;
use crate::dynamics::collisions::Track;
use crate::dynamics::friction::WallShear;
use crate::parallel::{SharedMut, Workers};

/// Bodies per chunk of a shared [`WallContacts::refresh_on`] (scheduling
/// only: the lists do not depend on it).
const REFRESH_CHUNK: usize = 1024;

/// An element of a wall: the wall's index among the surfaces (the plane
/// index of a scene of planes) and the element's index in the wall.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
pub struct WallElement {
    pub wall: u32,
    pub element: u32,
}

/// One entry with its state, as moved between lists and ranks.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NearEntry {
    pub key: WallElement,
    pub touching: bool,
    pub history: ContactHistory,
    pub shear: WallShear,
    pub track: Track,
    /// What the wall took from this contact in the last force pass (read
    /// only while `touching`; not saved in checkpoints nor sent to other
    /// ranks: the next force pass writes it again).
    pub load: WallLoad,
}

impl NearEntry {
    /// Holds state worth keeping when the body is no longer near.
    fn has_state(&self) -> bool {
        self.touching || self.track != Track::default()
    }
}

/// The near lists of all bodies (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct WallContacts {
    /// Body i's entries are `start[i]..start[i + 1]` (bodies + 1 values).
    pub start: Vec<u32>,
    pub key: Vec<WallElement>,
    pub touching: Vec<bool>,
    /// Per entry when the law keeps histories, else empty.
    pub history: Vec<ContactHistory>,
    /// Per entry with friction, else empty.
    pub shear: Vec<WallShear>,
    /// Per entry with the collision log, else empty.
    pub track: Vec<Track>,
    /// Per entry: the force and torque the wall took from this contact
    /// in the last force pass that found it touching (written by the
    /// worker that owns the body; read only where `touching`): the wall
    /// loads of the observables ([`WallLoad::of_contact`]).
    pub load: Vec<WallLoad>,
    pub keep_history: bool,
    pub keep_shear: bool,
    pub keep_track: bool,
}

impl WallContacts {
    /// `bodies` bodies with no entries; which states are stored.
    pub fn new(bodies: usize, history: bool, shear: bool, track: bool) -> Self {
        Self {
            start: vec![0; bodies + 1],
            keep_history: history,
            keep_shear: shear,
            keep_track: track,
            ..Self::default()
        }
    }

    /// Bodies.
    pub fn bodies(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Entries of body i.
    #[inline(always)]
    pub fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.start[i] as usize..self.start[i + 1] as usize
    }

    /// Entry k with its state.
    pub fn entry(&self, k: usize) -> NearEntry {
        NearEntry {
            key: self.key[k],
            touching: self.touching[k],
            history: self.history.get(k).copied().unwrap_or_default(),
            shear: self.shear.get(k).copied().unwrap_or_default(),
            track: self.track.get(k).copied().unwrap_or_default(),
            load: self.load[k],
        }
    }

    /// Body i's entries with their state.
    pub fn entries(&self, i: usize) -> Vec<NearEntry> {
        self.range(i).map(|k| self.entry(k)).collect()
    }

    /// The entry of body i for `key`, if listed.
    pub fn find(&self, i: usize, key: WallElement) -> Option<usize> {
        let r = self.range(i);
        let s = r.start;
        self.key[r].binary_search(&key).ok().map(|k| s + k)
    }

    fn push(&mut self, e: &NearEntry) {
        self.key.push(e.key);
        self.touching.push(e.touching);
        self.load.push(e.load);
        if self.keep_history {
            self.history.push(e.history);
        }
        if self.keep_shear {
            self.shear.push(e.shear);
        }
        if self.keep_track {
            self.track.push(e.track);
        }
    }

    /// An empty list with the same stored states.
    fn empty_like(&self, bodies: usize, entries: usize) -> Self {
        let mut out = Self::new(0, self.keep_history, self.keep_shear, self.keep_track);
        out.start = Vec::with_capacity(bodies + 1);
        out.start.push(0);
        out.key.reserve(entries);
        out.touching.reserve(entries);
        out.load.reserve(entries);
        out
    }

    /// Appends a body with `entries` (ascending by key).
    pub fn push_body(&mut self, entries: &[NearEntry]) {
        if self.start.is_empty() {
            self.start.push(0);
        }
        for e in entries {
            self.push(e);
        }
        self.start.push(self.key.len() as u32);
    }

    /// Keeps bodies `order` (new body k ← old `order[k]`; a subset
    /// drops the others) with their entries.
    pub fn permute(&mut self, order: &[u32]) {
        let mut out = self.empty_like(order.len(), self.key.len());
        for &o in order {
            for k in self.range(o as usize) {
                let e = self.entry(k);
                out.push(&e);
            }
            out.start.push(out.key.len() as u32);
        }
        *self = out;
    }

    /// New lists for `bodies` (in the current order): the elements within
    /// `range` (m) of each free body, and the entries that touch or are
    /// tracked, their state carried; of the surfaces that act only
    /// (`active`, flags by surface; `None`: all), the others' entries
    /// dropped with their state (`walls::gate`).
    pub fn refresh(
        &mut self,
        bodies: &Bodies,
        surfaces: &[Surface],
        range: f64,
        active: Option<&[bool]>,
    ) {
        *self = self.refreshed(bodies, surfaces, range, active, 0, bodies.len());
    }

    /// [`Self::refresh`] with the bodies shared among `workers` in chunks
    /// of [`REFRESH_CHUNK`], the chunks' lists joined in body order: each
    /// body's entries are its own, so the lists are the same whatever
    /// the chunks and threads.
    pub fn refresh_on(
        &mut self,
        bodies: &Bodies,
        surfaces: &[Surface],
        range: f64,
        active: Option<&[bool]>,
        workers: &Workers,
    ) {
        let n = bodies.len();
        if workers.threads() < 2 || n <= REFRESH_CHUNK {
            return self.refresh(bodies, surfaces, range, active);
        }
        let parts = workers.map_bodies(n, REFRESH_CHUNK, |c| {
            let lo = c * REFRESH_CHUNK;
            self.refreshed(
                bodies,
                surfaces,
                range,
                active,
                lo,
                (lo + REFRESH_CHUNK).min(n),
            )
        });
        let mut out = self.empty_like(n, self.key.len());
        for p in parts {
            out.append(p);
        }
        *self = out;
    }

    /// Appends `other`'s bodies and entries.
    fn append(&mut self, other: Self) {
        let base = self.key.len() as u32;
        self.start.extend(other.start[1..].iter().map(|s| s + base));
        self.key.extend_from_slice(&other.key);
        self.touching.extend_from_slice(&other.touching);
        self.load.extend_from_slice(&other.load);
        self.history.extend_from_slice(&other.history);
        self.shear.extend_from_slice(&other.shear);
        self.track.extend_from_slice(&other.track);
    }

    /// The refreshed lists of bodies `lo..hi` alone (their entries from
    /// index 0).
    fn refreshed(
        &self,
        bodies: &Bodies,
        surfaces: &[Surface],
        range: f64,
        active: Option<&[bool]>,
        lo: usize,
        hi: usize,
    ) -> Self {
        let acts = |s: usize| active.is_none_or(|a| a.get(s).copied().unwrap_or(true));
        let n = hi - lo;
        let mut out = self.empty_like(
            n,
            if lo == 0 && hi == bodies.len() {
                self.key.len()
            } else {
                0
            },
        );
        let mut near = Vec::new();
        for i in lo..hi {
            near.clear();
            if !bodies.fixed[i] {
                for (s, surface) in surfaces.iter().enumerate() {
                    if !acts(s) {
                        continue;
                    }
                    surface.wall().near_elements(
                        bodies.position[i],
                        bodies.radius[i],
                        range,
                        &mut |e| {
                            near.push(WallElement {
                                wall: s as u32,
                                element: e,
                            })
                        },
                    );
                }
            }
            let old = if i < self.bodies() {
                self.range(i)
            } else {
                0..0
            };
            // Merge two ascending sequences.
            let (mut a, mut b) = (old.start, 0);
            loop {
                let ka = (a < old.end).then(|| self.key[a]);
                let kb = near.get(b).copied();
                match (ka, kb) {
                    (None, None) => break,
                    (Some(x), Some(y)) if x == y => {
                        out.push(&self.entry(a));
                        a += 1;
                        b += 1;
                    }
                    (Some(x), y) if y.is_none_or(|y| x < y) => {
                        let e = self.entry(a);
                        if e.has_state() && acts(x.wall as usize) {
                            out.push(&e);
                        }
                        a += 1;
                    }
                    (_, Some(y)) => {
                        out.push(&NearEntry {
                            key: y,
                            ..NearEntry::default()
                        });
                        b += 1;
                    }
                    // Covered above (the guard holds with no near key).
                    (Some(_), None) => break,
                }
            }
            out.start.push(out.key.len() as u32);
        }
        out
    }

    /// The entry of body i for `key`, inserted (relaxed) if not listed.
    pub fn insert(&mut self, i: usize, key: WallElement) -> usize {
        if let Some(k) = self.find(i, key) {
            return k;
        }
        let r = self.range(i);
        let at = r.start + self.key[r].partition_point(|&x| x < key);
        self.key.insert(at, key);
        self.touching.insert(at, false);
        self.load.insert(at, WallLoad::default());
        if self.keep_history {
            self.history.insert(at, ContactHistory::default());
        }
        if self.keep_shear {
            self.shear.insert(at, WallShear::default());
        }
        if self.keep_track {
            self.track.insert(at, Track::default());
        }
        for s in &mut self.start[i + 1..] {
            *s += 1;
        }
        at
    }

    /// Relaxes every entry (no contact, no history, no springs, no track).
    pub fn relax(&mut self) {
        self.touching.fill(false);
        self.history.fill(ContactHistory::default());
        self.shear.fill(WallShear::default());
        self.track.fill(Track::default());
    }

    /// Shared pointers for per-body parallel access.
    pub fn shared(&mut self) -> WallContactsMut {
        WallContactsMut {
            keep: self.keep_history,
            start: SharedMut::new(&mut self.start),
            key: SharedMut::new(&mut self.key),
            history: SharedMut::new(&mut self.history),
            touching: SharedMut::new(&mut self.touching),
            shear: SharedMut::new(&mut self.shear),
            load: SharedMut::new(&mut self.load),
        }
    }
}

/// Shared pointers into a [`WallContacts`] for per-body parallel access:
/// a body's entries are touched by the thread that owns the body.
#[derive(Clone, Copy)]
pub struct WallContactsMut {
    /// Histories are kept.
    pub keep: bool,
    pub start: SharedMut<u32>,
    pub key: SharedMut<WallElement>,
    pub history: SharedMut<ContactHistory>,
    pub touching: SharedMut<bool>,
    pub shear: SharedMut<WallShear>,
    pub load: SharedMut<WallLoad>,
}

impl WallContactsMut {
    /// Body i's entries.
    ///
    /// # Safety
    /// i < the body count.
    #[inline(always)]
    pub unsafe fn range(&self, i: usize) -> (usize, usize) {
        (*self.start.at(i) as usize, *self.start.at(i + 1) as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walls::PlaneWall;

    fn floor(wall: usize, z: f64) -> Surface {
        Surface::Plane(PlaneWall {
            wall,
            point: [0.0, 0.0, z],
            normal: [0.0, 0.0, 1.0],
            slot: wall,
            moving: None,
        })
    }

    fn bodies(z: &[f64]) -> Bodies {
        let mut b = Bodies::default();
        for (k, &z) in z.iter().enumerate() {
            b.position.push([0.0, 0.0, z]);
            b.radius.push(0.5);
            b.fixed.push(false);
            b.id.push(k as u32);
        }
        b
    }

    /// Entries are the near elements in wall order; a touching entry
    /// survives a build that finds it far, with its state; permutation
    /// and insertion keep each body's entries ascending.
    #[test]
    fn refresh_keeps_state_and_order() {
        let walls = [floor(0, 0.0), floor(1, -10.0), floor(2, 0.2)];
        let b = bodies(&[0.6, 5.0]);
        let mut c = WallContacts::new(2, true, false, false);
        c.refresh(&b, &walls, 0.2, None);
        // Body 0 (bottom at 0.1): walls 0 and 2 and (10.1 m away) not 1.
        let keys: Vec<u32> = c.range(0).map(|k| c.key[k].wall).collect();
        assert_eq!(keys, vec![0, 2]);
        assert!(c.range(1).is_empty());
        c.touching[1] = true;
        c.history[1].max_overlap = 1e-3;
        // Body 0 moves away: wall 2's entry stays (touching), wall 0's goes.
        let b2 = bodies(&[3.0, 5.0]);
        c.refresh(&b2, &walls, 0.2, None);
        assert_eq!(c.entries(0).len(), 1);
        assert_eq!(c.entries(0)[0].history.max_overlap, 1e-3);
        c.permute(&[1, 0]);
        assert!(c.range(0).is_empty() && c.range(1).len() == 1);
        let k = c.insert(
            1,
            WallElement {
                wall: 0,
                element: 0,
            },
        );
        assert_eq!(k, c.start[1] as usize);
        let keys: Vec<u32> = c.range(1).map(|k| c.key[k].wall).collect();
        assert_eq!(keys, vec![0, 2]);
    }

    /// The shared refresh lists what the serial one lists, entry for
    /// entry with its state, whatever the threads: 3000 bodies (three
    /// chunks and a part) at heights that put some near both floors, some
    /// near one, some near none, with states carried from a first build.
    #[test]
    fn shared_refresh_equals_the_serial_refresh() {
        let walls = [floor(0, 0.0), floor(1, 3.0), floor(2, 0.2)];
        let heights = |shift: f64| -> Vec<f64> {
            (0..3000)
                .map(|k| 0.4 + shift + 4.0 * ((k * 7919) % 1000) as f64 / 1000.0)
                .collect()
        };
        let mut first = WallContacts::new(3000, true, false, false);
        first.refresh(&bodies(&heights(0.0)), &walls, 0.2, None);
        for k in (0..first.key.len()).step_by(3) {
            first.touching[k] = true;
            first.history[k].max_overlap = k as f64;
        }
        let moved = bodies(&heights(0.05));
        let mut serial = first.clone();
        serial.refresh(&moved, &walls, 0.2, Some(&[true, true, false]));
        assert!(serial.key.len() > 1000 && serial.bodies() == 3000);
        for threads in [2, 3] {
            let workers = Workers::new(threads).expect("threads start");
            let mut shared = first.clone();
            shared.refresh_on(&moved, &walls, 0.2, Some(&[true, true, false]), &workers);
            assert_eq!(shared.start, serial.start, "{threads} threads");
            assert_eq!(shared.key, serial.key);
            assert_eq!(shared.touching, serial.touching);
            assert_eq!(shared.history, serial.history);
            assert_eq!(shared.load, serial.load);
        }
    }
}
