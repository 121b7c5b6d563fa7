//! The plane wall: an elastic half-space of its own material (the paper's
//! r = ∞, ζ = E_wall/E, `PairProperties::sphere_plane`). One element.

use super::Wall;

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

    fn contact(&self, _element: u32, x: [f64; 3], v: [f64; 3], r: f64) -> super::WallPoint {
        let (overlap, rate) = plane_overlap(self, x, v, r);
        super::WallPoint {
            overlap,
            rate,
            normal: self.normal,
        }
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
