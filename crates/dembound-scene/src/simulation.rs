//! The public API: build a [`Simulation`] from a [`SceneSetup`], step it,
//! read its state (always in input order), checkpoint and restore it.

use std::collections::HashMap;

use dembound_physics::contact::ContactHistory;
use serde::{Deserialize, Serialize};

use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::collisions::{Collision, Track};
use crate::dynamics::contacts::{self, LawTable, PairHistories};
use crate::dynamics::friction::{self, FrictionTable, PairShear, WallShear};
use crate::energy_guard::{EnergyBalance, EnergyGuard};
use crate::error::SceneError;
use crate::fingerprint::Fingerprint;
use crate::geometry::domain::Domain;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::Workers;
use crate::pipeline::{observe, Local, Pipeline, Tracks, WallKind, World};
use crate::setup::{RunLength, SceneSetup, Scheme, WallSetup};
use crate::time_step;
use crate::walls::{
    Curvature, CylinderWall, LawSlot, PlaneWall, Surface, WallContacts, WallElement,
};

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
    /// Force on each wall (file order), N.
    pub wall_forces: Vec<[f64; 3]>,
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
}

fn finite3(v: [f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn show3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

impl Simulation {
    /// Validates `setup` and prepares the run on `threads` worker threads
    /// (≥ 1; results do not depend on it).
    pub fn new(setup: SceneSetup, threads: usize) -> Result<Self, SceneError> {
        let mut sim = Self::prepare(&setup, threads)?;
        sim.pipeline.start(&mut sim.world, &sim.workers);
        sim.initial_energy = sim.mechanical_energy();
        Ok(sim)
    }

    pub(crate) fn prepare(setup: &SceneSetup, threads: usize) -> Result<Self, SceneError> {
        if threads == 0 {
            return Err(SceneError::invalid("threads", 0, "at least 1"));
        }
        setup.contact.validate().map_err(|e| SceneError::Invalid {
            key: e.key,
            value: e.value,
            allowed: e.allowed,
        })?;
        validate_friction(setup)?;
        let d = &setup.domain;
        for a in 0..3 {
            if !(d.lower[a].is_finite() && d.upper[a].is_finite() && d.lower[a] < d.upper[a]) {
                return Err(SceneError::invalid(
                    format!("domain.upper[{a}]"),
                    d.upper[a],
                    format!("finite and above domain.lower[{a}] = {} m", d.lower[a]),
                ));
            }
        }
        for (k, m) in setup.materials.iter().enumerate() {
            let m = &m.material;
            if !(m.density.is_finite() && m.density > 0.0) {
                return Err(SceneError::invalid(
                    format!("materials[{k}].density"),
                    m.density,
                    "finite and > 0 kg/m³",
                ));
            }
            if m.youngs_modulus.is_nan() || m.youngs_modulus <= 0.0 {
                return Err(SceneError::invalid(
                    format!("materials[{k}].youngs_modulus"),
                    m.youngs_modulus,
                    "> 0 Pa (inf for rigid)",
                ));
            }
            if !(m.poisson_ratio > -1.0 && m.poisson_ratio <= 0.5) {
                return Err(SceneError::invalid(
                    format!("materials[{k}].poisson_ratio"),
                    m.poisson_ratio,
                    "in (-1, 0.5]",
                ));
            }
        }
        let nm = setup.materials.len();
        for (k, s) in setup.spheres.iter().enumerate() {
            if !(s.radius.is_finite() && s.radius > 0.0) {
                return Err(SceneError::invalid(
                    format!("spheres[{k}].radius"),
                    s.radius,
                    "finite and > 0 m",
                ));
            }
            if !finite3(s.position) {
                return Err(SceneError::invalid(
                    format!("spheres[{k}].position"),
                    show3(s.position),
                    "finite, m",
                ));
            }
            if !finite3(s.velocity) {
                return Err(SceneError::invalid(
                    format!("spheres[{k}].velocity"),
                    show3(s.velocity),
                    "finite, m/s",
                ));
            }
            if s.material >= nm {
                return Err(SceneError::invalid(
                    format!("spheres[{k}].material"),
                    s.material,
                    format!("a material index below {nm}"),
                ));
            }
            if let Some(g) = s.group {
                let ok = matches!(
                    setup.walls.get(g),
                    Some(WallSetup::BoundaryParticles { .. })
                );
                if !ok || !s.fixed {
                    return Err(SceneError::invalid(
                        format!("spheres[{k}].group"),
                        g,
                        "the index of a boundary-particle wall, on a fixed sphere",
                    ));
                }
            }
            if !s.fixed && !setup.materials[s.material].material.density.is_finite() {
                return Err(SceneError::invalid(
                    format!("spheres[{k}].material"),
                    s.material,
                    "a finite density",
                ));
            }
        }
        if setup.spheres.len() >= u32::MAX as usize {
            return Err(SceneError::invalid(
                "spheres",
                setup.spheres.len(),
                "fewer than 2^32 − 1",
            ));
        }
        let mut planes: Vec<Surface> = Vec::new();
        let mut slots: Vec<LawSlot> = Vec::new();
        let mut kinds = Vec::new();
        for (w, wall) in setup.walls.iter().enumerate() {
            match *wall {
                WallSetup::Plane {
                    point,
                    normal,
                    material,
                } => {
                    let mut len =
                        (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2])
                            .sqrt();
                    if !(len.is_finite() && len > 1e-150) {
                        // Squares that overflow or underflow ([0, 0, 1e300]):
                        // the scaled norm (the formula above, kept for the
                        // bits of every other normal).
                        len = crate::limits::norm(normal);
                    }
                    if !(len.is_finite() && len > 0.0) {
                        return Err(SceneError::invalid(
                            format!("wall[{w}].plane.normal"),
                            show3(normal),
                            "finite and non-zero",
                        ));
                    }
                    if !finite3(point) {
                        return Err(SceneError::invalid(
                            format!("walls[{w}].point"),
                            show3(point),
                            "finite, m",
                        ));
                    }
                    if material >= nm {
                        return Err(SceneError::invalid(
                            format!("walls[{w}].material"),
                            material,
                            format!("a material index below {nm}"),
                        ));
                    }
                    kinds.push(WallKind::Surface(planes.len()));
                    planes.push(Surface::Plane(PlaneWall {
                        wall: w,
                        point,
                        normal: [normal[0] / len, normal[1] / len, normal[2] / len],
                        slot: slots.len(),
                    }));
                    slots.push(LawSlot {
                        material: material as u32,
                        wall: w,
                        curvature: Curvature::Flat,
                    });
                }
                WallSetup::Cylinder {
                    point,
                    axis,
                    radius,
                    inside,
                    length,
                    material,
                } => {
                    let surface = cylinder_wall(w, point, axis, radius, inside, length)?;
                    if material >= nm {
                        return Err(SceneError::invalid(
                            format!("walls[{w}].material"),
                            material,
                            format!("a material index below {nm}"),
                        ));
                    }
                    let surface = CylinderWall {
                        slot: slots.len(),
                        ..surface
                    };
                    let (tube, caps) = surface.curvatures();
                    for curvature in std::iter::once(tube).chain(caps) {
                        slots.push(LawSlot {
                            material: material as u32,
                            wall: w,
                            curvature,
                        });
                    }
                    kinds.push(WallKind::Surface(planes.len()));
                    planes.push(Surface::Cylinder(surface));
                }
                WallSetup::BoundaryParticles { first_body, count } => {
                    let end = first_body
                        .checked_add(count)
                        .filter(|&e| e <= setup.spheres.len());
                    let Some(end) = end else {
                        return Err(SceneError::invalid(
                            format!("walls[{w}].count"),
                            count,
                            format!(
                                "spheres {first_body}.. within the {} spheres",
                                setup.spheres.len()
                            ),
                        ));
                    };
                    for k in first_body..end {
                        let s = &setup.spheres[k];
                        if !s.fixed || s.group != Some(w) {
                            return Err(SceneError::invalid(
                                format!("spheres[{k}].group"),
                                format!("{:?}", s.group),
                                format!("Some({w}) and fixed: sphere {k} belongs to boundary-particle wall {w}"),
                            ));
                        }
                    }
                    kinds.push(WallKind::Particles);
                }
            }
        }
        if !finite3(setup.gravity) {
            return Err(SceneError::invalid(
                "motion.gravity",
                show3(setup.gravity),
                "finite, m/s²",
            ));
        }
        crate::setup_checks::check(setup, &crate::setup_checks::by_index)?;

        // Bodies in input order.
        let n = setup.spheres.len();
        let mut b = Bodies::default();
        for (k, s) in setup.spheres.iter().enumerate() {
            let mat = &setup.materials[s.material].material;
            b.position.push(s.position);
            b.velocity.push(if s.fixed { [0.0; 3] } else { s.velocity });
            b.force.push([0.0; 3]);
            b.radius.push(s.radius);
            let m = if s.fixed {
                f64::INFINITY
            } else {
                mat.sphere_mass(s.radius)
            };
            b.mass.push(m);
            b.inverse_mass.push(if s.fixed { 0.0 } else { 1.0 / m });
            b.angular_velocity.push([0.0; 3]);
            b.torque.push([0.0; 3]);
            // A solid sphere: I = 2/5 m R².
            b.inverse_inertia.push(if s.fixed {
                0.0
            } else {
                1.0 / (0.4 * m * s.radius * s.radius)
            });
            b.material.push(s.material as u32);
            b.fixed.push(s.fixed);
            b.id.push(k as u32);
            b.group.push(s.group.map_or(NO_GROUP, |g| g as u32));
        }
        let materials: Vec<_> = setup.materials.iter().map(|m| m.material).collect();
        let laws = LawTable::new(setup.contact, materials, &mut b, slots);
        let friction = setup
            .friction
            .clone()
            .map(|f| FrictionTable::new(f, &laws, &b));

        // Neighbour geometry.
        let free_min = b
            .radius
            .iter()
            .zip(&b.fixed)
            .filter(|(_, &f)| !f)
            .map(|(&r, _)| r)
            .fold(f64::INFINITY, f64::min);
        let any_min = b.radius.iter().copied().fold(f64::INFINITY, f64::min);
        let reference_radius = if free_min.is_finite() {
            free_min
        } else {
            any_min
        };
        let skin = match setup.neighbour.skin {
            Some(s) => {
                if !(s.is_finite() && s > 0.0) {
                    return Err(SceneError::invalid("neighbour.skin", s, "finite and > 0 m"));
                }
                s
            }
            None if reference_radius.is_finite() => 0.2 * reference_radius,
            None => 1.0e-4,
        };
        let large_radius = LARGE_FACTOR * reference_radius;
        let small_max = b
            .radius
            .iter()
            .copied()
            .filter(|&r| r <= large_radius)
            .fold(0.0, f64::max);
        let cell_size = 2.0 * small_max + skin;
        let len = [
            d.upper[0] - d.lower[0],
            d.upper[1] - d.lower[1],
            d.upper[2] - d.lower[2],
        ];
        for (a, &len) in len.iter().enumerate() {
            if d.periodic[a] && len < 2.0 * cell_size {
                return Err(SceneError::invalid(
                    format!("domain.upper[{a}]"),
                    d.upper[a],
                    format!(
                        "a periodic box at least 2 × (largest diameter + skin) = {} m long on axis {a}",
                        2.0 * cell_size
                    ),
                ));
            }
        }
        if d.periodic.iter().any(|&p| p) && b.radius.iter().any(|&r| r > large_radius) {
            return Err(SceneError::invalid(
                "domain.periodic",
                format!("{:?}", d.periodic),
                format!("no periodic axis with spheres larger than {LARGE_FACTOR} × the smallest free sphere"),
            ));
        }

        // Time step (`time_step`: the bound against stability).
        let rayleigh_time = time_step::rayleigh_time(setup);
        let time_step::StepChoice {
            dt,
            contact_time,
            impact_speed,
        } = time_step::choose(setup)?;
        let total_steps = match setup.integration.length {
            RunLength::Steps(s) => s,
            RunLength::Duration(t) => {
                if !(t.is_finite() && t >= 0.0) {
                    return Err(SceneError::invalid(
                        "integration.duration",
                        t,
                        "finite and ≥ 0 s",
                    ));
                }
                let s = (t / dt).ceil();
                if s > 1.0e15 {
                    return Err(SceneError::invalid(
                        "integration.duration",
                        t,
                        format!("at most 1e15 steps of {dt} s"),
                    ));
                }
                s as u64
            }
        };
        let workers = Workers::new(threads)?;
        let world = World {
            wall_contacts: WallContacts::new(n, laws.history, friction.is_some(), setup.collisions),
            tracks: setup.collisions.then(|| Tracks {
                main: Vec::new(),
                extra: Vec::new(),
            }),
            bodies: b,
            surfaces: planes,
            walls: kinds,
            domain: Domain {
                lower: d.lower,
                upper: d.upper,
                periodic: d.periodic,
            },
            laws,
            gravity: setup.gravity,
            scheme: setup.integration.scheme,
            dt,
            steps_done: 0,
            skin,
            cell_size,
            large_radius,
            list: PairList::default(),
            histories: PairHistories::default(),
            ghosts: Ghosts::default(),
            collisions: Vec::new(),
            rebuilds: 0,
            friction,
            shear: PairShear::default(),
        };
        Ok(Simulation {
            world,
            pipeline: Pipeline::default(),
            workers,
            total_steps,
            time_step: TimeStepReport {
                dt,
                contact_time,
                impact_speed,
                rayleigh_time,
            },
            initial_energy: 0.0,
            energy_guard: EnergyGuard::new(setup, dt),
            fingerprint: Fingerprint::of(setup),
        })
    }

    /// Advances `n` steps.
    pub fn step(&mut self, n: u64) {
        self.pipeline
            .steps(&mut self.world, &self.workers, n, &mut Local);
    }

    /// [`Self::step`], then the state checked: an error
    /// ([`SceneError::Unstable`]) when a position, velocity or spin is no
    /// longer finite, so that a blown-up run is never reported as numbers.
    pub fn step_checked(&mut self, n: u64) -> Result<(), SceneError> {
        self.step(n);
        self.check_finite()
    }

    /// An error when a body's position, velocity or spin is not finite
    /// (one pass over the bodies).
    pub fn check_finite(&self) -> Result<(), SceneError> {
        let b = &self.world.bodies;
        let finite = |v: &[[f64; 3]]| v.iter().flatten().all(|x| x.is_finite());
        if finite(&b.position) && finite(&b.velocity) && finite(&b.angular_velocity) {
            return Ok(());
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

    /// [`Self::observe`], checked by the energy guard: an error when the
    /// run has created energy beyond the integration error allowed
    /// (`energy_guard`) or its energies are not finite.
    pub fn observe_checked(&mut self) -> Result<Observation, SceneError> {
        let o = self.observe();
        self.energy_guard.check(&o, self.initial_energy)?;
        Ok(o)
    }

    /// [`Self::step_checked`], then one [`Self::observe_checked`] (for
    /// callers that do not observe between stretches: Python).
    pub fn step_guarded(&mut self, n: u64) -> Result<(), SceneError> {
        self.step_checked(n)?;
        self.observe_checked().map(|_| ())
    }

    /// The energy balance at observation `o` of this run, with the largest
    /// gain the guard has seen.
    pub fn energy_balance(&self, o: &Observation) -> EnergyBalance {
        self.energy_guard.balance(o, self.initial_energy)
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

    /// Σ ½ m v² over free bodies, plus Σ ½ I ω² with friction, J.
    pub fn kinetic_energy(&self) -> f64 {
        observe::kinetic_energy(&self.world, &self.workers)
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
        if self.world.friction.is_none() || id >= b.len() {
            return false;
        }
        let k = b.index_of_ids()[id] as usize;
        if b.fixed[k] {
            return false;
        }
        b.angular_velocity[k] = omega;
        true
    }

    /// −Σ m g·x over free bodies, J.
    pub fn potential_energy(&self) -> f64 {
        observe::potential_energy(&self.world, &self.workers)
    }

    /// Energy stored in the contacts (pairs and plane walls), J, friction
    /// springs included ([`Observation::elastic_energy`]).
    pub fn elastic_energy(&self) -> f64 {
        self.observe().elastic_energy
    }

    /// Energy lost since the start, J: the initial kinetic + elastic +
    /// potential energy minus the current one (damping and integration
    /// error).
    pub fn dissipated_energy(&self) -> f64 {
        self.observe().dissipated_energy
    }

    fn mechanical_energy(&self) -> f64 {
        let o = self.observe();
        o.kinetic_energy + o.elastic_energy + o.potential_energy
    }

    /// Sphere pairs in contact now (neither a boundary particle).
    pub fn particle_contacts(&self) -> usize {
        self.observe().particle_contacts
    }

    /// Sphere–wall contacts now (planes and boundary particles).
    pub fn wall_contacts(&self) -> usize {
        self.observe().wall_contacts
    }

    /// Force on each wall in file order, N (for a boundary-particle wall
    /// the sum over its spheres).
    pub fn wall_forces(&self) -> Vec<[f64; 3]> {
        self.observe().wall_forces
    }

    /// Every global observable at the current state.
    pub fn observe(&self) -> Observation {
        observe::observation(&self.world, &self.workers, self.initial_energy, &Local)
    }

    /// The contact observables pass by pass: pair counts and energy, plane
    /// forces, counts and energy, plane tangential forces, spring energy
    /// (see [`Self::observe`]); for the test of the fused pass.
    #[cfg(test)]
    #[allow(clippy::type_complexity)]
    pub(crate) fn contact_observables(
        &self,
    ) -> (
        usize,
        usize,
        f64,
        Vec<[f64; 3]>,
        usize,
        f64,
        Vec<[f64; 3]>,
        f64,
    ) {
        let c = observe::contact_passes(&self.world, &self.workers);
        (
            c.particle_contacts,
            c.boundary_contacts,
            c.pair_energy,
            c.plane_forces,
            c.plane_contacts,
            c.plane_energy,
            c.plane_tangential,
            c.spring_energy,
        )
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
        }
    }

    /// Continues a checkpointed run of the same `setup`.
    pub fn restore(
        setup: SceneSetup,
        checkpoint: &Checkpoint,
        threads: usize,
    ) -> Result<Self, SceneError> {
        let mut sim = Self::prepare(&setup, threads)?;
        let c = checkpoint;
        c.fingerprint.check(&sim.fingerprint)?;
        let n = sim.world.bodies.len();
        let same_len = |len: usize| len == n;
        if !(same_len(c.order.len())
            && same_len(c.position.len())
            && same_len(c.velocity.len())
            && same_len(c.force.len())
            && same_len(c.reference.len())
            && (c.higher.is_empty() || same_len(c.higher.len())))
        {
            return Err(SceneError::Checkpoint(format!(
                "it holds {} bodies, the scene {n}",
                c.order.len()
            )));
        }
        if c.dt.to_bits() != sim.world.dt.to_bits() {
            return Err(SceneError::Checkpoint(format!(
                "its Δt is {} s, the scene's {} s",
                c.dt, sim.world.dt
            )));
        }
        let mut seen = vec![false; n];
        for &id in &c.order {
            if id as usize >= n || seen[id as usize] {
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
        sim.pipeline.neighbours(w, &sim.workers);
        // The build sorts the bodies by cell: a checkpoint written in the
        // engine's order is already sorted (the order stays), one in
        // another order (a decomposed run's, input order) is not; the
        // arrays not moved with the bodies are taken by id.
        let mut entry = vec![0usize; n];
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
            .map(|k| k as usize)
            .collect();
        restore_wall_records(w, c, &at)?;
        Ok(sim)
    }
}

/// The cylinder of `wall[w]` (its law row still to set), or the first bad
/// value named.
fn cylinder_wall(
    w: usize,
    point: [f64; 3],
    axis: [f64; 3],
    radius: f64,
    inside: bool,
    length: Option<f64>,
) -> Result<CylinderWall, SceneError> {
    let key = |k: &str| format!("wall[{w}].cylinder.{k}");
    let len = crate::limits::norm(axis);
    if !(finite3(axis) && len.is_finite() && len > 0.0) {
        return Err(SceneError::invalid(
            key("axis"),
            show3(axis),
            "finite and non-zero",
        ));
    }
    if !finite3(point) {
        return Err(SceneError::invalid(key("point"), show3(point), "finite, m"));
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(SceneError::invalid(
            key("radius"),
            radius,
            "finite and > 0 m",
        ));
    }
    if let Some(l) = length {
        if !(l.is_finite() && l > 0.0) {
            return Err(SceneError::invalid(key("length"), l, "finite and > 0 m"));
        }
        if !inside {
            return Err(SceneError::invalid(
                key("length"),
                l,
                "none for a post (inside = false): a finite post has rims, which this wall does \
                 not model; omit length (infinite post)",
            ));
        }
    }
    Ok(CylinderWall {
        wall: w,
        point,
        axis: axis.map(|x| x / len),
        radius,
        inside,
        half_length: length.map(|l| 0.5 * l),
        slot: 0,
    })
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
        if i != usize::MAX {
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
    pub pair_tracks: Vec<(u32, u32, Track)>,
    pub plane_tracks: Vec<(u32, u32, Track)>,
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
}

/// Friction coefficients finite and ≥ 0.
fn validate_friction(setup: &SceneSetup) -> Result<(), SceneError> {
    let Some(f) = &setup.friction else {
        return Ok(());
    };
    let invalid = |e: dembound_physics::PhysicsError| SceneError::Invalid {
        key: e.key,
        value: e.value,
        allowed: e.allowed,
    };
    f.model.validate().map_err(invalid)?;
    use dembound_physics::contact::tangential::check_coefficient;
    for (k, m) in f.materials.iter().enumerate() {
        if let Some((mu, roll)) = m {
            check_coefficient(&format!("materials[{k}].friction"), *mu, "μ").map_err(invalid)?;
            check_coefficient(&format!("materials[{k}].rolling_friction"), *roll, "μ_r")
                .map_err(invalid)?;
        }
    }
    for (k, w) in f.walls.iter().enumerate() {
        if let Some((mu, roll)) = w {
            check_coefficient(&format!("walls[{k}].friction"), *mu, "μ").map_err(invalid)?;
            check_coefficient(&format!("walls[{k}].rolling_friction"), *roll, "μ_r")
                .map_err(invalid)?;
        }
    }
    Ok(())
}
