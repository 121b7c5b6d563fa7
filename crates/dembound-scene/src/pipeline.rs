//! One time step as named stages: ghosts, neighbours, forces, integrate,
//! observe. The [`World`] is the data set; the [`Pipeline`] holds only
//! scratch (the reference positions of the displacement check and the
//! cell grid).
//!
//! The step (Verlet, fused or not, with the collision log or not; Gear5)
//! is written once, here; what differs between one process and one rank
//! of a decomposed scene (the halo, migration at list rebuilds, the order
//! of the pair sums, which logged collisions a process keeps) is a
//! [`StepHooks`] implementation: [`Local`] here, the rank's in
//! `comm::distributed`. The stages: `neighbours` (ghosts and list
//! builds), `forces`, `verlet` (the first half fused with the per-body
//! forces), `collisions` (the collision log), `observe` (the global
//! observables, with their own hooks; `wall_loads` the walls' force and
//! torque from what the force stage recorded).

/// Four bodies' values (lane k: body k) spread over the lanes of their
/// three components stored body after body, `[x0 y0 z0 x1] [y1 z1 x2 y2]
/// [z2 x3 y3 z3]`: lanes [0 0 0 1], [1 1 2 2], [2 3 3 3]. For the AVX2
/// body passes (`verlet`, `closing_kick`); a macro, not a function or a
/// closure, so that it is compiled inside their AVX2 functions.
#[cfg(target_arch = "x86_64")]
macro_rules! spread_lanes {
    ($a:expr) => {{
        let a = $a;
        [
            _mm256_permute4x64_pd::<0x40>(a),
            _mm256_permute4x64_pd::<0xA5>(a),
            _mm256_permute4x64_pd::<0xFE>(a),
        ]
    }};
}

pub(crate) mod closing_kick;
mod collisions;
pub mod dissipation;
mod forces;
pub mod moving_groups;
pub(crate) mod moving_walls;
mod neighbours;
pub(crate) mod observe;
pub(crate) mod servo_walls;
pub(crate) mod triangle_loads;
mod verlet;
mod verlet_four;
pub(crate) mod wall_loads;
pub mod wall_states;

pub(crate) use collisions::partner_key;
pub(crate) use neighbours::{
    celled_extent, save_pairs, saved_tracks_public, SavedPairs, WholeGrid,
};
use verlet::friction_spin_kick;

use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::collisions::{Collision, Track};
use crate::dynamics::contacts::{LawTable, PairHistories};
use crate::dynamics::friction::{self, FrictionTable, PairShear};
use crate::dynamics::gear5_rotation;
use crate::dynamics::halo_split::HaloSplit;
use crate::dynamics::integrate;
use crate::dynamics::kinks::Kinks;
use crate::geometry::cells::CellGrid;
use crate::geometry::domain::Domain;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::Workers;
use crate::setup::Scheme;
use crate::walls::{Surface, WallContacts};

/// What a wall in file order is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WallKind {
    /// Index into [`World::surfaces`].
    Surface(usize),
    /// Boundary particles: the bodies whose group is this wall; their
    /// loads' torque point is the centroid of their positions at the
    /// start, m (`wall_loads::particle_wall_torque_point`).
    Particles { torque_point: [f64; 3] },
}

/// Collision tracking state, aligned with the lists.
#[derive(Debug, Clone, Default)]
pub struct Tracks {
    pub main: Vec<Track>,
    pub extra: Vec<Track>,
    /// The bodies' and ghosts' state at the log's last step and which
    /// main entries were in contact after it; while it is that of the
    /// current lists and step ([`collisions::LoggedStep::current`]), a main
    /// track out of contact holds its overlap, rate and motion of that
    /// step only here (the log stage skips pairs that do not touch).
    pub(crate) logged: Option<Box<collisions::LoggedStep>>,
    /// Tests: the log stage visits every listed pair every step, storing
    /// each one's state in its track (the path before [`Self::logged`]).
    #[cfg(test)]
    pub(crate) every_pair: bool,
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
    /// The moving walls and their work (issue 27, `moving_walls`); `None`
    /// when every wall is fixed.
    pub moving: Option<Box<moving_walls::MovingWalls>>,
    /// The removal of lost spheres (`domain.outside = "delete"`,
    /// `crate::removal`); `None` otherwise.
    pub removal: Option<Box<crate::removal::Removal>>,
    /// The walls that appear and vanish (issue 28, `walls::gate`); `None`
    /// when every wall acts always.
    pub gates: Option<Box<crate::walls::gate::Gates>>,
    /// The inlets (`[[inlet]]`, `crate::inlets`); `None` without.
    pub inlets: Option<Box<crate::inlets::Inlets>>,
    /// The dissipation summed contact by contact (`output.dissipation`,
    /// `dissipation`); `None` when off.
    pub dissipation: Option<Box<dissipation::Dissipation>>,
}

impl World {
    pub fn time(&self) -> f64 {
        self.steps_done as f64 * self.dt
    }
}

/// Each wall's force summed over the steps since the sum started
/// (`Simulation::start_wall_force_mean`).
#[derive(Debug, Clone, Default)]
pub(crate) struct WallForceSum {
    /// Σ F_s over the steps, N, file order.
    pub(crate) force: Vec<[f64; 3]>,
    /// How many steps were summed.
    pub(crate) steps: u64,
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
    /// Set by a domain decomposition after each list build: which pairs
    /// wait for the halo exchange (`dynamics::halo_split`), so that the
    /// others are computed while it is in flight.
    pub(crate) halo_split: Option<HaloSplit>,
    /// The halo exchange of this step is left to the force stage
    /// ([`StepHooks::halo_during`]).
    halo_deferred: bool,
    /// The contacts' observables of the state after the next
    /// [`Pipeline::steps`] are wanted: its last pair pass tallies them
    /// ([`Self::pair_tally`]).
    pub(crate) tally_wanted: bool,
    /// The pair pass running now tallies.
    tallying: bool,
    /// When set (one process only: `Simulation::start_wall_force_mean`),
    /// each step's wall forces (N, file order; the force pass's loads,
    /// what [`observe::ObserveHooks::wall_loads`] sums) are added here
    /// after the step, inside [`Self::steps`], which then does not fuse a
    /// step's pair pass with the next one's body pass (the same bits, see
    /// `step`).
    pub(crate) wall_force_sum: Option<WallForceSum>,
    /// The body passes running now (frictionless) tally the walls'
    /// observables: they may be the last before the series row.
    pub(crate) wall_tallying: bool,
    /// The last body pass tallied ([`Self::wall_energy`] describes its
    /// state).
    pub(crate) wall_tally_valid: bool,
    /// Each wall entry's normal elastic energy (J) where touching, by the
    /// last body pass that tallied (`walls::add_wall_forces_tallied`),
    /// valid at step [`Self::wall_tally_step`].
    pub(crate) wall_energy: Vec<f64>,
    /// The step whose end state [`Self::wall_energy`] describes.
    wall_tally_step: Option<u64>,
    /// Each body's tally of its listed pairs' observables, with friction
    /// (`friction::PairTally`) or without (`contacts::PairTally`), valid
    /// at step [`Self::tally_step`].
    pair_tally: Vec<friction::PairTally>,
    plain_tally: Vec<crate::dynamics::contacts::PairTally>,
    /// Asked by a rank of a decomposed scene (`Some`): each main entry's
    /// own terms, written by the pair pass that writes the rows' tally
    /// and valid with it (`dynamics::entry_tally`).
    pub(crate) entry_tally: Option<crate::dynamics::entry_tally::EntryTally>,
    /// The step whose end state [`Self::pair_tally`] describes; `None`:
    /// none does.
    tally_step: Option<u64>,
    /// The step whose end state's kinetic and potential energy the last
    /// half kick summed (J), when asked ([`Self::tally_wanted`]).
    energies: Option<(u64, closing_kick::KickedState)>,
    /// The box the state check tests the centres against
    /// (`Simulation::outside_box`), for the last half kick's test.
    pub(crate) check_box: Option<([f64; 3], [f64; 3])>,
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
    /// [`Self::max_moved2`] and [`Self::halo`] in one exchange, where
    /// every process trades halo state with every other each step (the
    /// largest displacement rides with the halo records): the largest
    /// over every process, the halo copies then holding their owners'
    /// state. `None`: nothing done; the caller takes the two apart. Every
    /// process answers alike (the choice is agreed at each list build).
    fn max_moved2_with_halo(&mut self, world: &mut World, moved2: f64) -> Option<f64>;
    /// New lists (a rank first migrates bodies and rebuilds its halo).
    fn rebuild(&mut self, pipeline: &mut Pipeline, world: &mut World, workers: &Workers);
    /// Halo copies take their owners' state (before the ghosts follow).
    fn halo(&mut self, world: &mut World);
    /// As [`Self::halo`], with `interior` (the force stage's pairs that
    /// need none of the halo's new state, `dynamics::halo_split`) run
    /// while the exchange is in flight; `interior` lets the exchange
    /// progress by calling its second argument now and then.
    fn halo_during(
        &mut self,
        world: &mut World,
        interior: &mut dyn FnMut(&mut World, &mut dyn FnMut()),
    );
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
    /// The loads on the servo walls (file order; the other walls' zero)
    /// from the last force stage, summed over every process in input-id
    /// order (`servo_walls`).
    fn servo_loads(&mut self, world: &World) -> Vec<crate::walls::WallLoad>;
}

/// One process: no halo beyond the periodic ghosts, no migration, the
/// engine's own sums.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Local;

impl StepHooks for Local {
    fn max_moved2(&mut self, moved2: f64) -> f64 {
        moved2
    }
    fn max_moved2_with_halo(&mut self, _world: &mut World, _moved2: f64) -> Option<f64> {
        None
    }
    fn rebuild(&mut self, pipeline: &mut Pipeline, world: &mut World, workers: &Workers) {
        if world.removal.is_some() || world.inlets.is_some() {
            // The pair state by input ids first: removal and insertion
            // resize the bodies.
            let saved = save_pairs(world);
            crate::removal::remove_lost(world);
            crate::inlets::insert_due(world, &mut crate::inlets::OneProcess);
            pipeline.rebuild(world, workers, saved);
        } else {
            pipeline.neighbours(world, workers);
        }
    }
    fn halo(&mut self, _world: &mut World) {}
    fn halo_during(
        &mut self,
        world: &mut World,
        interior: &mut dyn FnMut(&mut World, &mut dyn FnMut()),
    ) {
        interior(world, &mut || {});
    }
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
    fn servo_loads(&mut self, world: &World) -> Vec<crate::walls::WallLoad> {
        let walls = servo_walls::servo_file_indices(world);
        let records = servo_walls::servo_load_records(world, &walls);
        wall_loads::sum_records(&records, world.walls.len())
    }
}

impl Pipeline {
    /// Builds the lists and evaluates the first forces.
    pub fn start(&mut self, world: &mut World, workers: &Workers) {
        world.place_walls(world.steps_done);
        self.neighbours(world, workers);
        self.forces(world, workers);
        walls_measured(world, &mut Local, false);
        world.account_group_work(false);
        world.start_dissipation();
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
        let wanted = std::mem::take(&mut self.tally_wanted);
        self.tally_step = None;
        self.wall_tally_step = None;
        self.wall_tally_valid = false;
        self.energies = None;
        for k in 0..n {
            // The last step's pair pass (Verlet: the state the steps end
            // in; only the velocities' last half kick follows).
            self.tallying = wanted && k + 1 == n && world.scheme == Scheme::Verlet;
            // The body pass that places the bodies where the steps end:
            // the last step's, or fused into the step before it (a list
            // rebuild after it repeats it).
            self.wall_tallying = wanted && k + 2 >= n && world.scheme == Scheme::Verlet;
            self.step(world, workers, k + 1 < n, hooks);
            if let Some(sum) = self.wall_force_sum.as_mut() {
                let loads = observe::ObserveHooks::wall_loads(&Local, world, workers);
                for (s, l) in sum.force.iter_mut().zip(&loads) {
                    for (x, f) in s.iter_mut().zip(l.force) {
                        *x += f;
                    }
                }
                sum.steps += 1;
            }
        }
        self.tallying = false;
        self.wall_tallying = false;
        if wanted && n > 0 && self.wall_tally_valid {
            self.wall_tally_step = Some(world.steps_done);
        }
        if wanted && n > 0 && self.pending_kick {
            // The last half kick sums the energies on the way.
            self.pending_kick = false;
            let kicked = closing_kick::kick_then_energies(world, workers, self.check_box);
            self.energies = Some((world.steps_done, kicked));
            self.ghosts(world);
        } else {
            self.finish(world, workers);
        }
        if self.tally_step.is_some() {
            self.tally_step = Some(world.steps_done);
        }
    }

    /// What the last steps tallied of their end state no longer describes
    /// the state (a body changed outside the steps).
    pub(crate) fn forget_tally(&mut self) {
        self.tally_step = None;
        self.wall_tally_step = None;
        self.energies = None;
    }

    /// Each body's tally of its listed pairs' observables when the last
    /// pair pass made one at this state (see [`Self::tally_wanted`]).
    pub(crate) fn pair_tally(&self, world: &World) -> observe::Tallied<'_> {
        let now = self.tally_step == Some(world.steps_done);
        let n = world.bodies.len();
        let friction = world.friction.is_some();
        observe::Tallied {
            friction: (now && friction && self.pair_tally.len() == n)
                .then_some(&self.pair_tally[..]),
            plain: (now && !friction && self.plain_tally.len() == n)
                .then_some(&self.plain_tally[..]),
            walls: (self.wall_tally_step == Some(world.steps_done)
                && !friction
                && self.wall_energy.len() == world.wall_contacts.key.len())
            .then_some(&self.wall_energy[..]),
            energies: self
                .energies
                .filter(|&(step, _)| step == world.steps_done)
                .map(|(_, e)| e.energies),
            entries: self
                .entry_tally
                .as_ref()
                .filter(|e| now && e.fits(world.list.j.len(), friction)),
        }
    }

    /// The last half kick found every position, velocity and spin finite
    /// and every centre within the check's box at this state
    /// ([`closing_kick::KickedState::sound`]).
    pub(crate) fn sound(&self, world: &World) -> bool {
        self.energies
            .is_some_and(|(step, e)| step == world.steps_done && e.sound)
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
                    world.place_walls(world.steps_done + 1);
                    let moved2 = self.verlet_advance(world, workers);
                    self.after_advance(world, workers, moved2, hooks);
                }
                // The fused form does the same operations on each body in
                // the same order: the same bits. It needs every pair in
                // the blocks (no extra pairs) and no per-step observers.
                // Not with a moving group: its spheres would be placed
                // for the next step before this one's pair forces. Not
                // while summing each step's wall forces: the fused pass
                // evaluates the next step's before this one is read.
                let fuse = more
                    && self.wall_force_sum.is_none()
                    && world.tracks.is_none()
                    && world.dissipation.is_none()
                    && hooks.fusable(world)
                    && !world.has_moving_groups();
                if fuse {
                    // The next step's wall forces are evaluated inside.
                    world.place_walls(world.steps_done + 2);
                    let moved2 = if std::mem::take(&mut self.halo_deferred) {
                        self.pair_forces_around_halo_then_advance(world, workers, hooks)
                    } else {
                        self.pair_forces_then_advance(world, workers)
                    };
                    world.list.rebalance();
                    self.share_cuts(world, workers);
                    world.steps_done += 1;
                    self.advanced = true;
                    self.after_advance(world, workers, moved2, hooks);
                    return;
                }
                if std::mem::take(&mut self.halo_deferred) {
                    hooks.halo(world);
                    self.ghosts(world);
                }
                hooks.pair_forces(self, world, workers, dt);
                world.account_group_work(true);
                world.list.rebalance();
                self.share_cuts(world, workers);
                if world.tracks.is_some() || world.dissipation.is_some() {
                    integrate::verlet_kick(&mut world.bodies, dt, workers);
                    if world.friction.is_some() {
                        friction_spin_kick(&mut world.bodies, dt, workers);
                    }
                } else {
                    self.pending_kick = true;
                }
            }
            Scheme::Gear5 => {
                world.place_walls(world.steps_done + 1);
                let moved2 =
                    integrate::gear5_predict(&mut world.bodies, &self.reference, dt, workers);
                let friction = world.friction.is_some();
                if friction {
                    gear5_rotation::predict(&mut world.bodies, workers);
                }
                let moved2 = hooks.max_moved2(moved2);
                let switched = world.switch_gates(world.steps_done + 1);
                if switched.is_some() || needs_rebuild(moved2, world.rebuild_budget()) {
                    hooks.rebuild(self, world, workers);
                    if let Some(on) = switched {
                        world.gates_opened(&on);
                    }
                } else {
                    hooks.halo(world);
                    self.ghosts(world);
                }
                // At the predicted state. With friction the springs move
                // by Δt of the predicted slip (`gear5_rotation`); without,
                // Δt plays no part in the forces.
                let springs_dt = if friction { dt } else { 0.0 };
                self.body_forces(world, workers, springs_dt);
                walls_measured(world, hooks, true);
                hooks.pair_forces(self, world, workers, springs_dt);
                world.account_group_work(true);
                world.list.rebalance();
                self.share_cuts(world, workers);
                self.gear5_correct(world, workers);
            }
        }
        world.steps_done += 1;
        // At the step's end state (`dissipation`: Verlet's kicks are not
        // deferred then).
        world.account_dissipation();
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
    /// follow their owners (the halo during the force stage when it can:
    /// [`Self::halo_overlaps`]).
    fn after_advance(
        &mut self,
        world: &mut World,
        workers: &Workers,
        moved2: f64,
        hooks: &mut impl StepHooks,
    ) {
        // One exchange for both where the hooks can (a list build then
        // replaces the halo copies it updated).
        let (moved2, halo_done) = match hooks.max_moved2_with_halo(world, moved2) {
            Some(m) => (m, true),
            None => (hooks.max_moved2(moved2), false),
        };
        // A wall appearing or vanishing at this state (`walls::gate`):
        // the lists again, without the walls that no longer act.
        let switched = world.switch_gates(world.steps_done + 1);
        if switched.is_some() || needs_rebuild(moved2, world.rebuild_budget()) {
            hooks.rebuild(self, world, workers);
            if let Some(on) = switched {
                world.gates_opened(&on);
            }
            self.body_forces(world, workers, world.dt);
        } else if halo_done {
            self.ghosts(world);
        } else if self.halo_overlaps(world) {
            // Nothing before the force stage reads the halo copies.
            self.halo_deferred = true;
        } else {
            hooks.halo(world);
            self.ghosts(world);
        }
        walls_measured(world, hooks, true);
    }

    /// The force stage can run the pairs that need no halo state while
    /// the exchange is in flight: a decomposition set a split for these
    /// lists, the loop runs the rows in order on one thread, frictionless
    /// Verlet without periodic ghosts, per-step observers or moving
    /// groups (those paths read the halo copies elsewhere, or sum in
    /// other loops).
    fn halo_overlaps(&self, world: &World) -> bool {
        self.halo_split
            .as_ref()
            .is_some_and(|s| s.fits(&world.list))
            && world.list.sequential
            && world.list.extra.is_empty()
            && world.ghosts.is_empty()
            && world.friction.is_none()
            && world.scheme == Scheme::Verlet
            && world.tracks.is_none()
            && world.dissipation.is_none()
            && !world.has_moving_groups()
    }
}

/// After the walls' forces of a step (or of the start): the moving walls'
/// work (`integrate`: of the step) and the servos' speeds from their
/// loads over every process.
pub(crate) fn walls_measured(world: &mut World, hooks: &mut impl StepHooks, integrate: bool) {
    world.account_wall_work(integrate);
    if world.has_servos() {
        let loads = hooks.servo_loads(world);
        world.steer_servos(&loads);
    }
}

/// A body moved more than `budget` (half the skin, less what the moving
/// walls moved: `World::rebuild_budget`), or a position is not finite.
pub(crate) fn needs_rebuild(moved2: f64, budget: f64) -> bool {
    moved2.is_nan() || budget <= 0.0 || moved2 > budget * budget
}

/// Whether body k belongs to a boundary-particle wall.
pub fn in_group(bodies: &Bodies, k: usize) -> bool {
    bodies.group[k] != NO_GROUP
}
