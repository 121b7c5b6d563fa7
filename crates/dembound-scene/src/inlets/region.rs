//! The region an inlet places its spheres in (`[[inlet]] region`): a box
//! or a cylinder, its volume, bounds and uniform centres.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// An inlet's region, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InletRegion {
    Box {
        lower: [f64; 3],
        upper: [f64; 3],
    },
    /// `axis` a unit vector; `center` the middle of the axis segment of
    /// `length`.
    Cylinder {
        center: [f64; 3],
        axis: [f64; 3],
        radius: f64,
        length: f64,
    },
}

/// `v` over its length (the zero vector stays zero).
pub fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n > 0.0 {
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

impl InletRegion {
    /// The axis-aligned bounding box, m.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        match *self {
            InletRegion::Box { lower, upper } => (lower, upper),
            InletRegion::Cylinder {
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
            InletRegion::Box { lower, upper } => {
                (upper[0] - lower[0]) * (upper[1] - lower[1]) * (upper[2] - lower[2])
            }
            InletRegion::Cylinder { radius, length, .. } => PI * radius * radius * length,
        }
    }

    /// A sphere of radius `r` (m) fits wholly inside.
    pub fn fits(&self, r: f64) -> bool {
        match *self {
            InletRegion::Box { lower, upper } => (0..3).all(|a| upper[a] - lower[a] >= 2.0 * r),
            InletRegion::Cylinder { radius, length, .. } => radius >= r && length >= 2.0 * r,
        }
    }

    /// A centre uniform in the region shrunk by `r` (m): the sphere lies
    /// wholly inside.
    pub(crate) fn sample(&self, rng: &mut ChaCha8Rng, r: f64) -> [f64; 3] {
        match *self {
            InletRegion::Box { lower, upper } => [0, 1, 2].map(|a| {
                let (lo, hi) = (lower[a] + r, upper[a] - r);
                lo + (hi - lo) * rng.gen::<f64>()
            }),
            InletRegion::Cylinder {
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
