//! One rank's share of a decomposed scene (issue 16).
//!
//! Each rank owns the bodies inside its sub-domain
//! ([`Decomposition::owner`]) and holds a *halo*: copies of the other
//! ranks' bodies that come within (own radius + largest radius + skin) of
//! its sub-domain, so that every listed pair with an owned body has both
//! bodies on the rank. Halo copies are stored in the engine's body store
//! flagged `fixed` (never integrated, never paired with each other, no
//! wall forces); the engine's periodic ghost layer is left as it is
//! (periodic axes are not split).
//!
//! What crosses ranks, and when:
//! - every step: position and velocity (and spin, with friction) of each
//!   free halo body, 48 (72) bytes, from its owner to each rank holding a
//!   copy;
//! - at a list rebuild (decided on the largest displacement over all
//!   ranks, so every rank rebuilds at the same step): bodies that left
//!   their sub-domain move to their new owner as whole records
//!   ([`pack::write_body`]) with their pair histories (and friction
//!   springs; with Gear5 their Nordsieck vectors, with friction the
//!   spins' too), then the halo is sent again as whole records;
//! - reductions: the rebuild test (one max per step), the whole scene's
//!   cell grid at rebuilds, the observables (sums, when observed).
//!
//! Forces: a pair across two sub-domains is computed on both ranks
//! (LAMMPS's `newton off`): no force goes back to the owner, at the price
//! of computing those pairs twice. The trajectory does not depend on the
//! decomposition: 1, 2 or 3 ranks give bit-identical positions, because
//! each owned body's force is summed in an order the whole scene fixes:
//! - normally (no extra pairs on any rank) every rank sorts its bodies by
//!   the cells of one grid over the whole scene
//!   (`pipeline::WholeGrid`, cropped to the rank's bodies), and
//!   by input id within a cell, and runs the engine's own force loop with
//!   its rows in order ([`crate::geometry::neighbour::PairList::sequential`]).
//!   A pair is listed in the row of whichever body comes first in that
//!   order — the same on every rank — so each body gets the forces of the
//!   partners before it, in order, then its own row's sum of the partners
//!   after it: the same additions in the same order on any rank. This is
//!   the engine's loop (and its fused Verlet step), at the engine's speed;
//! - with extra pairs (periodic images, bodies too large for the cells)
//!   the pair forces are stored and each body's sum is gathered in the
//!   order of its partners' input ids (the pair values being the same
//!   bits on either side: the pair geometry is antisymmetric to the bit);
//!   without periodic axes only, where an image's shifted coordinates
//!   round differently on either side. Friction needs the first way.

use std::collections::{BTreeMap, HashMap};
use std::time::Instant;

use dembound_physics::contact::ContactHistory;

use super::pack::{self, get_vec3, put_vec3, Reader, Writer};
use super::Transport;
use crate::dynamics::collisions::Track;
use crate::dynamics::friction::Springs;
use crate::dynamics::halo_split::HaloSplit;
use crate::dynamics::{gear5_rotation, integrate};
use crate::geometry::decomposition::Decomposition;
use crate::parallel::Workers;
use crate::pipeline::observe::observation;
use crate::pipeline::{
    celled_extent, save_pairs, Pipeline, SavedPairs, StepHooks, WholeGrid, World,
};
use crate::setup::{SceneSetup, Scheme};
use crate::simulation::Simulation;
use crate::walls::WallLoad;
use crate::{Observation, SceneError};

// Checkpoint and restart on any number of ranks, load re-balancing, the
// contacts a rank counts when observed, what a run reports, the order of
// the pair sums (child modules: they reach this rank's private state).
pub mod balance;
mod checkpoint;
mod checkpoint_parts;
mod checkpoint_records;
mod inlets;
pub mod input;
mod observe;
mod report;
mod sums;
mod triangle_loads;

pub use report::{GatheredState, RankReport};

/// The error of a rank whose setup was fine when another rank's was not
/// (that rank's error says why).
pub const PEER_REFUSED: &str = "another MPI rank refused the scene";

/// One rank of a decomposed scene: the engine ([`Simulation`], whose
/// pipeline steps the rank's bodies) and what a rank adds to it
/// ([`RankComm`]: halo, migration, the order of sums).
pub struct DistributedSimulation<T: Transport> {
    sim: Simulation,
    comm: RankComm<T>,
    steps_run: u64,
    stepping: f64,
    /// The scene's input spheres and of them the fixed ones.
    inputs: (usize, usize),
}

/// What one rank adds to the engine's step: the pipeline's
/// [`StepHooks`] of a decomposed scene.
pub(crate) struct RankComm<T: Transport> {
    transport: T,
    decomposition: Decomposition,
    /// Largest radius of the scene, m.
    largest_radius: f64,
    /// Input index → the body is fixed (halo copies are flagged fixed
    /// locally; this is the truth).
    fixed_by_id: Vec<bool>,
    /// Local body → a halo copy.
    halo: Vec<bool>,
    /// Local body → removed at this list build (`crate::removal`): it
    /// neither stays nor migrates.
    dropping: Vec<bool>,
    /// Every step: local indices of the free bodies sent to each rank.
    sends: Vec<(usize, Vec<u32>)>,
    /// Every step: local indices of the free halo bodies received from
    /// each rank, in arrival order.
    receives: Vec<(usize, Vec<u32>)>,
    /// The per-step halo messages out, by rank, and in, one per rank of
    /// `receives`: kept from step to step (grown when needed, never
    /// zeroed), the bytes of the last step's exchange.
    halo_out: Vec<(usize, Vec<u8>)>,
    halo_in: Vec<Vec<u8>>,
    incidence_start: Vec<u32>,
    /// Each body's incident pair entries in partner-id order: entry index,
    /// bit 31 set when the body is the pair's i (it gets minus the force).
    incidence: Vec<u32>,
    /// (incidence, wall, the boundary particle's local index) of the pairs
    /// with a boundary particle.
    walled: Vec<(u32, u32, u32)>,
    pair_force: Vec<[f64; 3]>,
    /// The pair of each entry touches (its force is set).
    hit: Vec<bool>,
    /// Load on each wall from this rank's free bodies' pairs with its
    /// boundary particles (file order; other walls zero), N and N m.
    particle_wall_load: Vec<WallLoad>,
    bytes_sent: u64,
    rebuild_bytes: u64,
    /// Bodies this rank has sent to new owners.
    migrated: u64,
    /// The engine's half-list sums instead (order set by the local list).
    plain_sums: bool,
    /// The forces are summed by the engine's own loop over the rows in
    /// whole-scene cell order (`pipeline::WholeGrid`); otherwise
    /// (some rank lists extra pairs: periodic images, large bodies) by the
    /// incidences in partner-id order.
    in_cell_order: bool,
    /// Input index → this rank owns the body (the collision log's owner).
    owned_by_id: Vec<bool>,
    /// The step at which each entry of the local collision log was
    /// completed (the merged log's order).
    collision_steps: Vec<u64>,
    /// The first entries of the local log came from a checkpoint (rank 0).
    restored_collisions: usize,
    /// Load re-balancing ([`balance`]).
    balance: balance::Balance,
    /// Overlap the halo exchange with the pairs that need none of it
    /// (`parallel.halo_overlap`, default off; `dynamics::halo_split`).
    overlap: bool,
    /// Steps whose halo exchange ran during the force stage's pairs.
    overlapped_steps: u64,
    /// Pairs of the current lists that wait for the halo (0 without a
    /// split).
    deferred_pairs: usize,
    /// Seconds spent in the per-step halo exchange beyond the work it
    /// overlapped (posting, waiting, unpacking).
    halo_wait: f64,
    /// Every rank sends halo state to every other and receives it from
    /// every other each step, and none overlaps the exchange with its
    /// pairs: the step's largest displacement rides with the halo records
    /// instead of a collective of its own ([`Self::halo_update`]).
    /// Agreed by every rank at each list build ([`Self::split_halo`]).
    max_in_halo: bool,
}

/// The collision log with friction or Gear5 is refused under MPI (exit 2). Friction: see [`refuse_unsupported_world`].
fn refuse_unsupported(setup: &SceneSetup) -> Result<(), SceneError> {
    if setup.dissipation {
        return Err(SceneError::invalid(
            "output.dissipation",
            true,
            "false under MPI (the contact-by-contact sum runs on one process for now: run \
             without mpirun, on threads)",
        ));
    }
    if setup.collisions && (setup.friction.is_some() || setup.integration.scheme != Scheme::Verlet)
    {
        return Err(SceneError::invalid(
            "output.collisions",
            true,
            "false under MPI with friction or Gear5 (the log keeps contacts that \
             separated fast as extra pairs, which those runs cannot sum across ranks \
             yet); run without mpirun",
        ));
    }
    Ok(())
}

/// Friction and Gear5 under MPI need every pair in the cell-ordered force
/// loop (the partner-id sums carry no torques, and Gear5's corrections of
/// the contacts that begin or end inside a step are added in list order):
/// no periodic axis (images are extra pairs) and no body too large for
/// the cells.
fn refuse_unsupported_world(world: &World) -> Result<(), SceneError> {
    let (key, value, what) = if world.friction.is_some() {
        (
            "contact.friction",
            "> 0",
            "the periodic images' pairs and the large bodies' carry no torques across ranks yet",
        )
    } else if world.scheme == Scheme::Gear5 {
        (
            "integration.scheme",
            "\"gear5\"",
            "Gear5's corrections of those pairs are not ordered across ranks yet",
        )
    } else {
        return Ok(());
    };
    if world.domain.periodic.iter().any(|&p| p) {
        return Err(SceneError::invalid(
            key,
            format!("{value} with a periodic axis"),
            format!("not under MPI when an axis is periodic ({what}); run without mpirun"),
        ));
    }
    let inlet_radii = world
        .inlets
        .iter()
        .flat_map(|i| i.inlets.iter().map(|i| i.setup.size.max_radius()));
    if let Some(r) = world
        .bodies
        .radius
        .iter()
        .copied()
        .chain(inlet_radii)
        .find(|&r| r > world.large_radius)
    {
        return Err(SceneError::invalid(
            key,
            format!("{value} with a body of radius {r:e} m"),
            format!(
                "not under MPI when a body is larger than the cells allow ({:e} m: such \
                 bodies are paired outside the cells, and {what}); run without mpirun",
                world.large_radius
            ),
        ));
    }
    Ok(())
}

/// The largest radius of the scene's bodies and of the inlets' spheres
/// (`crate::inlets::radii`), m.
fn largest_radius(w: &World, setup: &SceneSetup) -> f64 {
    w.bodies
        .radius
        .iter()
        .copied()
        .chain(crate::inlets::radii(setup))
        .fold(0.0, f64::max)
}

/// Keeps bodies `order` (in that order) and their plane-wall state.
fn select(world: &mut World, order: &[u32]) {
    world.bodies.permute(order);
    world.wall_contacts.permute(order);
}

impl<T: Transport> DistributedSimulation<T> {
    /// Validates `setup` (every rank reads the whole scene), keeps this
    /// rank's bodies, builds the halo and the lists and evaluates the
    /// first forces. `grid`: `parallel.grid`, else chosen from the ranks.
    pub fn new(
        setup: &SceneSetup,
        threads: usize,
        grid: Option<[usize; 3]>,
        transport: T,
    ) -> Result<Self, SceneError> {
        let checked = refuse_unsupported(setup)
            .and_then(|()| Simulation::prepare(setup, threads))
            .and_then(|sim| refuse_unsupported_world(&sim.world).map(|()| sim))
            .and_then(|sim| {
                let w = &sim.world;
                let mut lo = [f64::INFINITY; 3];
                let mut hi = [f64::NEG_INFINITY; 3];
                for x in &w.bodies.position {
                    let x = w.domain.wrap(*x);
                    for a in 0..3 {
                        lo[a] = lo[a].min(x[a]);
                        hi[a] = hi[a].max(x[a]);
                    }
                }
                // The inlets' regions too: where their spheres will be.
                for i in &setup.inlets {
                    let (rlo, rhi) = i.region.bounds();
                    for a in 0..3 {
                        lo[a] = lo[a].min(rlo[a]);
                        hi[a] = hi[a].max(rhi[a]);
                    }
                }
                let extent = Some((lo, hi));
                let d = Decomposition::new(w.domain, transport.size(), grid, w.cell_size, extent)?;
                Ok((sim, d))
            });
        // Every rank learns whether any refused, before the first exchange.
        let refused = transport.max(if checked.is_err() { 1.0 } else { 0.0 });
        let (mut sim, decomposition) = match checked {
            Err(e) => return Err(e),
            Ok(_) if refused > 0.0 => return Err(SceneError::input(PEER_REFUSED)),
            Ok(c) => c,
        };
        let w = &mut sim.world;
        let largest_radius = largest_radius(w, setup);
        let rank = transport.rank();
        let mut mine = Vec::new();
        for k in 0..w.bodies.len() {
            let x = w.domain.wrap(w.bodies.position[k]);
            w.bodies.position[k] = x;
            if decomposition.owner(x) == rank {
                mine.push(k as u32);
            }
        }
        select(w, &mine);
        let fixed_by_id = setup.spheres.iter().map(|s| s.fixed).collect();
        Ok(Self::start(
            sim,
            decomposition,
            largest_radius,
            fixed_by_id,
            transport,
        ))
    }

    /// The rank's run from its own bodies (in input order) in `sim`: halo,
    /// lists, first forces. `fixed_by_id`: each input index fixed or free.
    fn start(
        sim: Simulation,
        decomposition: Decomposition,
        largest_radius: f64,
        fixed_by_id: Vec<bool>,
        transport: T,
    ) -> Self {
        let n = sim.world.bodies.len();
        let total = fixed_by_id.len();
        let inputs = (total, fixed_by_id.iter().filter(|&&x| x).count());
        let comm = RankComm {
            transport,
            decomposition,
            largest_radius,
            fixed_by_id,
            halo: vec![false; n],
            dropping: Vec::new(),
            sends: Vec::new(),
            receives: Vec::new(),
            halo_out: Vec::new(),
            halo_in: Vec::new(),
            incidence_start: Vec::new(),
            incidence: Vec::new(),
            walled: Vec::new(),
            pair_force: Vec::new(),
            hit: Vec::new(),
            particle_wall_load: Vec::new(),
            bytes_sent: 0,
            rebuild_bytes: 0,
            plain_sums: false,
            migrated: 0,
            in_cell_order: false,
            owned_by_id: vec![false; total],
            collision_steps: Vec::new(),
            restored_collisions: 0,
            balance: balance::Balance::default(),
            overlap: false,
            overlapped_steps: 0,
            deferred_pairs: 0,
            halo_wait: 0.0,
            max_in_halo: false,
        };
        let mut me = Self {
            inputs,
            sim,
            comm,
            steps_run: 0,
            stepping: 0.0,
        };
        // The series rows read each listed pair's terms (`observe`).
        me.sim.pipeline.entry_tally = Some(Default::default());
        me.sim.world.place_walls(0);
        me.rebuild();
        let sim = &mut me.sim;
        sim.pipeline.body_forces(&mut sim.world, &sim.workers, 0.0);
        crate::pipeline::walls_measured(&mut sim.world, &mut me.comm, false);
        me.pair_forces();
        let w = &mut me.sim.world;
        if w.scheme == Scheme::Gear5 {
            // r₂ = Δt² a/2 from the first forces (summed as every step's:
            // the same bits on any rank), r₃..r₅ = 0, as the engine starts.
            integrate::gear5_start(&mut w.bodies, w.dt);
            if w.friction.is_some() {
                gear5_rotation::start(&mut w.bodies, w.dt);
            }
        }
        let o = me.observe();
        me.sim.initial_energy = o.kinetic_energy + o.elastic_energy + o.potential_energy;
        me
    }

    pub fn rank(&self) -> usize {
        self.comm.transport.rank()
    }

    /// Experiment (tests/decomposition.rs): sum the pair forces with the
    /// engine's half lists, in the order of each rank's own list, instead
    /// of by partner id. No boundary-particle wall forces then.
    pub fn use_plain_sums(&mut self) {
        self.comm.plain_sums = true;
        self.comm.in_cell_order = false;
        self.sim.pipeline.whole_grid = None;
        self.sim.pipeline.halo_split = None;
        self.sim.world.list.sequential = false;
    }

    pub fn ranks(&self) -> usize {
        self.comm.transport.size()
    }

    /// `parallel.halo_overlap`: whether the halo exchange runs during the
    /// force stage's pairs that need none of it or before the force stage
    /// (default). The same bits either way.
    pub fn set_halo_overlap(&mut self, on: bool) {
        self.comm.overlap = on;
        let sim = &mut self.sim;
        self.comm.split_halo(&mut sim.pipeline, &sim.world);
    }

    pub fn transport(&self) -> &T {
        &self.comm.transport
    }

    pub fn grid(&self) -> [usize; 3] {
        self.comm.decomposition.grid
    }

    /// The local engine (owned bodies and halo copies).
    pub fn local(&self) -> &Simulation {
        &self.sim
    }

    /// Whether the pair forces are summed by the engine's loop in
    /// whole-scene cell order (else by partner id: some rank lists extra
    /// pairs). Either order is independent of the decomposition.
    pub fn sums_in_cell_order(&self) -> bool {
        self.comm.in_cell_order
    }

    /// The scene's input spheres and of them the fixed ones (inserted
    /// spheres not counted).
    pub fn input_counts(&self) -> (usize, usize) {
        self.inputs
    }

    /// Bodies this rank owns.
    pub fn owned(&self) -> usize {
        self.comm.halo.iter().filter(|&&h| !h).count()
    }
}

impl<T: Transport> RankComm<T> {
    /// Sends whole-body messages (`out[rank]`) and returns what the other
    /// ranks sent here, in rank order. Collective.
    fn send_records(&mut self, out: BTreeMap<usize, Writer>) -> Vec<(usize, Vec<u8>)> {
        let size = self.transport.size();
        let mut to = vec![false; size];
        for r in out.keys() {
            to[*r] = true;
        }
        let from: Vec<usize> = self
            .transport
            .who_sends(&to)
            .iter()
            .enumerate()
            .filter_map(|(r, &s)| s.then_some(r))
            .collect();
        let sends: Vec<(usize, Vec<u8>)> = out.into_iter().map(|(r, w)| (r, w.0)).collect();
        let bytes: u64 = sends.iter().map(|(_, b)| b.len() as u64).sum();
        self.bytes_sent += bytes;
        self.rebuild_bytes += bytes;
        let got = self.transport.exchange(&sends, &from);
        from.into_iter().zip(got).collect()
    }

    /// Migration, a new halo and new lists. Collective.
    /// `saved`: the pair state by input ids when the caller took it before
    /// changing the bodies (insertion), else taken here.
    fn migrate_and_rebuild(
        &mut self,
        pipeline: &mut Pipeline,
        world: &mut World,
        workers: &Workers,
        saved: Option<SavedPairs>,
    ) {
        // Re-balancing may move the cuts first (the migration follows).
        self.rebalance(world);
        let rank = self.transport.rank();
        let mut saved = saved.unwrap_or_else(|| save_pairs(world));
        let keep = world.laws.history;
        let spin = world.friction.is_some();
        let gear5 = world.scheme == Scheme::Gear5;
        // Pair histories (and springs) by body, for the bodies that leave.
        let mut by_body: HashMap<u32, Vec<(u32, u32, ContactHistory)>> = HashMap::new();
        if keep {
            for (&(a, b), h) in &saved.histories {
                by_body.entry(a).or_default().push((a, b, *h));
                by_body.entry(b).or_default().push((a, b, *h));
            }
        }
        let tracked = world.tracks.is_some();
        let mut tracks_by_body: HashMap<u32, Vec<(u32, u32, Track)>> = HashMap::new();
        for (&(a, b), t) in saved.tracks.iter().flatten() {
            tracks_by_body.entry(a).or_default().push((a, b, *t));
            tracks_by_body.entry(b).or_default().push((a, b, *t));
        }
        let mut springs_by_body: HashMap<u32, Vec<(u32, u32, Springs)>> = HashMap::new();
        for (&(a, b), sp) in &saved.shear {
            springs_by_body.entry(a).or_default().push((a, b, *sp));
            springs_by_body.entry(b).or_default().push((a, b, *sp));
        }
        // 1. Migration: owned bodies outside the sub-domain go to its owner.
        let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
        let mut stay = Vec::new();
        for k in 0..world.bodies.len() {
            if self.halo.get(k).copied().unwrap_or(false)
                || self.dropping.get(k).copied().unwrap_or(false)
            {
                continue;
            }
            let x = world.domain.wrap(world.bodies.position[k]);
            world.bodies.position[k] = x;
            let dest = self.decomposition.owner(x);
            if dest == rank {
                stay.push(k as u32);
                continue;
            }
            self.migrated += 1;
            let w = out.entry(dest).or_default();
            pack::write_body(w, &world.bodies, Some(&world.wall_contacts), k);
            let hs = by_body.get(&world.bodies.id[k]).map_or(&[][..], |v| &v[..]);
            w.u32(hs.len() as u32);
            for (a, b, h) in hs {
                w.u32(*a);
                w.u32(*b);
                w.history(h);
            }
            if gear5 {
                pack::write_higher(w, &world.bodies.higher, k);
                if spin {
                    pack::write_angular_higher(w, &world.bodies.angular_higher, k);
                }
            }
            if tracked {
                // The collision log's tracks of the body's pairs (its wall
                // tracks travel in its body record).
                let id = world.bodies.id[k];
                let pairs = tracks_by_body.get(&id).cloned().unwrap_or_default();
                w.blob(&pack::encode(&pairs));
            }
            if spin {
                let ss = springs_by_body
                    .get(&world.bodies.id[k])
                    .map_or(&[][..], |v| &v[..]);
                w.u32(ss.len() as u32);
                for (a, b, sp) in ss {
                    w.u32(*a);
                    w.u32(*b);
                    for x in sp {
                        w.f64(*x);
                    }
                }
            }
        }
        select(world, &stay);
        for (_, bytes) in self.send_records(out) {
            let mut r = Reader::new(&bytes);
            while !r.done() {
                pack::read_body(&mut r, &mut world.bodies, &mut world.wall_contacts);
                for _ in 0..r.u32() {
                    let (a, b, h) = (r.u32(), r.u32(), r.history());
                    saved.histories.insert((a, b), h);
                }
                if tracked {
                    let pairs: Vec<(u32, u32, Track)> = pack::decode(r.blob()).unwrap_or_default();
                    if let Some(saved) = saved.tracks.as_mut() {
                        for (a, b, t) in pairs {
                            saved.insert((a, b), t);
                        }
                    }
                }
                if gear5 {
                    let mut higher = Vec::with_capacity(1);
                    pack::read_higher(&mut r, &mut higher);
                    // Before the first forces (gear5_start) there are none.
                    if world.bodies.higher.len() + 1 == world.bodies.len() {
                        world.bodies.higher.extend(higher);
                    }
                    if spin {
                        let mut higher = Vec::with_capacity(1);
                        pack::read_angular_higher(&mut r, &mut higher);
                        if world.bodies.angular_higher.len() + 1 == world.bodies.len() {
                            world.bodies.angular_higher.extend(higher);
                        }
                    }
                }
                if spin {
                    for _ in 0..r.u32() {
                        let (a, b) = (r.u32(), r.u32());
                        let mut sp = [0.0; 6];
                        for x in &mut sp {
                            *x = r.f64();
                        }
                        saved.shear.insert((a, b), sp);
                    }
                }
            }
        }
        // 2. The halo: every owned body to the ranks within its reach.
        let owned = world.bodies.len();
        let reach = self.largest_radius + world.skin;
        let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
        let mut sent_ids: BTreeMap<usize, Vec<u32>> = BTreeMap::new();
        for k in 0..owned {
            let b = &world.bodies;
            for r in self
                .decomposition
                .ranks_within(b.position[k], b.radius[k] + reach)
            {
                pack::write_body(out.entry(r).or_default(), b, None, k);
                sent_ids.entry(r).or_default().push(b.id[k]);
            }
        }
        let mut got_ids: Vec<(usize, Vec<u32>)> = Vec::new();
        for (from, bytes) in self.send_records(out) {
            let mut r = Reader::new(&bytes);
            let mut ids = Vec::new();
            while !r.done() {
                ids.push(pack::read_body(
                    &mut r,
                    &mut world.bodies,
                    &mut world.wall_contacts,
                ));
                if let Some(f) = world.bodies.fixed.last_mut() {
                    *f = true;
                }
                if gear5 && world.bodies.higher.len() + 1 == world.bodies.len() {
                    // Nor is it integrated.
                    world.bodies.higher.push(Default::default());
                }
                if gear5 && spin && world.bodies.angular_higher.len() + 1 == world.bodies.len() {
                    world.bodies.angular_higher.push(Default::default());
                }
            }
            got_ids.push((from, ids));
        }
        // 3. The lists (bodies re-sorted by the whole scene's cells), pair
        // state restored.
        pipeline.whole_grid = if self.plain_sums {
            None
        } else {
            Some(self.whole_grid(world))
        };
        pipeline.rebuild(world, workers, saved);
        let extra = !world.list.extra.is_empty();
        self.in_cell_order =
            !self.plain_sums && self.transport.max(if extra { 1.0 } else { 0.0 }) == 0.0;
        // 4. Per-step plans by the new local indices.
        let b = &world.bodies;
        let at: HashMap<u32, u32> =
            b.id.iter()
                .enumerate()
                .map(|(k, &id)| (id, k as u32))
                .collect();
        let free = |id: &u32| !self.fixed_by_id.get(*id as usize).copied().unwrap_or(false);
        let local = |ids: &[u32]| -> Vec<u32> {
            ids.iter()
                .filter(|id| free(id))
                .filter_map(|id| at.get(id).copied())
                .collect()
        };
        self.halo = vec![false; b.len()];
        for (_, ids) in &got_ids {
            for id in ids {
                if let Some(&k) = at.get(id) {
                    self.halo[k as usize] = true;
                }
            }
        }
        self.sends = sent_ids
            .iter()
            .map(|(&r, ids)| (r, local(ids)))
            .filter(|(_, v)| !v.is_empty())
            .collect();
        self.receives = got_ids
            .iter()
            .map(|(r, ids)| (*r, local(ids)))
            .filter(|(_, v)| !v.is_empty())
            .collect();
        self.owned_by_id.fill(false);
        for (k, &id) in world.bodies.id.iter().enumerate() {
            if !self.halo[k] {
                if let Some(o) = self.owned_by_id.get_mut(id as usize) {
                    *o = true;
                }
            }
        }
        if self.in_cell_order {
            self.incidence_start.clear();
            self.incidence.clear();
            self.walled.clear();
        } else {
            self.build_incidence(world);
        }
        self.split_halo(pipeline, world);
    }

    /// Which pairs of the lists wait for the halo exchange
    /// ([`HaloSplit`]): those with a free halo copy (its state arrives
    /// every step). Only where the split's loop applies: the forces summed
    /// in cell order, frictionless Verlet (the pipeline checks the rest
    /// at each step), and this rank receives halo state (without, every
    /// pair is early: the engine's own loop runs them, as on one process).
    fn split_halo(&mut self, pipeline: &mut Pipeline, world: &World) {
        let applies = self.overlap
            && !self.receives.is_empty()
            && self.in_cell_order
            && !self.plain_sums
            && world.friction.is_none()
            && world.scheme == Scheme::Verlet;
        pipeline.halo_split = applies.then(|| {
            let mut stale = vec![false; world.bodies.len()];
            for (_, idx) in &self.receives {
                for &k in idx {
                    stale[k as usize] = true;
                }
            }
            HaloSplit::new(&world.list, &stale)
        });
        self.deferred_pairs = pipeline
            .halo_split
            .as_ref()
            .map_or(0, HaloSplit::deferred_pairs);
        // Collective (one per list build): every rank takes the same path
        // in each step's exchange.
        let others = |list: &[(usize, Vec<u32>)]| {
            let mut to: Vec<usize> = list.iter().map(|(r, _)| *r).collect();
            to.sort_unstable();
            to.dedup();
            to.len() + 1 == self.transport.size() && to.iter().all(|&r| r != self.transport.rank())
        };
        let fits = others(&self.sends) && others(&self.receives) && pipeline.halo_split.is_none();
        self.max_in_halo = self.transport.max(if fits { 0.0 } else { 1.0 }) == 0.0;
    }

    /// The whole scene's cell grid: the extent of every rank's celled
    /// bodies and their number. Collective.
    fn whole_grid(&self, world: &World) -> WholeGrid {
        let (lo, hi) = celled_extent(world);
        let owned = self.halo.iter().filter(|&&h| !h).count() as f64;
        let mut whole = WholeGrid {
            lower: [0.0; 3],
            upper: [0.0; 3],
            bodies: self.transport.sum(&[owned])[0] as usize,
        };
        for a in 0..3 {
            // min(x) = −max(−x), exactly.
            whole.lower[a] = -self.transport.max(-lo[a]);
            whole.upper[a] = self.transport.max(hi[a]);
        }
        whole
    }

    /// The per-step halo messages into `halo_out`: position and velocity
    /// (and spin) of each free body another rank holds a copy of, by
    /// rank, written into the buffers of the last step.
    fn halo_sends(&mut self, world: &World) {
        let spin = world.friction.is_some();
        let record = halo_record(spin);
        let b = &world.bodies;
        self.halo_out
            .resize_with(self.sends.len(), Default::default);
        let mut bytes = 0u64;
        for ((r, idx), (to, out)) in self.sends.iter().zip(self.halo_out.iter_mut()) {
            *to = *r;
            out.clear();
            out.reserve(idx.len() * record);
            // Records of a fixed size each way (copies of known length).
            if spin {
                for &k in idx {
                    let k = k as usize;
                    let mut at = [0u8; 72];
                    put_vec3(&mut at[..24], b.position[k]);
                    put_vec3(&mut at[24..48], b.velocity[k]);
                    put_vec3(&mut at[48..], b.angular_velocity[k]);
                    out.extend_from_slice(&at);
                }
            } else {
                for &k in idx {
                    let k = k as usize;
                    let mut at = [0u8; 48];
                    put_vec3(&mut at[..24], b.position[k]);
                    put_vec3(&mut at[24..], b.velocity[k]);
                    out.extend_from_slice(&at);
                }
            }
            bytes += out.len() as u64;
        }
        self.bytes_sent += bytes;
    }

    /// `halo_in` sized for this step's messages: one per rank of
    /// `receives`, of their exact lengths (grown when needed; the bytes
    /// left from the last step are overwritten by the receive).
    fn size_halo_in(&mut self, spin: bool) {
        let record = halo_record(spin);
        self.halo_in
            .resize_with(self.receives.len(), Default::default);
        for ((_, idx), buf) in self.receives.iter().zip(self.halo_in.iter_mut()) {
            buf.resize(idx.len() * record, 0);
        }
    }

    /// The halo copies take the state [`Self::halo_sends`] sent (`got`:
    /// one message per rank of `receives`, in that order).
    fn halo_receive(&self, world: &mut World, got: &[Vec<u8>]) {
        let spin = world.friction.is_some();
        let b = &mut world.bodies;
        let record = halo_record(spin);
        for ((_, idx), bytes) in self.receives.iter().zip(got) {
            for (&k, at) in idx.iter().zip(bytes.chunks_exact(record)) {
                let k = k as usize;
                b.position[k] = get_vec3(&at[..24]);
                b.velocity[k] = get_vec3(&at[24..48]);
                if spin {
                    b.angular_velocity[k] = get_vec3(&at[48..]);
                }
            }
        }
    }

    /// Position and velocity of every free halo body from its owner,
    /// before the force stage (`parallel.halo_overlap = false`): the
    /// overlapped exchange with nothing to overlap, so both schedules
    /// receive into the same kept buffers (no allocation, no probe).
    /// With `moved2`, this rank's largest squared displacement travels
    /// after each message's records (8 bytes, not counted in the halo's
    /// bytes) and the largest over the ranks it hears from is returned:
    /// over every rank when each rank exchanges with every other
    /// ([`Self::max_in_halo`]), without a collective of its own.
    fn halo_update(&mut self, world: &mut World, moved2: Option<f64>) -> Option<f64> {
        self.halo_sends(world);
        self.size_halo_in(world.friction.is_some());
        if let Some(m) = moved2 {
            for (_, out) in &mut self.halo_out {
                out.extend_from_slice(&m.to_le_bytes());
            }
            for buf in &mut self.halo_in {
                buf.resize(buf.len() + 8, 0);
            }
        }
        let from: Vec<usize> = self.receives.iter().map(|(r, _)| *r).collect();
        let clock = Instant::now();
        self.transport
            .exchange_during(&self.halo_out, &from, &mut self.halo_in, &mut |_| {});
        // With `moved2` the records are whole chunks before the 8 bytes
        // (`halo_receive` reads one chunk per halo body).
        self.halo_receive(world, &self.halo_in);
        let largest = moved2.map(|m| {
            self.halo_in.iter().fold(m, |m, buf| {
                let mut last = [0u8; 8];
                last.copy_from_slice(&buf[buf.len() - 8..]);
                max_or_nan(m, f64::from_le_bytes(last))
            })
        });
        self.halo_wait += clock.elapsed().as_secs_f64();
        largest
    }
}

/// The larger of two squared displacements, a NaN winning (a position
/// no longer finite asks for a list build on every rank, as
/// `ThreadTransport::max` gives).
fn max_or_nan(a: f64, b: f64) -> f64 {
    if b > a || b.is_nan() {
        b
    } else {
        a
    }
}

/// Bytes of a free halo body's per-step record: position and velocity,
/// and spin with friction.
fn halo_record(spin: bool) -> usize {
    if spin {
        72
    } else {
        48
    }
}

impl<T: Transport> DistributedSimulation<T> {
    /// Advances `n` steps: the engine's pipeline with this rank's hooks
    /// (halo, migration, sums in an order the whole scene fixes).
    /// Collective.
    pub fn step(&mut self, n: u64) {
        let clock = Instant::now();
        let sim = &mut self.sim;
        // The box the last half kick tests when it checks the state
        // (`Simulation::check_finite`), as `Simulation::step` sets it.
        sim.pipeline.check_box = sim.outside_box;
        sim.pipeline
            .steps(&mut sim.world, &sim.workers, n, &mut self.comm);
        self.steps_run += n;
        self.stepping += clock.elapsed().as_secs_f64();
    }

    /// Migration, a new halo and new lists. Collective.
    fn rebuild(&mut self) {
        let sim = &mut self.sim;
        self.comm
            .migrate_and_rebuild(&mut sim.pipeline, &mut sim.world, &sim.workers, None);
    }

    /// The pair stage as a step runs it. Collective.
    fn pair_forces(&mut self) {
        let sim = &mut self.sim;
        let dt = sim.world.dt;
        self.comm
            .sum_pair_forces(&mut sim.pipeline, &mut sim.world, &sim.workers, dt);
    }

    pub fn steps_done(&self) -> u64 {
        self.sim.world.steps_done
    }

    /// This rank's bodies (owned and halo copies) finite
    /// ([`Simulation::check_finite`]); not collective: the caller agrees
    /// on the outcome across the ranks.
    pub fn check_finite(&self) -> Result<(), SceneError> {
        self.sim.check_finite()
    }

    pub fn total_steps(&self) -> u64 {
        self.sim.total_steps()
    }

    /// [`Self::observe`] (collective), checked by the energy guard: every
    /// rank sees the same summed observation and so takes the same
    /// decision ([`Simulation::observe_checked`]).
    pub fn observe_checked(&mut self) -> Result<Observation, SceneError> {
        let o = self.observe();
        self.sim.energy_guard.check(&o, self.sim.initial_energy)?;
        Ok(o)
    }

    /// What the restart dropped and added of the checkpoint's walls
    /// ([`Simulation::restart_notes`]).
    pub fn restart_notes(&self) -> &[String] {
        self.sim.restart_notes()
    }

    /// The energy balance at observation `o` ([`Simulation::energy_balance`]).
    pub fn energy_balance(&self, o: &Observation) -> crate::energy_guard::EnergyBalance {
        self.sim.energy_balance(o)
    }

    /// The point each wall's torque is taken about (file order), m
    /// ([`Simulation::wall_torque_points`]).
    pub fn wall_torque_points(&self) -> Vec<[f64; 3]> {
        self.sim.wall_torque_points()
    }

    /// The global observables (sums over the ranks), from what the last
    /// steps tallied of this state when they were asked to
    /// ([`Self::will_observe`]; the same bits). Collective.
    pub fn observe(&self) -> Observation {
        let sim = &self.sim;
        let hooks = observe::RankTallied {
            comm: &self.comm,
            tally: sim.pipeline.pair_tally(&sim.world),
        };
        observation(&sim.world, &sim.workers, sim.initial_energy, &hooks)
    }

    /// [`Self::observe`] without the last steps' tallies: every listed
    /// pair visited again and the bodies' energies summed again, as a rank
    /// observes a state no step was asked to tally. For tests: it must
    /// give [`Self::observe`]'s numbers, bit for bit. Collective.
    #[doc(hidden)]
    pub fn observe_visiting(&self) -> Observation {
        let sim = &self.sim;
        observation(&sim.world, &sim.workers, sim.initial_energy, &self.comm)
    }

    /// The next [`Self::step`] ends where the caller observes
    /// ([`Self::observe`]): its last pair pass writes each listed pair's
    /// terms and its last half kick sums the bodies' energies, so that
    /// the observation visits neither again ([`Simulation::will_observe`];
    /// the same numbers, bit for bit).
    pub fn will_observe(&mut self) {
        self.sim.will_observe();
    }
}

impl<T: Transport> StepHooks for RankComm<T> {
    /// One max per step over the ranks: every rank rebuilds at the same
    /// step.
    fn max_moved2(&mut self, moved2: f64) -> f64 {
        self.transport.max(moved2)
    }

    /// Where every rank exchanges halo state with every other
    /// ([`RankComm::max_in_halo`]): the halo messages carry the
    /// displacement, one exchange a step instead of a collective and an
    /// exchange.
    fn max_moved2_with_halo(&mut self, world: &mut World, moved2: f64) -> Option<f64> {
        if self.max_in_halo {
            self.halo_update(world, Some(moved2))
        } else {
            None
        }
    }

    /// Migration, a new halo and new lists; under `domain.outside =
    /// "delete"` the lost spheres first leave (`crate::removal`): every
    /// rank books every rank's removals, in input-id order, so the totals
    /// are the one process's bits; then the inlets insert (every rank
    /// places the same spheres, each keeps its sub-domain's).
    fn rebuild(&mut self, pipeline: &mut Pipeline, world: &mut World, workers: &Workers) {
        if world.removal.is_some() {
            let (dropping, gone) = crate::removal::lost_spheres(world);
            let mut out: BTreeMap<usize, Writer> = BTreeMap::new();
            if !gone.is_empty() {
                for r in (0..self.transport.size()).filter(|&r| r != self.transport.rank()) {
                    let w = out.entry(r).or_default();
                    for &(id, m, e, place) in &gone {
                        w.u32(id);
                        w.f64(m);
                        w.f64(e);
                        w.u32(place);
                    }
                }
            }
            let mut all = gone;
            for (_, bytes) in self.send_records(out) {
                let mut r = Reader::new(&bytes);
                while !r.done() {
                    all.push((r.u32(), r.f64(), r.f64(), r.u32()));
                }
            }
            crate::removal::book(world, all);
            self.dropping = dropping;
        }
        // Then the inlets' spheres due (`inlets`): the same on every rank;
        // the pair state by input ids first (insertion resizes the bodies).
        let saved = self.insert_due(world);
        self.migrate_and_rebuild(pipeline, world, workers, saved);
        self.dropping.clear();
    }

    /// Position and velocity (and spin) of every free halo body from its
    /// owner.
    fn halo(&mut self, world: &mut World) {
        self.halo_update(world, None);
    }

    /// [`Self::halo`] with `interior` run while the messages are in
    /// flight (`Transport::exchange_during`).
    fn halo_during(
        &mut self,
        world: &mut World,
        interior: &mut dyn FnMut(&mut World, &mut dyn FnMut()),
    ) {
        self.halo_sends(world);
        self.size_halo_in(world.friction.is_some());
        let from: Vec<usize> = self.receives.iter().map(|(r, _)| *r).collect();
        let clock = Instant::now();
        let mut working = 0.0;
        self.transport
            .exchange_during(&self.halo_out, &from, &mut self.halo_in, &mut |progress| {
                let started = Instant::now();
                interior(world, progress);
                working += started.elapsed().as_secs_f64();
            });
        self.halo_receive(world, &self.halo_in);
        self.halo_wait += clock.elapsed().as_secs_f64() - working;
        self.overlapped_steps += 1;
    }

    fn pair_forces(
        &mut self,
        pipeline: &mut Pipeline,
        world: &mut World,
        workers: &Workers,
        dt: f64,
    ) {
        self.sum_pair_forces(pipeline, world, workers, dt);
    }

    /// Summing in whole-scene cell order, the engine's fused Verlet step
    /// runs as it is (the halo exchange then sits between the fused
    /// stages).
    fn fusable(&self, _world: &World) -> bool {
        self.in_cell_order
    }

    /// A collision is kept by the rank owning its sphere i; each entry
    /// remembers its step (the merged log's order).
    fn logged(&mut self, world: &mut World, before: usize) {
        let new = world.collisions.split_off(before);
        let owned = &self.owned_by_id;
        world.collisions.extend(
            new.into_iter()
                .filter(|c| owned.get(c.i).copied().unwrap_or(false)),
        );
        self.collision_steps
            .resize(world.collisions.len(), world.steps_done);
    }

    /// Every rank's records on the servo walls, merged by input id and
    /// summed as on one process. Collective.
    fn servo_loads(&mut self, world: &World) -> Vec<crate::walls::WallLoad> {
        use crate::pipeline::{servo_walls, wall_loads};
        let walls = servo_walls::servo_file_indices(world);
        let records = self.merge_records(servo_walls::servo_load_records(world, &walls));
        wall_loads::sum_records(&records, world.walls.len())
    }
}
