//! The region of an inlet or an outlet (`[[inlet]] region`, `[[outlet]]
//! region`, issue 28): `{ box = { lower, upper } }` or `{ cylinder = {
//! center, axis, radius, length } }`, m; one type for the scene file and
//! the engine. Its volume, bounds, uniform centres (inlets) and whether
//! it holds a point (outlets).

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::error::SceneError;
use crate::io::config::checks::{check, finite3, nonzero3, positive};

/// A region, m: exactly one shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Region {
    /// An axis-aligned box.
    Box { lower: [f64; 3], upper: [f64; 3] },
    /// A solid circular cylinder: `center` the middle of its axis segment
    /// of `length`, `axis` its direction (a unit vector in the engine:
    /// [`Region::normalized`]), `radius`.
    Cylinder {
        center: [f64; 3],
        axis: [f64; 3],
        radius: f64,
        length: f64,
    },
}

/// `v` over its length (the zero vector stays zero). Where the plain
/// square underflows or overflows (|v| ≤ 1e-150 or not finite: [0, 0,
/// 1e-170] squares to 0 and stayed unnormalised, [0, 0, 1e200] to ∞ and
/// became 0, both accepted as "finite, non-zero" axes), the length is the
/// norm scaled by the largest component (every other vector keeps the
/// plain root's bits).
pub fn unit(v: [f64; 3]) -> [f64; 3] {
    let mut n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if !(n.is_finite() && n > 1e-150) {
        n = crate::limits::norm(v);
    }
    if n > 0.0 && n.is_finite() {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        v
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Two unit vectors perpendicular to the unit `a` and to each other.
fn perpendiculars(a: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let t = if a[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = unit(cross(a, t));
    (u, cross(a, u))
}

impl Region {
    /// The same region with a unit cylinder axis (the engine's form).
    pub fn normalized(self) -> Region {
        match self {
            Region::Cylinder {
                center,
                axis,
                radius,
                length,
            } => Region::Cylinder {
                center,
                axis: unit(axis),
                radius,
                length,
            },
            other => other,
        }
    }

    /// Checks the region of the entry `key` (e.g. `outlet[0].region`):
    /// the first bad value named with its key and range.
    pub fn validate(&self, key: &str) -> Result<(), SceneError> {
        match *self {
            Region::Box { lower, upper } => {
                finite3(&format!("{key}.box.lower"), lower, "m")?;
                finite3(&format!("{key}.box.upper"), upper, "m")?;
                check(
                    (0..3).all(|a| upper[a] > lower[a]),
                    &format!("{key}.box.upper"),
                    format!("{upper:?}"),
                    &format!("each coordinate > {key}.box.lower's ({lower:?}), m"),
                )
            }
            Region::Cylinder {
                center,
                axis,
                radius,
                length,
            } => {
                finite3(&format!("{key}.cylinder.center"), center, "m")?;
                nonzero3(&format!("{key}.cylinder.axis"), axis)?;
                positive(&format!("{key}.cylinder.radius"), radius, "m")?;
                positive(&format!("{key}.cylinder.length"), length, "m")
            }
        }
    }

    /// The point `x` (m) is inside (the surface included). The cylinder's
    /// axis must be a unit vector ([`Region::normalized`]).
    #[inline]
    pub fn holds(&self, x: &[f64; 3]) -> bool {
        match *self {
            Region::Box { lower, upper } => (0..3).all(|a| x[a] >= lower[a] && x[a] <= upper[a]),
            Region::Cylinder {
                center,
                axis,
                radius,
                length,
            } => {
                let d = [0, 1, 2].map(|a| x[a] - center[a]);
                let h = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
                // The distance from the axis: the part of d across it.
                let p = [0, 1, 2].map(|a| d[a] - h * axis[a]);
                h.abs() <= 0.5 * length
                    && p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= radius * radius
            }
        }
    }

    /// The axis-aligned bounding box, m.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        match *self {
            Region::Box { lower, upper } => (lower, upper),
            Region::Cylinder {
                center,
                axis,
                radius,
                length,
            } => {
                let e = [0, 1, 2].map(|a| {
                    0.5 * length * axis[a].abs()
                        + radius * (1.0 - axis[a] * axis[a]).max(0.0).sqrt()
                });
                (
                    [0, 1, 2].map(|a| center[a] - e[a]),
                    [0, 1, 2].map(|a| center[a] + e[a]),
                )
            }
        }
    }

    /// m³.
    pub fn volume(&self) -> f64 {
        match *self {
            Region::Box { lower, upper } => {
                (upper[0] - lower[0]) * (upper[1] - lower[1]) * (upper[2] - lower[2])
            }
            Region::Cylinder { radius, length, .. } => PI * radius * radius * length,
        }
    }

    /// A sphere of radius `r` (m) fits wholly inside.
    pub fn fits(&self, r: f64) -> bool {
        match *self {
            Region::Box { lower, upper } => (0..3).all(|a| upper[a] - lower[a] >= 2.0 * r),
            Region::Cylinder { radius, length, .. } => radius >= r && length >= 2.0 * r,
        }
    }

    /// A centre uniform in the region shrunk by `r` (m): the sphere lies
    /// wholly inside.
    pub(crate) fn sample(&self, rng: &mut ChaCha8Rng, r: f64) -> [f64; 3] {
        match *self {
            Region::Box { lower, upper } => [0, 1, 2].map(|a| {
                let (lo, hi) = (lower[a] + r, upper[a] - r);
                lo + (hi - lo) * rng.gen::<f64>()
            }),
            Region::Cylinder {
                center,
                axis,
                radius,
                length,
            } => {
                // Uniform in the disc: radius √u (area element r dr).
                let (u, w) = perpendiculars(axis);
                let s = (radius - r) * rng.gen::<f64>().sqrt();
                let phi = 2.0 * PI * rng.gen::<f64>();
                let h = (0.5 * length - r) * (2.0 * rng.gen::<f64>() - 1.0);
                let (c, si) = (s * phi.cos(), s * phi.sin());
                [0, 1, 2].map(|a| center[a] + c * u[a] + si * w[a] + h * axis[a])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cylinder along (1, 1, 0) (written unnormalised) about the origin,
    /// radius 1, length 4: points by their axial coordinate h and distance
    /// s from the axis, inside exactly when |h| ≤ 2 and s ≤ 1 (surface
    /// included; the test points sit 1e-9 off it, far above rounding).
    #[test]
    fn a_tilted_cylinder_holds_by_its_radius_and_length() {
        let c = Region::Cylinder {
            center: [0.0; 3],
            axis: [1.0, 1.0, 0.0],
            radius: 1.0,
            length: 4.0,
        }
        .normalized();
        let a = unit([1.0, 1.0, 0.0]);
        let across = unit([1.0, -1.0, 0.0]);
        let at = |h: f64, s: f64, up: bool| {
            let p = if up { [0.0, 0.0, 1.0] } else { across };
            [0, 1, 2].map(|k| h * a[k] + s * p[k])
        };
        for up in [false, true] {
            assert!(c.holds(&at(0.0, 0.0, up)));
            assert!(c.holds(&at(2.0 - 1e-9, 1.0 - 1e-9, up)));
            assert!(c.holds(&at(-2.0 + 1e-9, 1.0 - 1e-9, up)));
            assert!(!c.holds(&at(0.0, 1.0 + 1e-9, up)));
            assert!(!c.holds(&at(2.0 + 1e-9, 0.0, up)));
            assert!(!c.holds(&at(-2.0 - 1e-9, 0.5, up)));
        }
        // Inside the bounding box, outside the radius: (0.9, -0.9, 0) is
        // √1.62 ≈ 1.27 from the axis.
        let (lo, hi) = c.bounds();
        let p = [0.9, -0.9, 0.0];
        assert!((0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]));
        assert!(!c.holds(&p));
    }

    /// A cylinder axis of any finite non-zero length is the unit one:
    /// along z, 1e-160 (a subnormal square: 1 + 5.7e-6 long before),
    /// 1e-170 and 1e200 (squares 0 and ∞: left 1e-170 long, or made 0)
    /// give [0, 0, 1] to the bit.
    #[test]
    fn tiny_and_huge_cylinder_axes_normalise_to_unit_ones() {
        let c = |z: f64| {
            Region::Cylinder {
                center: [0.0; 3],
                axis: [0.0, 0.0, z],
                radius: 1.0,
                length: 4.0,
            }
            .normalized()
        };
        for z in [1e-160, 1e-170, 1e200] {
            assert_eq!(c(z), c(1.0), "{z}");
        }
    }

    /// The scene file's spellings, and the keys of bad values.
    #[test]
    fn reads_both_shapes_and_names_bad_keys() {
        #[derive(Deserialize)]
        struct S {
            region: Region,
        }
        let r = |t: &str| toml::from_str::<S>(t).map(|s| s.region);
        assert_eq!(
            r("region = { box = { lower = [0, 0, 0], upper = [1, 2, 3] } }").unwrap(),
            Region::Box {
                lower: [0.0; 3],
                upper: [1.0, 2.0, 3.0]
            }
        );
        let c = r("region = { cylinder = { center = [0, 0, 1], axis = [0, 0, 2], radius = 0.5, length = 1 } }")
            .unwrap();
        assert_eq!(c.volume(), PI * 0.25);
        assert!(r(
            "region = { cylinder = { center = [0, 0, 1], axis = [0, 0, 2], radius = 0.5 } }"
        )
        .is_err());
        assert!(r("region = { sphere = { center = [0, 0, 1] } }").is_err());
        let msg = |reg: Region| reg.validate("outlet[3].region").unwrap_err().to_string();
        let m = msg(Region::Box {
            lower: [0.0; 3],
            upper: [1.0, 0.0, 1.0],
        });
        assert!(m.contains("outlet[3].region.box.upper"), "{m}");
        let m = msg(Region::Cylinder {
            center: [0.0; 3],
            axis: [0.0; 3],
            radius: 1.0,
            length: 1.0,
        });
        assert!(m.contains("outlet[3].region.cylinder.axis"), "{m}");
    }
}
