//! The analytic cylinder wall (issue 25): a circular tube of radius R_c
//! about an axis through `point` along unit `axis`, holding the spheres
//! inside it (`inside`) or keeping them outside a post, infinite or, for a
//! tube, closed by two flat discs.
//!
//! Geometry. For a sphere at x, with d = x − point, s = d·axis (its
//! position along the axis) and ρ = d − s axis (its radial vector,
//! r = |ρ|):
//! - element 0, the tube's surface: overlap h = R + r − R_c inside
//!   (normal −ρ/r, towards the axis), h = R + R_c − r outside (normal
//!   ρ/r); with a length L it exists for |s| ≤ L/2 only;
//! - elements 1 and 2, the caps of a tube of length L: the discs of
//!   radius R_c at point − (L/2) axis (normal +axis) and point + (L/2) axis
//!   (normal −axis), each a flat wall for the spheres whose centre lies
//!   over it (r ≤ R_c): h = R − (s + L/2) and R − (L/2 − s).
//!
//! A sphere in the corner of a capped tube touches two elements at once,
//! each with its own force, history and springs (the corner is concave:
//! the two contacts do not overlap in volume).
//!
//! Curvature model (the contact law's effective radius): LAMMPS's
//! `wall/gran ... zcylinder`, the tube a sphere of radius −R_c seen from
//! inside (R_eff = R R_c/(R_c − R)) or +R_c from outside
//! (R_eff = R R_c/(R_c + R)); the caps are flat (R_eff = R). The true
//! Hertz contact of a sphere on a cylinder is elliptic; this model keeps
//! the sphere-pair formulas and can be compared with LAMMPS.
//!
//! The wall is fixed: its surface velocity is zero.
//!
//! Everything about the type is here (`walls::registry`): the
//! `[[wall]] cylinder = { … }` entry and its checks, the setup
//! ([`Cylinder`]), the placement checks, the law rows, the engine record
//! ([`CylinderWall`]) and its geometry.

use super::motion::WallState;
use super::registry::{finite3, show3, WallKey, WallType};
use super::{Curvature, Surface, Wall, WallPoint};
use crate::error::SceneError;
use crate::io::config::checks::{check, finite3 as finite3_key, nonzero3, positive};
use crate::io::config::SceneFile;
use crate::io::resolve::WallResolve;
use crate::limits::{self, metres, norm};
use crate::setup::SceneSetup;
use crate::setup_checks::{invalid, percent, Label, AXES};
use serde::{Deserialize, Serialize};

/// `cylinder = { point, axis, radius, inside, length }`: a tube of radius
/// `radius` (m) about the axis through `point` (m) along `axis`; the
/// spheres are inside it (`inside = true`, the default) or outside a post
/// (`false`); `length` (m): a tube closed by flat discs at
/// point ± length/2 · axis (omitted: infinite, no caps).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderConfig {
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

/// A fixed cylinder: axis through `point` (m) along `axis` (any
/// non-zero length), radius `radius` (m); the spheres are `inside` the
/// tube (else outside a post); `length` (m): a tube closed by flat discs at
/// point ± length/2 · axis (`None`: infinite). Of `material`, like a
/// plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    pub point: [f64; 3],
    pub axis: [f64; 3],
    pub radius: f64,
    pub inside: bool,
    pub length: Option<f64>,
    pub material: usize,
}

impl WallType for Cylinder {
    const KEY: &'static str = "cylinder";
    type Config = CylinderConfig;

    fn validate(
        c: &CylinderConfig,
        file: &SceneFile,
        key: &str,
        material: &str,
    ) -> Result<(), SceneError> {
        let k = |s: &str| format!("{key}.cylinder.{s}");
        finite3_key(&k("point"), c.point, "m")?;
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
        let periodic = file.domain.periodic;
        for a in 0..3 {
            if !periodic[a] {
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
                    periodic,
                    ["x", "y", "z"][a],
                    limits::show(len)
                ),
            )?;
        }
        crate::io::config::surface_material(file, key, material)
    }

    fn resolve(
        c: &mut CylinderConfig,
        _w: usize,
        material: &str,
        cx: &mut WallResolve<'_>,
    ) -> Result<Self, SceneError> {
        Ok(Cylinder {
            point: c.point,
            axis: c.axis,
            radius: c.radius,
            inside: c.inside,
            length: c.length,
            material: cx.material_index(material),
        })
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

    /// The tube (curved: the module doc's curvature model) and, capped,
    /// the caps (flat).
    fn law_rows(&self) -> Vec<(usize, Curvature)> {
        let rho = if self.inside {
            -self.radius
        } else {
            self.radius
        };
        let mut v = vec![(self.material, Curvature::Radius(rho))];
        if self.length.is_some() {
            v.push((self.material, Curvature::Flat));
        }
        v
    }

    fn build(
        &self,
        w: usize,
        setup: &SceneSetup,
        slot: usize,
    ) -> Result<Option<Surface>, SceneError> {
        let Cylinder {
            point,
            axis,
            radius,
            inside,
            length,
            material,
        } = *self;
        let key = |k: &str| format!("wall[{w}].cylinder.{k}");
        let len = crate::limits::norm(axis);
        if !(finite3(axis) && len.is_finite() && len > 0.0) {
            return Err(SceneError::invalid(
                key("axis"),
                show3(axis),
                "finite and non-zero",
            ));
        }
        if !finite3(point) {
            return Err(SceneError::invalid(key("point"), show3(point), "finite, m"));
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(SceneError::invalid(
                key("radius"),
                radius,
                "finite and > 0 m",
            ));
        }
        if let Some(l) = length {
            if !(l.is_finite() && l > 0.0) {
                return Err(SceneError::invalid(key("length"), l, "finite and > 0 m"));
            }
            if !inside {
                return Err(SceneError::invalid(
                    key("length"),
                    l,
                    "none for a post (inside = false): a finite post has rims, which this wall \
                     does not model; omit length (infinite post)",
                ));
            }
        }
        let nm = setup.materials.len();
        if material >= nm {
            return Err(SceneError::invalid(
                format!("walls[{w}].material"),
                material,
                format!("a material index below {nm}"),
            ));
        }
        Ok(Some(Surface::Cylinder(CylinderWall {
            wall: w,
            point,
            axis: axis.map(|x| x / len),
            radius,
            inside,
            half_length: length.map(|l| 0.5 * l),
            slot,
            moving: None,
        })))
    }

    fn summary(&self) -> String {
        if self.inside { "cylinder" } else { "post" }.to_string()
    }

    fn export_note(&self) -> Option<String> {
        Some(
            "LAMMPS's `fix wall/gran ... zcylinder` is a tube about the z axis through x = y = 0 \
             only, and dembound's caps and posts have no `wall/gran` counterpart"
                .into(),
        )
    }

    fn keys() -> Vec<WallKey> {
        let row = |name, unit, default, allowed: &str, meaning| {
            WallKey::new(Self::KEY, name, unit, default, allowed, meaning)
        };
        vec![
            row(
                "point",
                "m",
                "—",
                "three finite numbers",
                "a point of the axis (a capped tube's middle)",
            ),
            row(
                "axis",
                "",
                "—",
                "a finite non-zero vector; along every periodic axis",
                "the axis direction",
            ),
            row(
                "radius",
                "m",
                "—",
                "> 0; above the largest free radius (inside)",
                "R_c",
            ),
            row(
                "inside",
                "",
                "true",
                "true, false",
                "spheres inside the tube, or outside a post",
            ),
            row(
                "length",
                "m",
                "infinite",
                "> 0; tubes only, no periodic axis",
                "caps: discs at point ± length/2 · axis",
            ),
        ]
    }
}

/// The refusals and warnings of the cylinders (`setup_checks`): one not
/// along every periodic axis, or capped while the domain is periodic; an
/// inside tube no wider than the largest free sphere; a free sphere whose
/// centre is on the wrong side (outside an inside tube or its caps,
/// inside a post) or that overlaps the tube or a cap by more than
/// [`limits::OVERLAP_REFUSAL`] of its radius; above
/// [`limits::OVERLAP_WARNING`] one warning for all cylinders.
fn placements(
    walls: &[(usize, &Cylinder)],
    setup: &SceneSetup,
    label: Label<'_>,
    warnings: &mut crate::setup_checks::Overlaps<'_>,
) -> Result<(), SceneError> {
    let mut tally = warnings.wall_tally();
    let largest_free = setup
        .spheres
        .iter()
        .filter(|s| !s.fixed)
        .map(|s| s.radius)
        .fold(0.0f64, f64::max);
    for &(w, c) in walls {
        let Cylinder {
            point,
            axis,
            radius,
            inside,
            length,
            ..
        } = *c;
        let key = format!("wall[{w}].cylinder");
        let len = norm(axis);
        let a = axis.map(|x| x / len);
        for (k, name) in AXES.iter().enumerate() {
            if setup.domain.periodic[k]
                && (length.is_some() || (0..3).any(|b| b != k && a[b] != 0.0))
            {
                return Err(invalid(
                    &format!("{key}.axis"),
                    format!("{axis:?}"),
                    &format!(
                        "along every periodic axis and infinite (`domain.periodic` = {:?}: an \
                         axis along {} only, no length): a tube that crosses a periodic face at \
                         an angle, or ends, is not invariant under the period's translation",
                        setup.domain.periodic, name
                    ),
                ));
            }
        }
        if inside && radius <= largest_free {
            return Err(invalid(
                &format!("{key}.radius"),
                metres(radius),
                &format!(
                    "above the largest free sphere's radius {} for a tube the spheres are inside: \
                     no free sphere fits",
                    metres(largest_free)
                ),
            ));
        }
        let half = length.map(|l| 0.5 * l);
        for (k, sp) in setup.spheres.iter().enumerate() {
            if sp.fixed {
                continue;
            }
            let d = [
                sp.position[0] - point[0],
                sp.position[1] - point[1],
                sp.position[2] - point[2],
            ];
            let along = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
            let rho = [
                d[0] - along * a[0],
                d[1] - along * a[1],
                d[2] - along * a[2],
            ];
            let r = norm(rho);
            let wrong_side = if inside {
                r >= radius || half.is_some_and(|h| along.abs() >= h)
            } else {
                r <= radius
            };
            if wrong_side {
                return Err(SceneError::input(format!(
                    "{} and `{key}`: its centre is {} the {} (at {} from the axis, R_c = {}) \
                     (allowed: the centre {}): move the sphere or the wall, or check \
                     `{key}.inside`",
                    label(k),
                    if inside { "outside" } else { "inside" },
                    if inside { "tube and its caps" } else { "post" },
                    metres(r),
                    metres(radius),
                    if inside {
                        "inside the tube, between its caps"
                    } else {
                        "outside the post"
                    }
                )));
            }
            // The largest overlap with the tube and the caps.
            let mut overlap = if inside {
                sp.radius + r - radius
            } else {
                sp.radius + radius - r
            };
            if let Some(h) = half {
                overlap = overlap
                    .max(sp.radius - (along + h))
                    .max(sp.radius - (h - along));
            }
            let share = overlap / sp.radius;
            if share > limits::OVERLAP_REFUSAL {
                return Err(SceneError::input(format!(
                    "{} and `{key}`: it overlaps the wall by {}, {} of its radius {} (allowed: an \
                     overlap of at most {} of the radius; a warning above {}): move the sphere or \
                     the wall",
                    label(k),
                    metres(overlap),
                    percent(share),
                    metres(sp.radius),
                    percent(limits::OVERLAP_REFUSAL),
                    percent(limits::OVERLAP_WARNING)
                )));
            }
            tally.note(share, k, w, overlap);
        }
    }
    warnings.push_walls("cylinder", tally);
    Ok(())
}

/// The tube's element.
pub const TUBE: u32 = 0;
/// The cap at point − (L/2) axis.
pub const LOWER_CAP: u32 = 1;
/// The cap at point + (L/2) axis.
pub const UPPER_CAP: u32 = 2;

/// A cylinder wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CylinderWall {
    /// Index of the wall in file order.
    pub wall: usize,
    /// A point of the axis (the middle of a capped tube), m.
    pub point: [f64; 3],
    /// Unit axis.
    pub axis: [f64; 3],
    /// R_c, m.
    pub radius: f64,
    /// The spheres are inside the tube (else outside a post).
    pub inside: bool,
    /// L/2 of a capped tube, m (`None`: infinite, no caps).
    pub half_length: Option<f64>,
    /// The tube's row of the law tables; the caps' is the next.
    pub slot: usize,
    /// Its pose and velocities when it moves (`walls::motion`): `point`
    /// and `axis` are then the placed ones.
    pub moving: Option<WallState>,
}

impl CylinderWall {
    /// The curvature of the tube's surface and of the caps, in the
    /// law-table rows `slot` and `slot + 1`.
    pub fn curvatures(&self) -> (Curvature, Option<Curvature>) {
        let tube = Curvature::Radius(if self.inside {
            -self.radius
        } else {
            self.radius
        });
        (tube, self.half_length.map(|_| Curvature::Flat))
    }

    /// (s, ρ, r): position along the axis, radial vector and its length.
    #[inline(always)]
    fn split(&self, x: [f64; 3]) -> (f64, [f64; 3], f64) {
        let a = self.axis;
        let d = [
            x[0] - self.point[0],
            x[1] - self.point[1],
            x[2] - self.point[2],
        ];
        let s = d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
        let rho = [d[0] - s * a[0], d[1] - s * a[1], d[2] - s * a[2]];
        let r = (rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2]).sqrt();
        (s, rho, r)
    }

    /// The geometry of element `element` for a sphere at `x` of radius
    /// `radius`: (overlap, unit normal from the wall into the sphere);
    /// overlap −∞ where the element does not face the sphere.
    #[inline(always)]
    pub fn geometry(&self, element: u32, x: [f64; 3], radius: f64) -> (f64, [f64; 3]) {
        const NONE: (f64, [f64; 3]) = (f64::NEG_INFINITY, [0.0; 3]);
        let (s, rho, r) = self.split(x);
        match element {
            TUBE => {
                if self.half_length.is_some_and(|l| s.abs() > l) || r == 0.0 {
                    return NONE;
                }
                let e = [rho[0] / r, rho[1] / r, rho[2] / r];
                if self.inside {
                    (radius + r - self.radius, [-e[0], -e[1], -e[2]])
                } else {
                    (radius + self.radius - r, e)
                }
            }
            LOWER_CAP | UPPER_CAP => {
                let Some(l) = self.half_length else {
                    return NONE;
                };
                if r > self.radius {
                    return NONE;
                }
                let a = self.axis;
                if element == LOWER_CAP {
                    (radius - (s + l), a)
                } else {
                    (radius - (l - s), [-a[0], -a[1], -a[2]])
                }
            }
            _ => NONE,
        }
    }
}

impl Wall for CylinderWall {
    fn file_index(&self) -> usize {
        self.wall
    }

    fn elements(&self) -> u32 {
        if self.half_length.is_some() {
            3
        } else {
            1
        }
    }

    fn near_elements(&self, x: [f64; 3], r: f64, range: f64, found: &mut dyn FnMut(u32)) {
        for e in 0..self.elements() {
            if self.geometry(e, x, r).0 > -range {
                found(e);
            }
        }
    }

    #[inline(always)]
    fn contact(&self, element: u32, x: [f64; 3], v: [f64; 3], r: f64) -> WallPoint {
        let (overlap, n) = self.geometry(element, x, r);
        let rate = match &self.moving {
            None => -(v[0] * n[0] + v[1] * n[1] + v[2] * n[2]),
            // ḣ = −(v − v_w(p))·n, p = x − r n.
            Some(m) => {
                let w = m.velocity_at([x[0] - r * n[0], x[1] - r * n[1], x[2] - r * n[2]]);
                let u = [v[0] - w[0], v[1] - w[1], v[2] - w[2]];
                -(u[0] * n[0] + u[1] * n[1] + u[2] * n[2])
            }
        };
        WallPoint {
            overlap,
            rate,
            normal: n,
        }
    }

    fn moving(&self) -> Option<&WallState> {
        self.moving.as_ref()
    }

    fn posed(&self, state: &WallState) -> Option<Surface> {
        Some(Surface::Cylinder(CylinderWall {
            point: state.place(self.point),
            axis: state.rotate(self.axis),
            moving: Some(*state),
            ..*self
        }))
    }

    fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for k in 0..3 {
            let a = self.axis[k];
            // The tube's cross-section spans R_c √(1 − a_k²) along k.
            let across = self.radius * (1.0 - a * a).max(0.0).sqrt();
            let along = match self.half_length {
                Some(l) => l * a.abs(),
                None if a != 0.0 => f64::INFINITY,
                None => 0.0,
            };
            lo[k] = self.point[k] - along - across;
            hi[k] = self.point[k] + along + across;
        }
        if !self.inside {
            // A post bounds the region outside it: nothing.
            return ([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]);
        }
        (lo, hi)
    }

    fn torque_point(&self) -> [f64; 3] {
        self.point
    }

    #[inline(always)]
    fn law_slot(&self, element: u32) -> usize {
        if element == TUBE {
            self.slot
        } else {
            self.slot + 1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tube(inside: bool, half_length: Option<f64>) -> CylinderWall {
        CylinderWall {
            wall: 3,
            point: [1.0, 2.0, 0.0],
            axis: [0.0, 0.0, 1.0],
            radius: 0.5,
            inside,
            half_length,
            slot: 4,
            moving: None,
        }
    }

    /// Overlaps, normals and rates against hand-computed values: a sphere
    /// of radius 0.1 at radial distance 0.45 from the axis (x direction).
    #[test]
    fn tube_and_post_geometry() {
        let x = [1.45, 2.0, 7.0];
        let v = [2.0, 0.0, 0.0];
        let c = tube(true, None).contact(TUBE, x, v, 0.1);
        // Inside: h = R + r − R_c = 0.1 + 0.45 − 0.5 = 0.05, pushed to −x,
        // approaching at 2 m/s.
        assert!((c.overlap - 0.05).abs() < 1e-15, "{}", c.overlap);
        assert_eq!(c.normal, [-1.0, 0.0, 0.0]);
        assert_eq!(c.rate, 2.0);
        // A post of the same radius: the sphere's centre inside it,
        // h = R + R_c − r = 0.15, pushed to +x, moving away at 2 m/s.
        let p = tube(false, None).contact(TUBE, x, v, 0.1);
        assert!((p.overlap - 0.15).abs() < 1e-15);
        assert_eq!((p.normal, p.rate), ([1.0, 0.0, 0.0], -2.0));
        assert_eq!(tube(true, None).law_slot(TUBE), 4);
    }

    /// A capped tube of length 2: the caps face the spheres over them,
    /// the tube only along its length; the near test lists ascending.
    #[test]
    fn caps_and_near_test() {
        let w = tube(true, Some(1.0));
        assert_eq!(w.elements(), 3);
        // Centre 0.05 above the lower cap (z = −1), radius 0.1.
        let (h, n) = w.geometry(LOWER_CAP, [1.0, 2.0, -0.95], 0.1);
        assert!((h - 0.05).abs() < 1e-15 && n == [0.0, 0.0, 1.0]);
        let (h, n) = w.geometry(UPPER_CAP, [1.0, 2.0, 0.95], 0.1);
        assert!((h - 0.05).abs() < 1e-15 && n == [0.0, 0.0, -1.0]);
        // Beyond the length the tube does not exist.
        assert_eq!(w.geometry(TUBE, [1.45, 2.0, 1.2], 0.1).0, f64::NEG_INFINITY);
        // In the corner: tube and lower cap both near.
        let mut seen = Vec::new();
        w.near_elements([1.42, 2.0, -0.92], 0.1, 0.01, &mut |e| seen.push(e));
        assert_eq!(seen, vec![TUBE, LOWER_CAP]);
        assert_eq!((w.law_slot(TUBE), w.law_slot(UPPER_CAP)), (4, 5));
        let (lo, hi) = w.bounding_box();
        assert_eq!((lo, hi), ([0.5, 1.5, -1.0], [1.5, 2.5, 1.0]));
    }

    /// A centre exactly on the axis (r = 0) has no radial direction: the
    /// tube does not face it (overlap −∞, normal 0, rate 0, not near)
    /// rather than giving the normal 0/0 = NaN; the caps answer as
    /// anywhere. A centre 1e-160 m off the axis (r² a subnormal) gets a
    /// finite normal and the overlap R + r − R_c = −0.4 m (inside, R_c >
    /// R: the tube never pushes there).
    #[test]
    fn a_centre_on_the_axis_is_not_faced_by_the_tube() {
        let w = tube(true, Some(1.0));
        let x = [1.0, 2.0, -0.95];
        assert_eq!(w.geometry(TUBE, x, 0.1), (f64::NEG_INFINITY, [0.0; 3]));
        let c = w.contact(TUBE, x, [0.3, -0.2, 0.1], 0.1);
        assert_eq!((c.overlap, c.normal, c.rate), (f64::NEG_INFINITY, [0.0; 3], 0.0));
        let mut seen = Vec::new();
        w.near_elements(x, 0.1, 0.01, &mut |e| seen.push(e));
        assert_eq!(seen, vec![LOWER_CAP]);
        let (h, n) = w.geometry(LOWER_CAP, x, 0.1);
        assert!((h - 0.05).abs() < 1e-15 && n == [0.0, 0.0, 1.0]);
        let off = CylinderWall {
            point: [0.0; 3],
            ..w
        };
        let (h, n) = off.geometry(TUBE, [1e-160, 0.0, 0.3], 0.1);
        // 0.1 + 1e-160 − 0.5 rounds to −0.4 (1e-160 is far below its ulp).
        assert_eq!(h, 0.1 - 0.5);
        assert!(n.iter().all(|c| c.is_finite()) && n[0] < 0.0, "{n:?}");
    }

    /// The law rows: the tube a sphere of radius −R_c inside (LAMMPS
    /// `wall/gran` cylinders: R_eff = R R_c/(R_c − R)), +R_c outside.
    #[test]
    fn curvature_gives_the_lammps_effective_radius() {
        use dembound_physics::material::Material;
        let m = Material {
            density: 1000.0,
            youngs_modulus: 1e7,
            poisson_ratio: 0.3,
        };
        for (inside, expected) in [(true, 0.1 * 0.5 / 0.4), (false, 0.1 * 0.5 / 0.6)] {
            let (curv, _) = tube(inside, None).curvatures();
            let slot = super::super::LawSlot {
                material: 0,
                wall: 0,
                curvature: curv,
            };
            let r = slot.properties(0.1, 1.0, &m, &m).radius;
            assert!((r / expected - 1.0).abs() < 1e-14, "{r} {expected}");
        }
    }
}
