//! Stages "ghosts" and "neighbours": the ghost layer follows its owners;
//! a list build wraps the bodies into the box, sorts them by cell (a
//! decomposed run: by the whole scene's cells), rebuilds the ghosts and
//! the lists and carries every pair's state (histories, springs,
//! collision tracks) over by input ids.

use dembound_physics::contact::ContactHistory;
use rustc_hash::FxHashMap;

use super::{Pipeline, Tracks, World};
use crate::bodies::Bodies;
use crate::dynamics::collisions::Track;
use crate::dynamics::contacts::{self, extended, PairHistories};
use crate::dynamics::friction;
use crate::geometry::cells::{sort_by_cell, CellGrid};
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::{PairList, SearchInput};
use crate::parallel::{SharedMut, Workers, STEP_CHUNK};

/// The cell grid of the whole scene (every rank's bodies).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WholeGrid {
    /// Extent of the celled bodies of all ranks (the box on periodic
    /// axes), m.
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    /// Bodies of all ranks.
    pub bodies: usize,
}

/// The extent the cell grid spans: the celled bodies' (wrapped) positions,
/// the box on periodic axes; `None` on an axis no celled body has.
pub(crate) fn celled_extent(world: &World) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for k in 0..world.bodies.len() {
        if world.bodies.radius[k] > world.large_radius {
            continue;
        }
        let x = world.bodies.position[k];
        for a in 0..3 {
            if x[a].is_finite() {
                lo[a] = lo[a].min(x[a]);
                hi[a] = hi[a].max(x[a]);
            }
        }
    }
    for a in 0..3 {
        if world.domain.periodic[a] {
            lo[a] = world.domain.lower[a];
            hi[a] = world.domain.upper[a];
        }
    }
    (lo, hi)
}

/// Wraps every body into the box (`Domain::wrap`) and returns
/// [`celled_extent`] of the wrapped positions, the bodies shared among
/// `workers`: each chunk wraps its bodies and takes the extent of its
/// celled ones, the chunks' extents combined in chunk order (a minimum
/// or maximum of the same values, whatever the grouping).
pub(crate) fn wrap_then_extent(world: &mut World, workers: &Workers) -> ([f64; 3], [f64; 3]) {
    let n = world.bodies.len();
    let large = world.large_radius;
    let domain = &world.domain;
    let radius = &world.bodies.radius;
    let position = SharedMut::new(&mut world.bodies.position);
    let parts = workers.map_bodies(n, STEP_CHUNK, |c| {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let first = c * STEP_CHUNK;
        let chunk = &radius[first..(first + STEP_CHUNK).min(n)];
        for (k, &r) in (first..).zip(chunk) {
            // SAFETY: chunk c touches bodies of its own range only.
            let x = unsafe { position.at(k) };
            *x = domain.wrap(*x);
            if r > large {
                continue;
            }
            for a in 0..3 {
                if x[a].is_finite() {
                    lo[a] = lo[a].min(x[a]);
                    hi[a] = hi[a].max(x[a]);
                }
            }
        }
        (lo, hi)
    });
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (l, h) in parts {
        for a in 0..3 {
            lo[a] = lo[a].min(l[a]);
            hi[a] = hi[a].max(h[a]);
        }
    }
    for a in 0..3 {
        if domain.periodic[a] {
            lo[a] = domain.lower[a];
            hi[a] = domain.upper[a];
        }
    }
    (lo, hi)
}

/// Each body's cell index in `grid` (`grid.count()` for the large ones,
/// a bucket after every cell), the bodies shared among `workers`.
fn cells_of_bodies(world: &World, grid: &CellGrid, workers: &Workers) -> Vec<u32> {
    let n = world.bodies.len();
    let cells = grid.count() as u32;
    let (large, bodies) = (world.large_radius, &world.bodies);
    let mut cell = vec![0u32; n];
    let out = SharedMut::new(&mut cell);
    workers.run_bodies(n, STEP_CHUNK, |c| {
        for k in c * STEP_CHUNK..((c + 1) * STEP_CHUNK).min(n) {
            let v = if bodies.radius[k] > large {
                cells
            } else {
                grid.index(grid.coords(bodies.position[k])) as u32
            };
            // SAFETY: chunk c writes entries of its own range only.
            unsafe { *out.at(k) = v };
        }
    });
    cell
}

/// Pair state by input ids (a < b), carried across a list rebuild.
///
/// Keyed by pairs of input ids and looked up once per listed pair at each
/// rebuild: hashed with `rustc_hash`'s Fx hash, not the standard SipHash
/// (which guards against chosen keys, none here; nothing iterates these
/// maps in an order that reaches the results, the standard maps' order
/// being random per process anyway).
#[derive(Debug, Clone, Default)]
pub(crate) struct SavedPairs {
    pub histories: FxHashMap<(u32, u32), ContactHistory>,
    pub tracks: Option<FxHashMap<(u32, u32), Track>>,
    pub shear: FxHashMap<(u32, u32), friction::Springs>,
}

/// Histories, collision tracks and tangential springs of the listed
/// pairs, by input ids.
pub(crate) fn save_pairs(world: &World) -> SavedPairs {
    let histories =
        contacts::active_histories(&world.bodies, &world.ghosts, &world.list, &world.histories)
            .into_iter()
            .map(|(a, b, h)| ((a, b), h))
            .collect();
    let tracks = world.tracks.as_ref().map(|t| saved_tracks(world, t));
    let shear = if world.friction.is_some() {
        friction::active_shear_map(&world.bodies, &world.ghosts, &world.list, &world.shear)
    } else {
        FxHashMap::default()
    };
    SavedPairs {
        histories,
        tracks,
        shear,
    }
}

/// Extended index of body j's image nearest to body i: j itself or one of
/// its ghosts.
fn nearest_image(bodies: &Bodies, ghosts: &Ghosts, i: usize, j: usize) -> usize {
    let d2 = |x: [f64; 3]| crate::dynamics::integrate::displacement2(x, bodies.position[i]);
    let mut best = (d2(bodies.position[j]), j);
    for (g, &owner) in ghosts.owner.iter().enumerate() {
        if owner as usize == j {
            let d = d2(ghosts.position[g]);
            if d < best.0 {
                best = (d, bodies.len() + g);
            }
        }
    }
    best.1
}

/// The tracks of the listed couples that have a previous step, by input ids.
pub(crate) fn saved_tracks_public(world: &World, tracks: &Tracks) -> FxHashMap<(u32, u32), Track> {
    saved_tracks(world, tracks)
}

fn saved_tracks(world: &World, tracks: &Tracks) -> FxHashMap<(u32, u32), Track> {
    let bodies = &world.bodies;
    let list = &world.list;
    let mut out = FxHashMap::default();
    if tracks.main.len() != list.j.len() || list.start.len() != bodies.len() + 1 {
        return out;
    }
    // A track out of contact holds the log's last step only in `logged`,
    // a contact in progress its motion at that step.
    let logged = tracks
        .logged
        .as_deref()
        .filter(|l| l.current(world, world.steps_done));
    for i in 0..bodies.len() {
        for k in list.start[i] as usize..list.start[i + 1] as usize {
            let mut track = tracks.main[k];
            if let Some(l) = logged {
                let j = list.j[k] as usize;
                l.settle(&mut track, bodies, &world.ghosts, i, j);
            }
            if track.is_known() {
                let (a, b) = (bodies.id[i], bodies.id[list.j[k] as usize]);
                out.insert((a.min(b), a.max(b)), track);
            }
        }
    }
    for (k, &(i, j)) in list.extra.iter().enumerate() {
        if tracks.extra.get(k).is_some_and(|t| t.is_known()) {
            let (_, _, owner) = extended(bodies, &world.ghosts, j as usize);
            let (a, b) = (bodies.id[i as usize], bodies.id[owner]);
            out.insert((a.min(b), a.max(b)), tracks.extra[k]);
        }
    }
    out
}

impl Pipeline {
    /// Stage "ghosts": images follow their owners.
    pub fn ghosts(&mut self, world: &mut World) {
        world
            .ghosts
            .update(&world.bodies.position, &world.bodies.velocity);
    }

    /// Stage "neighbours": wrap into the box, sort bodies by cell, rebuild
    /// the ghost layer and the lists, carry every pair's history over.
    pub fn neighbours(&mut self, world: &mut World, workers: &Workers) {
        let saved = save_pairs(world);
        self.rebuild(world, workers, saved);
    }

    /// [`Self::neighbours`] from pair state saved by [`save_pairs`] (a
    /// domain decomposition changes the bodies in between: migration).
    pub(crate) fn rebuild(&mut self, world: &mut World, workers: &Workers, saved: SavedPairs) {
        world.rebuilds += 1;
        let SavedPairs {
            histories: saved,
            tracks: saved_tracks,
            shear: saved_shear,
        } = saved;
        // The old list and the arrays aligned with it are in `saved`: freed
        // before the new ones are made (not two copies of them at once).
        world.list = PairList::default();
        world.histories = PairHistories::default();
        if world.friction.is_some() {
            world.shear = friction::PairShear::default();
        }

        let n = world.bodies.len();
        // Grid bounds: the box on periodic axes, the celled bodies' extent elsewhere.
        let large = world.large_radius;
        let (mut lo, mut hi) = wrap_then_extent(world, workers);
        for a in 0..3 {
            if lo[a] > hi[a] {
                lo[a] = 0.0;
                hi[a] = 0.0;
            }
        }
        self.grid = match self.whole_grid {
            None => CellGrid::new(lo, hi, world.cell_size, (2 * n).max(64)),
            Some(whole) => {
                // The whole scene's grid, cropped to the cells of this
                // rank's bodies.
                let mut lower = whole.lower;
                let mut upper = whole.upper;
                for a in 0..3 {
                    if lower[a] > upper[a] {
                        lower[a] = 0.0;
                        upper[a] = 0.0;
                    }
                }
                let g = CellGrid::new(lower, upper, world.cell_size, (2 * whole.bodies).max(64));
                let mut c_lo = [usize::MAX; 3];
                let mut c_hi = [0usize; 3];
                for k in 0..n {
                    if world.bodies.radius[k] <= large {
                        let c = g.whole_coords(world.bodies.position[k]);
                        for a in 0..3 {
                            c_lo[a] = c_lo[a].min(c[a]);
                            c_hi[a] = c_hi[a].max(c[a]);
                        }
                    }
                }
                g.crop(c_lo, c_hi)
            }
        };
        let cells = self.grid.count();
        let cell = cells_of_bodies(world, &self.grid, workers);
        let (mut order, start) = sort_by_cell(&cell, cells);
        if self.whole_grid.is_some() {
            // By input id within a cell: the order is the whole scene's,
            // not this rank's history of arrivals.
            let id = &world.bodies.id;
            for c in 0..=cells {
                order[start[c] as usize..start[c + 1] as usize]
                    .sort_unstable_by_key(|&o| id[o as usize]);
            }
        }
        world.bodies.permute_on(&order, workers);
        world.wall_contacts.permute(&order);
        let range = wall_range(world);
        let active = world.gates.as_deref().map(|g| &g.active[..]);
        world
            .wall_contacts
            .refresh_on(&world.bodies, &world.surfaces, range, active, workers);
        world.walls_listed();
        let celled = start[cells] as usize;
        let bodies = &world.bodies;
        world.ghosts = Ghosts::build(&world.domain, &bodies.position, world.cell_size, |k| {
            bodies.radius[k] > large
        });
        world.ghosts.update(&bodies.position, &bodies.velocity);
        world.list = PairList::build(
            &SearchInput {
                position: &bodies.position,
                radius: &bodies.radius,
                fixed: &bodies.fixed,
                celled,
                grid: &self.grid,
                cell_start: &start,
                ghosts: &world.ghosts,
                skin: world.skin,
            },
            workers,
        );
        // A decomposed run adds each body's pair forces in body order.
        world.list.sequential = self.whole_grid.is_some();
        let list = &world.list;
        let key = |i: usize, j_ext: usize| {
            let (_, _, owner) = extended(bodies, &world.ghosts, j_ext);
            let (a, b) = (bodies.id[i], bodies.id[owner]);
            (a.min(b), a.max(b))
        };
        let keep = world.laws.history;
        let mut main = vec![ContactHistory::default(); if keep { list.j.len() } else { 0 }];
        let mut extra = vec![ContactHistory::default(); if keep { list.extra.len() } else { 0 }];
        if keep && !saved.is_empty() {
            for (i, k) in list.entries() {
                if let Some(h) = saved.get(&key(i, list.j[k] as usize)) {
                    main[k] = *h;
                }
            }
            for (k, &(i, j)) in list.extra.iter().enumerate() {
                if let Some(h) = saved.get(&key(i as usize, j as usize)) {
                    extra[k] = *h;
                }
            }
        }
        world.histories = PairHistories { main, extra };
        if world.friction.is_some() {
            let rolling = world.friction.as_ref().is_some_and(|t| t.rolling());
            world.shear =
                friction::restore_shear(bodies, &world.ghosts, list, &saved_shear, rolling);
        }
        // Tracked contacts that are still open but no longer listed (they
        // separated by more than the skin within one step) stay listed, as
        // extra pairs, until the log has seen them end.
        let mut kept: Vec<(u32, u32, Track)> = Vec::new();
        if let (Some(saved), Some(tracks)) = (saved_tracks, world.tracks.as_mut()) {
            tracks.main = vec![Track::default(); list.j.len()];
            tracks.extra = vec![Track::default(); list.extra.len()];
            let mut found = rustc_hash::FxHashSet::default();
            for (i, k) in list.entries() {
                let key = key(i, list.j[k] as usize);
                if let Some(t) = saved.get(&key) {
                    tracks.main[k] = *t;
                    found.insert(key);
                }
            }
            for (k, &(i, j)) in list.extra.iter().enumerate() {
                let key = key(i as usize, j as usize);
                if let Some(t) = saved.get(&key) {
                    tracks.extra[k] = *t;
                    found.insert(key);
                }
            }
            let mut open: Vec<_> = saved
                .iter()
                .filter(|(key, t)| t.in_contact() && !found.contains(*key))
                .map(|(key, t)| (*key, *t))
                .collect();
            open.sort_by_key(|(key, _)| *key);
            // By input id (a rank of a decomposed run holds some bodies
            // only: a pair with one elsewhere is kept by the other rank).
            let at: FxHashMap<u32, usize> = bodies
                .id
                .iter()
                .enumerate()
                .map(|(k, &id)| (id, k))
                .collect();
            for ((a, b), t) in open {
                let (Some(&i), Some(&j)) = (at.get(&a), at.get(&b)) else {
                    continue;
                };
                if bodies.fixed[i] && bodies.fixed[j] {
                    continue;
                }
                kept.push((
                    i as u32,
                    nearest_image(bodies, &world.ghosts, i, j) as u32,
                    t,
                ));
            }
        }
        for (i, j, t) in kept {
            world.list.extra.push((i, j));
            if world.laws.history {
                // A contact that separated keeps no history worth carrying.
                world.histories.extra.push(ContactHistory::default());
            }
            if world.friction.is_some() {
                world.shear.push_extra();
            }
            if let Some(tracks) = world.tracks.as_mut() {
                tracks.extra.push(t);
            }
        }
        self.reference.clone_from(&world.bodies.position);
    }
}

/// The near range of the wall lists, m: the skin; with the collision log
/// twice the skin, since a track starts at −skin, which a body may reach
/// from 1.5 skins away at the last build (it moves ≤ skin/2 between
/// builds).
pub(crate) fn wall_range(world: &World) -> f64 {
    if world.wall_contacts.keep_track {
        2.0 * world.skin
    } else {
        world.skin
    }
}
