//! Placing a mesh read from a file: x' = R (s x) + t, scale s first, then
//! the rotation R about the origin (axis, angle in degrees, right-handed),
//! then the translation t (LIGGGHTS `fix mesh/surface`'s order: scale,
//! rotate, move).

use super::geometry::{cross, dot, norm};
use super::read::MeshError;

/// The placement of a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    /// Scale factor s (> 0): file units to metres.
    pub scale: f64,
    /// Translation t, m.
    pub translate: [f64; 3],
    /// Rotation axis (any non-zero length).
    pub axis: [f64; 3],
    /// Rotation angle, degrees.
    pub angle_degrees: f64,
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            scale: 1.0,
            translate: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            angle_degrees: 0.0,
        }
    }
}

impl Transform {
    /// Checks every value's range.
    pub fn validate(&self) -> Result<(), MeshError> {
        let bad = |key, value: String, allowed| MeshError::Transform {
            key,
            value,
            allowed,
        };
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(bad("scale", self.scale.to_string(), "finite, > 0"));
        }
        if !self.translate.iter().all(|c| c.is_finite()) {
            return Err(bad("translate", format!("{:?}", self.translate), "finite"));
        }
        if !self.angle_degrees.is_finite() {
            return Err(bad(
                "rotate.angle",
                self.angle_degrees.to_string(),
                "finite, degrees",
            ));
        }
        let l = axis_length(self.axis);
        if !(l.is_finite() && l > 0.0) {
            return Err(bad(
                "rotate.axis",
                format!("{:?}", self.axis),
                "finite, non-zero",
            ));
        }
        Ok(())
    }

    /// The placed point. The identity is exact (an angle of 0 skips the
    /// rotation, a scale of 1 multiplies exactly, a zero translation
    /// adds exactly).
    pub fn apply(&self, x: [f64; 3]) -> [f64; 3] {
        let mut p = x.map(|c| c * self.scale);
        if self.angle_degrees != 0.0 {
            // Rodrigues: p cos θ + (k × p) sin θ + k (k·p)(1 − cos θ).
            let l = axis_length(self.axis);
            let k = self.axis.map(|c| c / l);
            let (s, c) = self.angle_degrees.to_radians().sin_cos();
            let kxp = cross(k, p);
            let kp = dot(k, p);
            p = [0, 1, 2].map(|i| p[i] * c + kxp[i] * s + k[i] * kp * (1.0 - c));
        }
        [0, 1, 2].map(|i| p[i] + self.translate[i])
    }
}

/// |axis|, m: the plain root of the sum of squares (the bits of every
/// axis of ordinary length), or, where that square underflows or
/// overflows (|axis| ≤ 1e-150 or not finite: [0, 0, 1e-160] squares to a
/// subnormal that keeps 11 bits, [0, 0, 1e-170] to 0, [0, 0, 1e200] to
/// ∞), the norm scaled by the largest component, so that the rotation
/// axis is of unit length to round-off (as `walls::plane` does for a
/// plane's normal).
fn axis_length(axis: [f64; 3]) -> f64 {
    let l = norm(axis);
    if l.is_finite() && l > 1e-150 {
        l
    } else {
        crate::limits::norm(axis)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Scale 2, a quarter turn about z, then a shift: (1, 0, 0) → (2, 0, 0)
    /// → (0, 2, 0) → (1, 2, 3).
    #[test]
    fn scale_rotate_translate_in_that_order() {
        let t = Transform {
            scale: 2.0,
            translate: [1.0, 0.0, 3.0],
            axis: [0.0, 0.0, 5.0],
            angle_degrees: 90.0,
        };
        let p = t.apply([1.0, 0.0, 0.0]);
        // cos 90° is 6e-17 in f64: 1e-15 absolute.
        for (a, b) in p.iter().zip([1.0, 2.0, 3.0]) {
            assert!((a - b).abs() < 1e-15, "{p:?}");
        }
        assert_eq!(
            Transform::default().apply([0.1, -0.2, 0.3]),
            [0.1, -0.2, 0.3]
        );
    }

    /// Axes of any finite non-zero length turn alike. Along z, 1e-160
    /// (its square a subnormal keeping 11 bits: the axis over that root
    /// was 1 + 5.7e-6 long, the rotation stretched by as much), 1e-170
    /// and 1e200 (squares 0 and ∞: refused as zero or infinite) give the
    /// quarter turn of [0, 0, 1] to the bit; skew tiny axes keep a point's
    /// distance from the origin (rigid) to round-off.
    #[test]
    fn tiny_and_huge_axes_rotate_as_unit_ones() {
        let turn = |axis: [f64; 3], angle_degrees: f64, p: [f64; 3]| {
            let t = Transform {
                axis,
                angle_degrees,
                ..Default::default()
            };
            t.validate().map(|()| t.apply(p))
        };
        let unit = turn([0.0, 0.0, 1.0], 90.0, [1.0, 0.0, 0.0]).unwrap();
        for z in [1e-160, 1e-170, 1e200] {
            assert_eq!(turn([0.0, 0.0, z], 90.0, [1.0, 0.0, 0.0]), Ok(unit), "{z}");
        }
        let p = [1.0, 2.0, 3.0];
        for axis in [[1e-160, 1e-160, 0.0], [3e-160, 0.0, 4e-160], [0.0, 2e-170, 1e-170]] {
            let q = turn(axis, 37.0, p).unwrap();
            // |p| = √14 ≈ 3.7: a rotation's few roundings, < 1e-15 × 4.
            assert!((norm(q) - norm(p)).abs() < 4e-15, "{axis:?}: {q:?}");
        }
    }

    #[test]
    fn out_of_range_values_are_named() {
        let t = Transform {
            scale: 0.0,
            ..Default::default()
        };
        let e = t.validate().unwrap_err().to_string();
        assert!(e.contains("scale = 0") && e.contains("> 0"), "{e}");
        let t = Transform {
            axis: [0.0; 3],
            ..Default::default()
        };
        assert!(t
            .validate()
            .unwrap_err()
            .to_string()
            .contains("rotate.axis"));
    }
}
