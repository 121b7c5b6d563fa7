//! `[[wall]]`: a plane, a cylinder or a wall of boundary particles, and
//! its checks.

use super::checks::{check, finite3, nonzero3, positive, ranged};
use super::{SceneError, SceneFile, RIGID};
use crate::limits;
use serde::{Deserialize, Serialize};

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

impl SceneFile {
    pub(super) fn validate_wall(&self, i: usize, w: &WallSection) -> Result<(), SceneError> {
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
}
