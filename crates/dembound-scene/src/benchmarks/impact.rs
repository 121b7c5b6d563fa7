//! One impact run by the engine: a sphere on a plane or two spheres, from
//! given velocities and spins, until the contact has ended and the bodies
//! separate. What the benchmarks measure of it: the velocities and spins
//! after, and the collision log's duration, largest overlap and force.

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::ContactModel;
use dembound_physics::material::Material;

use crate::setup::{
    DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, SceneSetup, SphereInit, TimeStep,
    WallSetup,
};
use crate::{SceneError, Simulation};

/// A sphere of an impact: material, radius, velocity and spin at the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    pub material: Material,
    pub radius: f64,
    pub velocity: [f64; 3],
    pub spin: [f64; 3],
}

/// What is against the first ball: the plane z = 0 (normal +z) of a
/// material, or a second ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    Plane(Material),
    Ball(Ball),
}

/// An impact: the first ball starts just above the plane z = 0 (a gap of
/// 3 steps of its normal approach), or touching-minus-gap the second ball
/// along x (the second at the origin, the first on −x).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    pub ball: Ball,
    pub target: Target,
    pub contact: ContactModel,
    /// Coulomb μ with the Mindlin spring (`None`: frictionless, no spin).
    pub friction: Option<f64>,
    /// Δt, s.
    pub dt: f64,
    /// The relative normal approach speed, m/s (for the gap and the run length).
    pub approach_speed: f64,
    /// The expected contact duration, s (bounds the run).
    pub contact_time: f64,
}

/// The state after the impact.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Velocity and spin of the first ball, and of the second (zero for a plane).
    pub velocity: [[f64; 3]; 2],
    pub spin: [[f64; 3]; 2],
    /// From the collision log: duration (s), largest overlap (m), largest
    /// normal force (N).
    pub duration: f64,
    pub max_overlap: f64,
    pub max_force: f64,
    /// Contacts in the log (1 for one clean impact).
    pub contacts: usize,
    pub steps: u64,
    /// (overlap m, normal force N) at every step in contact, when asked for.
    pub history: Vec<(f64, f64)>,
}

impl Impact {
    fn setup(&self) -> SceneSetup {
        let r = self.ball.radius;
        let gap = 3.0 * self.dt * self.approach_speed;
        let (reach, first) = match self.target {
            Target::Plane(_) => (4.0 * r, [0.0, 0.0, r + gap]),
            Target::Ball(b) => {
                let d = r + b.radius + gap;
                (4.0 * (r + b.radius), [-d, 0.0, 0.0])
            }
        };
        let mut s = SceneSetup::new(
            DomainSetup {
                lower: [-reach, -reach, -reach],
                upper: [reach, reach, reach],
                periodic: [false; 3],
            },
            self.contact,
            TimeStep::Fixed(self.dt),
            RunLength::Steps(0),
        );
        s.materials.push(NamedMaterial {
            name: "ball".into(),
            material: self.ball.material,
        });
        s.spheres.push(SphereInit {
            position: first,
            velocity: self.ball.velocity,
            radius: r,
            material: 0,
            fixed: false,
            group: None,
        });
        match self.target {
            Target::Plane(m) => {
                s.materials.push(NamedMaterial {
                    name: "plane".into(),
                    material: m,
                });
                s.walls.push(WallSetup::Plane(Plane {
                    point: [0.0; 3],
                    normal: [0.0, 0.0, 1.0],
                    material: 1,
                }));
            }
            Target::Ball(b) => {
                s.materials.push(NamedMaterial {
                    name: "target".into(),
                    material: b.material,
                });
                s.spheres.push(SphereInit {
                    position: [0.0; 3],
                    velocity: b.velocity,
                    radius: b.radius,
                    material: 1,
                    fixed: false,
                    group: None,
                });
            }
        }
        s.friction = self.friction.map(|mu| {
            FrictionSetup::uniform(FrictionModel {
                tangential: TangentialKind::Mindlin,
                friction: mu,
                rolling_friction: 0.0,
            })
        });
        s.collisions = true;
        s
    }

    /// Runs the impact until the log holds the contact and the bodies
    /// move apart (at most 10 contact times past the approach).
    pub fn run(&self) -> Result<Outcome, SceneError> {
        self.run_recording(false)
    }

    /// [`Self::run`], with the force–overlap history of a frictionless
    /// impact when `record` (one step at a time: the force on the first
    /// ball is then the contact force).
    pub fn run_recording(&self, record: bool) -> Result<Outcome, SceneError> {
        let mut sim = Simulation::new(self.setup(), 1)?;
        if self.friction.is_some() {
            sim.set_angular_velocity(0, self.ball.spin);
            if let Target::Ball(b) = self.target {
                sim.set_angular_velocity(1, b.spin);
            }
        }
        let max_steps = (10.0 * self.contact_time / self.dt) as u64 + 100;
        let chunk = if record {
            1
        } else {
            ((0.02 * self.contact_time / self.dt) as u64).max(1)
        };
        let reach = self.ball.radius
            + match self.target {
                Target::Ball(b) => b.radius,
                Target::Plane(_) => 0.0,
            };
        let mut history = Vec::new();
        let mut done = 0;
        loop {
            sim.step_checked(chunk)?;
            done += chunk;
            if record {
                let p = sim.positions();
                let overlap = match self.target {
                    Target::Plane(_) => reach - p[0][2],
                    Target::Ball(_) => {
                        reach
                            - (0..3)
                                .map(|k| (p[1][k] - p[0][k]).powi(2))
                                .sum::<f64>()
                                .sqrt()
                    }
                };
                if overlap > 0.0 {
                    let f = sim.forces()[0];
                    history.push((overlap, (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()));
                }
            }
            let ended = !sim.collisions().is_empty();
            let apart = match self.target {
                Target::Plane(_) => sim.wall_contacts() == 0 && sim.velocities()[0][2] > 0.0,
                Target::Ball(_) => {
                    let v = sim.velocities();
                    let p = sim.positions();
                    let rel: f64 = (0..3)
                        .map(|k| (p[1][k] - p[0][k]) * (v[1][k] - v[0][k]))
                        .sum();
                    let dist: f64 = (0..3)
                        .map(|k| (p[1][k] - p[0][k]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    rel > 0.0 && dist > reach
                }
            };
            if ended && apart {
                break;
            }
            if done > max_steps {
                return Err(SceneError::input(format!(
                    "benchmark impact: no separation after {done} steps (Δt = {:e} s)",
                    self.dt
                )));
            }
        }
        let v = sim.velocities();
        let w = sim.angular_velocities();
        let log = sim.collisions();
        let second = |x: &Vec<[f64; 3]>| x.get(1).copied().unwrap_or([0.0; 3]);
        Ok(Outcome {
            velocity: [v[0], second(&v)],
            spin: [w[0], second(&w)],
            duration: log.iter().map(|c| c.duration).sum(),
            max_overlap: log.iter().map(|c| c.max_overlap).fold(0.0, f64::max),
            max_force: log.iter().map(|c| c.max_normal_force).fold(0.0, f64::max),
            contacts: log.len(),
            steps: done,
            history,
        })
    }
}
