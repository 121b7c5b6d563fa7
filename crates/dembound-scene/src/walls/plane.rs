//! The plane wall: an elastic half-space of its own material (the paper's
//! r = ∞, ζ = E_wall/E, `PairProperties::sphere_plane`). One element.
//!
//! Everything about the type is here (`walls::registry`): the
//! `[[wall]] plane = { point, normal }` entry and its checks, the setup
//! ([`Plane`]), the placement checks (a normal with a component along a
//! periodic axis; a free sphere behind the plane or overlapping it too
//! much), the law row, the engine record ([`PlaneWall`]) and its geometry.

use super::motion::WallState;
use super::registry::{finite3, show3, WallKey, WallType};
use super::{Curvature, Surface, Wall};
use crate::error::SceneError;
use crate::io::config::checks::{finite3 as finite3_key, nonzero3};
use crate::io::config::SceneFile;
use crate::io::resolve::WallResolve;
use crate::limits::{self, metres, norm, show};
use crate::setup::SceneSetup;
use crate::setup_checks::{percent, Label, AXES};
use serde::{Deserialize, Serialize};

/// `plane = { point, normal }`: the normal points into the domain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneConfig {
    pub point: [f64; 3],
    pub normal: [f64; 3],
}

/// A fixed plane through `point` (m) whose `normal` (any length > 0)
/// points into the domain: spheres touch it from the normal's side. It
/// is an elastic half-space of `material` (index into
/// `SceneSetup::materials`): the paper's r = ∞, ζ = E_wall/E.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub point: [f64; 3],
    pub normal: [f64; 3],
    pub material: usize,
}

impl WallType for Plane {
    const KEY: &'static str = "plane";
    type Config = PlaneConfig;

    fn validate(
        c: &PlaneConfig,
        file: &SceneFile,
        key: &str,
        material: &str,
    ) -> Result<(), SceneError> {
        finite3_key(&format!("{key}.plane.point"), c.point, "m")?;
        nonzero3(&format!("{key}.plane.normal"), c.normal)?;
        crate::io::config::surface_material(file, key, material)
    }

    fn resolve(
        c: &mut PlaneConfig,
        _w: usize,
        material: &str,
        cx: &mut WallResolve<'_>,
    ) -> Result<Self, SceneError> {
        Ok(Plane {
            point: c.point,
            normal: c.normal,
            material: cx.material_index(material),
        })
    }

    fn check_placements(
        walls: &[(usize, &Self)],
        setup: &SceneSetup,
        label: Label<'_>,
        warnings: &mut crate::setup_checks::Overlaps<'_>,
    ) -> Result<(), SceneError> {
        let planes = periodic_check(walls, setup)?;
        overlaps(setup, &planes, label, warnings)
    }

    fn material(&self) -> Option<usize> {
        Some(self.material)
    }

    fn law_rows(&self) -> Vec<(usize, Curvature)> {
        vec![(self.material, Curvature::Flat)]
    }

    fn build(
        &self,
        w: usize,
        setup: &SceneSetup,
        slot: usize,
    ) -> Result<Option<Surface>, SceneError> {
        let Plane {
            point,
            normal,
            material,
        } = *self;
        let mut len = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
        if !(len.is_finite() && len > 1e-150) {
            // Squares that overflow or underflow ([0, 0, 1e300]): the
            // scaled norm (the formula above, kept for the bits of every
            // other normal).
            len = crate::limits::norm(normal);
        }
        if !(len.is_finite() && len > 0.0) {
            return Err(SceneError::invalid(
                format!("wall[{w}].plane.normal"),
                show3(normal),
                "finite and non-zero",
            ));
        }
        if !finite3(point) {
            return Err(SceneError::invalid(
                format!("walls[{w}].point"),
                show3(point),
                "finite, m",
            ));
        }
        let nm = setup.materials.len();
        if material >= nm {
            return Err(SceneError::invalid(
                format!("walls[{w}].material"),
                material,
                format!("a material index below {nm}"),
            ));
        }
        Ok(Some(Surface::Plane(PlaneWall {
            wall: w,
            point,
            normal: [normal[0] / len, normal[1] / len, normal[2] / len],
            slot,
            moving: None,
        })))
    }

    fn summary(&self) -> String {
        "plane".into()
    }

    fn export_note(&self) -> Option<String> {
        None // `fix wall/gran ... zplane` or `wall/gran/region`
    }

    fn keys() -> Vec<WallKey> {
        vec![
            WallKey::new(
                Self::KEY,
                "point",
                "m",
                "—",
                "three finite numbers",
                "a point of the plane",
            ),
            WallKey::new(
                Self::KEY,
                "normal",
                "",
                "—",
                "finite, non-zero (any length); 0 along every periodic axis",
                "into the domain",
            ),
        ]
    }
}

/// A plane as the placement checks need it: wall index, point, unit
/// normal.
struct Placed {
    wall: usize,
    point: [f64; 3],
    normal: [f64; 3],
}

/// A normal with a component along a periodic axis is refused: the
/// half-space is not invariant under the period's translation (a sphere
/// re-entering through the periodic face lands behind the wall, which
/// then pushes it through and creates energy).
fn periodic_check(walls: &[(usize, &Plane)], setup: &SceneSetup) -> Result<Vec<Placed>, SceneError> {
    let mut out = Vec::new();
    for &(w, p) in walls {
        let Plane { point, normal, .. } = *p;
        let len = norm(normal);
        let unit = normal.map(|x| x / len);
        for a in 0..3 {
            if setup.domain.periodic[a] && unit[a] != 0.0 {
                return Err(SceneError::input(format!(
                    "invalid value for `wall[{w}].plane.normal`: {normal:?} has a component along \
                     {} (n_{} = {}), which `domain.periodic` = {:?} makes periodic (allowed: a \
                     normal perpendicular to every periodic axis, its component exactly 0 there: \
                     a sphere leaving through the periodic face would re-enter behind the wall, \
                     which would push it through and create energy; make the axis not periodic \
                     or turn the wall)",
                    AXES[a],
                    AXES[a],
                    show(unit[a]),
                    setup.domain.periodic
                )));
            }
        }
        out.push(Placed {
            wall: w,
            point,
            normal: unit,
        });
    }
    Ok(out)
}

/// A free sphere whose centre is behind a plane, or that overlaps it by
/// more than [`limits::OVERLAP_REFUSAL`] of its radius, is refused; above
/// [`limits::OVERLAP_WARNING`] one warning for all planes.
fn overlaps(
    setup: &SceneSetup,
    planes: &[Placed],
    label: Label<'_>,
    warnings: &mut crate::setup_checks::Overlaps<'_>,
) -> Result<(), SceneError> {
    let mut tally = warnings.wall_tally();
    for p in planes {
        for (k, s) in setup.spheres.iter().enumerate() {
            if s.fixed {
                continue;
            }
            let d = [
                s.position[0] - p.point[0],
                s.position[1] - p.point[1],
                s.position[2] - p.point[2],
            ];
            let distance = d[0] * p.normal[0] + d[1] * p.normal[1] + d[2] * p.normal[2];
            let overlap = s.radius - distance;
            let share = overlap / s.radius;
            if distance < 0.0 || share > limits::OVERLAP_REFUSAL {
                let place = if distance < 0.0 {
                    format!(
                        "its centre is {} behind the plane (on the side the normal points away \
                         from)",
                        metres(-distance)
                    )
                } else {
                    format!(
                        "it overlaps the plane by {}, {} of its radius {}",
                        metres(overlap),
                        percent(share),
                        metres(s.radius)
                    )
                };
                return Err(SceneError::input(format!(
                    "{} and `wall[{}].plane`: {place} (allowed: the centre on the normal's side \
                     and an overlap of at most {} of the radius, {}; a warning above {}): move \
                     the sphere or the wall, or check the sign of `wall[{}].plane.normal`, which \
                     points into the domain",
                    label(k),
                    p.wall,
                    percent(limits::OVERLAP_REFUSAL),
                    metres(limits::OVERLAP_REFUSAL * s.radius),
                    percent(limits::OVERLAP_WARNING),
                    p.wall
                )));
            }
            tally.note(share, k, p.wall, overlap);
        }
    }
    warnings.push_walls("plane", tally);
    Ok(())
}

/// A plane wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneWall {
    /// Index of the wall in file order.
    pub wall: usize,
    /// A point of the plane, m.
    pub point: [f64; 3],
    /// Unit normal into the domain.
    pub normal: [f64; 3],
    /// Its row of the law tables.
    pub slot: usize,
    /// Its pose and velocities when it moves (`walls::motion`): `point`
    /// and `normal` are then the placed ones.
    pub moving: Option<WallState>,
}

/// Overlap (m) and overlap rate (m/s) of a sphere against a plane.
#[inline(always)]
pub fn plane_overlap(plane: &PlaneWall, x: [f64; 3], v: [f64; 3], radius: f64) -> (f64, f64) {
    let n = plane.normal;
    let d = (x[0] - plane.point[0]) * n[0]
        + (x[1] - plane.point[1]) * n[1]
        + (x[2] - plane.point[2]) * n[2];
    let rate = -(v[0] * n[0] + v[1] * n[1] + v[2] * n[2]);
    (radius - d, rate)
}

impl Wall for PlaneWall {
    fn file_index(&self) -> usize {
        self.wall
    }

    fn elements(&self) -> u32 {
        1
    }

    fn near_elements(&self, x: [f64; 3], r: f64, range: f64, found: &mut dyn FnMut(u32)) {
        let (h, _) = plane_overlap(self, x, [0.0; 3], r);
        if h > -range {
            found(0);
        }
    }

    #[inline(always)]
    fn contact(&self, _element: u32, x: [f64; 3], v: [f64; 3], r: f64) -> super::WallPoint {
        let (overlap, rate) = plane_overlap(self, x, v, r);
        let n = self.normal;
        let rate = match &self.moving {
            None => rate,
            // ḣ = −(v − v_w(p))·n, p = x − r n.
            Some(m) => {
                let w = m.velocity_at([x[0] - r * n[0], x[1] - r * n[1], x[2] - r * n[2]]);
                rate + (w[0] * n[0] + w[1] * n[1] + w[2] * n[2])
            }
        };
        super::WallPoint {
            overlap,
            rate,
            normal: n,
        }
    }

    fn moving(&self) -> Option<&WallState> {
        self.moving.as_ref()
    }

    fn posed(&self, state: &WallState) -> Option<Surface> {
        Some(Surface::Plane(PlaneWall {
            point: state.place(self.point),
            normal: state.rotate(self.normal),
            moving: Some(*state),
            ..*self
        }))
    }

    fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        // Unbounded except along an axis it is normal to.
        let mut lo = [f64::NEG_INFINITY; 3];
        let mut hi = [f64::INFINITY; 3];
        for a in 0..3 {
            let axis_aligned = (0..3).all(|b| b == a || self.normal[b] == 0.0);
            if axis_aligned {
                lo[a] = self.point[a];
                hi[a] = self.point[a];
            }
        }
        (lo, hi)
    }

    fn torque_point(&self) -> [f64; 3] {
        self.point
    }

    #[inline(always)]
    fn law_slot(&self, _element: u32) -> usize {
        self.slot
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_normal_and_near_test_of_a_floor() {
        let floor = PlaneWall {
            wall: 0,
            point: [0.0, 0.0, 1.0],
            normal: [0.0, 0.0, 1.0],
            slot: 0,
            moving: None,
        };
        // A sphere of radius 0.5 at height 1.4: 0.1 m of overlap, moving
        // down at 2 m/s (ḣ = +2).
        let c = floor.contact(0, [3.0, -1.0, 1.4], [0.0, 0.0, -2.0], 0.5);
        assert!((c.overlap - 0.1).abs() < 1e-15 && c.rate == 2.0);
        assert_eq!(c.normal, [0.0, 0.0, 1.0]);
        let mut seen = Vec::new();
        // 0.3 m above: near within a range of 0.31, not of 0.29.
        floor.near_elements([0.0, 0.0, 1.8], 0.5, 0.31, &mut |e| seen.push(e));
        floor.near_elements([0.0, 0.0, 1.8], 0.5, 0.29, &mut |e| seen.push(e + 10));
        assert_eq!(seen, vec![0]);
        let (lo, hi) = floor.bounding_box();
        assert_eq!((lo[2], hi[2]), (1.0, 1.0));
        assert!(lo[0].is_infinite() && hi[1].is_infinite());
    }
}
