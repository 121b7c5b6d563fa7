//! The public API: build a [`Simulation`] from a [`SceneSetup`], step it,
//! read its state (always in input order), checkpoint and restore it.
//! Building from the setup is in `build`, the observables and energies in
//! `observables`, checkpoint and restore in `checkpoint` (the completed
//! collisions stored in columns by `collision_columns`); the time-step rule
//! is `crate::time_step`.

// (child modules: they reach the run's private state)
pub(crate) mod build;
mod checkpoint;
pub(crate) mod collision_columns;
mod keyed_columns;
mod observables;
mod wall_force_mean;

pub(crate) use checkpoint::restore_wall_records;
pub use checkpoint::{Checkpoint, ElementRecord, HistoryRecord};

use serde::{Deserialize, Serialize};

use crate::dynamics::collisions::Collision;
use crate::energy_guard::EnergyGuard;
use crate::error::SceneError;
use crate::fingerprint::Fingerprint;
use crate::parallel::Workers;
use crate::pipeline::{Local, Pipeline, World};
use crate::setup::{SceneSetup, Scheme};
use crate::time_step;

/// Bodies larger than this many times the smallest free sphere are paired
/// outside the cell grid (boundary spheres of r = 100 would otherwise make
/// every cell as large as they are).
pub const LARGE_FACTOR: f64 = 4.0;

/// How the time step came about.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeStepReport {
    /// The step used, s.
    pub dt: f64,
    /// The smallest pair contact-time estimate at `impact_speed`, s (when
    /// Δt comes from η).
    pub contact_time: Option<f64>,
    /// m/s.
    pub impact_speed: Option<f64>,
    /// The smallest Rayleigh time of a free sphere,
    /// π R √(ρ/G)/(0.1631 ν + 0.8766), G = E/(2(1 + ν)), s (`None` when
    /// no free sphere has a finite modulus).
    pub rayleigh_time: Option<f64>,
}

/// The scene's global state at one instant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Observation {
    pub step: u64,
    /// s.
    pub time: f64,
    /// J.
    pub kinetic_energy: f64,
    /// Stored in contacts (pairs and walls), J: the normal law's, and with
    /// friction the tangential and rolling springs' (½ k_t |δ|², ½ |M_r|²/k_r).
    pub elastic_energy: f64,
    /// −Σ m g·x over free bodies, J.
    pub potential_energy: f64,
    /// Energy lost since the start (damping, and the integration error), J.
    pub dissipated_energy: f64,
    /// Pairs of spheres in contact, neither in a boundary-particle wall.
    pub particle_contacts: usize,
    /// Sphere–plane contacts plus contacts with boundary particles.
    pub wall_contacts: usize,
    /// Force on each wall (file order), N: what the last force stage
    /// applied to it (`pipeline::wall_loads`).
    pub wall_forces: Vec<[f64; 3]>,
    /// Torque on each wall (file order), N m, about its torque point
    /// (`Simulation::wall_torque_points`: a plane's point, a cylinder's
    /// axis point, the centroid of a boundary-particle wall's spheres).
    pub wall_torques: Vec<[f64; 3]>,
    /// Work done on the spheres by the moving walls since t = 0, J
    /// (`pipeline::moving_walls`); `None` when every wall is fixed. The
    /// dissipated energy is then E₀ + W − (K + E + P).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub work_by_walls: Option<f64>,
    /// The spheres removed since t = 0, their mass and the energy they
    /// carried out (`crate::removal`); `None` when the scene removes none
    /// (`domain.outside` not `"delete"`). The dissipated energy is then
    /// E₀ + W − C − (K + E + P), C the energy carried out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub removed: Option<crate::removal::Removed>,
    /// Each moving or force-controlled wall's motion now, wall order
    /// (issue 27, `pipeline::wall_states`); empty when every wall is
    /// fixed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wall_motions: Vec<crate::pipeline::wall_states::WallMotionState>,
    /// Each moving `[[particles]]` group's motion and load now, file
    /// order (`pipeline::moving_groups`); empty when none moves.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub group_motions: Vec<crate::pipeline::moving_groups::GroupMotionState>,
    /// What each outlet removed since t = 0 (file order; empty without
    /// outlets).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outlets: Vec<crate::removal::OutletRemoved>,
    /// G: the elastic energy the walls that vanished took out of their
    /// contacts less what the walls that appeared put in, since t = 0, J
    /// (`walls::gate`); `None` when every wall acts always. The dissipated
    /// energy is then E₀ + W − C − G − (K + E + P).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gate_energy: Option<f64>,
    /// What each inlet inserted since t = 0 (file order; empty without
    /// inlets, `crate::inlets`). The dissipated energy is then
    /// E₀ + W − C + I − (K + E + P), I the energy they brought in.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inlets: Vec<crate::inlets::Inserted>,
    /// D_c: the dissipated energy summed contact by contact since t = 0,
    /// J (`output.dissipation`, `pipeline::dissipation`); `None` when off.
    /// `dissipated_energy` − D_c is the energy balance's error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dissipated_by_contacts: Option<f64>,
    /// Each wall's force averaged over every step since the previous
    /// series row (file order, N; `output.wall_force_mean`,
    /// [`Simulation::take_wall_force_mean`]), NaN at a row with no step
    /// before it; `None` when not asked ([`Simulation::observe`] never
    /// fills it: the caller that steps between rows does).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_force_means: Option<Vec<[f64; 3]>>,
}

/// A running scene.
pub struct Simulation {
    pub(crate) world: World,
    pub(crate) pipeline: Pipeline,
    pub(crate) workers: Workers,
    total_steps: u64,
    time_step: TimeStepReport,
    pub(crate) initial_energy: f64,
    /// The energy balance's run-time check (`energy_guard`).
    pub(crate) energy_guard: EnergyGuard,
    /// The scene as a checkpoint must match it (`crate::fingerprint`).
    pub(crate) fingerprint: Fingerprint,
    /// Under `domain.outside = "error"`: the box a free sphere must not
    /// leave ([`Simulation::check_finite`]): the domain grown to hold every
    /// fixed sphere (a boundary-particle floor lies below the face its
    /// tops are on, and a small sphere held in its hollows may sink below
    /// that face by more than its radius). `None` under `"keep"`.
    pub(crate) outside_box: Option<([f64; 3], [f64; 3])>,
    /// What a restart into changed walls dropped and added, one line per
    /// wall (`crate::restart_walls`); empty otherwise.
    pub(crate) restart_notes: Vec<String>,
}

/// Whether every coordinate is finite: an and over blocks of 64 values
/// without a branch inside a block (vectorised; `check_finite` runs after
/// every stretch of steps).
fn all_finite(v: &[[f64; 3]]) -> bool {
    v.as_flattened()
        .chunks(64)
        .all(|block| block.iter().fold(true, |ok, x| ok & x.is_finite()))
}

/// Whether every centre `x` lies within its radius `r` of the box
/// `lower..upper` along every axis (the bounds [`crate::removal::lost_axis`]
/// tests first, in the same arithmetic; a NaN coordinate is not within),
/// in blocks of 64 bodies without a branch inside a block.
fn all_within(x: &[[f64; 3]], r: &[f64], lower: &[f64; 3], upper: &[f64; 3]) -> bool {
    x.chunks(64).zip(r.chunks(64)).all(|(xs, rs)| {
        xs.iter().zip(rs).fold(true, |ok, (x, &r)| {
            let mut inside = ok;
            for a in 0..3 {
                inside &= (x[a] >= lower[a] - r) & (x[a] <= upper[a] + r);
            }
            inside
        })
    })
}

impl Simulation {
    /// Validates `setup` and prepares the run on `threads` worker threads
    /// (≥ 1; results do not depend on it).
    pub fn new(setup: SceneSetup, threads: usize) -> Result<Self, SceneError> {
        let mut sim = Self::prepare(&setup, threads)?;
        // The engine holds its own arrays now: the input list goes before
        // the first neighbour build (peak memory of large scenes).
        drop(setup);
        sim.pipeline.start(&mut sim.world, &sim.workers);
        sim.initial_energy = sim.mechanical_energy();
        Ok(sim)
    }

    /// Advances `n` steps.
    pub fn step(&mut self, n: u64) {
        self.pipeline.check_box = self.outside_box;
        self.pipeline
            .steps(&mut self.world, &self.workers, n, &mut Local);
    }

    /// The next [`Self::step`] ends where the caller observes
    /// ([`Self::observe`]): its last pair pass tallies the pairs'
    /// observables on the way (with friction, on one process, Verlet), so
    /// that the observation does not visit the pairs again. The same
    /// numbers, bit for bit; only the work moves.
    pub fn will_observe(&mut self) {
        self.pipeline.tally_wanted = true;
    }

    /// [`Self::step`], then the state checked: an error
    /// ([`SceneError::Unstable`]) when a position, velocity or spin is no
    /// longer finite, so that a blown-up run is never reported as numbers;
    /// an input error when a free sphere left the box
    /// ([`Self::check_finite`]).
    pub fn step_checked(&mut self, n: u64) -> Result<(), SceneError> {
        self.step(n);
        self.check_finite()
    }

    /// An error when a body's position, velocity or spin is not finite
    /// (one pass over the bodies), or, under `domain.outside = "error"`,
    /// when a free sphere's centre is outside the box along a non-periodic
    /// axis (a second pass).
    pub fn check_finite(&self) -> Result<(), SceneError> {
        if self.pipeline.sound(&self.world) {
            // Tested by the last half kick at this state (asked by
            // `will_observe`): the same tests, passed.
            return Ok(());
        }
        let b = &self.world.bodies;
        if all_finite(&b.position) && all_finite(&b.velocity) && all_finite(&b.angular_velocity) {
            return self.check_inside();
        }
        Err(SceneError::Unstable {
            step: self.world.steps_done,
            time: self.time(),
            dt: self.world.dt,
            scheme: match self.world.scheme {
                Scheme::Verlet => "verlet",
                Scheme::Gear5 => "gear5",
            }
            .to_string(),
            extreme_inputs: self.energy_guard.extreme_inputs().to_vec(),
        })
    }

    /// Under `domain.outside = "error"`: an input error naming the first
    /// free sphere (lowest input index) lost for good along a non-periodic
    /// axis, with the step, its position and the key. Lost: wholly outside
    /// the box grown to hold the fixed spheres ([`Simulation::outside_box`];
    /// its centre more than its radius beyond a face), moving away from
    /// the box or not towards it, and gravity not pulling it back: nothing
    /// brings it back (a sphere that starts above an open box and falls
    /// in, or bounces out through an open top and falls back, is not
    /// lost).
    fn check_inside(&self) -> Result<(), SceneError> {
        let Some((lower, upper)) = self.outside_box else {
            return Ok(());
        };
        let b = &self.world.bodies;
        // Every centre within its radius of the box: none is lost (the
        // common case, one pass without branches; `lost_axis` tests the
        // same two bounds first).
        if all_within(&b.position, &b.radius, &lower, &upper) {
            return Ok(());
        }
        let periodic = self.world.domain.periodic;
        let g = self.world.gravity;
        let lost = |i: usize| {
            crate::removal::lost_axis(
                &b.position[i],
                b.radius[i],
                &b.velocity[i],
                (&lower, &upper),
                &periodic,
                &g,
            )
        };
        let first = (0..b.len())
            .filter(|&i| !b.fixed[i])
            .filter_map(|i| lost(i).map(|a| (b.id[i], i, a)))
            .min();
        let Some((id, i, a)) = first else {
            return Ok(());
        };
        let x = b.position[i];
        let axis = ["x", "y", "z"][a];
        let d = &self.world.domain;
        let grown = if lower[a] < d.lower[a] || upper[a] > d.upper[a] {
            format!(
                "the domain along {axis} ([{:e}, {:e}] m) grown to hold the fixed spheres: \
                 [{:e}, {:e}] m",
                d.lower[a], d.upper[a], lower[a], upper[a]
            )
        } else {
            format!(
                "domain.lower..domain.upper along {axis} ([{:e}, {:e}] m)",
                lower[a], upper[a]
            )
        };
        Err(SceneError::input(format!(
            "sphere {id} left the domain for good by step {} (t = {:.6e} s): its centre ({:.6e}, \
             {:.6e}, {:.6e}) m is more than its radius ({:.6e} m) outside {grown}, moving away, \
             and nothing brings it back; the scene's numbers would no longer describe the scene \
             given; allowed: walls that keep the spheres in, a larger domain, or \
             domain.outside = \"keep\" (they go on, unreported)",
            self.world.steps_done,
            self.time(),
            x[0],
            x[1],
            x[2],
            b.radius[i],
        )))
    }

    /// [`Self::step_checked`], then one [`Self::observe_checked`] (for
    /// callers that do not observe between stretches: Python).
    pub fn step_guarded(&mut self, n: u64) -> Result<(), SceneError> {
        self.will_observe();
        self.step_checked(n)?;
        self.observe_checked().map(|_| ())
    }

    /// Steps until the setup's run length is reached.
    pub fn run_to_end(&mut self) {
        self.step(self.remaining_steps());
    }

    /// The run length in steps (from `integration.steps` or `duration`).
    pub fn total_steps(&self) -> u64 {
        self.total_steps
    }

    pub fn remaining_steps(&self) -> u64 {
        self.total_steps.saturating_sub(self.world.steps_done)
    }

    pub fn steps_done(&self) -> u64 {
        self.world.steps_done
    }

    /// Simulated time, s (steps × Δt).
    pub fn time(&self) -> f64 {
        self.world.time()
    }

    /// s.
    pub fn dt(&self) -> f64 {
        self.world.dt
    }

    pub fn time_step(&self) -> &TimeStepReport {
        &self.time_step
    }

    pub fn threads(&self) -> usize {
        self.workers.threads()
    }

    /// Number of spheres (free and fixed).
    pub fn body_count(&self) -> usize {
        self.world.bodies.len()
    }

    /// Neighbour-list builds so far.
    pub fn list_builds(&self) -> u64 {
        self.world.rebuilds
    }

    /// Each worker's share of the force loop now, (force blocks, bodies),
    /// worker order; empty when the loop is not shared (one thread, a
    /// decomposed run). Test-visible: shows that a run splits its work.
    #[doc(hidden)]
    pub fn worker_shares(&self) -> Vec<(usize, usize)> {
        self.world.list.worker_shares(self.workers.threads())
    }

    /// Listed pairs (with skin) now.
    pub fn listed_pairs(&self) -> usize {
        self.world.list.pair_count()
    }

    /// The input index of each sphere still here, ascending: the order of
    /// every per-sphere output (all of 0..n without removal; spheres an
    /// inlet placed take the next indices in the order they came).
    pub fn ids(&self) -> Vec<u32> {
        self.world.bodies.ids_in_input_order()
    }

    /// Centres, m, input order.
    pub fn positions(&self) -> Vec<[f64; 3]> {
        self.world
            .bodies
            .in_input_order(&self.world.bodies.position)
    }

    /// m/s, input order.
    pub fn velocities(&self) -> Vec<[f64; 3]> {
        self.world
            .bodies
            .in_input_order(&self.world.bodies.velocity)
    }

    /// Force on each body at the last force evaluation (contacts, walls and
    /// gravity; for a fixed body the contact forces only), N, input order.
    pub fn forces(&self) -> Vec<[f64; 3]> {
        self.world.bodies.in_input_order(&self.world.bodies.force)
    }

    /// m, input order.
    pub fn radii(&self) -> Vec<f64> {
        self.world.bodies.in_input_order(&self.world.bodies.radius)
    }

    /// Input order.
    pub fn fixed(&self) -> Vec<bool> {
        self.world.bodies.in_input_order(&self.world.bodies.fixed)
    }

    /// Material index of each body, input order.
    pub fn material_indices(&self) -> Vec<usize> {
        let m: Vec<usize> = self
            .world
            .bodies
            .material
            .iter()
            .map(|&m| m as usize)
            .collect();
        self.world.bodies.in_input_order(&m)
    }

    /// Angular velocity of each body, rad/s, input order (0 without friction).
    pub fn angular_velocities(&self) -> Vec<[f64; 3]> {
        self.world
            .bodies
            .in_input_order(&self.world.bodies.angular_velocity)
    }

    /// Torque on each body at the last force evaluation, N m, input order.
    pub fn torques(&self) -> Vec<[f64; 3]> {
        let b = &self.world.bodies;
        if b.torque.len() != b.len() {
            return vec![[0.0; 3]; b.len()];
        }
        b.in_input_order(&b.torque)
    }

    /// Sets the angular velocity (rad/s) of the body of input index `id`
    /// (a free body of a scene with friction; `false` otherwise). For
    /// initial spins, before stepping.
    pub fn set_angular_velocity(&mut self, id: usize, omega: [f64; 3]) -> bool {
        let b = &mut self.world.bodies;
        if self.world.friction.is_none() {
            return false;
        }
        let Some(&k) = b.index_of_ids().get(id) else {
            return false;
        };
        let k = k as usize;
        if b.fixed.get(k).is_none_or(|&f| f) {
            return false;
        }
        b.angular_velocity[k] = omega;
        // The kinetic energy summed by the last kick is no longer this
        // state's.
        self.pipeline.forget_tally();
        true
    }

    /// The spheres removed so far, their mass and the energy they carried
    /// out (`domain.outside = "delete"`, `crate::removal`); `None` when the
    /// scene removes none.
    pub fn removed(&self) -> Option<crate::removal::Removed> {
        self.world.removal.as_ref().map(|r| r.removed)
    }

    /// What the restart that made this run dropped and added of the
    /// checkpoint's walls, one line per wall (`crate::restart_walls`);
    /// empty when the walls are the checkpoint's or the run is new.
    pub fn restart_notes(&self) -> &[String] {
        &self.restart_notes
    }

    /// Completed contacts so far, in the order they ended.
    pub fn collisions(&self) -> &[Collision] {
        &self.world.collisions
    }

    /// The smallest pair contact-time estimate of the scene at
    /// `impact_speed` (m/s), s.
    pub fn contact_time_estimate(setup: &SceneSetup, impact_speed: f64) -> f64 {
        time_step::smallest_contact_time(setup, impact_speed)
    }
}

#[cfg(test)]
mod check_tests {
    use super::{all_finite, all_within};

    /// A non-finite value anywhere (first, inside a block, in the partial
    /// last block) is found; only finite values pass.
    #[test]
    fn all_finite_finds_any_non_finite_value() {
        let v = vec![[1.0, -2.0, 3.0e300]; 70];
        assert!(all_finite(&v));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for k in [0, 63, 64, 69] {
                for a in 0..3 {
                    let mut w = v.clone();
                    w[k][a] = bad;
                    assert!(!all_finite(&w), "{bad} at body {k} axis {a}");
                }
            }
        }
    }

    /// Within means lower − r ≤ x ≤ upper + r on every axis (the bounds
    /// `removal::lost_axis` tests): on the bound is within, any body a
    /// little beyond either bound on any axis is not.
    #[test]
    fn all_within_is_lost_axis_first_test() {
        let (lower, upper) = ([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]);
        let r = vec![0.25; 70];
        let mut x = vec![[0.5, 1.0, 1.5]; 70];
        assert!(all_within(&x, &r, &lower, &upper));
        x[3] = [-0.25, 2.25, 3.25];
        assert!(all_within(&x, &r, &lower, &upper));
        for k in [0, 64, 69] {
            for a in 0..3 {
                for beyond in [lower[a] - 0.25 - 1e-9, upper[a] + 0.25 + 1e-9] {
                    let mut y = x.clone();
                    y[k][a] = beyond;
                    assert!(!all_within(&y, &r, &lower, &upper), "body {k} axis {a}");
                }
            }
        }
    }
}
