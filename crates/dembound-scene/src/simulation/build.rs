//! Building a [`Simulation`] from a [`SceneSetup`]: the setup validated
//! (every bad value named with its key and range), the bodies, walls,
//! contact laws and friction tables made, the skin and cells chosen, Δt
//! from the time-step rule.

use super::{Simulation, TimeStepReport, LARGE_FACTOR};
use crate::bodies::{Bodies, NO_GROUP};
use crate::dynamics::contacts::{LawTable, PairHistories};
use crate::dynamics::friction::{FrictionTable, PairShear};
use crate::energy_guard::EnergyGuard;
use crate::error::SceneError;
use crate::fingerprint::Fingerprint;
use crate::geometry::domain::Domain;
use crate::geometry::ghosts::Ghosts;
use crate::geometry::neighbour::PairList;
use crate::parallel::Workers;
use crate::pipeline::{Pipeline, Tracks, WallKind, World};
use crate::setup::{Outside, RunLength, SceneSetup};
use crate::time_step;
use crate::walls::registry::{finite3, show3};
use crate::walls::{LawSlot, Surface, WallContacts};

impl Simulation {
    /// Validates `setup` and builds the run without its first forces
    /// ([`Simulation::new`] adds them; a decomposed run first keeps its
    /// rank's bodies).
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
        check_spheres(setup, &setup.spheres, |k| k)?;
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
            match wall.build(w, setup, slots.len())? {
                Some(surface) => {
                    for (material, curvature) in wall.law_rows() {
                        slots.push(LawSlot {
                            material: material as u32,
                            wall: w,
                            curvature,
                        });
                    }
                    kinds.push(WallKind::Surface(planes.len()));
                    planes.push(surface);
                }
                None => {
                    // Built: its spheres are in range (`WallType::build`).
                    let at: Vec<[f64; 3]> = wall
                        .bodies()
                        .and_then(|r| setup.spheres.range(r))
                        .map(|r| r.map(|s| s.position).collect())
                        .unwrap_or_default();
                    kinds.push(WallKind::Particles {
                        torque_point: crate::pipeline::wall_loads::particle_wall_torque_point(&at),
                    });
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
        let mut b = bodies_of(setup, &setup.spheres, n, |k| k as u32);
        let materials: Vec<_> = setup.materials.iter().map(|m| m.material).collect();
        let laws = LawTable::new(setup.contact, materials, &mut b, slots);
        let friction = setup.friction.clone().map(|f| FrictionTable::new(f, &laws));

        // Neighbour geometry.
        // The radii the inlets will bring (`crate::inlets`): none without.
        let inlet_radii = crate::inlets::radii(setup);
        let free_min = b
            .radius
            .iter()
            .zip(&b.fixed)
            .filter(|(_, &f)| !f)
            .map(|(&r, _)| r)
            .chain(inlet_radii.iter().copied())
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
            .chain(inlet_radii.iter().copied())
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
        // With inlets, their spheres count as the scene's (`crate::inlets`).
        let probed = crate::inlets::with_probes(setup);
        let rayleigh_time = time_step::rayleigh_time(&probed);
        let time_step::StepChoice {
            dt,
            contact_time,
            impact_speed,
        } = time_step::choose(&probed)?;
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
        let moving = crate::pipeline::moving_walls::MovingWalls::new(
            &setup.wall_motions,
            &setup.wall_servos,
            &planes,
        );
        let gates = crate::walls::gate::Gates::new(&setup.wall_active, &planes, dt);
        let moving = crate::pipeline::moving_groups::with_groups(
            moving,
            crate::pipeline::moving_groups::drives(setup, &kinds)?,
        );
        let world = World {
            wall_contacts: WallContacts::new(n, laws.history, friction.is_some(), setup.collisions),
            tracks: setup.collisions.then(Tracks::default),
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
            moving,
            removal: None,
            gates,
            inlets: None,
            dissipation: setup
                .dissipation
                .then(|| Box::new(crate::pipeline::dissipation::Dissipation::default())),
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
            outside_box: None,
            restart_notes: Vec::new(),
        })
        .map(|mut sim| {
            // Lost: outside the box grown to hold the fixed spheres, for
            // the error and for the removal alike.
            let lost_box = outside_box(setup);
            if setup.outside == Outside::Error {
                sim.outside_box = lost_box;
            }
            let lost = setup.outside == Outside::Delete;
            if lost || !setup.outlets.is_empty() {
                let (lower, upper) = lost_box.unwrap_or((setup.domain.lower, setup.domain.upper));
                sim.world.removal = Some(Box::new(crate::removal::Removal {
                    lost,
                    lower,
                    upper,
                    outlets: setup.outlets.clone(),
                    by_outlet: vec![Default::default(); setup.outlets.len()],
                    removed: Default::default(),
                }));
            }
            sim
        })
        .and_then(|mut sim| {
            if !setup.inlets.is_empty() {
                let densities: Vec<f64> =
                    setup.materials.iter().map(|m| m.material.density).collect();
                let run_time = total_steps as f64 * dt;
                sim.world.inlets = Some(Box::new(crate::inlets::Inlets::new(
                    &setup.inlets,
                    &densities,
                    setup.spheres.len(),
                    dt,
                    run_time,
                )?));
            }
            Ok(sim)
        })
    }
}

/// The box a free sphere must not leave under `domain.outside = "error"`
/// ([`Simulation::outside_box`]): the domain grown to hold every fixed
/// sphere; `None` under `"keep"`.
fn outside_box(setup: &SceneSetup) -> Option<([f64; 3], [f64; 3])> {
    if setup.outside == Outside::Keep {
        return None;
    }
    let (mut lower, mut upper) = (setup.domain.lower, setup.domain.upper);
    for s in setup.spheres.iter().filter(|s| s.fixed) {
        for a in 0..3 {
            lower[a] = lower[a].min(s.position[a] - s.radius);
            upper[a] = upper[a].max(s.position[a] + s.radius);
        }
    }
    Some((lower, upper))
}

/// Each sphere's radius, position, velocity, material and group in range;
/// `id(q)`: the input index of `spheres[q]`, named in messages.
pub(crate) fn check_spheres(
    setup: &SceneSetup,
    spheres: impl IntoIterator<Item = crate::setup::SphereInit>,
    id: impl Fn(usize) -> usize,
) -> Result<(), SceneError> {
    let nm = setup.materials.len();
    for (q, s) in spheres.into_iter().enumerate() {
        let k = id(q);
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
            let ok = setup.walls.get(g).is_some_and(|w| w.is_particles());
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
    Ok(())
}

/// The engine's bodies of `spheres` (in that order, `count` of them:
/// the arrays' reserved length), `id(q)` the input index of `spheres[q]`.
pub(crate) fn bodies_of(
    setup: &SceneSetup,
    spheres: impl IntoIterator<Item = crate::setup::SphereInit>,
    count: usize,
    id: impl Fn(usize) -> u32,
) -> Bodies {
    let mut b = Bodies::default();
    b.reserve_exact(count);
    for (k, s) in spheres.into_iter().enumerate() {
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
        b.id.push(id(k));
        b.group.push(s.group.map_or(NO_GROUP, |g| g as u32));
    }
    b
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
