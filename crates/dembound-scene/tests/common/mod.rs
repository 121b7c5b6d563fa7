//! Scenes shared by the integration tests.
#![allow(dead_code)]

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_physics::material::Material;
use dembound_scene::setup::{
    DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, Scheme, SphereInit, TimeStep,
    WallSetup,
};
use dembound_scene::SceneSetup;

pub fn grain(youngs_modulus: f64) -> Material {
    Material {
        density: 1000.0,
        youngs_modulus,
        poisson_ratio: 0.3,
    }
}

/// A small deterministic generator (SplitMix64) for test scenes.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    pub fn symmetric(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
}

/// The lattice-drop layout (make_lattice.py): `side`² spheres per layer,
/// `layers` layers, odd layers offset by half a cell; six plane walls of
/// the grains' own material. R = 0.5 mm, E = 1e7 Pa, Hertz, g along −z.
pub fn lattice_drop(side: usize, layers: usize, dt: f64, steps: u64) -> SceneSetup {
    let (a, c, z0, r) = (1.2e-3, 0.54e-3, 0.505e-3, 0.5e-3);
    let l = side as f64 * a + 0.5 * a;
    let upper = [l, l, 0.03];
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [0.0; 3],
            upper,
            periodic: [false; 3],
        },
        ContactModel::elastic(NormalLaw::Hertz),
        TimeStep::Fixed(dt),
        RunLength::Steps(steps),
    );
    s.gravity = [0.0, 0.0, -9.81];
    s.neighbour.skin = Some(1.0e-4);
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: grain(1.0e7),
    });
    for k in 0..layers {
        let shift = 0.5 * a * (k % 2) as f64;
        for j in 0..side {
            for i in 0..side {
                s.spheres.push(SphereInit {
                    position: [
                        0.5 * a + i as f64 * a + shift,
                        0.5 * a + j as f64 * a + shift,
                        z0 + k as f64 * c,
                    ],
                    velocity: [0.0; 3],
                    radius: r,
                    material: 0,
                    fixed: false,
                    group: None,
                });
            }
        }
    }
    for axis in 0..3 {
        let mut n = [0.0; 3];
        n[axis] = 1.0;
        s.walls.push(WallSetup::Plane(Plane {
            point: [0.0; 3],
            normal: n,
            material: 0,
        }));
        n[axis] = -1.0;
        s.walls.push(WallSetup::Plane(Plane {
            point: upper,
            normal: n,
            material: 0,
        }));
    }
    s
}

/// A frictionless elastic Hertz gas in a fully periodic cube: `per_side`³
/// spheres of R = 0.5 mm on a simple cubic lattice of spacing 2.5 mm,
/// random velocities of up to `speed` per component (zero total momentum
/// not enforced), no gravity, Δt = η × the contact-time estimate at
/// `speed`.
pub fn periodic_gas(per_side: usize, eta: f64, speed: f64, seed: u64) -> SceneSetup {
    let spacing = 2.5e-3;
    let l = per_side as f64 * spacing;
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [0.0; 3],
            upper: [l; 3],
            periodic: [true; 3],
        },
        ContactModel::elastic(NormalLaw::Hertz),
        TimeStep::Eta {
            eta,
            impact_speed: speed,
        },
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: grain(1.0e7),
    });
    let mut rng = Rng(seed);
    for k in 0..per_side {
        for j in 0..per_side {
            for i in 0..per_side {
                let v = [
                    rng.symmetric() * speed,
                    rng.symmetric() * speed,
                    rng.symmetric() * speed,
                ];
                s.spheres.push(SphereInit {
                    position: [
                        (i as f64 + 0.5) * spacing,
                        (j as f64 + 0.5) * spacing,
                        (k as f64 + 0.5) * spacing,
                    ],
                    velocity: v,
                    radius: 0.5e-3,
                    material: 0,
                    fixed: false,
                    group: None,
                });
            }
        }
    }
    s
}

/// One sphere of `radius` and `material` at `position` with `velocity`
/// over the plane z = 0 of the same material, normal law `contact`,
/// friction (kind, μ, μ_r) on everything (`None`: no friction at all),
/// `scheme`, Δt given (the friction tests' single-contact scene).
#[allow(clippy::too_many_arguments)]
pub fn sphere_on_plane(
    radius: f64,
    material: Material,
    position: [f64; 3],
    velocity: [f64; 3],
    contact: ContactModel,
    friction: Option<(TangentialKind, f64, f64)>,
    scheme: Scheme,
    dt: f64,
) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-1.0, -1.0, -0.01],
            upper: [1.0, 1.0, 1.0],
            periodic: [false; 3],
        },
        contact,
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.integration.scheme = scheme;
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material,
    });
    s.spheres.push(SphereInit {
        position,
        velocity,
        radius,
        material: 0,
        fixed: false,
        group: None,
    });
    s.walls.push(WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    }));
    s.friction = friction.map(|(tangential, mu, roll)| {
        FrictionSetup::uniform(FrictionModel {
            tangential,
            friction: mu,
            rolling_friction: roll,
        })
    });
    s
}

/// The frictional bed of `friction_bed.rs`: `lattice_drop(side, layers)`
/// with E = 1e8 Pa, Hertz + Tsuji e = 0.3, Mindlin μ = 0.5 and μ_r = 0.05
/// on the grains and the floor (wall 4), the side walls and the lid
/// frictionless (with friction they would hold part of the weight).
pub fn frictional_bed(side: usize, layers: usize, dt: f64) -> SceneSetup {
    let mut s = lattice_drop(side, layers, dt, 0);
    s.materials[0].material.youngs_modulus = 1.0e8;
    s.contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.3)),
    );
    let mut walls = vec![Some((0.0, 0.0)); 6];
    walls[4] = None;
    s.friction = Some(FrictionSetup {
        model: FrictionModel {
            tangential: TangentialKind::Mindlin,
            friction: 0.5,
            rolling_friction: 0.05,
        },
        materials: Vec::new(),
        walls,
        tangential_damping: true,
        torque_arm: Default::default(),
        spring_rotation: Default::default(),
    });
    s
}

/// `lattice_drop(side, layers, dt)` with the frictional bed's Mindlin
/// μ = 0.5 and rolling friction 0.05 (grains and floor), the collision log
/// on; elastic Hertz, E = 1e7 Pa, Verlet.
pub fn frictional_lattice(side: usize, layers: usize, dt: f64) -> SceneSetup {
    let mut setup = lattice_drop(side, layers, dt, 0);
    setup.friction = frictional_bed(2, 2, dt).friction;
    setup.collisions = true;
    setup
}

/// `lattice_drop(side, layers)` under Gear5 at Δt = 2 µs with the
/// frictional bed's materials (E = 1e8 Pa) and friction, Hertz + Tsuji
/// e = 0.6, the collision log on, every sphere thrown with a random
/// velocity of at most `speed` m/s per component (`Rng(7)`).
pub fn gear5_frictional_lattice(side: usize, layers: usize, speed: f64) -> SceneSetup {
    let mut setup = lattice_drop(side, layers, 2.0e-6, 0);
    let bed = frictional_bed(2, 2, 2.0e-6);
    setup.materials = bed.materials;
    setup.friction = bed.friction;
    setup.contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.6)),
    );
    setup.integration.scheme = Scheme::Gear5;
    setup.collisions = true;
    let mut rng = Rng(7);
    for sphere in &mut setup.spheres {
        sphere.velocity = std::array::from_fn(|_| speed * rng.symmetric());
    }
    setup
}

/// Everything a run reports, printed (Debug prints every f64 exactly):
/// positions, velocities, spins, forces, torques, the observables and
/// the collision log.
pub fn state(sim: &dembound_scene::Simulation) -> String {
    format!(
        "{:?} {:?} {:?} {:?} {:?} {:?} {:?}",
        sim.positions(),
        sim.velocities(),
        sim.angular_velocities(),
        sim.forces(),
        sim.torques(),
        sim.observe(),
        sim.collisions(),
    )
}
