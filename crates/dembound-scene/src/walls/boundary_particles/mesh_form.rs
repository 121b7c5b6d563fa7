//! The mesh form of a wall of boundary particles (issue 29):
//! `boundary_particles = { mesh = "part.stl", scale, translate, rotate,
//! flip, radius_ratio, modulus_ratio, tiling, spacing, reference_radius }`.
//! The file is read relative to the scene file (its absolute path is
//! written back, as a `mesh` wall's), placed as a `mesh` wall is
//! (x' = R (s x) + t, `walls::mesh::Transform`) and covered by
//! `sources::mesh_tiling::cover` with the plane form's radius, spacing and
//! pattern: a flat square part gives exactly the plane form's spheres over
//! the same square. Everything after the spheres (their material, the
//! fixed group of the wall) is the plane form's resolution.
//!
//! Refused, naming the key: the plane form's `point`/`normal` together
//! with `mesh`, a placement key without `mesh`, an unreadable file, a
//! covering whose part does not meet the domain, and a periodic domain (a
//! covering does not repeat with a period; the plane form does).

use std::path::PathBuf;

use super::BoundaryParticlesConfig;
use crate::error::SceneError;
use crate::io::config::checks::{check, finite3, invalid, nonzero3, positive};
use crate::io::config::SceneFile;
use crate::io::resolve::WallResolve;
use crate::io::resolve::CoveringHole;
use crate::sources::mesh_tiling::measure::holes;
use crate::sources::mesh_tiling::{cover_named, CoveringOptions, Names};
use crate::sources::tiling::Pattern;
use crate::sources::SourceSphere;
use crate::walls::mesh::{read::read_triangles, MeshConfig};
use crate::walls::registry::{show3, WallKey};

/// The plane form's (point, normal), m and any length; `None`: the mesh
/// form.
pub(super) type PlaneForm = Option<([f64; 3], [f64; 3])>;

/// Checks which form the entry `key` (`wall[K]`) is: `Some((point,
/// normal))` for the plane form, `None` for a checked mesh form.
pub(super) fn validate_form(
    b: &BoundaryParticlesConfig,
    file: &SceneFile,
    key: &str,
) -> Result<PlaneForm, SceneError> {
    let k = |s: &str| format!("{key}.boundary_particles.{s}");
    let Some(mesh) = &b.mesh else {
        let placement = [
            ("scale", b.scale.is_some()),
            ("translate", b.translate.is_some()),
            ("rotate", b.rotate.is_some()),
            ("flip", b.flip.is_some()),
        ];
        if let Some((name, _)) = placement.iter().find(|(_, given)| *given) {
            return Err(invalid(
                &k(name),
                "given without `mesh`",
                "only with `mesh = \"part.stl\"` (the mesh form); the plane form is placed \
                 by `point` and `normal`",
            ));
        }
        return match (b.point, b.normal) {
            (Some(p), Some(n)) => Ok(Some((p, n))),
            (None, _) => Err(invalid(
                &k("point"),
                "missing",
                "three finite numbers, m, with `normal` (the plane form), or `mesh = \
                 \"part.stl\"` instead of both (the mesh form)",
            )),
            (Some(_), None) => Err(invalid(
                &k("normal"),
                "missing",
                "a non-zero vector into the domain, with `point` (the plane form)",
            )),
        };
    };
    for (name, given) in [("point", b.point.is_some()), ("normal", b.normal.is_some())] {
        check(
            !given,
            &k(name),
            "given with `mesh`",
            "either `point` and `normal` (the plane form) or `mesh` (the mesh form), not both",
        )?;
    }
    if mesh.as_os_str().is_empty() {
        return Err(invalid(
            &k("mesh"),
            "\"\"",
            "the path of an .stl or .obj file, relative to the scene file",
        ));
    }
    if let Some(s) = b.scale {
        positive(&k("scale"), s, "file units to m (a factor)")?;
    }
    if let Some(t) = b.translate {
        finite3(&k("translate"), t, "m")?;
    }
    if let Some(r) = &b.rotate {
        nonzero3(&k("rotate.axis"), r.axis)?;
        check(
            r.angle.is_finite(),
            &k("rotate.angle"),
            r.angle,
            "finite, in degrees",
        )?;
    }
    check(
        !file.domain.periodic.iter().any(|&p| p),
        &k("mesh"),
        format!("given in a domain periodic along {:?}", file.domain.periodic),
        "a domain with no periodic axis (a covered part does not repeat with the period; \
         the plane form does)",
    )?;
    Ok(None)
}

/// The covering's spheres of the mesh form of wall `key` (`wall[K]`), of
/// radius `radius` and site distance `spacing`, m; the file path in `b`
/// made absolute.
pub(super) fn spheres(
    b: &mut BoundaryParticlesConfig,
    key: &str,
    radius: f64,
    spacing: f64,
    pattern: Pattern,
    cx: &mut WallResolve<'_>,
) -> Result<Vec<SourceSphere>, SceneError> {
    let k = format!("{key}.boundary_particles.mesh");
    let Some(file) = b.mesh.clone() else {
        return Err(invalid(
            &format!("{key}.boundary_particles.point"),
            "missing",
            "`point` and `normal` (the plane form) or `mesh` (the mesh form)",
        ));
    };
    let path = if file.is_absolute() {
        file.clone()
    } else {
        cx.base_dir.join(&file)
    };
    let path: PathBuf = std::path::absolute(&path).unwrap_or(path);
    let transform = placement(b).transform();
    transform
        .validate()
        .map_err(|e| SceneError::input(format!("`{k}` = {file:?}: {e}")))?;
    let soup = read_triangles(&path)
        .map_err(|e| SceneError::input(format!("`{k}` = {file:?}: {e}")))?;
    let placed: Vec<_> = soup
        .iter()
        .map(|t| t.map(|v| transform.apply(v)))
        .collect();
    let options = CoveringOptions {
        radius,
        spacing,
        pattern,
        flip: b.flip.unwrap_or(false),
    };
    let (radius_key, spacing_key) = (
        format!("{key}.boundary_particles.radius_ratio"),
        format!("{key}.boundary_particles.spacing"),
    );
    let names = Names {
        radius: &radius_key,
        spacing: &spacing_key,
    };
    let covering = cover_named(&path, &placed, &options, names)
        .map_err(|e| SceneError::input(format!("`{k}` = {file:?}: {e}")))?;
    b.mesh = Some(path);
    let (lo, hi) = (covering.mesh.lo, covering.mesh.hi);
    let (lower, upper) = (cx.extent.lower, cx.extent.upper);
    if let Some(a) = (0..3).find(|&a| hi[a] < lower[a] || lo[a] > upper[a]) {
        return Err(SceneError::input(format!(
            "`{k}` = {file:?}: the placed part's bounding box {} to {} m does not meet the \
             domain {} to {} m (apart along {}): its spheres could touch no particle \
             (allowed: a part whose box meets the domain); check `scale`, `translate`, \
             `rotate` and the file's units",
            show3(lo),
            show3(hi),
            show3(lower),
            show3(upper),
            ["x", "y", "z"][a]
        )));
    }
    // A particle smaller than the largest hole may leak (the covering's
    // measure samples the centres' surface every s/8: the bound is the
    // hole found plus that spacing).
    let smallest = cx
        .spheres
        .iter()
        .filter(|s| !s.fixed)
        .map(|s| s.radius)
        .fold(f64::INFINITY, f64::min);
    let h = holes(&covering);
    cx.covering_holes.push(CoveringHole {
        wall: 0,
        spheres: covering.spheres.len(),
        largest_hole: h.hole,
        largest_hole_bound: h.hole_bound,
    });
    if smallest.is_finite() && h.hole_bound >= smallest {
        cx.warnings.push(format!(
            "`{k}`: the largest hole between its {} spheres is {:e} m (≤ {:e} m), not \
             below the smallest particle radius {smallest:e} m: particles may pass \
             through; lower `radius_ratio` or `spacing`",
            covering.spheres.len(),
            h.hole,
            h.hole_bound
        ));
    }
    Ok(covering.spheres)
}

/// The placement keys as a `mesh` wall's entry.
fn placement(b: &BoundaryParticlesConfig) -> MeshConfig {
    MeshConfig {
        file: b.mesh.clone().unwrap_or_default(),
        scale: b.scale.unwrap_or(1.0),
        translate: b.translate.unwrap_or([0.0; 3]),
        rotate: b.rotate.clone(),
    }
}

/// The mesh form's rows of the key table.
pub(super) fn keys() -> Vec<WallKey> {
    let row = |name, unit, default, allowed: &str, meaning| {
        WallKey::new("boundary_particles", name, unit, default, allowed, meaning)
    };
    vec![
        row(
            "mesh",
            "",
            "—",
            "an .stl or .obj file, relative to the scene file (mesh form: not with point, normal)",
            "the covered part",
        ),
        row(
            "scale",
            "",
            "1",
            "finite, > 0 (mesh form)",
            "file units to m (applied first)",
        ),
        row(
            "rotate",
            "°",
            "none",
            "{ axis = non-zero vector, angle = finite degrees } (mesh form)",
            "rotation about the origin",
        ),
        row(
            "translate",
            "m",
            "[0, 0, 0]",
            "three finite numbers (mesh form)",
            "shift (applied last)",
        ),
        row(
            "flip",
            "",
            "false",
            "true, false (mesh form)",
            "spheres on the normals' side",
        ),
    ]
}
