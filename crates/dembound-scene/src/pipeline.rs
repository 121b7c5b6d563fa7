//! One time step as named stages: ghosts, neighbours, forces, integrate,
//! observe. The [`World`] is the data set; the [`Pipeline`] holds only
//! scratch (the reference positions of the displacement check and the
//! cell grid).

pub(crate) mod observe;

use std::collections::HashMap;
use std::time::Instant;

use dembound_physics::contact::ContactHistory;

use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::collisions::{Collision, Motion, Partner, Track};
use crate::dynamics::contacts::{self, extended, LawTable, PairHistories};
use crate::dynamics::friction::{self, FrictionTable, PairShear};
use crate::dynamics::gear5_rotation;
use crate::dynamics::integrate;
use crate::dynamics::kinks::Kinks;
use crate::dynamics::walls;
use crate::geometry::cells::{sort_by_cell, CellGrid};
use crate::geometry::domain::Domain;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::{PairList, SearchInput};
use crate::parallel::{SharedMut, Workers, STEP_CHUNK};
use crate::setup::Scheme;
use crate::walls::{Surface, WallContacts, WallContactsMut};

/// What a wall in file order is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WallKind {
    /// Index into [`World::surfaces`].
    Surface(usize),
    /// Boundary particles: the bodies whose group is this wall.
    Particles,
}

/// Collision tracking state, aligned with the lists.
#[derive(Debug, Clone, Default)]
pub struct Tracks {
    pub main: Vec<Track>,
    pub extra: Vec<Track>,
}

/// The data set of a simulation.
#[derive(Debug, Clone)]
pub struct World {
    pub bodies: Bodies,
    /// The walls other than boundary particles (planes, cylinders), in
    /// file order.
    pub surfaces: Vec<Surface>,
    /// Each body's near wall elements with their contact state (springs
    /// and collision tracks included).
    pub wall_contacts: WallContacts,
    pub walls: Vec<WallKind>,
    pub domain: Domain,
    pub laws: LawTable,
    pub gravity: [f64; 3],
    pub scheme: Scheme,
    /// s.
    pub dt: f64,
    pub steps_done: u64,
    /// Neighbour skin, m.
    pub skin: f64,
    /// Cell edge (≥ the largest pair range among celled bodies), m.
    pub cell_size: f64,
    /// Bodies larger than this (m) are paired outside the cells.
    pub large_radius: f64,
    pub list: PairList,
    pub histories: PairHistories,
    pub ghosts: Ghosts,
    /// `Some` when the collision log is on.
    pub tracks: Option<Tracks>,
    pub collisions: Vec<Collision>,
    pub rebuilds: u64,
    /// Friction and rotation (issue 13); `None`: frictionless.
    pub friction: Option<FrictionTable>,
    /// Tangential displacements of the listed pairs (friction only).
    pub shear: PairShear,
}

impl World {
    pub fn time(&self) -> f64 {
        self.steps_done as f64 * self.dt
    }
}

/// Scratch of the stages.
#[derive(Debug, Clone, Default)]
pub struct Pipeline {
    /// Positions at the last list build, m.
    pub reference: Vec<[f64; 3]>,
    grid: CellGrid,
    /// Verlet's last half kick of the previous step is still to apply.
    pub(crate) pending_kick: bool,
    /// Verlet: this step's first half (kicks, drift, per-body forces) is
    /// done: it was fused into the last step's force stage.
    advanced: bool,
    /// Gear5: the contacts that began or ended inside the step.
    kinks: Kinks,
    /// Set by a domain decomposition before each list build: the whole
    /// scene's grid, so that every rank sorts its bodies by the same cells
    /// (and by input id within a cell) and adds each body's pair forces in
    /// that order, whatever part of the scene it holds.
    pub(crate) whole_grid: Option<WholeGrid>,
}

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

/// What differs between one process and one rank of a decomposed scene
/// (`comm::distributed`), called by the step at fixed points: what fills
/// the halo, what a list rebuild migrates, in which order a body's pair
/// forces are summed, which logged collisions a process keeps. The stages
/// themselves (integration, per-body forces, the collision log) are the
/// pipeline's, the same for both.
pub(crate) trait StepHooks {
    /// The largest squared displacement since the last list build over
    /// every process (all rebuild at the same step), m².
    fn max_moved2(&mut self, moved2: f64) -> f64;
    /// New lists (a rank first migrates bodies and rebuilds its halo).
    fn rebuild(&mut self, pipeline: &mut Pipeline, world: &mut World, workers: &Workers);
    /// Halo copies take their owners' state (before the ghosts follow).
    fn halo(&mut self, world: &mut World);
    /// Adds the pair forces (springs moved by `dt` s of slip) to each
    /// body's force, in the order this kind of run fixes.
    fn pair_forces(
        &mut self,
        pipeline: &mut Pipeline,
        world: &mut World,
        workers: &Workers,
        dt: f64,
    );
    /// Verlet may fuse the next step's first half into the force stage
    /// (every pair in the force blocks, summed by the engine's loop).
    fn fusable(&self, world: &World) -> bool;
    /// The collision log got entries `before..` this step.
    fn logged(&mut self, world: &mut World, before: usize);
}

/// One process: no halo beyond the periodic ghosts, no migration, the
/// engine's own sums.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Local;

impl StepHooks for Local {
    fn max_moved2(&mut self, moved2: f64) -> f64 {
        moved2
    }
    fn rebuild(&mut self, pipeline: &mut Pipeline, world: &mut World, workers: &Workers) {
        pipeline.neighbours(world, workers);
    }
    fn halo(&mut self, _world: &mut World) {}
    fn pair_forces(
        &mut self,
        pipeline: &mut Pipeline,
        world: &mut World,
        workers: &Workers,
        dt: f64,
    ) {
        pipeline.pair_forces(world, workers, dt);
    }
    fn fusable(&self, world: &World) -> bool {
        world.list.extra.is_empty()
    }
    fn logged(&mut self, _world: &mut World, _before: usize) {}
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

impl Pipeline {
    /// Builds the lists and evaluates the first forces.
    pub fn start(&mut self, world: &mut World, workers: &Workers) {
        self.neighbours(world, workers);
        self.forces(world, workers);
        if world.scheme == Scheme::Gear5 && world.bodies.higher.len() != world.bodies.len() {
            integrate::gear5_start(&mut world.bodies, world.dt);
        }
        if world.scheme == Scheme::Gear5
            && world.friction.is_some()
            && world.bodies.angular_higher.len() != world.bodies.len()
        {
            gear5_rotation::start(&mut world.bodies, world.dt);
        }
    }

    /// `n` steps. Verlet's last half kick of a step is fused with the first
    /// of the next (the same operations in the same order as two passes:
    /// the same bits however the steps are grouped); the state is complete
    /// again when this returns. `hooks`: what one process or one rank of a
    /// decomposed scene does at the points where they differ ([`StepHooks`]).
    pub(crate) fn steps(
        &mut self,
        world: &mut World,
        workers: &Workers,
        n: u64,
        hooks: &mut impl StepHooks,
    ) {
        for k in 0..n {
            self.step(world, workers, k + 1 < n, hooks);
        }
        self.finish(world, workers);
    }

    /// Applies a pending half kick.
    pub fn finish(&mut self, world: &mut World, workers: &Workers) {
        if self.pending_kick {
            integrate::verlet_kick(&mut world.bodies, world.dt, workers);
            if world.friction.is_some() {
                friction_spin_kick(&mut world.bodies, world.dt, workers);
            }
            self.pending_kick = false;
            self.ghosts(world);
        }
    }

    /// One step; `more`: another follows in this call (Verlet may then
    /// fuse the next step's first half into this one's force stage).
    fn step(
        &mut self,
        world: &mut World,
        workers: &Workers,
        more: bool,
        hooks: &mut impl StepHooks,
    ) {
        let dt = world.dt;
        match world.scheme {
            Scheme::Verlet => {
                // Stages integrate (first half) and forces (per body:
                // gravity, walls) in one pass over the bodies.
                if !std::mem::take(&mut self.advanced) {
                    let moved2 = self.verlet_advance(world, workers);
                    self.after_advance(world, workers, moved2, hooks);
                }
                // The fused form does the same operations on each body in
                // the same order: the same bits. It needs every pair in
                // the blocks (no extra pairs) and no per-step observers.
                let fuse = more && world.tracks.is_none() && hooks.fusable(world);
                if fuse {
                    let moved2 = self.pair_forces_then_advance(world, workers);
                    world.list.rebalance();
                    self.share_cuts(world, workers);
                    world.steps_done += 1;
                    self.advanced = true;
                    self.after_advance(world, workers, moved2, hooks);
                    return;
                }
                hooks.pair_forces(self, world, workers, dt);
                world.list.rebalance();
                self.share_cuts(world, workers);
                if world.tracks.is_some() {
                    integrate::verlet_kick(&mut world.bodies, dt, workers);
                    if world.friction.is_some() {
                        friction_spin_kick(&mut world.bodies, dt, workers);
                    }
                } else {
                    self.pending_kick = true;
                }
            }
            Scheme::Gear5 => {
                let moved2 =
                    integrate::gear5_predict(&mut world.bodies, &self.reference, dt, workers);
                let friction = world.friction.is_some();
                if friction {
                    gear5_rotation::predict(&mut world.bodies, workers);
                }
                let moved2 = hooks.max_moved2(moved2);
                if needs_rebuild(moved2, 0.5 * world.skin) {
                    hooks.rebuild(self, world, workers);
                } else {
                    hooks.halo(world);
                    self.ghosts(world);
                }
                // At the predicted state. With friction the springs move
                // by Δt of the predicted slip (`gear5_rotation`); without,
                // Δt plays no part in the forces.
                let springs_dt = if friction { dt } else { 0.0 };
                self.body_forces(world, workers, springs_dt);
                hooks.pair_forces(self, world, workers, springs_dt);
                world.list.rebalance();
                self.share_cuts(world, workers);
                self.gear5_correct(world, workers);
            }
        }
        world.steps_done += 1;
        if world.tracks.is_some() {
            // The copies' state at the step's end: every process tracks a
            // pair with the same bits.
            hooks.halo(world);
            self.ghosts(world);
            let before = world.collisions.len();
            self.observe(world);
            hooks.logged(world, before);
        }
    }

    /// Gear5's corrector with the forces at the predicted state, the
    /// contacts that began or ended inside the step integrated exactly
    /// ([`Kinks`]).
    pub(crate) fn gear5_correct(&mut self, world: &mut World, workers: &Workers) {
        let dt = world.dt;
        // At the predicted state, before the corrector moves it.
        self.kinks.collect(
            &world.bodies,
            &world.ghosts,
            &world.list,
            &world.surfaces,
            &world.wall_contacts,
            &world.laws,
            dt,
        );
        let c = integrate::gear5_corrector(world.laws.model.depends_on_rate());
        integrate::gear5_correct(&mut world.bodies, dt, c, workers);
        self.kinks.apply(&mut world.bodies, dt, c);
        if world.friction.is_some() {
            gear5_rotation::correct(&mut world.bodies, dt, workers);
        }
    }

    /// Hands the shares' body cuts to the workers' per-body passes.
    fn share_cuts(&self, world: &World, workers: &Workers) {
        let threads = workers.threads();
        if threads < 2 {
            return;
        }
        let mut cuts = Vec::with_capacity(threads + 1);
        for t in 0..threads {
            match world.list.share(t, threads) {
                Some((lo, _)) => cuts.push(lo),
                None => return,
            }
        }
        cuts.push(world.bodies.len());
        workers.set_body_cuts(&cuts);
    }

    /// After Verlet's first half: the lists again if a body (of any
    /// process) moved more than half the skin since they were built (then
    /// the per-body forces again: the wall masks are new; the same state,
    /// so history updates are idempotent), else the halo and the ghosts
    /// follow their owners.
    fn after_advance(
        &mut self,
        world: &mut World,
        workers: &Workers,
        moved2: f64,
        hooks: &mut impl StepHooks,
    ) {
        let moved2 = hooks.max_moved2(moved2);
        if needs_rebuild(moved2, 0.5 * world.skin) {
            hooks.rebuild(self, world, workers);
            self.body_forces(world, workers, world.dt);
        } else {
            hooks.halo(world);
            self.ghosts(world);
        }
    }

    /// The pair forces of this step and, fused, Verlet's first half of the
    /// next: each block's bodies are kicked, drifted and given their
    /// per-body forces as soon as their pair forces are complete
    /// (`contacts::run_blocks_then`), by the worker that forced them. One
    /// hand-off between the workers per step instead of two. Returns the
    /// largest squared displacement since the last list build, m².
    pub(crate) fn pair_forces_then_advance(&mut self, world: &mut World, workers: &Workers) -> f64 {
        let n = world.bodies.len();
        assert!(
            self.reference.len() == n
                && world.bodies.mass.len() == n
                && world.bodies.fixed.len() == n
                && world.bodies.force.len() == n
        );
        if world.friction.is_some() {
            world.bodies.torque.resize(n, [0.0; 3]);
        }
        let f = SharedMut::new(&mut world.bodies.force);
        let torque = SharedMut::new(&mut world.bodies.torque);
        let spin = SharedMut::new(&mut world.bodies.angular_velocity);
        let ctx = AdvanceContext {
            x: SharedMut::new(&mut world.bodies.position),
            v: SharedMut::new(&mut world.bodies.velocity),
            f,
            walls: world.wall_contacts.shared(),
            bodies: &world.bodies,
            surfaces: &world.surfaces,
            laws: &world.laws,
            gravity: world.gravity,
            reference: &self.reference,
            dt: world.dt,
            // This step's closing half kick, not applied yet.
            pending: true,
            spin,
            torque,
            friction: world.friction.as_ref(),
            // The next step's forces.
            step: world.steps_done + 2,
        };
        // SAFETY (the follow-ups): each block's bodies lo..hi are given
        // once, to one worker, when their forces (and torques) are complete
        // and no block still reads them (run_blocks_then); lengths asserted.
        let follow = |lo: usize, hi: usize| unsafe { verlet_chunk(&ctx, lo, hi) };
        let follow_friction = |lo: usize, hi: usize| unsafe { verlet_chunk_friction(&ctx, lo, hi) };
        if let Some(table) = world.friction.as_ref() {
            // SAFETY: `f` and `torque` hold one entry per body; only the
            // force loop and the follow-up touch them, under the blocks'
            // rule.
            return unsafe {
                friction::add_pair_forces_then(
                    &friction::PairForceInput {
                        bodies: &world.bodies,
                        ghosts: &world.ghosts,
                        list: &world.list,
                        laws: &world.laws,
                        friction: table,
                        dt: world.dt,
                    },
                    &mut world.histories,
                    &mut world.shear,
                    (f, torque),
                    workers,
                    Some(&follow_friction),
                )
            };
        }
        // SAFETY: as above, for the forces.
        unsafe {
            contacts::add_pair_forces_then(
                &world.bodies,
                &world.ghosts,
                &world.list,
                &mut world.histories,
                &world.laws,
                f,
                workers,
                Some(&follow),
            )
        }
    }

    /// Verlet: the pending half kick of the last step (if any), the half
    /// kick and drift of this one, and the body's gravity and wall forces
    /// at its new position. Returns the largest squared displacement since
    /// the last list build, m².
    pub(crate) fn verlet_advance(&mut self, world: &mut World, workers: &Workers) -> f64 {
        let n = world.bodies.len();
        let pending = self.pending_kick;
        self.pending_kick = false;
        let spin = SharedMut::new(&mut world.bodies.angular_velocity);
        let torque = SharedMut::new(&mut world.bodies.torque);
        let ctx = AdvanceContext {
            x: SharedMut::new(&mut world.bodies.position),
            v: SharedMut::new(&mut world.bodies.velocity),
            f: SharedMut::new(&mut world.bodies.force),
            walls: world.wall_contacts.shared(),
            bodies: &world.bodies,
            surfaces: &world.surfaces,
            laws: &world.laws,
            gravity: world.gravity,
            reference: &self.reference,
            dt: world.dt,
            pending,
            spin,
            torque,
            friction: world.friction.as_ref(),
            step: world.steps_done + 1,
        };
        assert!(
            self.reference.len() == n
                && world.bodies.mass.len() == n
                && world.bodies.fixed.len() == n
        );
        // SAFETY (both calls): the ranges are disjoint ranges of bodies;
        // lengths asserted.
        let advance = |lo: usize, hi: usize| unsafe {
            if ctx.friction.is_some() {
                verlet_chunk_friction(&ctx, lo, hi)
            } else {
                verlet_chunk(&ctx, lo, hi)
            }
        };
        let threads = workers.threads();
        let partial = if world.list.share(threads - 1, threads).map(|s| s.1) == Some(n) {
            // Each worker advances the bodies of its share of the force
            // loop: they stay in its core's cache (a maximum is exact in
            // any order: the same bits).
            let list = &world.list;
            workers.broadcast(|t| {
                let started = Instant::now();
                let moved2 = list
                    .share(t, threads)
                    .map_or(0.0, |(lo, hi)| advance(lo, hi));
                list.shares
                    .record_advance(t, started.elapsed().as_nanos() as u64);
                moved2
            })
        } else {
            workers.map(n.div_ceil(STEP_CHUNK), |c| {
                advance(c * STEP_CHUNK, ((c + 1) * STEP_CHUNK).min(n))
            })
        };
        partial.into_iter().fold(0.0, f64::max)
    }

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

        let n = world.bodies.len();
        for k in 0..n {
            world.bodies.position[k] = world.domain.wrap(world.bodies.position[k]);
        }
        // Grid bounds: the box on periodic axes, the celled bodies' extent elsewhere.
        let large = world.large_radius;
        let (mut lo, mut hi) = celled_extent(world);
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
        let cell: Vec<u32> = (0..n)
            .map(|k| {
                if world.bodies.radius[k] > large {
                    cells as u32
                } else {
                    self.grid.index(self.grid.coords(world.bodies.position[k])) as u32
                }
            })
            .collect();
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
        world.bodies.permute(&order);
        world.wall_contacts.permute(&order);
        world
            .wall_contacts
            .refresh(&world.bodies, &world.surfaces, wall_range(world));
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
            let mut found = std::collections::HashSet::new();
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
            let at: HashMap<u32, usize> = bodies
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

    /// Stage "forces": gravity and plane walls per body, then the pairs.
    /// With friction the tangential springs do not move (LAMMPS's setup):
    /// used at the start only (Gear5 with friction steps with the body
    /// and pair force stages over Δt).
    pub fn forces(&mut self, world: &mut World, workers: &Workers) {
        self.body_forces(world, workers, 0.0);
        self.pair_forces(world, workers, 0.0);
    }

    /// Gravity and plane walls: sets each body's force (and torque, with
    /// friction; the springs move by `dt` s of slip).
    pub(crate) fn body_forces(&mut self, world: &mut World, workers: &Workers, dt: f64) {
        world.bodies.force.resize(world.bodies.len(), [0.0; 3]);
        if world.friction.is_some() {
            self.body_forces_friction(world, workers, dt);
            return;
        }
        let mut force = std::mem::take(&mut world.bodies.force);
        walls::start_forces(
            &world.bodies,
            &world.surfaces,
            &mut world.wall_contacts,
            &world.laws,
            world.gravity,
            &mut force,
            workers,
        );
        world.bodies.force = force;
    }

    /// [`Self::body_forces`] with friction: forces and torques.
    fn body_forces_friction(&mut self, world: &mut World, workers: &Workers, dt: f64) {
        let n = world.bodies.len();
        world.bodies.torque.resize(n, [0.0; 3]);
        let mut force = std::mem::take(&mut world.bodies.force);
        let mut torque = std::mem::take(&mut world.bodies.torque);
        let (f, t) = (SharedMut::new(&mut force), SharedMut::new(&mut torque));
        let walls = world.wall_contacts.shared();
        if let Some(table) = world.friction.as_ref() {
            let input = friction::BodyForceInput {
                bodies: &world.bodies,
                surfaces: &world.surfaces,
                laws: &world.laws,
                friction: table,
                gravity: world.gravity,
                step: world.steps_done + u64::from(dt > 0.0),
                dt,
            };
            let b = &world.bodies;
            workers.run_bodies(n, crate::parallel::BODY_CHUNK, |c| {
                let chunk = crate::parallel::BODY_CHUNK;
                for i in c * chunk..((c + 1) * chunk).min(n) {
                    // SAFETY: chunks are disjoint ranges of bodies.
                    unsafe {
                        let (fi, ti) = friction::body_force(
                            &input,
                            i,
                            (b.position[i], b.velocity[i], b.angular_velocity[i]),
                            &walls,
                        );
                        *f.at(i) = fi;
                        *t.at(i) = ti;
                    }
                }
            });
        }
        world.bodies.force = force;
        world.bodies.torque = torque;
    }

    /// Adds the pair forces (and torques, with friction; the springs move
    /// by `dt` s of slip).
    pub(crate) fn pair_forces(&mut self, world: &mut World, workers: &Workers, dt: f64) {
        if let Some(table) = world.friction.as_ref() {
            let mut force = std::mem::take(&mut world.bodies.force);
            let mut torque = std::mem::take(&mut world.bodies.torque);
            friction::add_pair_forces(
                &friction::PairForceInput {
                    bodies: &world.bodies,
                    ghosts: &world.ghosts,
                    list: &world.list,
                    laws: &world.laws,
                    friction: table,
                    dt,
                },
                &mut world.histories,
                &mut world.shear,
                &mut force,
                &mut torque,
                workers,
            );
            world.bodies.force = force;
            world.bodies.torque = torque;
            return;
        }
        let mut force = std::mem::take(&mut world.bodies.force);
        contacts::add_pair_forces(
            &world.bodies,
            &world.ghosts,
            &world.list,
            &mut world.histories,
            &world.laws,
            &mut force,
            workers,
        );
        world.bodies.force = force;
    }

    /// Stage "observe": the collision log at the end of the step.
    pub fn observe(&mut self, world: &mut World) {
        let t = world.time();
        let Some(tracks) = world.tracks.as_mut() else {
            return;
        };
        let dt = world.dt;
        let bodies = &world.bodies;
        let n = bodies.len();
        let laws = &world.laws;
        let mut log = Vec::new();
        let mut visit = |i: usize, j_ext: usize, track: &mut Track, history: &ContactHistory| {
            let (xj, vj, owner) = extended(bodies, &world.ghosts, j_ext);
            let g = contacts::separation(
                bodies.position[i],
                bodies.velocity[i],
                bodies.radius[i],
                xj,
                vj,
                bodies.radius[owner],
            );
            let law = laws.pair(bodies, i, owner);
            let spin = |k: usize| bodies.angular_velocity.get(k).copied().unwrap_or([0.0; 3]);
            let vi = bodies.velocity[i];
            let motion = Motion {
                tangential: friction::tangential(
                    [vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2]],
                    g.normal,
                ),
                spin_i: spin(i),
                spin_j: spin(owner),
            };
            if let Some((c, before, after)) =
                track.advance_with_motion(t, dt, g.overlap, g.overlap_rate, motion, |h, r| {
                    law.force(h, r, history)
                })
            {
                let (a, b) = (bodies.id[i] as usize, bodies.id[owner] as usize);
                let (i, j) = collision_pair(a, bodies.group[i], b, bodies.group[owner]);
                let (vt_in, vt_out) = Motion::tangential_pair(&before, &after);
                // The log's sphere i is the engine's owner, not i: spins swap.
                let swap = i != a;
                let pick =
                    |m: &Motion, first: bool| if first != swap { m.spin_i } else { m.spin_j };
                log.push(Collision {
                    i,
                    j,
                    t_start: c.t_start,
                    t_end: c.t_end,
                    duration: c.t_end - c.t_start,
                    max_overlap: c.max_overlap,
                    max_normal_force: c.max_force,
                    impact_normal_velocity: c.impact,
                    rebound_normal_velocity: c.rebound,
                    impact_tangential_velocity: vt_in,
                    rebound_tangential_velocity: vt_out,
                    impact_spin_i: pick(&before, true),
                    rebound_spin_i: pick(&after, true),
                    impact_spin_j: pick(&before, false),
                    rebound_spin_j: pick(&after, false),
                });
            }
        };
        for i in 0..n {
            for k in world.list.start[i] as usize..world.list.start[i + 1] as usize {
                visit(
                    i,
                    world.list.j[k] as usize,
                    &mut tracks.main[k],
                    world.histories.main(k),
                );
            }
        }
        for (k, &(i, j)) in world.list.extra.iter().enumerate() {
            visit(
                i as usize,
                j as usize,
                &mut tracks.extra[k],
                world.histories.extra(k),
            );
        }
        let wc = &mut world.wall_contacts;
        if wc.bodies() == n && wc.track.len() == wc.key.len() {
            for i in 0..n {
                if bodies.fixed[i] {
                    continue;
                }
                for k in wc.range(i) {
                    let key = wc.key[k];
                    let surface = &world.surfaces[key.wall as usize];
                    let c = surface.contact(
                        key.element,
                        bodies.position[i],
                        bodies.velocity[i],
                        bodies.radius[i],
                    );
                    let (h, rate) = (c.overlap, c.rate);
                    let track = &mut wc.track[k];
                    // Only couples near contact are worth tracking.
                    if h < -world.skin && !track.is_known() {
                        continue;
                    }
                    let law = laws.wall(bodies, i, surface.law_slot(key.element));
                    let hist = wc.history.get(k).unwrap_or(&contacts::NO_HISTORY);
                    let v = bodies.velocity[i];
                    let motion = Motion {
                        tangential: friction::tangential(v, c.normal),
                        spin_i: bodies.angular_velocity.get(i).copied().unwrap_or([0.0; 3]),
                        spin_j: [0.0; 3],
                    };
                    if let Some((c, before, after)) =
                        track.advance_with_motion(t, dt, h, rate, motion, |h, r| {
                            law.force(h, r, hist)
                        })
                    {
                        let (vt_in, vt_out) = Motion::tangential_pair(&before, &after);
                        log.push(Collision {
                            i: bodies.id[i] as usize,
                            j: Partner::Wall(surface.file_index()),
                            t_start: c.t_start,
                            t_end: c.t_end,
                            duration: c.t_end - c.t_start,
                            max_overlap: c.max_overlap,
                            max_normal_force: c.max_force,
                            impact_normal_velocity: c.impact,
                            rebound_normal_velocity: c.rebound,
                            impact_tangential_velocity: vt_in,
                            rebound_tangential_velocity: vt_out,
                            impact_spin_i: before.spin_i,
                            rebound_spin_i: after.spin_i,
                            impact_spin_j: [0.0; 3],
                            rebound_spin_j: [0.0; 3],
                        });
                    }
                    if h < -world.skin {
                        *track = Track::default();
                    }
                }
            }
        }
        // A fixed order within the step: by pair.
        log.sort_by_key(|c| (c.i, partner_key(c.j)));
        world.collisions.extend(log);
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

/// Pair state by input ids (a < b), carried across a list rebuild.
#[derive(Debug, Clone, Default)]
pub(crate) struct SavedPairs {
    pub histories: HashMap<(u32, u32), ContactHistory>,
    pub tracks: Option<HashMap<(u32, u32), Track>>,
    pub shear: HashMap<(u32, u32), friction::Springs>,
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
        friction::active_shear(&world.bodies, &world.ghosts, &world.list, &world.shear)
            .into_iter()
            .map(|(a, b, s)| ((a, b), s))
            .collect()
    } else {
        HashMap::new()
    };
    SavedPairs {
        histories,
        tracks,
        shear,
    }
}

/// What [`verlet_chunk`] needs. `bodies` is read only for radius, mass,
/// fixed flag and class; positions, velocities and forces go through the
/// raw pointers.
struct AdvanceContext<'a> {
    x: SharedMut<[f64; 3]>,
    v: SharedMut<[f64; 3]>,
    f: SharedMut<[f64; 3]>,
    walls: WallContactsMut,
    bodies: &'a Bodies,
    surfaces: &'a [Surface],
    laws: &'a LawTable,
    gravity: [f64; 3],
    reference: &'a [[f64; 3]],
    dt: f64,
    pending: bool,
    spin: SharedMut<[f64; 3]>,
    torque: SharedMut<[f64; 3]>,
    friction: Option<&'a FrictionTable>,
    /// The step being made (its forces' stamp).
    step: u64,
}

unsafe impl Sync for AdvanceContext<'_> {}

/// Verlet's first half (after a pending closing half kick) and the
/// per-body forces of bodies lo..hi. Returns their largest squared
/// displacement since the last list build, m².
///
/// # Safety
/// lo..hi within the bodies, and no other thread touches these bodies.
#[inline(never)]
unsafe fn verlet_chunk(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    let b = c.bodies;
    let half_dt = 0.5 * c.dt;
    let mut m = 0.0f64;
    // Local slices: their headers are not reloaded after the raw writes.
    let (fixed, mass, reference) = (&b.fixed[..], &b.mass[..], c.reference);
    for i in lo..hi {
        let fi = c.f.at(i);
        if *fixed.get_unchecked(i) {
            *fi = [0.0; 3];
            continue;
        }
        let (xi, vi) = (c.x.at(i), c.v.at(i));
        let dtfm = half_dt / *mass.get_unchecked(i);
        if c.pending {
            integrate::half_kick(vi, *fi, dtfm);
        }
        integrate::half_kick(vi, *fi, dtfm);
        integrate::drift(xi, *vi, c.dt);
        m = m.max(integrate::displacement2(*xi, *reference.get_unchecked(i)));
        *fi = walls::body_force(b, i, *xi, *vi, c.surfaces, &c.walls, c.laws, c.gravity);
    }
    m
}

/// [`verlet_chunk`] with rotation: ω gets the same half kicks from the
/// torque (Δt/2 · τ/I, LAMMPS `nve/sphere`), and the per-body forces are
/// the friction pass's ([`friction::body_force`]).
///
/// # Safety
/// As [`verlet_chunk`].
#[inline(never)]
unsafe fn verlet_chunk_friction(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (just checked); the rest as ours.
        return verlet_chunk_friction_avx2(c, lo, hi);
    }
    verlet_chunk_friction_body(c, lo, hi)
}

/// [`verlet_chunk_friction`] compiled for AVX2 (the same operations in
/// the same order, no fused multiply–add: the same bits).
///
/// # Safety
/// As [`verlet_chunk`], and the processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2")]
unsafe fn verlet_chunk_friction_avx2(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    verlet_chunk_friction_body(c, lo, hi)
}

/// # Safety
/// As [`verlet_chunk`].
#[inline(always)]
unsafe fn verlet_chunk_friction_body(c: &AdvanceContext, lo: usize, hi: usize) -> f64 {
    let b = c.bodies;
    let half_dt = 0.5 * c.dt;
    let mut m = 0.0f64;
    let Some(table) = c.friction else {
        return m;
    };
    let input = friction::BodyForceInput {
        bodies: b,
        surfaces: c.surfaces,
        laws: c.laws,
        friction: table,
        gravity: c.gravity,
        step: c.step,
        dt: c.dt,
    };
    // Two passes over the chunk: the integration and the weights of all
    // bodies, then the plane walls' forces of the few near a wall. One
    // pass spilled the wall code's registers on every body. Each body gets
    // the same operations in the same order: the same bits.
    for i in lo..hi {
        // SAFETY: a body of this chunk; its springs are read in the
        // second pass.
        friction::prefetch_wall_springs(i, &c.walls);
        let fi = c.f.at(i);
        let ti = c.torque.at(i);
        if b.fixed[i] {
            *fi = [0.0; 3];
            *ti = [0.0; 3];
            continue;
        }
        let (xi, vi, wi) = (c.x.at(i), c.v.at(i), c.spin.at(i));
        let dtfm = half_dt / b.mass[i];
        let dtfi = half_dt * b.inverse_inertia[i];
        // Kicks and drift on copies, stored once: written and read back
        // through memory, the halves of a vector store do not forward to
        // the next load and each body stalled on it. The same operations
        // in the same order.
        let (mut x, mut v, mut w, f0, t0) = (*xi, *vi, *wi, *fi, *ti);
        if c.pending {
            integrate::half_kick(&mut v, f0, dtfm);
            integrate::half_kick(&mut w, t0, dtfi);
        }
        integrate::half_kick(&mut v, f0, dtfm);
        integrate::half_kick(&mut w, t0, dtfi);
        integrate::drift(&mut x, v, c.dt);
        (*xi, *vi, *wi) = (x, v, w);
        m = m.max(integrate::displacement2(x, c.reference[i]));
        *fi = friction::gravity_force(&input, i);
        *ti = [0.0; 3];
    }
    for i in lo..hi {
        let (s, e) = c.walls.range(i);
        if b.fixed[i] || s == e {
            continue;
        }
        let (fi, ti) = (c.f.at(i), c.torque.at(i));
        let (mut f, mut t) = (*fi, *ti);
        let state = (*c.x.at(i), *c.v.at(i), *c.spin.at(i));
        friction::add_plane_forces(&input, i, state, &c.walls, &mut f, &mut t);
        (*fi, *ti) = (f, t);
    }
    m
}

/// Verlet's last half kick of the spins: ω ← ω + Δt/2 · τ/I.
fn friction_spin_kick(bodies: &mut Bodies, dt: f64, workers: &Workers) {
    let n = bodies.len();
    let w = SharedMut::new(&mut bodies.angular_velocity);
    let (torque, inv, fixed) = (&bodies.torque, &bodies.inverse_inertia, &bodies.fixed);
    workers.run_bodies(n, STEP_CHUNK, |c| {
        for i in c * STEP_CHUNK..((c + 1) * STEP_CHUNK).min(n) {
            if !fixed[i] {
                // SAFETY: one body per iteration.
                integrate::half_kick(unsafe { w.at(i) }, torque[i], 0.5 * dt * inv[i]);
            }
        }
    });
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

/// A body moved more than half the skin (or a position is not finite).
pub(crate) fn needs_rebuild(moved2: f64, half_skin: f64) -> bool {
    moved2.is_nan() || moved2 > half_skin * half_skin
}

pub(crate) fn partner_key(p: Partner) -> (u8, usize) {
    match p {
        Partner::Body(j) => (0, j),
        Partner::Wall(w) => (1, w),
        Partner::BoundaryParticle { body, .. } => (0, body),
    }
}

/// The two sides of a sphere–sphere collision, by input index a, b and
/// wall group: a boundary particle of a wall is named as the wall's
/// partner; two free (or two grouped) spheres in index order.
fn collision_pair(a: usize, group_a: u32, b: usize, group_b: u32) -> (usize, Partner) {
    match (group_a != NO_GROUP, group_b != NO_GROUP) {
        (false, true) => (
            a,
            Partner::BoundaryParticle {
                wall: group_b as usize,
                body: b,
            },
        ),
        (true, false) => (
            b,
            Partner::BoundaryParticle {
                wall: group_a as usize,
                body: a,
            },
        ),
        _ => (a.min(b), Partner::Body(a.max(b))),
    }
}

/// The tracks of the listed couples that have a previous step, by input ids.
pub(crate) fn saved_tracks_public(world: &World, tracks: &Tracks) -> HashMap<(u32, u32), Track> {
    saved_tracks(world, tracks)
}

fn saved_tracks(world: &World, tracks: &Tracks) -> HashMap<(u32, u32), Track> {
    let bodies = &world.bodies;
    let list = &world.list;
    let mut out = HashMap::new();
    if tracks.main.len() != list.j.len() || list.start.len() != bodies.len() + 1 {
        return out;
    }
    for i in 0..bodies.len() {
        for k in list.start[i] as usize..list.start[i + 1] as usize {
            if tracks.main[k].is_known() {
                let (a, b) = (bodies.id[i], bodies.id[list.j[k] as usize]);
                out.insert((a.min(b), a.max(b)), tracks.main[k]);
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

/// Whether body k belongs to a boundary-particle wall.
pub fn in_group(bodies: &Bodies, k: usize) -> bool {
    bodies.group[k] != NO_GROUP
}
