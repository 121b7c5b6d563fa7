//! The scene file (issue 12): TOML, SI, every section and key below. The
//! keys of issue 12 are kept exactly; additions are marked "addition".
//!
//! Loading: the file is parsed to a TOML table, `--set KEY=VALUE`
//! overrides are applied to it ([`apply_set`]), the table is deserialised
//! with unknown keys refused (the error names the key path, e.g.
//! `wall[1].boundary_particles.tiling`), then [`SceneFile::validate`]
//! checks every value: an error names the key, the value and the allowed
//! range. All errors are [`SceneError::Input`] (exit 2 in the CLI).

use crate::{limits, SceneError};
use dembound_physics::contact::tangential::{tangential_names, TangentialKind};
use dembound_physics::contact::{ContactModel, ContactSpec, LawParams};
use serde::{Deserialize, Serialize};
use std::path::Path;
use toml::{Table, Value};

/// A whole scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub domain: DomainSection,
    #[serde(rename = "material")]
    pub materials: Vec<MaterialSection>,
    #[serde(default)]
    pub contact: ContactSection,
    #[serde(default)]
    pub particles: Vec<ParticlesSection>,
    #[serde(default, rename = "wall")]
    pub walls: Vec<WallSection>,
    #[serde(default)]
    pub motion: MotionSection,
    pub integration: IntegrationSection,
    #[serde(default)]
    pub output: OutputSection,
    /// `[parallel]` (addition, issue 16): the MPI decomposition.
    #[serde(default, skip_serializing_if = "ParallelSection::is_default")]
    pub parallel: ParallelSection,
}

/// `[parallel]` (addition, issue 16): how `mpirun -np N dembound scene`
/// (feature `mpi`) cuts the box. Ignored by runs on one process.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelSection {
    /// Sub-domains along x, y, z; their product must be the number of
    /// ranks, and periodic axes are not split. Default: the grid of least
    /// sub-domain surface for the box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<[usize; 3]>,
    /// Move the cuts between sub-domains (at a neighbour-list rebuild)
    /// when the largest rank's owned free particles exceed this many times
    /// the mean; > 1, `inf`: never. Default 1.2
    /// (`comm::distributed::balance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rebalance_threshold: Option<f64>,
}

impl ParallelSection {
    pub fn is_default(&self) -> bool {
        self == &Self::default()
    }
}

/// `[domain]`: the box, m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainSection {
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    #[serde(default)]
    pub periodic: [bool; 3],
}

/// `[[material]]`: a named particle material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    pub name: String,
    /// kg/m³.
    pub density: f64,
    /// Pa; `inf` for a rigid material.
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    /// Coulomb friction coefficient μ of this material's surface (addition,
    /// issue 13; default `contact.friction`). A pair's μ is the geometric
    /// mean of its two surfaces'.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// Rolling friction μ_r of this material's surface (addition; default
    /// `contact.rolling_friction`; mixed like μ).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
}

/// The reserved material name of a rigid plane wall.
pub const RIGID: &str = "rigid";

/// `[contact]`: the keys of `dembound run`'s `[contact]`, checked against
/// the physics crate's registry ([`ContactSection::model`]). Unknown keys
/// are refused by [`LawParams`], which takes the rest of the table (a
/// flattened field cannot be combined with `deny_unknown_fields`).
/// Written by hand ([`Serialize`] below) as the struct it was before the
/// parameters came from the registry, so that checkpoints keep their bytes.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ContactSection {
    /// `"linear"`, `"hertz"`, `"walton-braun"`, … or `{ power = α }`
    /// (default `"hertz"`, also when `[contact]` gives other keys only).
    #[serde(default = "hertz")]
    pub law: Law,
    /// `"none"`, `"viscous"`, `"tsuji"`, `"viscoelastic"`.
    #[serde(default = "no_damping")]
    pub damping: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// `"exact"` or `"formula"`.
    #[serde(default = "exact")]
    pub calibration: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_coefficient: Option<f64>,
    #[serde(default)]
    pub attractive: bool,
    /// The normal laws' parameters by their registry keys
    /// (`contact.stiffness`: k_n of `"hooke"` in N/m, of `"hertz-kn"` in
    /// Pa; `contact.exponent`: α of `"power"`), as `dembound run`'s.
    #[serde(flatten)]
    pub params: LawParams,
    /// Coulomb friction coefficient μ ≥ 0 of every surface (issue 13):
    /// with friction (here, on a material or on a wall) the spheres rotate
    /// and each contact carries a tangential spring.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// The tangential spring: `"mindlin"` (default; Hertz–Mindlin no-slip)
    /// or `"linear"` (Cundall–Strack, k_t = 2/7 E_eff R_eff).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangential: Option<String>,
    /// Rolling friction μ_r ≥ 0 (LIGGGHTS epsd2: a constant torque
    /// μ_r R_eff |F_n| against rolling).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
}

/// A struct of the fields in declaration order, each optional one only
/// when given, the law parameters where `contact.stiffness` stood (after
/// `attractive`): what `#[derive(Serialize)]` wrote without the flattened
/// map (a flattened field makes it a map of unknown length, other bytes in
/// a checkpoint).
impl Serialize for ContactSection {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let given = |o: bool| o as usize;
        let len = 4
            + given(self.restitution.is_some())
            + given(self.damping_coefficient.is_some())
            + self.params.iter().count()
            + given(self.friction.is_some())
            + given(self.tangential.is_some())
            + given(self.rolling_friction.is_some());
        let mut s = serializer.serialize_struct("ContactSection", len)?;
        s.serialize_field("law", &self.law)?;
        s.serialize_field("damping", &self.damping)?;
        if let Some(e) = &self.restitution {
            s.serialize_field("restitution", e)?;
        }
        s.serialize_field("calibration", &self.calibration)?;
        if let Some(c) = &self.damping_coefficient {
            s.serialize_field("damping_coefficient", c)?;
        }
        s.serialize_field("attractive", &self.attractive)?;
        for (key, value) in self.params.iter() {
            s.serialize_field(key, &value)?;
        }
        if let Some(mu) = &self.friction {
            s.serialize_field("friction", mu)?;
        }
        if let Some(t) = &self.tangential {
            s.serialize_field("tangential", t)?;
        }
        if let Some(mu_r) = &self.rolling_friction {
            s.serialize_field("rolling_friction", mu_r)?;
        }
        s.end()
    }
}

fn hertz() -> Law {
    Law::Name("hertz".into())
}

fn no_damping() -> String {
    "none".into()
}

fn exact() -> String {
    "exact".into()
}

impl Default for ContactSection {
    fn default() -> Self {
        Self {
            law: hertz(),
            damping: no_damping(),
            restitution: None,
            calibration: exact(),
            damping_coefficient: None,
            attractive: false,
            params: LawParams::default(),
            friction: None,
            tangential: None,
            rolling_friction: None,
        }
    }
}

/// `contact.law`: a registry name, or `{ name = value }` (the law's first
/// parameter: `{ power = 1.25 }`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Law {
    Name(String),
    WithValue(std::collections::BTreeMap<String, f64>),
}

impl ContactSection {
    /// The contact model, through the physics crate's registry;
    /// `reference_speed` (m/s) is the impact speed of a speed-dependent
    /// calibration (the viscoelastic law's).
    pub fn model(&self, reference_speed: Option<f64>) -> Result<ContactModel, SceneError> {
        let mut spec = match &self.law {
            Law::Name(name) => ContactSpec::law(name),
            Law::WithValue(map) => {
                let mut entries = map.iter();
                match (entries.next(), entries.next()) {
                    (Some((name, value)), None) => ContactSpec::law_with_value(name, *value),
                    _ => {
                        return Err(invalid(
                            "contact.law",
                            format!("{map:?}"),
                            "a law name, or one `{ name = value }` such as { power = 1.25 }",
                        ))
                    }
                }
            }
        };
        spec.law_params
            .extend(self.params.iter().map(|(k, v)| (k.to_string(), v)));
        spec.damping = self.damping.clone();
        spec.restitution = self.restitution;
        spec.damping_coefficient = self.damping_coefficient;
        spec.calibration = self.calibration.clone();
        spec.attractive = self.attractive;
        spec.reference_speed = reference_speed;
        // The registry names a law's parameter by its own key (`contact.
        // exponent`), as a scene may write it; or the scene wrote it
        // `law = { power = α }`.
        let key = |k: &str| -> String {
            let given = k
                .strip_prefix("contact.")
                .is_some_and(|p| self.params.get(p).is_some());
            match &self.law {
                Law::WithValue(map) if !given && !SCENE_CONTACT_KEYS.contains(&k) => map
                    .keys()
                    .next()
                    .map_or(k.to_string(), |name| format!("contact.law.{name}")),
                _ => k.to_string(),
            }
        };
        let model = ContactModel::from_spec(&spec)
            .map_err(|e| invalid(&key(&e.key), e.value, &e.allowed))?;
        model
            .validate()
            .map_err(|e| invalid(&key(&e.key), e.value, &e.allowed))?;
        let walton_braun = matches!(&self.law, Law::Name(n) if n == "walton-braun");
        check(
            !(walton_braun && self.attractive),
            "contact.attractive",
            self.attractive,
            "false for law = \"walton-braun\" (the law has no tensile branch; `dembound run` \
             refuses it likewise)",
        )?;
        Ok(model)
    }
}

/// The `[contact]` keys a registry error may name as they are.
const SCENE_CONTACT_KEYS: [&str; 6] = [
    "contact.law",
    "contact.damping",
    "contact.restitution",
    "contact.calibration",
    "contact.damping_coefficient",
    "contact.attractive",
];

/// `[[particles]]`: one group of spheres of one material, from exactly one
/// source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticlesSection {
    /// A LAMMPS data file (`atom_style sphere`), relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lammps_data: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lattice: Option<LatticeSource>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random: Option<RandomSource>,
    /// A CSV file `x,y,z,radius[,vx,vy,vz]`, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub csv: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spheres: Option<Vec<InlineSphere>>,
    pub material: String,
    /// `lammps_data` only: the material of each LAMMPS atom type (`"2" =
    /// "glass"`); types not listed take `material`. Every atom's density
    /// must equal its material's (the engine's mass comes from the
    /// material), else the scene is refused naming the atom.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub types: Option<std::collections::BTreeMap<String, String>>,
    /// Boundary particles: infinite mass, never move.
    #[serde(default)]
    pub fixed: bool,
}

/// `lattice = { … }` (addition: the keys).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSource {
    /// Spheres along x, along y, and layers.
    pub counts: [usize; 3],
    /// Cell along x, y and the layer spacing, m.
    pub spacing: [f64; 3],
    /// Centre of the first sphere, m.
    pub origin: [f64; 3],
    /// m.
    pub radius: f64,
    /// Odd layers shifted by half a cell in x and y.
    #[serde(default = "yes")]
    pub stagger: bool,
    /// m/s, every sphere.
    #[serde(default)]
    pub velocity: [f64; 3],
}

fn yes() -> bool {
    true
}

/// `random = { … }` (addition: the keys).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomSource {
    pub count: usize,
    /// m: one radius, or `[min, max]` for radii uniform in the range.
    pub radius: RadiusSpec,
    /// Region corners, m.
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    #[serde(default)]
    pub seed: u64,
    /// m/s, every sphere.
    #[serde(default)]
    pub velocity: [f64; 3],
    #[serde(default = "default_attempts")]
    pub max_attempts: u64,
}

fn default_attempts() -> u64 {
    crate::sources::random::DEFAULT_MAX_ATTEMPTS
}

/// A radius or a range of radii, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum RadiusSpec {
    One(f64),
    Range([f64; 2]),
}

impl RadiusSpec {
    pub fn range(&self) -> [f64; 2] {
        match *self {
            RadiusSpec::One(r) => [r, r],
            RadiusSpec::Range(r) => r,
        }
    }
}

/// One sphere of `spheres = [ … ]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InlineSphere {
    pub position: [f64; 3],
    pub radius: f64,
    #[serde(default)]
    pub velocity: [f64; 3],
}

/// `[[wall]]`: a plane, a cylinder or a wall of boundary particles.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSection {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<PlaneWall>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub boundary_particles: Option<BoundaryParticlesWall>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cylinder: Option<CylinderWall>,
    /// A plane's or cylinder's material (or `"rigid"`); for boundary particles the
    /// particle material that r and ζ refer to.
    pub material: String,
    /// The wall's own μ (addition, issue 13; default its material's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// The wall's own μ_r (addition; default its material's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolling_friction: Option<f64>,
}

/// `plane = { point, normal }`: the normal points into the domain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneWall {
    pub point: [f64; 3],
    pub normal: [f64; 3],
}

/// `cylinder = { point, axis, radius, inside, length }`: a tube of radius
/// `radius` (m) about the axis through `point` (m) along `axis`; the
/// spheres are inside it (`inside = true`, the default) or outside a post
/// (`false`); `length` (m): a tube closed by flat discs at
/// point ± length/2 · axis (omitted: infinite, no caps).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderWall {
    pub point: [f64; 3],
    pub axis: [f64; 3],
    pub radius: f64,
    #[serde(default = "default_inside")]
    pub inside: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
}

fn default_inside() -> bool {
    true
}

/// `boundary_particles = { … }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryParticlesWall {
    pub point: [f64; 3],
    pub normal: [f64; 3],
    /// r = R_b/R_ref.
    pub radius_ratio: f64,
    /// ζ = E_b/E of the named material; `inf` for rigid boundary spheres.
    pub modulus_ratio: f64,
    #[serde(default)]
    pub tiling: TilingName,
    /// Centre distance of neighbouring boundary spheres, m (addition;
    /// default 2 R_b, touching).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// R_ref, m (addition; default: the largest radius of the mobile
    /// particles of the named material).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_radius: Option<f64>,
}

/// `tiling`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TilingName {
    #[default]
    Square,
    Hexagonal,
}

/// `[motion]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionSection {
    /// m/s².
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
}

fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

impl Default for MotionSection {
    fn default() -> Self {
        Self {
            gravity: default_gravity(),
        }
    }
}

/// `[integration]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegrationSection {
    #[serde(default)]
    pub scheme: Scheme,
    /// Δt, s (or `eta`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Δt = η × the smallest pair contact-time estimate (addition).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<f64>,
    /// Impact speed for the contact-time estimate, m/s (addition; default
    /// the fastest of √(2 |g| H), H the domain's extent along g, and the
    /// fastest initial particle speed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impact_speed: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<u64>,
    /// s (addition; or `steps`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
    /// Verlet-list skin, m (addition; default the engine's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skin: Option<f64>,
}

/// `integration.scheme`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scheme {
    #[default]
    Verlet,
    Gear5,
}

/// `[output]`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// One row per completed contact (JSON and `collisions.csv`).
    #[serde(default)]
    pub collisions: bool,
    /// Steps between VTK snapshots (addition; default: 20 intervals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every: Option<u64>,
    /// Steps between time-series rows (addition; default: 1000 intervals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub series_every: Option<u64>,
}

/// Most steps a scene may ask for (a typo guard, 10¹²).
pub const MAX_STEPS: u64 = 1_000_000_000_000;

fn invalid(key: &str, value: impl std::fmt::Display, allowed: &str) -> SceneError {
    SceneError::input(format!(
        "invalid value for `{key}`: {value} (allowed: {allowed})"
    ))
}

fn check(
    ok: bool,
    key: &str,
    value: impl std::fmt::Display,
    allowed: &str,
) -> Result<(), SceneError> {
    if ok {
        Ok(())
    } else {
        Err(invalid(key, value, allowed))
    }
}

fn positive(key: &str, x: f64, unit: &str) -> Result<(), SceneError> {
    check(
        x > 0.0 && x.is_finite(),
        key,
        x,
        &format!("finite and > 0, in {unit}"),
    )
}

fn finite3(key: &str, v: [f64; 3], unit: &str) -> Result<(), SceneError> {
    check(
        v.iter().all(|x| x.is_finite()),
        key,
        format!("{v:?}"),
        &format!("three finite numbers, in {unit}"),
    )
}

/// `x` in `range` (both ends included), in `unit`; the ranges are
/// [`crate::limits`]'s.
fn ranged(key: &str, x: f64, range: (f64, f64), unit: &str) -> Result<(), SceneError> {
    check(
        limits::within(x, range),
        key,
        limits::show(x),
        &limits::describe(range, unit),
    )
}

/// A velocity of at most [`limits::MAX_SPEED`].
fn speed(key: &str, v: [f64; 3]) -> Result<(), SceneError> {
    finite3(key, v, "m/s")?;
    let s = limits::norm(v);
    check(
        s <= limits::MAX_SPEED,
        key,
        format!("{v:?} (|v| = {} m/s)", limits::show(s)),
        &format!("|v| ≤ {} m/s", limits::show(limits::MAX_SPEED)),
    )
}

fn nonzero3(key: &str, v: [f64; 3]) -> Result<(), SceneError> {
    check(
        v.iter().all(|x| x.is_finite()) && v.iter().any(|x| *x != 0.0),
        key,
        format!("{v:?}"),
        "a finite non-zero vector",
    )
}

impl SceneFile {
    /// Checks every value; the first error names the key, value and range.
    pub fn validate(&self) -> Result<(), SceneError> {
        let d = &self.domain;
        finite3("domain.lower", d.lower, "m")?;
        finite3("domain.upper", d.upper, "m")?;
        for k in 0..3 {
            check(
                d.upper[k] > d.lower[k],
                "domain.upper",
                format!("{:?}", d.upper),
                &format!("each coordinate > domain.lower's ({:?}), m", d.lower),
            )?;
        }
        check(
            !self.materials.is_empty(),
            "material",
            "none",
            "at least one [[material]]",
        )?;
        for (i, m) in self.materials.iter().enumerate() {
            let key = |k: &str| format!("material[{i}].{k}");
            check(
                !m.name.is_empty() && m.name != RIGID,
                &key("name"),
                format!("{:?}", m.name),
                "a non-empty name other than \"rigid\" (reserved for rigid plane walls)",
            )?;
            check(
                !self.materials[..i].iter().any(|o| o.name == m.name),
                &key("name"),
                format!("{:?}", m.name),
                "a name not used by an earlier [[material]]",
            )?;
            ranged(&key("density"), m.density, limits::DENSITY, "kg/m³")?;
            check(
                limits::within(m.youngs_modulus, limits::YOUNGS_MODULUS)
                    || m.youngs_modulus == f64::INFINITY,
                &key("youngs_modulus"),
                limits::show(m.youngs_modulus),
                &format!(
                    "{}, or inf (rigid)",
                    limits::describe(limits::YOUNGS_MODULUS, "Pa")
                ),
            )?;
            check(
                m.poisson_ratio > limits::POISSON_RATIO.0
                    && m.poisson_ratio < limits::POISSON_RATIO.1,
                &key("poisson_ratio"),
                m.poisson_ratio,
                &format!(
                    "{} < ν < {} (both ends excluded)",
                    limits::POISSON_RATIO.0,
                    limits::POISSON_RATIO.1
                ),
            )?;
        }
        self.validate_contact()?;
        check(
            !self.particles.is_empty(),
            "particles",
            "none",
            "at least one [[particles]] group",
        )?;
        for (i, p) in self.particles.iter().enumerate() {
            self.validate_particles(i, p)?;
        }
        for (i, w) in self.walls.iter().enumerate() {
            self.validate_wall(i, w)?;
        }
        finite3("motion.gravity", self.motion.gravity, "m/s²")?;
        let g = limits::norm(self.motion.gravity);
        check(
            g == 0.0 || limits::within(g, limits::GRAVITY),
            "motion.gravity",
            format!("{:?} (|g| = {} m/s²)", self.motion.gravity, limits::show(g)),
            &format!("|g| = 0 or {}", limits::describe(limits::GRAVITY, "m/s²")),
        )?;
        self.validate_integration()?;
        let o = &self.output;
        if let Some(every) = o.every {
            check(every >= 1, "output.every", every, "≥ 1 step")?;
        }
        if let Some(every) = o.series_every {
            check(every >= 1, "output.series_every", every, "≥ 1 step")?;
        }
        if let Some(g) = self.parallel.grid {
            check(
                g.iter().all(|&k| (1..=1 << 20).contains(&k)),
                "parallel.grid",
                format!("{g:?}"),
                "three sub-domain counts, each ≥ 1 (their product: the number of MPI ranks)",
            )?;
        }
        if let Some(t) = self.parallel.rebalance_threshold {
            check(
                t > 1.0,
                "parallel.rebalance_threshold",
                t,
                "> 1 (largest over mean of the ranks' free particles; inf: never re-balance)",
            )?;
        }
        Ok(())
    }

    fn material_known(&self, name: &str) -> bool {
        self.materials.iter().any(|m| m.name == name)
    }

    fn material_names(&self) -> String {
        self.materials
            .iter()
            .map(|m| format!("\"{}\"", m.name))
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn validate_contact(&self) -> Result<(), SceneError> {
        // The impact speed matters only to the viscoelastic calibration,
        // solved again at resolution with the scene's own speed.
        self.contact.model(Some(1.0))?;
        self.validate_friction()
    }

    /// The friction keys (issue 13): each coefficient finite and ≥ 0, the
    /// tangential model a registry name (with Verlet or Gear5).
    fn validate_friction(&self) -> Result<(), SceneError> {
        let coefficient = |key: &str, v: Option<f64>, symbol: &str| -> Result<(), SceneError> {
            let range = if symbol == "μ" {
                limits::FRICTION
            } else {
                limits::ROLLING_FRICTION
            };
            match v {
                Some(x) => check(
                    limits::within(x, range),
                    key,
                    x,
                    &format!("{} ({symbol}, dimensionless)", limits::describe(range, "")),
                ),
                None => Ok(()),
            }
        };
        let c = &self.contact;
        coefficient("contact.friction", c.friction, "μ")?;
        coefficient("contact.rolling_friction", c.rolling_friction, "μ_r")?;
        if let Some(name) = &c.tangential {
            check(
                TangentialKind::from_name(name).is_some(),
                "contact.tangential",
                format!("{name:?}"),
                &format!("one of {}", tangential_names()),
            )?;
        }
        for (i, m) in self.materials.iter().enumerate() {
            coefficient(&format!("material[{i}].friction"), m.friction, "μ")?;
            coefficient(
                &format!("material[{i}].rolling_friction"),
                m.rolling_friction,
                "μ_r",
            )?;
        }
        for (i, w) in self.walls.iter().enumerate() {
            coefficient(&format!("wall[{i}].friction"), w.friction, "μ")?;
            coefficient(
                &format!("wall[{i}].rolling_friction"),
                w.rolling_friction,
                "μ_r",
            )?;
        }
        Ok(())
    }

    /// Whether any friction key is given (the scene then rotates its
    /// spheres and carries tangential springs).
    pub fn has_friction(&self) -> bool {
        let c = &self.contact;
        c.friction.is_some()
            || c.tangential.is_some()
            || c.rolling_friction.is_some()
            || self
                .materials
                .iter()
                .any(|m| m.friction.is_some() || m.rolling_friction.is_some())
            || self
                .walls
                .iter()
                .any(|w| w.friction.is_some() || w.rolling_friction.is_some())
    }

    fn validate_particles(&self, i: usize, p: &ParticlesSection) -> Result<(), SceneError> {
        let key = format!("particles[{i}]");
        let sources = [
            p.lammps_data.is_some(),
            p.lattice.is_some(),
            p.random.is_some(),
            p.csv.is_some(),
            p.spheres.is_some(),
        ];
        check(
            sources.iter().filter(|s| **s).count() == 1,
            &key,
            format!("{} sources", sources.iter().filter(|s| **s).count()),
            "exactly one of lammps_data, lattice, random, csv, spheres",
        )?;
        let rigid_fixed = p.material == RIGID && p.fixed;
        check(
            self.material_known(&p.material) || rigid_fixed,
            &format!("{key}.material"),
            format!("{:?}", p.material),
            &format!(
                "a [[material]] name ({}), or \"rigid\" with fixed = true",
                self.material_names()
            ),
        )?;
        let radius_range = crate::setup_checks::radius_range(p.fixed);
        if let Some(l) = &p.lattice {
            speed(&format!("{key}.lattice.velocity"), l.velocity)?;
            ranged(
                &format!("{key}.lattice.radius"),
                l.radius,
                radius_range,
                "m",
            )?;
        }
        if let Some(r) = &p.random {
            speed(&format!("{key}.random.velocity"), r.velocity)?;
            for x in r.radius.range() {
                ranged(&format!("{key}.random.radius"), x, radius_range, "m")?;
            }
        }
        if let Some(types) = &p.types {
            check(
                p.lammps_data.is_some(),
                &format!("{key}.types"),
                "a table",
                "only with lammps_data (atom type → material)",
            )?;
            for (t, name) in types {
                check(
                    t.parse::<u32>().is_ok_and(|t| t >= 1),
                    &format!("{key}.types"),
                    format!("{t:?}"),
                    "atom types as whole numbers ≥ 1 (\"1\", \"2\", …)",
                )?;
                check(
                    self.material_known(name) || (name == RIGID && p.fixed),
                    &format!("{key}.types.{t}"),
                    format!("{name:?}"),
                    &format!(
                        "a [[material]] name ({}), or \"rigid\" with fixed = true",
                        self.material_names()
                    ),
                )?;
            }
        }
        if let Some(spheres) = &p.spheres {
            check(
                !spheres.is_empty(),
                &format!("{key}.spheres"),
                "[]",
                "at least one sphere",
            )?;
            for (j, s) in spheres.iter().enumerate() {
                let k = format!("{key}.spheres[{j}]");
                finite3(&format!("{k}.position"), s.position, "m")?;
                ranged(&format!("{k}.radius"), s.radius, radius_range, "m")?;
                speed(&format!("{k}.velocity"), s.velocity)?;
            }
        }
        for (name, path) in [("lammps_data", &p.lammps_data), ("csv", &p.csv)] {
            if let Some(path) = path {
                check(
                    !path.is_empty(),
                    &format!("{key}.{name}"),
                    "\"\"",
                    "a file path",
                )?;
            }
        }
        Ok(())
    }

    fn validate_wall(&self, i: usize, w: &WallSection) -> Result<(), SceneError> {
        let key = format!("wall[{i}]");
        let given: Vec<&str> = [
            ("plane", w.plane.is_some()),
            ("cylinder", w.cylinder.is_some()),
            ("boundary_particles", w.boundary_particles.is_some()),
        ]
        .iter()
        .filter(|x| x.1)
        .map(|x| x.0)
        .collect();
        check(
            given.len() == 1,
            &key,
            if given.is_empty() {
                "neither".to_string()
            } else {
                given.join(" and ")
            },
            "exactly one of plane, cylinder, boundary_particles",
        )?;
        if let Some(c) = &w.cylinder {
            let k = |s: &str| format!("{key}.cylinder.{s}");
            finite3(&k("point"), c.point, "m")?;
            nonzero3(&k("axis"), c.axis)?;
            positive(&k("radius"), c.radius, "m")?;
            if let Some(l) = c.length {
                positive(&k("length"), l, "m")?;
                check(
                    c.inside,
                    &k("length"),
                    l,
                    "none for a post (inside = false): a finite post has rims, which this wall \
                     does not model; omit length (an infinite post)",
                )?;
            }
            let len = limits::norm(c.axis);
            for a in 0..3 {
                if !self.domain.periodic[a] {
                    continue;
                }
                let along = (0..3).all(|b| b == a || c.axis[b] == 0.0);
                check(
                    along && c.length.is_none(),
                    &k("axis"),
                    format!(
                        "{:?}{}",
                        c.axis,
                        c.length
                            .map_or(String::new(), |l| format!(" with length = {l}"))
                    ),
                    &format!(
                        "along every periodic axis and infinite (`domain.periodic` = {:?}: an \
                         axis along {} only, no length): a tube that crosses a periodic face \
                         at an angle, or ends, is not invariant under the period's \
                         translation, and a sphere re-entering through the face would land \
                         in the wall; make the axis not periodic or turn the cylinder \
                         (|axis| = {})",
                        self.domain.periodic,
                        ["x", "y", "z"][a],
                        limits::show(len)
                    ),
                )?;
            }
            check(
                self.material_known(&w.material) || w.material == RIGID,
                &format!("{key}.material"),
                format!("{:?}", w.material),
                &format!(
                    "a [[material]] name ({}) or \"rigid\"",
                    self.material_names()
                ),
            )?;
        }
        if let Some(p) = &w.plane {
            finite3(&format!("{key}.plane.point"), p.point, "m")?;
            nonzero3(&format!("{key}.plane.normal"), p.normal)?;
            check(
                self.material_known(&w.material) || w.material == RIGID,
                &format!("{key}.material"),
                format!("{:?}", w.material),
                &format!(
                    "a [[material]] name ({}) or \"rigid\"",
                    self.material_names()
                ),
            )?;
        }
        if let Some(b) = &w.boundary_particles {
            let k = |s: &str| format!("{key}.boundary_particles.{s}");
            finite3(&k("point"), b.point, "m")?;
            nonzero3(&k("normal"), b.normal)?;
            check(
                limits::within(b.radius_ratio, limits::RADIUS_RATIO),
                &k("radius_ratio"),
                limits::show(b.radius_ratio),
                &format!(
                    "{} (dimensionless; above, the gap's rounding spoils the contact: use a \
                     plane, r = inf)",
                    limits::describe(limits::RADIUS_RATIO, "")
                ),
            )?;
            check(
                limits::within(b.modulus_ratio, limits::MODULUS_RATIO)
                    || b.modulus_ratio == f64::INFINITY,
                &k("modulus_ratio"),
                limits::show(b.modulus_ratio),
                &format!(
                    "{}, or inf (rigid boundary spheres)",
                    limits::describe(limits::MODULUS_RATIO, "")
                ),
            )?;
            for a in 0..3 {
                check(
                    !self.domain.periodic[a] || b.normal[a] == 0.0,
                    &k("normal"),
                    format!("{:?}", b.normal),
                    &format!(
                        "a normal perpendicular to every periodic axis (`domain.periodic` = {:?}: \
                         component {a} must be 0); a wall bounds the domain along its normal, \
                         which a periodic axis does not have: make the axis not periodic or \
                         turn the wall",
                        self.domain.periodic
                    ),
                )?;
            }
            if let Some(s) = b.spacing {
                positive(&k("spacing"), s, "m")?;
            }
            if let Some(r) = b.reference_radius {
                ranged(&k("reference_radius"), r, limits::RADIUS, "m")?;
            }
            check(
                self.material_known(&w.material),
                &format!("{key}.material"),
                format!("{:?}", w.material),
                &format!(
                    "a [[material]] name ({}), the material r and ζ refer to",
                    self.material_names()
                ),
            )?;
        }
        Ok(())
    }

    fn validate_integration(&self) -> Result<(), SceneError> {
        let n = &self.integration;
        match (n.dt, n.eta) {
            (Some(dt), None) => positive("integration.dt", dt, "s")?,
            (None, Some(eta)) => {
                check(eta > 0.0 && eta <= 1.0, "integration.eta", eta, "0 < η ≤ 1")?
            }
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "integration.dt",
                    "given with integration.eta",
                    "one of dt and eta",
                ))
            }
            (None, None) => return Err(invalid("integration.dt", "missing", "give dt (s) or eta")),
        }
        if let Some(v) = n.impact_speed {
            positive("integration.impact_speed", v, "m/s")?;
        }
        match (n.steps, n.duration) {
            (Some(s), None) => check(
                (1..=MAX_STEPS).contains(&s),
                "integration.steps",
                s,
                &format!("1 ≤ steps ≤ {MAX_STEPS}"),
            )?,
            (None, Some(t)) => positive("integration.duration", t, "s")?,
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "integration.steps",
                    "given with integration.duration",
                    "one of steps and duration",
                ))
            }
            (None, None) => {
                return Err(invalid(
                    "integration.steps",
                    "missing",
                    "give steps or duration (s)",
                ))
            }
        }
        if let Some(s) = n.skin {
            positive("integration.skin", s, "m")?;
        }
        Ok(())
    }
}

/// Reads a `--set` value: TOML if it parses, else the bare word as a string
/// (as `dembound run --set` does).
pub fn parse_value(raw: &str) -> Value {
    let raw = raw.trim();
    match toml::from_str::<Table>(&format!("value = {raw}")) {
        Ok(mut t) if t.len() == 1 => t.remove("value").unwrap_or(Value::String(raw.into())),
        _ => Value::String(raw.into()),
    }
}

/// The top-level keys of a scene file.
const SECTIONS: [&str; 9] = [
    "domain",
    "material",
    "contact",
    "particles",
    "wall",
    "motion",
    "integration",
    "output",
    "parallel",
];

/// The sections that are one table (a `--set` may create them).
const TABLE_SECTIONS: [&str; 6] = [
    "domain",
    "contact",
    "motion",
    "integration",
    "output",
    "parallel",
];

/// Keys of which only one may be given: setting one drops the other.
const EXCLUSIVE: [(&str, &str); 2] = [("dt", "eta"), ("steps", "duration")];

/// Applies one `--set KEY=VALUE` to the scene table. KEY is a dotted path;
/// an array of tables is indexed by a number: `wall.1.material=rigid` or
/// `wall[1].material=rigid`. Setting `integration.dt` drops
/// `integration.eta` (and the reverse), `steps` drops `duration`.
pub fn apply_set(table: &mut Table, arg: &str) -> Result<(), SceneError> {
    let malformed = |why: &str| {
        SceneError::input(format!(
            "malformed --set `{arg}`: {why} (expected KEY=VALUE, e.g. --set integration.steps=1000 \
             or --set wall.0.material=rigid)"
        ))
    };
    let (name, raw) = arg.split_once('=').ok_or_else(|| malformed("no `=`"))?;
    let name = name.trim().replace('[', ".").replace(']', "");
    let path: Vec<&str> = name.split('.').map(str::trim).collect();
    if path.len() < 2 || path.iter().any(|p| p.is_empty()) {
        return Err(malformed("KEY must be SECTION.KEY, with no empty part"));
    }
    let (last, parents) = path.split_last().ok_or_else(|| malformed("no key"))?;
    if !table.contains_key(parents[0]) {
        if !TABLE_SECTIONS.contains(&parents[0]) {
            return Err(SceneError::input(format!(
                "--set `{arg}`: unknown section `{}`; the sections are {}",
                parents[0],
                SECTIONS.map(|s| format!("`{s}`")).join(", ")
            )));
        }
        table.insert(parents[0].to_string(), Value::Table(Table::new()));
    }
    let mut here: &mut Value = table
        .get_mut(parents[0])
        .ok_or_else(|| malformed("unknown section"))?;
    for depth in 1..=parents.len() {
        let so_far = parents[..depth].join(".");
        // A value where a table is wanted is replaced (as `run --set`
        // does: `contact.law.power=1.25` over `law = "hertz"`).
        if !matches!(here, Value::Array(_) | Value::Table(_)) {
            *here = Value::Table(Table::new());
        }
        let Some(part) = parents.get(depth) else {
            break;
        };
        here = match here {
            Value::Array(items) => {
                let len = items.len();
                let index: usize = part.parse().map_err(|_| {
                    malformed(&format!(
                        "`{so_far}` is a list: index it by a number 0..{len}"
                    ))
                })?;
                items.get_mut(index).ok_or_else(|| {
                    SceneError::input(format!(
                        "--set `{arg}`: `{so_far}` has {len} entries, no index {index}"
                    ))
                })?
            }
            Value::Table(t) => t
                .entry(part.to_string())
                .or_insert_with(|| Value::Table(Table::new())),
            _ => return Err(malformed(&format!("`{so_far}` is a value, not a table"))),
        };
    }
    let target = match here {
        Value::Table(target) => target,
        Value::Array(items) => {
            // The last part indexes the list: replace that entry.
            let len = items.len();
            let index: usize = last.parse().map_err(|_| {
                malformed(&format!(
                    "`{}` is a list: index it by a number 0..{len}",
                    parents.join(".")
                ))
            })?;
            let entry = items.get_mut(index).ok_or_else(|| {
                SceneError::input(format!(
                    "--set `{arg}`: `{}` has {len} entries, no index {index}",
                    parents.join(".")
                ))
            })?;
            *entry = parse_value(raw);
            return Ok(());
        }
        _ => return Err(malformed(&format!("`{}` is a value", parents.join(".")))),
    };
    target.insert(last.to_string(), parse_value(raw));
    if parents.len() == 1 && parents[0] == "integration" {
        for (a, b) in EXCLUSIVE {
            if *last == a {
                target.remove(b);
            } else if *last == b {
                target.remove(a);
            }
        }
    }
    Ok(())
}

/// Parses a scene file's text (`name` is named in errors), applies the
/// `--set` overrides and validates. Paths inside stay as written (relative
/// to the scene file's directory).
pub fn load(text: &str, name: &str, sets: &[String]) -> Result<SceneFile, SceneError> {
    let mut table: Table = toml::from_str(text)
        .map_err(|e| SceneError::input(format!("cannot parse scene file `{name}`: {e}")))?;
    for arg in sets {
        apply_set(&mut table, arg)?;
    }
    from_table(table, name)
}

/// Reads a scene file from disk; see [`load`].
pub fn read(path: &Path, sets: &[String]) -> Result<SceneFile, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::io(path, e))?;
    load(&text, &path.display().to_string(), sets)
}

/// Deserialises and validates a scene table.
pub fn from_table(table: Table, name: &str) -> Result<SceneFile, SceneError> {
    let scene: SceneFile = serde_path_to_error::deserialize(Value::Table(table)).map_err(|e| {
        let mut path = e.path().to_string();
        let inner = e.inner().to_string();
        let mut inner = inner.trim_end();
        // A `[contact]` key that is neither the section's nor a law
        // parameter is refused by the flattened `LawParams`, whose error
        // names the key: the path gets it.
        if let Some(rest) = inner.strip_prefix("invalid value for law parameter `") {
            if let Some((key, message)) = rest.split_once("`: ") {
                path = format!("{path}.{key}");
                inner = message.lines().next().unwrap_or(message);
            }
        } else if let Some(rest) = inner.strip_prefix("unknown field `") {
            if let Some((key, _)) = rest.split_once('`') {
                if !path.ends_with(&format!(".{key}")) && path != key {
                    path = format!("{path}.{key}");
                }
            }
        }
        if inner.starts_with("unknown field") {
            SceneError::input(format!(
                "in scene file `{name}`: unknown key `{path}`: {inner}"
            ))
        } else if inner.starts_with("missing field") {
            SceneError::input(format!("in scene file `{name}`: `{path}`: {inner}"))
        } else {
            SceneError::input(format!(
                "in scene file `{name}`: invalid value for `{path}`: {inner}"
            ))
        }
    })?;
    scene
        .validate()
        .map_err(|e| SceneError::input(format!("in scene file `{name}`: {e}")))?;
    Ok(scene)
}

#[cfg(test)]
mod tests;
