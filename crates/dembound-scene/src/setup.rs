//! The engine's input: plain data, no files, SI units. The scene file
//! reader (`io::config`) and the particle sources build a [`SceneSetup`];
//! [`crate::Simulation::new`] validates it.

use dembound_physics::contact::tangential::FrictionModel;
use dembound_physics::contact::tangential::SpringRotation;
use dembound_physics::contact::{ContactModel, TorqueArm};
use dembound_physics::material::Material;

/// A wall, one variant per wall type (`walls::registry`), and each type's
/// setup (`Plane`, `Cylinder`, `BoundaryParticles`, …).
pub use crate::walls::registry::setups::*;

/// Everything a scene needs.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSetup {
    pub domain: DomainSetup,
    /// The materials, referred to by index from spheres and plane walls.
    /// A rigid wall is a material with E = ∞ ([`Material::rigid`]).
    pub materials: Vec<NamedMaterial>,
    /// The contact model of every pair (sphere–sphere and sphere–plane).
    pub contact: ContactModel,
    /// All spheres, free and fixed, in input order (the order every
    /// per-body output uses).
    pub spheres: crate::spheres::Spheres,
    /// Walls in file order (the order of the wall forces).
    pub walls: Vec<WallSetup>,
    /// Gravitational acceleration, m/s².
    pub gravity: [f64; 3],
    pub integration: IntegrationSetup,
    pub neighbour: NeighbourSetup,
    /// Keep a collision log (one row per completed contact).
    pub collisions: bool,
    /// Sum the dissipated energy contact by contact and report the
    /// balance error (`output.dissipation`, `pipeline::dissipation`).
    pub dissipation: bool,
    /// Friction and rotation (issue 13); `None`: frictionless, no spin.
    pub friction: Option<FrictionSetup>,
    /// What a free sphere lost for good outside the box does to the run
    /// (`domain.outside`, issue 28).
    pub outside: Outside,
    /// The outlets (`[[outlet]]`, issue 28; `crate::removal`): regions that
    /// remove the free spheres whose centres enter them.
    pub outlets: Vec<crate::region::Region>,
    /// The inlets (`[[inlet]]`, issue 28; `crate::inlets`): regions that
    /// insert spheres during the run.
    pub inlets: Vec<crate::inlets::InletSetup>,
    /// The prescribed motion of each wall in file order (issue 27,
    /// `walls::motion`); missing entries or `None`: fixed. Empty when no
    /// wall moves.
    pub wall_motions: Vec<Option<crate::walls::motion::WallMotion>>,
    /// The force control of each wall in file order (issue 27,
    /// `walls::servo`); missing entries or `None`: none. Empty when no
    /// wall has a servo.
    pub wall_servos: Vec<Option<crate::walls::servo::Servo>>,
    /// The window each wall acts in, file order (issue 28, `walls::gate`);
    /// missing entries or `None`: always. Empty when no wall has one.
    pub wall_active: Vec<Option<crate::walls::gate::ActiveWindow>>,
    /// The prescribed rigid motion of groups of fixed spheres given as
    /// `[[particles]]` (issue 27, `pipeline::moving_groups`); a moving
    /// boundary-particle wall's is its entry of `wall_motions`. Empty when
    /// no group moves.
    pub group_motions: Vec<GroupMotion>,
}

/// A group of fixed spheres moving as one rigid body
/// (`pipeline::moving_groups`).
#[derive(Debug, Clone, PartialEq)]
pub struct GroupMotion {
    /// The `[[particles]]` entry that gave it (K of `particles[K]`): its
    /// key in messages and outputs.
    pub group: usize,
    /// Its spheres: input indices into [`SceneSetup::spheres`], all fixed.
    pub spheres: std::ops::Range<usize>,
    pub motion: crate::walls::motion::WallMotion,
}

/// What a free sphere lost for good along a non-periodic axis does to
/// the run (`domain.outside`, issue 28; lost: wholly outside the box grown
/// to hold the fixed spheres, moving away, gravity not bringing it back).
/// Outside the box the scene's physics no longer holds (the cell grid
/// clamps it into its edge cells, nothing stops its fall, its potential
/// energy goes on falling): by default the run stops rather than report
/// numbers of a scene that is not the one described.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Outside {
    /// Stop with an input error (exit 2) naming the sphere, the step and
    /// its position.
    #[default]
    Error,
    /// Let it go on (the run reports it nowhere).
    Keep,
    /// Remove it, counted, its mass and the energy it carries out booked
    /// (`crate::removal`).
    Delete,
}

/// Friction of a scene: the model and each surface's coefficients.
///
/// A pair's μ is the geometric mean of its two surfaces' μ
/// ([`dembound_physics::contact::tangential::mix_friction`]), likewise μ_r.
/// A sphere's surface is its material's; a plane wall's is its own if
/// given (`wall`), else its material's.
#[derive(Clone, PartialEq)]
pub struct FrictionSetup {
    /// Tangential model and the default μ and μ_r of every surface.
    pub model: FrictionModel,
    /// (μ, μ_r) of each material (index as [`SceneSetup::materials`]);
    /// missing entries or `None`: the model's.
    pub materials: Vec<Option<(f64, f64)>>,
    /// (μ, μ_r) of each wall in file order (planes; a boundary-particle
    /// wall's spheres take theirs through their own material); missing or
    /// `None`: its material's.
    pub walls: Vec<Option<(f64, f64)>>,
    /// The tangential dashpot η_t of a sticking contact
    /// (`contact.tangential_damping`, default true: η_t has the normal
    /// contact's damping ratio); false: no tangential dashpot (LIGGGHTS's
    /// `tangential_damping off`), the rolling spring's damping kept.
    pub tangential_damping: bool,
    /// The lever arm of the tangential force's torque
    /// (`contact.torque_arm`, default the radius).
    pub torque_arm: TorqueArm,
    /// How the tangential spring follows a turning normal
    /// (`contact.spring_rotation`, default rescaled to its length).
    pub spring_rotation: SpringRotation,
}

/// The derived form, with `tangential_damping` only when false,
/// `torque_arm` only when not the radius and `spring_rotation` only when
/// not the rescale: a
/// checkpoint's fingerprint holds this text (crate::fingerprint), so the
/// default keeps the bytes of the checkpoints written before the switch.
impl std::fmt::Debug for FrictionSetup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct("FrictionSetup");
        d.field("model", &self.model)
            .field("materials", &self.materials)
            .field("walls", &self.walls);
        if !self.tangential_damping {
            d.field("tangential_damping", &self.tangential_damping);
        }
        if self.torque_arm != TorqueArm::Radius {
            d.field("torque_arm", &self.torque_arm);
        }
        if self.spring_rotation != SpringRotation::Rescale {
            d.field("spring_rotation", &self.spring_rotation);
        }
        d.finish()
    }
}

impl FrictionSetup {
    /// One model for every surface.
    pub fn uniform(model: FrictionModel) -> Self {
        Self {
            model,
            materials: Vec::new(),
            walls: Vec::new(),
            tangential_damping: true,
            torque_arm: TorqueArm::Radius,
            spring_rotation: SpringRotation::Rescale,
        }
    }

    /// (μ, μ_r) of material `m`.
    pub fn of_material(&self, m: usize) -> (f64, f64) {
        self.materials
            .get(m)
            .copied()
            .flatten()
            .unwrap_or((self.model.friction, self.model.rolling_friction))
    }

    /// (μ, μ_r) of wall `w` made of material `m`.
    pub fn of_wall(&self, w: usize, m: usize) -> (f64, f64) {
        self.walls
            .get(w)
            .copied()
            .flatten()
            .unwrap_or_else(|| self.of_material(m))
    }
}

/// The box. On a periodic axis bodies leave through one face and enter
/// through the other and interact across it; on the other axes the box only
/// bounds the neighbour search grid (walls are separate, [`WallSetup`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainSetup {
    /// Lower corner, m.
    pub lower: [f64; 3],
    /// Upper corner, m.
    pub upper: [f64; 3],
    pub periodic: [bool; 3],
}

/// A material with the name the scene file gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedMaterial {
    pub name: String,
    pub material: Material,
}

/// One sphere's initial state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereInit {
    /// Centre, m.
    pub position: [f64; 3],
    /// m/s (ignored for fixed spheres, which never move).
    pub velocity: [f64; 3],
    /// m, > 0.
    pub radius: f64,
    /// Index into [`SceneSetup::materials`].
    pub material: usize,
    /// A fixed sphere (boundary particle) has infinite mass and never moves;
    /// two fixed spheres never interact.
    pub fixed: bool,
    /// The wall (index into [`SceneSetup::walls`]) this sphere belongs to,
    /// for a boundary-particle wall.
    pub group: Option<usize>,
}

/// Integration scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Velocity Verlet (kick–drift–kick), 2nd order.
    Verlet,
    /// The paper's 5th-order Gear predictor–corrector (eqs 18–19), one
    /// Nordsieck vector per body.
    Gear5,
}

/// How the time step is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeStep {
    /// Δt given, s.
    Fixed(f64),
    /// Δt = η × the smallest pair contact-time estimate at `impact_speed`
    /// (m/s), over every kind of pair the scene holds.
    Eta { eta: f64, impact_speed: f64 },
}

/// How long to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunLength {
    Steps(u64),
    /// Simulated time, s; the step count is ⌈duration/Δt⌉.
    Duration(f64),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegrationSetup {
    pub scheme: Scheme,
    pub time_step: TimeStep,
    pub length: RunLength,
}

/// Neighbour search settings.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NeighbourSetup {
    /// Verlet skin, m: pairs closer than R_i + R_j + skin are listed, and the
    /// lists are rebuilt when a body has moved more than skin/2. `None`:
    /// 0.2 × the smallest radius of a free sphere (0.1 mm for R = 0.5 mm,
    /// LAMMPS's `neighbor 0.0001 bin` of the lattice-drop deck).
    pub skin: Option<f64>,
}

impl SceneSetup {
    /// An empty scene in `domain` with one contact model, Verlet, no
    /// gravity; fill in materials, spheres and walls.
    pub fn new(
        domain: DomainSetup,
        contact: ContactModel,
        time_step: TimeStep,
        length: RunLength,
    ) -> Self {
        Self {
            domain,
            materials: Vec::new(),
            contact,
            spheres: crate::spheres::Spheres::new(),
            walls: Vec::new(),
            gravity: [0.0; 3],
            integration: IntegrationSetup {
                scheme: Scheme::Verlet,
                time_step,
                length,
            },
            neighbour: NeighbourSetup::default(),
            collisions: false,
            dissipation: false,
            friction: None,
            outside: Outside::Error,
            outlets: Vec::new(),
            inlets: Vec::new(),
            wall_motions: Vec::new(),
            wall_servos: Vec::new(),
            wall_active: Vec::new(),
            group_motions: Vec::new(),
        }
    }
}
