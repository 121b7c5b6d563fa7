//! The paper's question in a many-particle setting (issue 13, `dembound
//! wall-study`): how far a wall of boundary particles (radius ratio r,
//! modulus ratio ζ, tiling) behaves like a plane of the particles' own
//! material, measured on single impacts at random points of the tiling and
//! on a bed poured and settled on it. No files here: the CLI writes the
//! CSV, figures and report from [`FloorResult`].

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_physics::material::Material;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

use crate::setup::{
    BoundaryParticles, DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, SceneSetup,
    SphereInit, TimeStep, WallSetup,
};
use crate::sources::tiling::{Extent, Pattern, Tiling};
use crate::{SceneError, Simulation};

pub mod chute;
pub mod part;
pub mod part_bed;
pub mod part_fill;
pub mod pour;
pub mod recommend;
pub use chute::{Chute, ChuteConfig, SlipFit};
pub use pour::Pour;
pub use recommend::{recommend, Tolerances};

/// A floor under study.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Floor {
    /// A plane of the particles' own material (r = ∞, ζ = 1): the reference.
    Plane,
    /// A rigid plane (r = ∞, ζ = ∞).
    Rigid,
    /// Boundary particles of R_b = r R and E_b = ζ E, touching, tiled.
    Particles {
        radius_ratio: f64,
        modulus_ratio: f64,
        pattern: Pattern,
    },
}

impl Floor {
    /// `plane`, `rigid`, `r=100 zeta=100 square`.
    pub fn label(&self) -> String {
        match *self {
            Floor::Plane => "plane".into(),
            Floor::Rigid => "rigid plane".into(),
            Floor::Particles {
                radius_ratio,
                modulus_ratio,
                pattern,
            } => format!(
                "r={radius_ratio} zeta={modulus_ratio} {}",
                match pattern {
                    Pattern::Square => "square",
                    Pattern::Hexagonal => "hexagonal",
                }
            ),
        }
    }
}

impl Floor {
    /// The radius of the largest sphere that fits through the hole between
    /// touching boundary spheres, in particle radii R: (√2 − 1) r for the
    /// square tiling (the hole between four spheres), (2/√3 − 1) r for the
    /// hexagonal one (between three). `None` for planes.
    pub fn gap_radius(&self) -> Option<f64> {
        match *self {
            Floor::Particles {
                radius_ratio,
                pattern,
                ..
            } => Some(radius_ratio * Self::gap_factor(pattern)),
            _ => None,
        }
    }

    fn gap_factor(pattern: Pattern) -> f64 {
        match pattern {
            Pattern::Square => 2f64.sqrt() - 1.0,
            Pattern::Hexagonal => 2.0 / 3f64.sqrt() - 1.0,
        }
    }

    /// The largest radius ratio whose touching spheres hold a particle:
    /// 1/(√2 − 1) = 2.414 (square), 1/(2/√3 − 1) = 6.464 (hexagonal).
    pub fn wall_limit(pattern: Pattern) -> f64 {
        1.0 / Self::gap_factor(pattern)
    }

    /// Why this floor is not a wall (a particle passes between its
    /// touching boundary spheres), or `None` when it is one.
    pub fn not_a_wall(&self) -> Option<String> {
        let gap = self.gap_radius()?;
        let Floor::Particles { pattern, .. } = *self else {
            return None;
        };
        (gap > 1.0).then(|| {
            format!(
                "not a wall: a particle passes between the touching boundary spheres (gap radius \
                 {gap:.3} R > R; r ≤ {:.3} for this tiling)",
                Self::wall_limit(pattern)
            )
        })
    }
}

/// What the study runs.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyConfig {
    /// The particles' material.
    pub material: Material,
    /// Particle radius R, m.
    pub radius: f64,
    /// Normal restitution e of the Tsuji-damped Hertz contacts.
    pub restitution: f64,
    /// Coulomb μ and the tangential spring.
    pub friction: f64,
    pub tangential: TangentialKind,
    /// Rolling friction μ_r.
    pub rolling_friction: f64,
    /// The floors, the plane first (the reference) is added if missing.
    pub floors: Vec<Floor>,
    /// Impacts per floor and incidence angle.
    pub impacts: usize,
    /// Impact speed, m/s.
    pub speed: f64,
    /// Incidence angles from the normal, degrees.
    pub angles: Vec<f64>,
    /// Particles in the bed (0: no bed).
    pub bed_particles: usize,
    /// Δt = η × the particle–plane contact time at `speed`.
    pub eta: f64,
    /// Bed settling time after the pour, s (the pour itself, the fall
    /// time from the top of the insertion region, is added).
    pub settle_time: f64,
    pub seed: u64,
    /// μ of the floor's surface (planes and boundary particles); a pair's
    /// μ is the geometric mean of its surfaces', so the particle–floor μ
    /// is √(μ μ_floor). `None`: μ.
    pub floor_friction: Option<f64>,
    /// The chute flow over each floor (`None`: none).
    pub chute: Option<ChuteConfig>,
}

/// One single impact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Incidence angle from the normal, degrees.
    pub angle: f64,
    /// Impact point in the tiling's cell, m.
    pub point: [f64; 2],
    /// v_n'/v_n along the floor's normal.
    pub normal_restitution: f64,
    /// v_t'/v_t along the incidence direction (NaN at normal incidence).
    pub tangential_restitution: f64,
    /// Angle of the rebound from the normal, degrees.
    pub rebound_angle: f64,
    /// Horizontal rebound speed across the incidence plane / impact speed.
    pub deflection: f64,
    /// From the first contact's onset to the last one's end, s.
    pub contact_time: f64,
    /// Contacts in the impact (several in a hollow of the tiling).
    pub contacts: usize,
    /// Rebound spin magnitude, rad/s.
    pub spin: f64,
}

/// The bed on one floor, settled.
#[derive(Debug, Clone, PartialEq)]
pub struct Bed {
    pub particles: usize,
    /// Box side, m.
    pub side: f64,
    /// 95th percentile of the particle tops above the floor plane, m.
    pub height: f64,
    /// (slab centre z, m; solid fraction) from the lowest particle bottom.
    pub profile: Vec<(f64, f64)>,
    /// Mean solid fraction for 0 ≤ z ≤ 2R (the first layer).
    pub wall_packing: f64,
    /// Mean solid fraction for 4R ≤ z ≤ 8R (the bulk), when the bed is that deep.
    pub bulk_packing: f64,
    /// Floor force / box area, Pa.
    pub floor_pressure: f64,
    /// Weight / box area, Pa.
    pub weight_pressure: f64,
    /// Standard deviation of the floor force over the last fifth of the
    /// run, relative to its mean.
    pub pressure_fluctuation: f64,
    /// Normal force on each loaded boundary particle, N.
    pub boundary_forces: Vec<f64>,
    /// Translational kinetic energy at the end, J.
    pub kinetic_energy: f64,
    /// Particles whose centre ended below the boundary spheres' centres:
    /// through the gaps of a tiling whose touching spheres leave a hole
    /// wider than a particle (r > 2.414 square, 6.464 hexagonal), where
    /// the floor is not a wall. They are counted in `particles` and the
    /// weight but carried by nothing.
    pub fell_through: usize,
    /// Side view: (x, z, R) of each particle, m.
    pub spheres: Vec<(f64, f64, f64)>,
    /// (x, z, R) of the floor's boundary particles.
    pub floor_spheres: Vec<(f64, f64, f64)>,
}

/// Everything measured on one floor.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorResult {
    pub floor: Floor,
    pub impacts: Vec<Impact>,
    pub bed: Option<Bed>,
    /// The chute flow, or why it was not run.
    pub chute: Option<Result<Chute, String>>,
    /// s.
    pub dt: f64,
}

fn contact_model(e: f64) -> ContactModel {
    ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(e)),
    )
}

fn invalid(key: &str, value: impl std::fmt::Display, allowed: &str) -> SceneError {
    SceneError::invalid(key, value, allowed)
}

impl StudyConfig {
    /// Checks the numbers; an error names the option, the value and the
    /// range. The material, grain, speed and friction ranges are the
    /// scene's ([`crate::limits`]: the study builds its scenes without a
    /// scene file, so it checks them itself; before session 36 it took
    /// any positive value, and e.g. `--rolling-friction 5`, which no
    /// scene accepts, ran with a rolling spring the step does not resolve).
    pub fn validate(&self) -> Result<(), SceneError> {
        use crate::limits::{self, describe, within};
        let m = &self.material;
        let ranged = |k: &str, x: f64, range: (f64, f64), unit: &str| {
            if x.is_finite() && within(x, range) {
                Ok(())
            } else {
                Err(invalid(k, x, &describe(range, unit)))
            }
        };
        let pos = |k: &str, x: f64, unit: &str| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(invalid(k, x, &format!("finite and > 0 {unit}")))
            }
        };
        ranged("--density", m.density, limits::DENSITY, "kg/m³")?;
        ranged(
            "--youngs-modulus",
            m.youngs_modulus,
            limits::YOUNGS_MODULUS,
            "Pa",
        )?;
        if !(m.poisson_ratio > -1.0 && m.poisson_ratio < 0.5) {
            return Err(invalid("--poisson-ratio", m.poisson_ratio, "-1 < ν < 0.5"));
        }
        ranged("--radius", self.radius, limits::RADIUS, "m")?;
        if !(self.restitution > 0.0 && self.restitution <= 1.0) {
            return Err(invalid("--restitution", self.restitution, "0 < e ≤ 1"));
        }
        ranged("--friction", self.friction, limits::FRICTION, "")?;
        ranged(
            "--rolling-friction",
            self.rolling_friction,
            limits::ROLLING_FRICTION,
            "",
        )?;
        if !(self.speed.is_finite() && self.speed > 0.0 && self.speed <= limits::MAX_SPEED) {
            return Err(invalid(
                "--speed",
                self.speed,
                &format!("0 < v ≤ {} m/s", limits::show(limits::MAX_SPEED)),
            ));
        }
        for &a in &self.angles {
            if !(0.0..90.0).contains(&a) {
                return Err(invalid("--angles", a, "0 ≤ θ < 90 degrees from the normal"));
            }
        }
        if !(self.eta > 0.0 && self.eta <= 0.5) {
            return Err(invalid("--eta", self.eta, "0 < η ≤ 0.5"));
        }
        pos("--settle-time", self.settle_time, "s")?;
        for f in &self.floors {
            if let Floor::Particles {
                radius_ratio,
                modulus_ratio,
                ..
            } = *f
            {
                if !(radius_ratio.is_finite() && (0.5..=1000.0).contains(&radius_ratio)) {
                    return Err(invalid("--radius-ratios", radius_ratio, "0.5 ≤ r ≤ 1000"));
                }
                if !(modulus_ratio == f64::INFINITY || within(modulus_ratio, limits::MODULUS_RATIO))
                {
                    return Err(invalid(
                        "--modulus-ratios",
                        modulus_ratio,
                        &format!("{}, or inf", describe(limits::MODULUS_RATIO, "")),
                    ));
                }
            }
        }
        if let Some(mu) = self.floor_friction {
            ranged("--floor-friction", mu, limits::FRICTION, "")?;
        }
        if let Some(chute) = &self.chute {
            chute.validate()?;
        }
        if self.impacts > 100_000 {
            return Err(invalid("--impacts", self.impacts, "at most 100000"));
        }
        if self.bed_particles > 200_000 {
            return Err(invalid("--particles", self.bed_particles, "at most 200000"));
        }
        Ok(())
    }

    /// The friction of a scene whose floor is wall `floor` (its surface
    /// μ [`Self::floor_friction`]), with the walls `frictionless` smooth.
    fn friction_setup(
        &self,
        s: &SceneSetup,
        floor: usize,
        frictionless: &[usize],
    ) -> Option<FrictionSetup> {
        let mut w = vec![None; s.walls.len()];
        for &k in frictionless {
            w[k] = Some((0.0, 0.0));
        }
        let mut materials = Vec::new();
        if let Some(mu) = self.floor_friction {
            // A surface's own μ, or its boundary spheres' material's.
            match s.walls[floor].bodies() {
                None => w[floor] = Some((mu, self.rolling_friction)),
                Some(bodies) => {
                    let m = s.spheres.get(bodies.start).map_or(0, |b| b.material);
                    materials = vec![None; s.materials.len()];
                    materials[m] = Some((mu, self.rolling_friction));
                }
            }
        }
        Some(FrictionSetup {
            model: FrictionModel {
                tangential: self.tangential,
                friction: self.friction,
                rolling_friction: self.rolling_friction,
            },
            materials,
            walls: w,
            tangential_damping: true,
            torque_arm: Default::default(),
            spring_rotation: Default::default(),
        })
    }

    /// The particle–plane Hertz contact time at the impact speed, s.
    pub fn contact_time(&self) -> f64 {
        let m = &self.material;
        let e_eff = 4.0 / 3.0 / (2.0 * m.compliance());
        let k = e_eff * self.radius.sqrt();
        let mass = m.sphere_mass(self.radius);
        let h_max = (1.25 * mass * self.speed * self.speed / k).powf(0.4);
        dembound_physics::contact::HERTZ_CONTACT_TIME_FACTOR * h_max / self.speed
    }

    /// Δt, s.
    pub fn dt(&self) -> f64 {
        self.eta * self.contact_time()
    }
}

/// Adds `floor` (contact plane z = 0, normal +z, covering x, y in
/// [lo, hi]) to `s`; returns the wall index.
fn add_floor(
    s: &mut SceneSetup,
    floor: Floor,
    lo: [f64; 2],
    hi: [f64; 2],
    centre: [f64; 2],
    radius: f64,
    periodic: bool,
) -> Result<usize, SceneError> {
    let w = s.walls.len();
    match floor {
        Floor::Plane | Floor::Rigid => {
            let material = if floor == Floor::Plane {
                0
            } else {
                s.materials.push(NamedMaterial {
                    name: "rigid".into(),
                    material: Material::rigid(1000.0),
                });
                s.materials.len() - 1
            };
            s.walls.push(WallSetup::Plane(Plane {
                point: [centre[0], centre[1], 0.0],
                normal: [0.0, 0.0, 1.0],
                material,
            }));
        }
        Floor::Particles {
            radius_ratio,
            modulus_ratio,
            pattern,
        } => {
            let base = s.materials[0].material;
            s.materials.push(NamedMaterial {
                name: "boundary".into(),
                material: Material {
                    youngs_modulus: base.youngs_modulus * modulus_ratio,
                    ..base
                },
            });
            let material = s.materials.len() - 1;
            let rb = radius_ratio * radius;
            let tiling = Tiling {
                point: [centre[0], centre[1], 0.0],
                normal: [0.0, 0.0, 1.0],
                radius: rb,
                spacing: 2.0 * rb,
                pattern,
            };
            let extent = Extent {
                lower: [lo[0], lo[1], -2.0 * rb],
                upper: [hi[0], hi[1], 0.0],
                periodic: [periodic, periodic, false],
            };
            let made = tiling.spheres(&extent, "floor")?;
            let first = s.spheres.len();
            for b in made {
                s.spheres.push(SphereInit {
                    position: b.position,
                    velocity: [0.0; 3],
                    radius: b.radius,
                    material,
                    fixed: true,
                    group: Some(w),
                });
            }
            s.walls
                .push(WallSetup::BoundaryParticles(BoundaryParticles {
                    first_body: first,
                    count: s.spheres.len() - first,
                }));
        }
    }
    Ok(w)
}

/// The tiling's cell (period along x and y), m.
fn cell(floor: Floor, radius: f64) -> [f64; 2] {
    match floor {
        Floor::Particles {
            radius_ratio,
            pattern,
            ..
        } => {
            let s = 2.0 * radius_ratio * radius;
            match pattern {
                Pattern::Square => [s, s],
                Pattern::Hexagonal => [s, s * 3f64.sqrt()],
            }
        }
        _ => [0.0, 0.0],
    }
}

fn base_setup(c: &StudyConfig, lower: [f64; 3], upper: [f64; 3], dt: f64) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower,
            upper,
            periodic: [false; 3],
        },
        contact_model(c.restitution),
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "particle".into(),
        material: c.material,
    });
    s
}

/// `count` spheres of radius `r` (material 0, at rest) placed at random,
/// without overlap, with their centres in `lower`–`upper` (seed
/// `c.seed`), pushed onto `s`'s sphere list; `label` names the set in an
/// error (the box too small for them).
fn insert_at_rest(
    s: &mut SceneSetup,
    c: &StudyConfig,
    label: &str,
    count: usize,
    r: f64,
    lower: [f64; 3],
    upper: [f64; 3],
) -> Result<(), SceneError> {
    let inserted = crate::sources::random::RandomInsertion {
        count,
        radius: [r, r],
        lower,
        upper,
        velocity: [0.0; 3],
        seed: c.seed,
        max_attempts: 1000,
    }
    .spheres(label, &[])?;
    s.spheres.extend(inserted.iter().map(|p| SphereInit {
        position: p.position,
        velocity: [0.0; 3],
        radius: r,
        material: 0,
        fixed: false,
        group: None,
    }));
    Ok(())
}

/// One impact on `floor` at `point` (x, y in the cell) at `angle` degrees.
fn impact(
    c: &StudyConfig,
    floor: Floor,
    point: [f64; 2],
    angle: f64,
) -> Result<Impact, SceneError> {
    let r = c.radius;
    let dt = c.dt();
    let cell = cell(floor, r);
    let half = 3.0 * cell[0].max(cell[1]).max(10.0 * r);
    let lo = [point[0] - half, point[1] - half];
    let hi = [point[0] + half, point[1] + half];
    let rb = match floor {
        Floor::Particles { radius_ratio, .. } => radius_ratio * r,
        _ => r,
    };
    let mut s = base_setup(
        c,
        [lo[0], lo[1], -2.5 * rb],
        [hi[0], hi[1], 10.0 * r + 2.5 * rb],
        dt,
    );
    let floor_wall = add_floor(&mut s, floor, lo, hi, [0.0, 0.0], r, false)?;
    let th = angle.to_radians();
    let (vn, vt) = (c.speed * th.cos(), c.speed * th.sin());
    let gap = 0.05 * r;
    s.spheres.insert(
        0,
        SphereInit {
            position: [point[0], point[1], r + gap],
            velocity: [vt, 0.0, -vn],
            radius: r,
            material: 0,
            fixed: false,
            group: None,
        },
    );
    // The boundary spheres moved one place up in the input order.
    for w in &mut s.walls {
        if let WallSetup::BoundaryParticles(b) = w {
            b.first_body += 1;
        }
    }
    s.friction = c.friction_setup(&s, floor_wall, &[]);
    s.collisions = true;
    let mut sim = Simulation::new(s, 1)?;
    // Until the sphere has left every contact, moving away, and the log
    // has seen the last one end; at most 20 contact times plus the fall
    // into the deepest hollow.
    let fall = (rb + 2.0 * r) / vn.max(1e-3 * c.speed);
    let max_steps = ((20.0 * c.contact_time() + fall) / dt) as u64 + 100;
    let mut done = 0;
    while done < max_steps {
        sim.step_guarded(50)?;
        done += 50;
        let v = sim.velocities()[0];
        if v[2] > 0.0 && sim.wall_contacts() == 0 && !sim.collisions().is_empty() {
            break;
        }
    }
    let v = sim.velocities()[0];
    let w = sim.angular_velocities()[0];
    let log = sim.collisions();
    let t0 = log.iter().map(|k| k.t_start).fold(f64::INFINITY, f64::min);
    let t1 = log
        .iter()
        .map(|k| k.t_end)
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(Impact {
        angle,
        point,
        normal_restitution: v[2] / vn,
        tangential_restitution: if vt > 0.0 { v[0] / vt } else { f64::NAN },
        rebound_angle: (v[0] * v[0] + v[1] * v[1]).sqrt().atan2(v[2]).to_degrees(),
        deflection: v[1] / c.speed,
        contact_time: t1 - t0,
        contacts: log.len(),
        spin: (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt(),
    })
}

/// Solid volume of a sphere (centre z c, radius R) between z = a and b, m³.
fn slab_volume(c: f64, r: f64, a: f64, b: f64) -> f64 {
    let f = |z: f64| {
        let u = (z - c).clamp(-r, r);
        PI * (r * r * u - u * u * u / 3.0)
    };
    (f(b) - f(a)).max(0.0)
}

/// The bed on `floor`.
fn bed(c: &StudyConfig, floor: Floor) -> Result<Bed, SceneError> {
    let r = c.radius;
    let n = c.bed_particles;
    let dt = c.dt();
    // A box about 10 layers deep at random close packing.
    let side = (n as f64 * (4.0 / 3.0) * PI * r * r * r / (0.6 * 20.0 * r))
        .sqrt()
        .max(6.0 * r);
    let height = Pour::fill_height(n, r, side, side);
    let rb = match floor {
        Floor::Particles { radius_ratio, .. } => radius_ratio * r,
        _ => r,
    };
    let pour = Pour {
        count: n,
        radius: r,
        lower: [0.0, 0.0, 2.0 * r],
        upper: [side, side, 2.0 * r + height],
        sides: [[0.0, side], [0.0, side]],
        domain_lower: [0.0, 0.0, -2.5 * rb],
        domain_upper: [side, side, 2.0 * r + height + r],
        base: 0.0,
    };
    let mut s = pour.scene(c, dt)?;
    let floor_wall = add_floor(
        &mut s,
        floor,
        [0.0, 0.0],
        [side, side],
        [0.5 * side, 0.5 * side],
        r,
        false,
    )?;
    s.friction = c.friction_setup(&s, floor_wall, &[0, 1, 2, 3]);
    let mut sim = Simulation::new(s, pour.threads())?;
    // The fall from the top of the insertion region, then the settling.
    let steps = pour.settle_steps(c.settle_time, dt);
    let chunk = (steps / 200).max(1);
    let mut forces = Vec::new();
    let mut done = 0;
    while done < steps {
        let k = chunk.min(steps - done);
        sim.step_guarded(k)?;
        done += k;
        forces.push(-sim.wall_forces()[floor_wall][2]);
    }
    let tail = &forces[forces.len() * 4 / 5..];
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    let var = tail.iter().map(|f| (f - mean) * (f - mean)).sum::<f64>() / tail.len() as f64;
    let area = side * side;
    let pos = sim.positions();
    let fixed = sim.fixed();
    let radii = sim.radii();
    let all_forces = sim.forces();
    let mass = c.material.sphere_mass(r);
    let v = sim.velocities();
    let kinetic: f64 = v
        .iter()
        .zip(&fixed)
        .filter(|(_, f)| !**f)
        .map(|(v, _)| 0.5 * mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]))
        .sum();
    let free: Vec<[f64; 3]> = pos
        .iter()
        .zip(&fixed)
        .filter(|(_, f)| !**f)
        .map(|(p, _)| *p)
        .collect();
    let mut tops: Vec<f64> = free.iter().map(|p| p[2] + r).collect();
    tops.sort_by(f64::total_cmp);
    let height = tops.get((tops.len() * 95) / 100).copied().unwrap_or(0.0);
    let bottom = free.iter().map(|p| p[2] - r).fold(0.0, f64::min);
    let dz = 0.25 * r;
    let mut profile = Vec::new();
    let mut z = bottom;
    while z < (10.0 * r).min(height) {
        let v: f64 = free.iter().map(|p| slab_volume(p[2], r, z, z + dz)).sum();
        profile.push((z + 0.5 * dz, v / (area * dz)));
        z += dz;
    }
    let window = |a: f64, b: f64| {
        let v: f64 = free.iter().map(|p| slab_volume(p[2], r, a, b)).sum();
        v / (area * (b - a))
    };
    let boundary_forces: Vec<f64> = all_forces
        .iter()
        .zip(&fixed)
        .filter(|(f, fx)| **fx && f[2] != 0.0)
        .map(|(f, _)| -f[2])
        .collect();
    let spheres = free.iter().map(|p| (p[0], p[2], r)).collect();
    let floor_spheres = pos
        .iter()
        .zip(&fixed)
        .zip(&radii)
        .filter(|((p, f), _)| **f && p[1].abs() <= radii[0].max(rb) * 2.0 + side)
        .map(|((p, _), &rr)| (p[0], p[2], rr))
        .collect();
    Ok(Bed {
        particles: free.len(),
        side,
        height,
        profile,
        wall_packing: window(0.0, 2.0 * r),
        bulk_packing: if height > 8.0 * r {
            window(4.0 * r, 8.0 * r)
        } else {
            f64::NAN
        },
        floor_pressure: mean / area,
        weight_pressure: free.len() as f64 * mass * 9.81 / area,
        pressure_fluctuation: var.sqrt() / mean,
        boundary_forces,
        kinetic_energy: kinetic,
        fell_through: match floor {
            Floor::Particles { .. } => free.iter().filter(|p| p[2] < -rb).count(),
            _ => 0,
        },
        spheres,
        floor_spheres,
    })
}

/// Runs the study on every floor (the plane first), `progress` called with
/// each floor's label as it starts.
pub fn run(
    c: &StudyConfig,
    mut progress: impl FnMut(&str),
) -> Result<Vec<FloorResult>, SceneError> {
    c.validate()?;
    let mut floors = c.floors.clone();
    if !floors.contains(&Floor::Plane) {
        floors.insert(0, Floor::Plane);
    }
    let mut out = Vec::with_capacity(floors.len());
    for (k, &floor) in floors.iter().enumerate() {
        progress(&floor.label());
        let mut rng = ChaCha8Rng::seed_from_u64(c.seed.wrapping_add(k as u64));
        let cell = cell(floor, c.radius);
        let mut impacts = Vec::new();
        for &angle in &c.angles {
            for _ in 0..c.impacts {
                let point = [rng.gen::<f64>() * cell[0], rng.gen::<f64>() * cell[1]];
                impacts.push(impact(c, floor, point, angle)?);
            }
        }
        let bed = if c.bed_particles > 0 {
            Some(bed(c, floor)?)
        } else {
            None
        };
        let chute = match &c.chute {
            Some(cc) => Some(match chute::plan(c, cc, floor) {
                Ok(plan) => Ok(chute::run(c, cc, floor, &plan)?),
                Err(why) => Err(why),
            }),
            None => None,
        };
        out.push(FloorResult {
            floor,
            impacts,
            bed,
            chute,
            dt: c.dt(),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::slab_volume;
    use std::f64::consts::PI;

    #[test]
    fn slab_volumes_add_up_to_the_sphere() {
        let r = 1.0;
        let whole = 4.0 / 3.0 * PI;
        assert!((slab_volume(0.0, r, -2.0, 2.0) - whole).abs() < 1e-15);
        // Half a sphere, and a cap of height h: π h² (3R − h)/3.
        assert!((slab_volume(0.0, r, 0.0, 5.0) - whole / 2.0).abs() < 1e-15);
        let h = 0.3;
        let cap = PI * h * h * (3.0 * r - h) / 3.0;
        assert!((slab_volume(0.0, r, 1.0 - h, 1.0) - cap).abs() < 1e-15);
    }
}
