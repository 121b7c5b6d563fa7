//! Prescribed rigid motion of a surface wall (issue 27): `[[wall]] motion
//! = { velocity, angular_velocity, center, start, end }` and `oscillation =
//! { amplitude, frequency }`, for planes, cylinders and meshes.
//!
//! **The pose.** A point X of the wall as given in the scene file (its
//! reference placement, time 0) is at
//!
//! x(t) = c(t) + R(t) (X − c₀),  c(t) = c₀ + d(t),
//!
//! with c₀ the `center`, the translation d(t) = V τ(t) + a sin(2π f t)
//! and R(t) the rotation by the angle |ω| τ(t) about ω̂ (Rodrigues'
//! formula, R = I + sin θ K + (1 − cos θ) K², K the cross-product matrix
//! of ω̂: exact for a constant ω, no accumulated steps). τ(t) =
//! clamp(t, start, end) − start is the time the motion has run; the
//! oscillation runs from t = 0 for ever (a shaker: x(t) = a sin(2π f t)).
//! The pose is a function of the time only, so a restart at t continues
//! with the same bits, and every thread and rank computes the same pose.
//!
//! **The surface velocity** of the wall at a point p is the rigid-body
//! field v(p) = ḋ(t) + ω × (p − c(t)), ḋ = V + 2π f a cos(2π f t), with V
//! and ω counted only while start ≤ t < end.
//!
//! **The displacement bound** of the neighbour lists: a surface point at
//! x_b at time t_b is at c(t) + R(t) R(t_b)ᵀ (x_b − c(t_b)) at t, so it
//! moved by d(t) − d(t_b) + (R_rel − I)(x_b − c(t_b)), whose length is at
//! most |d(t) − d(t_b)| + 2 sin(θ_rel/2) |x_b − c(t_b)| (θ_rel the angle
//! turned between the two times, capped at π); |x_b − c(t_b)| is bounded
//! by the farthest corner of the domain (only surface points where
//! spheres are count).

use serde::{Deserialize, Serialize};

use crate::error::SceneError;
use crate::io::config::checks::{check, finite3};
use crate::limits;

/// `motion = { velocity, angular_velocity, center, start, end }` of a
/// `[[wall]]` entry (m/s, rad/s, m, s, s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionConfig {
    #[serde(default)]
    pub velocity: [f64; 3],
    #[serde(default)]
    pub angular_velocity: [f64; 3],
    #[serde(default)]
    pub center: [f64; 3],
    #[serde(default)]
    pub start: f64,
    #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
    pub end: f64,
}

/// `oscillation = { amplitude, frequency }` (m, Hz): x(t) = a sin(2π f t).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OscillationConfig {
    pub amplitude: [f64; 3],
    pub frequency: f64,
}

fn infinite() -> f64 {
    f64::INFINITY
}

fn is_infinite(x: &f64) -> bool {
    *x == f64::INFINITY
}

/// The largest angular speed accepted, rad/s (a wall turning faster is
/// not a drum but a typo).
pub const MAX_ANGULAR_SPEED: f64 = 1e6;
/// The largest oscillation frequency accepted, Hz.
pub const MAX_FREQUENCY: f64 = 1e9;
/// The largest oscillation amplitude accepted, m.
pub const MAX_AMPLITUDE: f64 = 1e3;

/// Checks `key.motion` and `key.oscillation` (`key` = `wall[K]`): the
/// first bad value named with its range.
pub fn validate(
    key: &str,
    motion: Option<&MotionConfig>,
    oscillation: Option<&OscillationConfig>,
) -> Result<(), SceneError> {
    if let Some(m) = motion {
        crate::io::config::checks::speed(&format!("{key}.motion.velocity"), m.velocity)?;
        let k = format!("{key}.motion.angular_velocity");
        finite3(&k, m.angular_velocity, "rad/s")?;
        let w = limits::norm(m.angular_velocity);
        check(
            w <= MAX_ANGULAR_SPEED,
            &k,
            format!("{:?} (|ω| = {} rad/s)", m.angular_velocity, limits::show(w)),
            &format!("|ω| ≤ {} rad/s", limits::show(MAX_ANGULAR_SPEED)),
        )?;
        finite3(&format!("{key}.motion.center"), m.center, "m")?;
        check(
            m.start.is_finite() && m.start >= 0.0,
            &format!("{key}.motion.start"),
            limits::show(m.start),
            "finite and ≥ 0, in s",
        )?;
        check(
            !m.end.is_nan() && m.end > m.start,
            &format!("{key}.motion.end"),
            limits::show(m.end),
            &format!(
                "> motion.start = {} s, or inf (never stops), in s",
                limits::show(m.start)
            ),
        )?;
    }
    if let Some(o) = oscillation {
        let k = format!("{key}.oscillation.amplitude");
        finite3(&k, o.amplitude, "m")?;
        let a = limits::norm(o.amplitude);
        check(
            a <= MAX_AMPLITUDE,
            &k,
            format!("{:?} (|a| = {} m)", o.amplitude, limits::show(a)),
            &format!("|a| ≤ {} m", limits::show(MAX_AMPLITUDE)),
        )?;
        check(
            o.frequency.is_finite() && o.frequency > 0.0 && o.frequency <= MAX_FREQUENCY,
            &format!("{key}.oscillation.frequency"),
            limits::show(o.frequency),
            &format!("> 0 and ≤ {} Hz", limits::show(MAX_FREQUENCY)),
        )?;
        let v = 2.0 * std::f64::consts::PI * o.frequency * a;
        check(
            v <= limits::MAX_SPEED,
            &format!("{key}.oscillation"),
            format!(
                "amplitude {:?} m at {} Hz (peak speed 2π f |a| = {} m/s)",
                o.amplitude,
                limits::show(o.frequency),
                limits::show(v)
            ),
            &format!("a peak speed ≤ {} m/s", limits::show(limits::MAX_SPEED)),
        )?;
    }
    Ok(())
}

/// A wall's prescribed motion in SI (the engine's input).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallMotion {
    /// V, m/s.
    pub velocity: [f64; 3],
    /// ω, rad/s, about the axis through `center`.
    pub angular_velocity: [f64; 3],
    /// c₀, m: the rotation centre at t = 0 (it moves with the wall).
    pub center: [f64; 3],
    /// s.
    pub start: f64,
    /// s (∞: never stops).
    pub end: f64,
    /// (a, m; f, Hz) of the sinusoidal translation a sin(2π f t).
    pub oscillation: Option<([f64; 3], f64)>,
}

impl WallMotion {
    /// From the validated entries (`None` when neither is given).
    pub fn from_config(
        motion: Option<&MotionConfig>,
        oscillation: Option<&OscillationConfig>,
    ) -> Option<Self> {
        if motion.is_none() && oscillation.is_none() {
            return None;
        }
        let m = motion.cloned().unwrap_or(MotionConfig {
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            center: [0.0; 3],
            start: 0.0,
            end: f64::INFINITY,
        });
        Some(Self {
            velocity: m.velocity,
            angular_velocity: m.angular_velocity,
            center: m.center,
            start: m.start,
            end: m.end,
            oscillation: oscillation.map(|o| (o.amplitude, o.frequency)),
        })
    }

    /// τ(t): the time the prescribed velocities have acted by t, s.
    fn elapsed(&self, t: f64) -> f64 {
        t.clamp(self.start, self.end) - self.start
    }

    /// Whether V and ω act at t (start ≤ t < end).
    fn active(&self, t: f64) -> bool {
        t >= self.start && t < self.end
    }

    /// The translation d(t), m.
    fn shift(&self, t: f64) -> [f64; 3] {
        let tau = self.elapsed(t);
        let mut d = self.velocity.map(|v| v * tau);
        if let Some((a, f)) = self.oscillation {
            let s = (2.0 * std::f64::consts::PI * f * t).sin();
            for k in 0..3 {
                d[k] += a[k] * s;
            }
        }
        d
    }

    /// The angle turned by t about ω̂, rad.
    pub fn angle(&self, t: f64) -> f64 {
        limits::norm(self.angular_velocity) * self.elapsed(t)
    }

    /// The wall's pose and velocities at time t (s).
    pub fn state(&self, t: f64) -> WallState {
        let d = self.shift(t);
        let center = [
            self.center[0] + d[0],
            self.center[1] + d[1],
            self.center[2] + d[2],
        ];
        let active = self.active(t);
        let mut velocity = if active { self.velocity } else { [0.0; 3] };
        if let Some((a, f)) = self.oscillation {
            let w = 2.0 * std::f64::consts::PI * f;
            let c = (w * t).cos();
            for k in 0..3 {
                velocity[k] += a[k] * w * c;
            }
        }
        WallState {
            rotation: rodrigues(self.angular_velocity, self.angle(t)),
            center0: self.center,
            center,
            velocity,
            spin: if active {
                self.angular_velocity
            } else {
                [0.0; 3]
            },
        }
    }

    /// An upper bound of how far any surface point within `reach` (m) of
    /// the centre at time `from` moved between `from` and `to` (s), m
    /// (module doc).
    pub fn displacement_bound(&self, from: f64, to: f64, reach: f64) -> f64 {
        let (a, b) = (self.shift(from), self.shift(to));
        let shift = limits::norm([b[0] - a[0], b[1] - a[1], b[2] - a[2]]);
        let turned = (self.angle(to) - self.angle(from))
            .abs()
            .min(std::f64::consts::PI);
        shift + 2.0 * (0.5 * turned).sin() * reach
    }
}

/// The rotation matrix by `angle` (rad) about the direction of `omega`
/// (identity when ω = 0): Rodrigues' formula.
pub fn rodrigues(omega: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
    let w = limits::norm(omega);
    let mut r = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    if w == 0.0 || angle == 0.0 {
        return r;
    }
    let u = omega.map(|x| x / w);
    let (s, c) = angle.sin_cos();
    let k = [[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]];
    for i in 0..3 {
        for j in 0..3 {
            // K² = u uᵀ − I.
            let k2 = u[i] * u[j] - if i == j { 1.0 } else { 0.0 };
            r[i][j] += s * k[i][j] + (1.0 - c) * k2;
        }
    }
    r
}

/// A moving wall at one instant: its pose (x = c + R (X − c₀)) and its
/// rigid-body velocity field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallState {
    /// R(t).
    pub rotation: [[f64; 3]; 3],
    /// c₀, m.
    pub center0: [f64; 3],
    /// c(t), m.
    pub center: [f64; 3],
    /// ḋ(t), m/s: the velocity of the centre.
    pub velocity: [f64; 3],
    /// ω(t), rad/s.
    pub spin: [f64; 3],
}

#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl WallState {
    /// The surface velocity at point `p` (m): ḋ + ω × (p − c), m/s.
    #[inline(always)]
    pub fn velocity_at(&self, p: [f64; 3]) -> [f64; 3] {
        let w = cross(
            self.spin,
            [
                p[0] - self.center[0],
                p[1] - self.center[1],
                p[2] - self.center[2],
            ],
        );
        [
            self.velocity[0] + w[0],
            self.velocity[1] + w[1],
            self.velocity[2] + w[2],
        ]
    }

    /// R v.
    #[inline(always)]
    pub fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2])
    }

    /// Rᵀ v.
    #[inline(always)]
    pub fn rotate_back(&self, v: [f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        [0, 1, 2].map(|j| r[0][j] * v[0] + r[1][j] * v[1] + r[2][j] * v[2])
    }

    /// Where reference point X is now: c + R (X − c₀), m.
    #[inline(always)]
    pub fn place(&self, x: [f64; 3]) -> [f64; 3] {
        let y = self.rotate([
            x[0] - self.center0[0],
            x[1] - self.center0[1],
            x[2] - self.center0[2],
        ]);
        [
            self.center[0] + y[0],
            self.center[1] + y[1],
            self.center[2] + y[2],
        ]
    }

    /// The reference point of point x now: c₀ + Rᵀ (x − c), m.
    #[inline(always)]
    pub fn unplace(&self, x: [f64; 3]) -> [f64; 3] {
        let y = self.rotate_back([
            x[0] - self.center[0],
            x[1] - self.center[1],
            x[2] - self.center[2],
        ]);
        [
            self.center0[0] + y[0],
            self.center0[1] + y[1],
            self.center0[2] + y[2],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drum() -> WallMotion {
        WallMotion {
            velocity: [0.3, -0.1, 0.2],
            angular_velocity: [0.4, 1.1, -0.7],
            center: [1.0, 2.0, -0.5],
            start: 0.1,
            end: 2.0,
            oscillation: Some(([1e-3, 0.0, 2e-3], 7.0)),
        }
    }

    /// R is orthonormal, turns ω̂ onto itself and a vector ⟂ ω̂ by the
    /// angle (cos of the angle between them, by hand: cos θ).
    #[test]
    fn rodrigues_is_the_rotation_by_the_angle_about_the_axis() {
        let w = [0.0, 0.0, 2.0];
        let r = rodrigues(w, 0.3);
        let s = WallState {
            rotation: r,
            center0: [0.0; 3],
            center: [0.0; 3],
            velocity: [0.0; 3],
            spin: w,
        };
        let x = s.rotate([1.0, 0.0, 0.0]);
        assert!((x[0] - 0.3f64.cos()).abs() < 1e-15 && (x[1] - 0.3f64.sin()).abs() < 1e-15);
        let m = drum();
        let r = rodrigues(m.angular_velocity, 1.7);
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| r[i][k] * r[j][k]).sum();
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((dot - e).abs() < 1e-15, "{i}{j}: {dot}");
            }
        }
        let s = WallState { rotation: r, ..s };
        let u = m
            .angular_velocity
            .map(|x| x / limits::norm(m.angular_velocity));
        let ru = s.rotate(u);
        for k in 0..3 {
            assert!((ru[k] - u[k]).abs() < 1e-15);
        }
        let back = s.unplace(s.place([0.3, -2.0, 5.0]));
        for (a, b) in back.iter().zip([0.3, -2.0, 5.0]) {
            assert!((a - b).abs() < 1e-14);
        }
    }

    /// The surface velocity is the time derivative of a material point's
    /// placed position: central differences of x(t) = c(t) + R(t)(X − c₀)
    /// (h = 1e-6 s: truncation ~h² |x'''| ~ 1e-12 m/s, rounding ~1e-16/h
    /// ~ 1e-10 m/s → 1e-8 allowed).
    #[test]
    fn surface_velocity_is_the_derivative_of_the_pose() {
        let m = drum();
        let big_x = [0.7, -0.4, 1.9];
        let h = 1e-6;
        for t in [0.05, 0.5, 1.3, 2.5] {
            let (a, b) = (m.state(t - h), m.state(t + h));
            let (xa, xb) = (a.place(big_x), b.place(big_x));
            let fd = [0, 1, 2].map(|k| (xb[k] - xa[k]) / (2.0 * h));
            let s = m.state(t);
            let v = s.velocity_at(s.place(big_x));
            for k in 0..3 {
                assert!((v[k] - fd[k]).abs() < 1e-8, "t {t}, {k}: {v:?} vs {fd:?}");
            }
        }
    }

    /// The bound covers every material point within the reach: 2,000
    /// points of a ball of radius 3 m about c(t_b), between pairs of times.
    #[test]
    fn displacement_bound_covers_every_point() {
        let m = drum();
        let mut seed = 1u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for (t0, t1) in [(0.0, 0.3), (0.5, 0.51), (1.0, 3.0), (1.9, 2.2)] {
            let (a, b) = (m.state(t0), m.state(t1));
            let bound = m.displacement_bound(t0, t1, 3.0 * 3f64.sqrt());
            for _ in 0..2000 {
                let x = [0, 1, 2].map(|k| a.center[k] + 3.0 * rnd());
                let big_x = a.unplace(x);
                let y = b.place(big_x);
                let d = limits::norm([y[0] - x[0], y[1] - x[1], y[2] - x[2]]);
                assert!(d <= bound * (1.0 + 1e-12), "{d} > {bound}");
            }
        }
    }

    /// Bad values are named with the key and the range.
    #[test]
    fn refusals_name_key_value_and_range() {
        let ok = MotionConfig {
            velocity: [0.0, 0.0, -1e-3],
            angular_velocity: [0.0; 3],
            center: [0.0; 3],
            start: 0.0,
            end: f64::INFINITY,
        };
        assert!(validate("wall[1]", Some(&ok), None).is_ok());
        let cases = [
            (
                MotionConfig {
                    end: 0.0,
                    ..ok.clone()
                },
                "wall[1].motion.end",
            ),
            (
                MotionConfig {
                    start: -1.0,
                    ..ok.clone()
                },
                "wall[1].motion.start",
            ),
            (
                MotionConfig {
                    angular_velocity: [f64::NAN, 0.0, 0.0],
                    ..ok.clone()
                },
                "wall[1].motion.angular_velocity",
            ),
            (
                MotionConfig {
                    velocity: [1e9, 0.0, 0.0],
                    ..ok.clone()
                },
                "wall[1].motion.velocity",
            ),
        ];
        for (c, key) in cases {
            let e = validate("wall[1]", Some(&c), None).unwrap_err().to_string();
            assert!(e.contains(key) && e.contains("allowed"), "{e}");
        }
        let o = OscillationConfig {
            amplitude: [1e-3, 0.0, 0.0],
            frequency: 0.0,
        };
        let e = validate("wall[0]", None, Some(&o)).unwrap_err().to_string();
        assert!(e.contains("wall[0].oscillation.frequency"), "{e}");
    }
}
