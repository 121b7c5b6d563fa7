//! The scene file (issue 12): TOML, SI, every section and key below. The
//! keys of issue 12 are kept exactly; additions are marked "addition".
//!
//! Loading: the file is parsed to a TOML table, `--set KEY=VALUE`
//! overrides are applied to it ([`apply_set`]), the table is deserialised
//! with unknown keys refused (the error names the key path, e.g.
//! `wall[1].boundary_particles.tiling`), then [`SceneFile::validate`]
//! checks every value: an error names the key, the value and the allowed
//! range. All errors are [`SceneError::Input`] (exit 2 in the CLI).

pub(crate) mod checks;
mod contact;
mod inlets;
mod integration;
mod outlets;
mod overrides;
mod particles;
mod walls;

pub use crate::region::Region;
pub use contact::{ContactSection, Law};
pub use inlets::{InletSection, RateSection, SizeSection};
pub use integration::{
    IntegrationSection, MotionSection, OutputSection, ParallelSection, Scheme, MAX_STEPS,
};
pub use outlets::OutletSection;
pub use overrides::{apply_set, parse_value};
pub use particles::{InlineSphere, LatticeSource, ParticlesSection, RadiusSpec, RandomSource};
pub(crate) use walls::surface_material;
pub use walls::{BoundaryParticlesConfig, CylinderConfig, PlaneConfig, TilingName, WallSection};

use crate::{limits, SceneError};
use checks::{check, finite3, ranged};
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
    /// `[[outlet]]` (addition, issue 28): regions that remove the free
    /// spheres entering them.
    #[serde(default, rename = "outlet", skip_serializing_if = "Vec::is_empty")]
    pub outlets: Vec<OutletSection>,
    /// `[[inlet]]` (addition, issue 28): regions that insert spheres
    /// during the run (`crate::inlets`).
    #[serde(default, rename = "inlet", skip_serializing_if = "Vec::is_empty")]
    pub inlets: Vec<InletSection>,
}

/// `[domain]`: the box, m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainSection {
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    #[serde(default)]
    pub periodic: [bool; 3],
    /// What a free sphere lost for good outside the box does (addition,
    /// issue 28): `"error"` (default), `"keep"` or `"delete"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outside: Option<OutsideName>,
}

/// `domain.outside`: see [`crate::setup::Outside`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutsideName {
    /// Stop with exit 2 naming the sphere, the step and its position.
    Error,
    /// Let it go on.
    Keep,
    /// Remove it, counted and reported (`crate::removal`).
    Delete,
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

/// Whether a scene must name its spheres: a scene file run by the command
/// line must (`[[particles]]`); a scene built from code (Python's
/// `Scene.from_dict`) may get them later (`add_particles`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Particles {
    Required,
    Later,
}

impl SceneFile {
    /// Checks every value; the first error names the key, value and range.
    pub fn validate(&self) -> Result<(), SceneError> {
        self.validate_with(Particles::Required)
    }

    /// [`SceneFile::validate`], with `[[particles]]` optional under
    /// [`Particles::Later`].
    pub fn validate_with(&self, particles: Particles) -> Result<(), SceneError> {
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
            particles == Particles::Later || !self.particles.is_empty() || !self.inlets.is_empty(),
            "particles",
            "none",
            "at least one [[particles]] group (or an [[inlet]])",
        )?;
        for (i, p) in self.particles.iter().enumerate() {
            self.validate_particles(i, p)?;
        }
        for (i, w) in self.walls.iter().enumerate() {
            self.validate_wall(i, w)?;
        }
        self.validate_outlets()?;
        self.validate_inlets()?;
        self.validate_motion()?;
        self.validate_integration()?;
        self.validate_output()?;
        self.validate_parallel()?;
        Ok(())
    }

    pub(crate) fn material_known(&self, name: &str) -> bool {
        self.materials.iter().any(|m| m.name == name)
    }

    pub(crate) fn material_names(&self) -> String {
        self.materials
            .iter()
            .map(|m| format!("\"{}\"", m.name))
            .collect::<Vec<_>>()
            .join(", ")
    }
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
    from_table_with(table, name, Particles::Required)
}

/// [`from_table`], with `[[particles]]` optional under [`Particles::Later`].
pub fn from_table_with(
    table: Table,
    name: &str,
    particles: Particles,
) -> Result<SceneFile, SceneError> {
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
            // At the top level the path is "." (serde_path_to_error's
            // root): say "the file" instead.
            let place = if path == "." {
                "the file".to_string()
            } else {
                format!("`{path}`")
            };
            SceneError::input(format!("in scene file `{name}`: {place}: {inner}"))
        } else {
            SceneError::input(format!(
                "in scene file `{name}`: invalid value for `{path}`: {inner}"
            ))
        }
    })?;
    scene
        .validate_with(particles)
        .map_err(|e| SceneError::input(format!("in scene file `{name}`: {e}")))?;
    Ok(scene)
}

#[cfg(test)]
mod tests;
