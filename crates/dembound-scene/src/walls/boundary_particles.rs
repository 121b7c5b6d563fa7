//! The wall of boundary particles (the paper's wall): fixed spheres of
//! radius R_b = r R_ref and modulus E_b = ζ E tiling a plane
//! (`sources::tiling`). Its spheres live in the body store and meet the
//! free spheres as sphere pairs; this type owns its `[[wall]]` entry, its
//! resolution (the tiling, appended to the input order, and the scaled
//! material), the check of its setup against the spheres, and its
//! descriptions (`walls::registry`).
//!
//! Two forms: the plane (`point`, `normal`: `sources::tiling`) and the
//! mesh (`mesh = "part.stl"` and its placement: [`mesh_form`], the
//! covering of `sources::mesh_tiling`). Only the spheres' source differs:
//! both go through the same resolution (material, R_ref, the fixed
//! spheres of group = the wall).

mod mesh_form;

use std::ops::Range;

use super::registry::{WallKey, WallType};
use super::{Curvature, Surface};
use crate::error::SceneError;
use crate::io::config::checks::{check, finite3, nonzero3, positive, ranged};
use crate::io::config::SceneFile;
use crate::io::resolve::WallResolve;
use crate::limits::{self, describe};
use crate::setup::{NamedMaterial, SceneSetup, SphereInit};
use crate::sources::tiling::{Pattern, Tiling};
use dembound_physics::material::Material;
use serde::{Deserialize, Serialize};

/// `boundary_particles = { … }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryParticlesConfig {
    /// A point of the plane (plane form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<[f64; 3]>,
    /// Into the domain (plane form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 3]>,
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
    /// The mesh form: an STL or OBJ file (relative to the scene file),
    /// placed as a `mesh` wall's (`scale`, `translate`, `rotate`), the
    /// spheres behind its triangles' normals (`flip`: in front).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<std::path::PathBuf>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translate: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<crate::walls::mesh::RotateConfig>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flip: Option<bool>,
}

/// `tiling`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TilingName {
    #[default]
    Square,
    Hexagonal,
}

/// A wall of boundary particles: spheres `first_body..first_body+count`
/// of `SceneSetup::spheres`, all fixed, with `group` = this wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryParticles {
    pub first_body: usize,
    pub count: usize,
}

impl WallType for BoundaryParticles {
    const KEY: &'static str = "boundary_particles";
    const PARTICLES: bool = true;
    type Config = BoundaryParticlesConfig;

    fn validate(
        b: &BoundaryParticlesConfig,
        file: &SceneFile,
        key: &str,
        material: &str,
    ) -> Result<(), SceneError> {
        let k = |s: &str| format!("{key}.boundary_particles.{s}");
        let plane = mesh_form::validate_form(b, file, key)?;
        if let Some((point, normal)) = plane {
            finite3(&k("point"), point, "m")?;
            nonzero3(&k("normal"), normal)?;
        }
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
            let Some((_, normal)) = plane else { break };
            check(
                !file.domain.periodic[a] || normal[a] == 0.0,
                &k("normal"),
                format!("{normal:?}"),
                &format!(
                    "a normal perpendicular to every periodic axis (`domain.periodic` = {:?}: \
                     component {a} must be 0); a wall bounds the domain along its normal, \
                     which a periodic axis does not have: make the axis not periodic or \
                     turn the wall",
                    file.domain.periodic
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
            file.material_known(material),
            &format!("{key}.material"),
            format!("{material:?}"),
            &format!(
                "a [[material]] name ({}), the material r and ζ refer to",
                file.material_names()
            ),
        )
    }

    /// The tiling's spheres appended to the input order, of a material
    /// `"NAME:boundary(r=…, zeta=…)"` with E scaled by ζ; R_ref defaults
    /// to the largest free sphere of the named material made so far.
    fn resolve(
        b: &mut BoundaryParticlesConfig,
        w: usize,
        material: &str,
        cx: &mut WallResolve<'_>,
    ) -> Result<Self, SceneError> {
        let key = format!("wall[{w}]");
        let base = cx
            .materials
            .iter()
            .position(|m| m.name == material)
            .ok_or_else(|| SceneError::input(format!("`{key}.material`: unknown")))?;
        let reference = match b.reference_radius {
            Some(r) => r,
            None => cx
                .spheres
                .iter()
                .filter(|s| !s.fixed && s.material == base)
                .map(|s| s.radius)
                .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))))
                .ok_or_else(|| {
                    SceneError::input(format!(
                        "`{key}.boundary_particles.reference_radius` is needed: no free particle is made \
                         of \"{}\" to take R_ref from (give R_ref in m, > 0)",
                        material
                    ))
                })?,
        };
        let radius = b.radius_ratio * reference;
        let spacing = b.spacing.unwrap_or(2.0 * radius);
        let pattern = match b.tiling {
            TilingName::Square => Pattern::Square,
            TilingName::Hexagonal => Pattern::Hexagonal,
        };
        let made = match (b.point, b.normal) {
            (Some(point), Some(normal)) if b.mesh.is_none() => Tiling {
                point,
                normal,
                radius,
                spacing,
                pattern,
            }
            .spheres(&cx.extent, &key)?,
            _ => mesh_form::spheres(b, &key, radius, spacing, pattern, cx)?,
        };
        let m = &cx.materials[base].material;
        cx.materials.push(NamedMaterial {
            name: format!(
                "{}:boundary(r={}, zeta={})",
                material, b.radius_ratio, b.modulus_ratio
            ),
            material: Material {
                youngs_modulus: m.youngs_modulus * b.modulus_ratio,
                ..*m
            },
        });
        let scaled = cx.materials.len() - 1;
        cx.boundary_materials.push((scaled, base, w));
        let first = cx.spheres.len();
        cx.spheres.extend(made.into_iter().map(|s| SphereInit {
            position: s.position,
            velocity: [0.0; 3],
            radius: s.radius,
            material: scaled,
            fixed: true,
            group: Some(w),
        }));
        Ok(BoundaryParticles {
            first_body: first,
            count: cx.spheres.len() - first,
        })
    }

    fn material(&self) -> Option<usize> {
        None
    }

    fn law_rows(&self) -> Vec<(usize, Curvature)> {
        Vec::new()
    }

    /// Its spheres exist, fixed and of this wall.
    fn build(
        &self,
        w: usize,
        setup: &SceneSetup,
        _slot: usize,
    ) -> Result<Option<Surface>, SceneError> {
        let BoundaryParticles { first_body, count } = *self;
        let spheres = first_body
            .checked_add(count)
            .and_then(|end| setup.spheres.range(first_body..end));
        let Some(spheres) = spheres else {
            return Err(SceneError::invalid(
                format!("walls[{w}].count"),
                count,
                format!(
                    "spheres {first_body}.. within the {} spheres",
                    setup.spheres.len()
                ),
            ));
        };
        for (k, s) in (first_body..).zip(spheres) {
            if !s.fixed || s.group != Some(w) {
                return Err(SceneError::invalid(
                    format!("spheres[{k}].group"),
                    format!("{:?}", s.group),
                    format!(
                        "Some({w}) and fixed: sphere {k} belongs to boundary-particle wall {w}"
                    ),
                ));
            }
        }
        Ok(None)
    }

    fn bodies(&self) -> Option<Range<usize>> {
        Some(self.first_body..self.first_body + self.count)
    }

    fn summary(&self) -> String {
        format!("{} boundary particles", self.count)
    }

    fn export_note(&self) -> Option<String> {
        None // a frozen group of its spheres
    }

    fn keys() -> Vec<WallKey> {
        let row = |name, unit, default, allowed: String, meaning| {
            WallKey::new(Self::KEY, name, unit, default, allowed, meaning)
        };
        vec![
            row(
                "point",
                "m",
                "—",
                "three finite numbers (plane form)".into(),
                "a tiling site",
            ),
            row(
                "normal",
                "",
                "—",
                "finite, non-zero (any length); 0 along every periodic axis (plane form)".into(),
                "into the domain",
            ),
            row(
                "radius_ratio",
                "",
                "—",
                describe(limits::RADIUS_RATIO, ""),
                "r = R_b/R_ref",
            ),
            row(
                "modulus_ratio",
                "",
                "—",
                format!("{}, or inf", describe(limits::MODULUS_RATIO, "")),
                "ζ = E_b/E",
            ),
            row(
                "tiling",
                "",
                "\"square\"",
                "\"square\", \"hexagonal\"".into(),
                "site pattern",
            ),
            row(
                "spacing",
                "m",
                "2 R_b",
                "finite, > 0".into(),
                "site distance",
            ),
            row(
                "reference_radius",
                "m",
                "largest free radius",
                describe(limits::RADIUS, ""),
                "R_ref",
            ),
        ]
        .into_iter()
        .chain(mesh_form::keys())
        .collect()
    }
}
