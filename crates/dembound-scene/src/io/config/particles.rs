//! `[[particles]]`: a group of spheres from one source (LAMMPS data,
//! lattice, random, CSV or inline spheres), and its checks.

use super::checks::{check, finite3, ranged, speed};
use super::{SceneError, SceneFile, RIGID};
use serde::{Deserialize, Serialize};

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
    /// Boundary particles: infinite mass, never move (unless `motion`).
    #[serde(default)]
    pub fixed: bool,
    /// Prescribed rigid motion of a fixed group (issue 27; the table of
    /// `[[wall]] motion`, `walls::motion`): the group moves as one rigid
    /// body (`pipeline::moving_groups`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<crate::walls::motion::MotionConfig>,
    /// Sinusoidal translation of a fixed group (`[[wall]] oscillation`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub oscillation: Option<crate::walls::motion::OscillationConfig>,
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

impl SceneFile {
    pub(super) fn validate_particles(
        &self,
        i: usize,
        p: &ParticlesSection,
    ) -> Result<(), SceneError> {
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
        if p.motion.is_some() || p.oscillation.is_some() {
            let moved = if p.motion.is_some() {
                "motion"
            } else {
                "oscillation"
            };
            check(
                p.fixed,
                &format!("{key}.{moved}"),
                "given for a group of free spheres (fixed = false)",
                "only with fixed = true: a group of fixed spheres moves as one rigid body; \
                 free spheres move by their forces",
            )?;
            if let Some(a) = self.domain.periodic.iter().position(|&p| p) {
                return Err(super::checks::invalid(
                    &format!("{key}.{moved}"),
                    format!("given in a domain periodic along axis {a}"),
                    "a moving group of fixed spheres in a domain with no periodic axis \
                     (its spheres are not carried across periodic faces)",
                ));
            }
        }
        crate::walls::motion::validate(&key, p.motion.as_ref(), p.oscillation.as_ref())?;
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
}
