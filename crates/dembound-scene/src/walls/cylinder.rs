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

use super::{Curvature, Wall, WallPoint};

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
        WallPoint {
            overlap,
            rate: -(v[0] * n[0] + v[1] * n[1] + v[2] * n[2]),
            normal: n,
        }
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
