//! The triangle-mesh wall as a registry row (`walls::registry`): the
//! `[[wall]] mesh = { file, scale, translate, rotate }` entry and its
//! checks, the setup ([`Mesh`]: the loaded, cleaned and placed geometry),
//! the placement checks, its one law row, the engine record
//! ([`MeshWall`]), the summary and the exporter's refusal.
//!
//! Loading happens at resolution: the file is read relative to the scene
//! file's directory (its absolute path is written back into the entry, so
//! the resolved scene runs from anywhere), placed (scale, rotation, then
//! translation: [`Transform`]), cleaned and grouped into flat patches; the
//! cleaning's counts become warnings. Refused, naming the key and the
//! file: a missing, unreadable or malformed file, a mesh with no triangle
//! left, a mesh whose bounding box does not meet the domain.
//!
//! The setup's `Debug` (which the checkpoint fingerprint prints) names the
//! file, the counts and a SHA-256 digest of the placed, cleaned geometry,
//! never the triangles themselves: a restart with another mesh, or the
//! same file placed elsewhere, is refused by its digest.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::{MeshGeometry, MeshOptions, MeshWall, Transform};
use crate::error::SceneError;
use crate::io::config::checks::{finite3 as finite3_key, nonzero3, positive};
use crate::io::config::SceneFile;
use crate::io::resolve::WallResolve;
use crate::limits::{self, metres};
use crate::setup::SceneSetup;
use crate::setup_checks::{percent, Label};
use crate::walls::registry::{show3, WallKey, WallType};
use crate::walls::{Curvature, Surface};

/// `rotate = { axis, angle }`: a right-handed rotation about `axis` (any
/// non-zero length) through the origin, `angle` in degrees.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateConfig {
    pub axis: [f64; 3],
    pub angle: f64,
}

/// `mesh = { file, scale, translate, rotate }`: the triangles of `file`
/// (STL, binary or ASCII, or OBJ; relative to the scene file) placed by
/// x' = R (s x) + t.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshConfig {
    pub file: PathBuf,
    #[serde(default = "unit_scale")]
    pub scale: f64,
    #[serde(default)]
    pub translate: [f64; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<RotateConfig>,
}

fn unit_scale() -> f64 {
    1.0
}

impl MeshConfig {
    /// The placement the entry gives.
    pub fn transform(&self) -> Transform {
        let (axis, angle_degrees) = match &self.rotate {
            Some(r) => (r.axis, r.angle),
            None => ([0.0, 0.0, 1.0], 0.0),
        };
        Transform {
            scale: self.scale,
            translate: self.translate,
            axis,
            angle_degrees,
        }
    }
}

/// A fixed triangle-mesh wall of `material`: the geometry of `file`
/// placed by `transform`, cleaned, in flat patches (`walls::mesh`).
#[derive(Clone)]
pub struct Mesh {
    /// The file it was read from (absolute when resolved from a scene
    /// file).
    pub file: PathBuf,
    pub transform: Transform,
    /// The placed geometry, shared by the engine's record and its threads.
    pub geometry: Arc<MeshGeometry>,
    /// SHA-256 of the placed, cleaned geometry (hex).
    pub digest: String,
    pub material: usize,
}

impl Mesh {
    /// Reads `file` and places it by `transform`.
    pub fn load(file: &Path, transform: Transform, material: usize) -> Result<Self, SceneError> {
        let geometry = MeshGeometry::load(file, &transform, &MeshOptions::default())
            .map_err(|e| SceneError::input(e.to_string()))?;
        Ok(Self::new(file.to_path_buf(), transform, geometry, material))
    }

    /// The wall of a triangle soup (three vertices per triangle, m),
    /// placed by `transform`; `file` names it.
    pub fn from_triangles(
        file: &Path,
        soup: &[super::Triangle],
        transform: Transform,
        material: usize,
    ) -> Result<Self, SceneError> {
        let geometry =
            MeshGeometry::from_triangles(file, soup, &transform, &MeshOptions::default())
                .map_err(|e| SceneError::input(e.to_string()))?;
        Ok(Self::new(file.to_path_buf(), transform, geometry, material))
    }

    fn new(file: PathBuf, transform: Transform, geometry: MeshGeometry, material: usize) -> Self {
        let digest = digest(&geometry);
        Mesh {
            file,
            transform,
            geometry: Arc::new(geometry),
            digest,
            material,
        }
    }

    /// Refuses (naming `key`, the wall's key) a mesh whose bounding box
    /// does not meet the domain box [lower, upper]: no sphere can touch
    /// it (a file in other units, or a wrong translation).
    pub fn check_meets(&self, lower: [f64; 3], upper: [f64; 3], key: &str) -> Result<(), SceneError> {
        let g = &self.geometry;
        let apart = (0..3).find(|&a| g.hi[a] < lower[a] || g.lo[a] > upper[a]);
        let Some(a) = apart else {
            return Ok(());
        };
        Err(SceneError::input(format!(
            "`{key}` ({}): the placed mesh's bounding box {} to {} m does not meet the \
             domain {} to {} m (apart along {}): no sphere can touch it (allowed: a mesh \
             whose box meets the domain); check `{key}.scale`, `{key}.translate`, \
             `{key}.rotate` and the file's units",
            self.file_name(),
            show3(g.lo),
            show3(g.hi),
            show3(lower),
            show3(upper),
            ["x", "y", "z"][a]
        )))
    }

    /// The file's name (its last component), for messages.
    pub fn file_name(&self) -> String {
        self.file
            .file_name()
            .map_or_else(|| self.file.display().to_string(), |n| n.to_string_lossy().into_owned())
    }
}

/// SHA-256 of the vertices' bits and the triangles' indices.
fn digest(g: &MeshGeometry) -> String {
    let mut h = Sha256::new();
    for v in &g.vertices {
        for c in v {
            h.update(c.to_bits().to_le_bytes());
        }
    }
    for t in &g.triangles {
        for i in t {
            h.update(i.to_le_bytes());
        }
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

impl std::fmt::Debug for Mesh {
    /// File name, counts and digest: never the triangles.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mesh")
            .field("file", &self.file_name())
            .field("triangles", &self.geometry.triangles.len())
            .field("patches", &self.geometry.patch_count())
            .field("digest", &self.digest)
            .field("material", &self.material)
            .finish()
    }
}

impl PartialEq for Mesh {
    /// The same placed geometry (by digest) from the same file, of the
    /// same material.
    fn eq(&self, other: &Self) -> bool {
        self.file == other.file
            && self.transform == other.transform
            && self.digest == other.digest
            && self.material == other.material
    }
}

impl WallType for Mesh {
    const KEY: &'static str = "mesh";
    type Config = MeshConfig;

    fn validate(
        c: &MeshConfig,
        file: &SceneFile,
        key: &str,
        material: &str,
    ) -> Result<(), SceneError> {
        let k = |s: &str| format!("{key}.mesh.{s}");
        if c.file.as_os_str().is_empty() {
            return Err(SceneError::input(format!(
                "invalid value for `{}`: \"\" (allowed: the path of an .stl or .obj file, \
                 relative to the scene file)",
                k("file")
            )));
        }
        positive(&k("scale"), c.scale, "file units to m (a factor)")?;
        finite3_key(&k("translate"), c.translate, "m")?;
        if let Some(r) = &c.rotate {
            nonzero3(&k("rotate.axis"), r.axis)?;
            crate::io::config::checks::check(
                r.angle.is_finite(),
                &k("rotate.angle"),
                r.angle,
                "finite, in degrees",
            )?;
        }
        crate::io::config::surface_material(file, key, material)
    }

    fn resolve(
        c: &mut MeshConfig,
        w: usize,
        material: &str,
        cx: &mut WallResolve<'_>,
    ) -> Result<Self, SceneError> {
        let key = format!("wall[{w}].mesh");
        let path = if c.file.is_absolute() {
            c.file.clone()
        } else {
            cx.base_dir.join(&c.file)
        };
        let path = std::path::absolute(&path).unwrap_or(path);
        let material = cx.material_index(material);
        let mesh = Mesh::load(&path, c.transform(), material)
            .map_err(|e| SceneError::input(format!("`{key}.file` = {:?}: {e}", c.file)))?;
        c.file = path;
        mesh.check_meets(cx.extent.lower, cx.extent.upper, &key)?;
        let g = &mesh.geometry;
        for warning in g.warnings() {
            cx.warnings
                .push(format!("`{key}` ({}): {warning}", mesh.file_name()));
        }
        Ok(mesh)
    }

    fn check_placements(
        walls: &[(usize, &Self)],
        setup: &SceneSetup,
        label: Label<'_>,
        warnings: &mut crate::setup_checks::Overlaps<'_>,
    ) -> Result<(), SceneError> {
        placements(walls, setup, label, warnings)
    }

    fn material(&self) -> Option<usize> {
        Some(self.material)
    }

    /// One flat row: every patch is a plane.
    fn law_rows(&self) -> Vec<(usize, Curvature)> {
        vec![(self.material, Curvature::Flat)]
    }

    fn build(
        &self,
        w: usize,
        setup: &SceneSetup,
        slot: usize,
    ) -> Result<Option<Surface>, SceneError> {
        let nm = setup.materials.len();
        if self.material >= nm {
            return Err(SceneError::invalid(
                format!("walls[{w}].material"),
                self.material,
                format!("a material index below {nm}"),
            ));
        }
        Ok(Some(Surface::Mesh(MeshWall {
            wall: w,
            slot,
            mesh: Arc::clone(&self.geometry),
            moving: None,
        })))
    }

    fn summary(&self) -> String {
        format!(
            "mesh ({} triangles, {} flat patches, {})",
            self.geometry.triangles.len(),
            self.geometry.patch_count(),
            self.file_name()
        )
    }

    fn export_note(&self) -> Option<String> {
        Some(
            "LAMMPS's `fix wall/gran` has no triangle mesh (`dembound export liggghts` writes \
             it as LIGGGHTS's `fix mesh/surface` with `fix wall/gran ... mesh`)"
                .into(),
        )
    }

    fn keys() -> Vec<WallKey> {
        let row = |name, unit, default, allowed: &str, meaning| {
            WallKey::new(Self::KEY, name, unit, default, allowed, meaning)
        };
        vec![
            row(
                "file",
                "",
                "—",
                "an .stl (binary or ASCII) or .obj file; relative to the scene file",
                "the triangles",
            ),
            row(
                "scale",
                "",
                "1",
                "finite, > 0",
                "file units to m (applied first)",
            ),
            row(
                "rotate",
                "°",
                "none",
                "{ axis = non-zero vector, angle = finite degrees }",
                "rotation about the origin (after scaling)",
            ),
            row(
                "translate",
                "m",
                "[0, 0, 0]",
                "three finite numbers",
                "shift (applied last)",
            ),
        ]
    }
}

/// The refusals and warnings of the mesh walls (`setup_checks`): a free
/// sphere overlapping a patch of a mesh by more than
/// [`limits::OVERLAP_REFUSAL`] of its radius is refused; above
/// [`limits::OVERLAP_WARNING`] one warning for all meshes. The overlap is
/// the engine's own (the patch contacts under the one-force rule). Not
/// checked: which side of a surface a centre is on (a mesh is two-sided,
/// and an open part has no inside), so a sphere placed entirely behind a
/// face, or inside a closed part, farther than its radius from every face,
/// is not refused.
fn placements(
    walls: &[(usize, &Mesh)],
    setup: &SceneSetup,
    label: Label<'_>,
    warnings: &mut crate::setup_checks::Overlaps<'_>,
) -> Result<(), SceneError> {
    let mut tally = warnings.wall_tally();
    for &(w, m) in walls {
        let g = &m.geometry;
        for (k, sp) in setup.spheres.iter().enumerate() {
            if sp.fixed {
                continue;
            }
            let (x, r) = (sp.position, sp.radius);
            let mut overlap = f64::NEG_INFINITY;
            g.patches_within(x, r, &mut |p| {
                overlap = overlap.max(g.patch_contact(p, x, [0.0; 3], r).overlap);
            });
            let share = overlap / r;
            if share > limits::OVERLAP_REFUSAL {
                return Err(SceneError::input(format!(
                    "{} and `wall[{w}].mesh` ({}): it overlaps the mesh by {}, {} of its radius \
                     {} (allowed: an overlap of at most {} of the radius; a warning above {}): \
                     move the sphere or the mesh",
                    label(k),
                    m.file_name(),
                    metres(overlap),
                    percent(share),
                    metres(r),
                    percent(limits::OVERLAP_REFUSAL),
                    percent(limits::OVERLAP_WARNING)
                )));
            }
            tally.note(share, k, w, overlap);
        }
    }
    warnings.push_walls("mesh", tally);
    Ok(())
}
