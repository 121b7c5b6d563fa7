//! A force-controlled wall (issue 27 item 2): `[[wall]] servo = { force,
//! axis, max_velocity, gain }` moves a plane, cylinder or mesh along
//! `axis` to hold the spheres' push on it at `force` — the piston of an
//! oedometer or consolidation test.
//!
//! **The controller** is LIGGGHTS's `servo` mesh module with its default
//! proportional controller (`fix mesh/surface/stress/servo ... ctrlPV
//! force axis ... target_val F vel_max v kp k`; LIGGGHTS-PUBLIC
//! doc/mesh_module_servo.txt and src/fix_mesh_surface_stress_servo.cpp;
//! no integral or derivative part, no `mode auto`): after each force
//! evaluation, with N = −F_w·â the push of the spheres against the wall's
//! motion along the unit axis â (F_w the total force the wall takes from
//! the spheres, the sum the wall loads use),
//!
//! v = clamp(k v_max (F − N)/F, −v_max, v_max),
//!
//! and the wall moves by v Δt along â before the next force evaluation
//! (LIGGGHTS: the velocity set in `final_integrate`, the mesh moved by
//! Δt v in the next `initial_integrate`). With no sphere touching it the
//! wall advances at k v_max (at most v_max), pushed too hard it backs
//! off. At rest N = F exactly: the wall integrates the error, so a
//! proportional gain leaves none.
//!
//! **Stability.** Against a packing of stiffness K = dN/dx (N/m) the
//! discrete loop x ← x + Δt k v_max (F − N)/F is stable for
//! Δt k v_max K/F < 2 and monotone below 1; the sphere's own inertia
//! needs damping to settle (an undamped contact rings for ever). But the
//! contacts' dashpots see the wall's speed: N holds c v (c the summed
//! damping coefficient of the wall's contacts, N s/m), so the speed
//! feeds back on itself within one step, v ← k v_max (F − N_el − c v)/F,
//! which alternates and grows unless k v_max c/F < 1 (seen: a lid on a
//! damped bed at k v_max c/F ≈ 1 chatters between ±v from step to
//! step). Keep k v_max well below F/c.
//!
//! The wall keeps its orientation; its pose is the reference placement
//! moved by s â, s the offset integrated so far (in checkpoints).

use serde::{Deserialize, Serialize};

use crate::error::SceneError;
use crate::io::config::checks::check;
use crate::limits;

/// `servo = { force, axis, max_velocity, gain }` of a `[[wall]]` entry
/// (N, direction, m/s, dimensionless).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServoConfig {
    /// F, N: the push to hold (> 0).
    pub force: f64,
    /// The direction the wall moves to press harder (its length is
    /// ignored).
    pub axis: [f64; 3],
    /// v_max, m/s.
    pub max_velocity: f64,
    /// k (LIGGGHTS's `kp`, default 0.01 as there).
    #[serde(default = "default_gain")]
    pub gain: f64,
}

/// LIGGGHTS's default `kp`.
pub const DEFAULT_GAIN: f64 = 1e-2;
/// The largest servo force accepted, N.
pub const MAX_FORCE: f64 = 1e12;
/// The largest gain accepted.
pub const MAX_GAIN: f64 = 1e6;

fn default_gain() -> f64 {
    DEFAULT_GAIN
}

/// A servo in SI (the engine's input): the unit axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Servo {
    /// F, N.
    pub force: f64,
    /// â (unit).
    pub axis: [f64; 3],
    /// v_max, m/s.
    pub max_velocity: f64,
    /// k.
    pub gain: f64,
}

/// Checks `key.servo` (`key` = `wall[K]`): the first bad value named with
/// its range.
pub fn validate(key: &str, s: &ServoConfig) -> Result<(), SceneError> {
    check(
        s.force.is_finite() && s.force > 0.0 && s.force <= MAX_FORCE,
        &format!("{key}.servo.force"),
        format!("{} N", limits::show(s.force)),
        &format!("> 0 and ≤ {} N", limits::show(MAX_FORCE)),
    )?;
    check(
        s.axis.iter().all(|x| x.is_finite()) && limits::norm(s.axis) > 0.0,
        &format!("{key}.servo.axis"),
        format!("{:?}", s.axis),
        "three finite numbers, not all zero (a direction)",
    )?;
    check(
        s.max_velocity.is_finite() && s.max_velocity > 0.0 && s.max_velocity <= limits::MAX_SPEED,
        &format!("{key}.servo.max_velocity"),
        format!("{} m/s", limits::show(s.max_velocity)),
        &format!("> 0 and ≤ {} m/s", limits::show(limits::MAX_SPEED)),
    )?;
    check(
        s.gain.is_finite() && s.gain > 0.0 && s.gain <= MAX_GAIN,
        &format!("{key}.servo.gain"),
        limits::show(s.gain),
        &format!("> 0 and ≤ {} (dimensionless)", limits::show(MAX_GAIN)),
    )?;
    Ok(())
}

impl Servo {
    /// From a validated entry.
    pub fn from_config(c: &ServoConfig) -> Self {
        let n = limits::norm(c.axis);
        Self {
            force: c.force,
            axis: c.axis.map(|x| x / n),
            max_velocity: c.max_velocity,
            gain: c.gain,
        }
    }

    /// N = −F_w·â: the push on the wall against its axis from the total
    /// force `on_wall` (N) it takes from the spheres, N.
    pub fn push(&self, on_wall: [f64; 3]) -> f64 {
        -(on_wall[0] * self.axis[0] + on_wall[1] * self.axis[1] + on_wall[2] * self.axis[2])
    }

    /// The wall's speed along â for a push `push` (N), m/s (module doc).
    pub fn velocity(&self, push: f64) -> f64 {
        let v = self.gain * self.max_velocity * (self.force - push) / self.force;
        v.clamp(-self.max_velocity, self.max_velocity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok() -> ServoConfig {
        ServoConfig {
            force: 2.0,
            axis: [0.0, 0.0, -3.0],
            max_velocity: 0.1,
            gain: 0.5,
        }
    }

    /// The controller by hand: no push → k v_max along â; F → 0; a push
    /// of 3F → k v_max (−2) = −v_max here (clamped); the axis normalised.
    #[test]
    fn proportional_controller_clamped() {
        let s = Servo::from_config(&ok());
        assert_eq!(s.axis, [0.0, 0.0, -1.0]);
        assert_eq!(s.velocity(0.0), 0.05);
        assert_eq!(s.velocity(2.0), 0.0);
        assert_eq!(s.velocity(1.0), 0.025);
        assert_eq!(s.velocity(6.0), -0.1);
        assert_eq!(s.velocity(1e9), -0.1);
        // A sphere below the piston pushes it up (+z): N > 0.
        assert_eq!(s.push([0.0, 0.0, 1.5]), 1.5);
        let g: ServoConfig =
            toml::from_str("force = 1.0\naxis = [0, 0, -1]\nmax_velocity = 0.01").unwrap();
        assert_eq!(g.gain, DEFAULT_GAIN);
    }

    /// Bad values are named with the key, the value and the range.
    #[test]
    fn refusals_name_key_value_and_range() {
        assert!(validate("wall[1]", &ok()).is_ok());
        let cases = [
            (ServoConfig { force: 0.0, ..ok() }, "wall[1].servo.force"),
            (
                ServoConfig {
                    force: -1.0,
                    ..ok()
                },
                "wall[1].servo.force",
            ),
            (
                ServoConfig {
                    axis: [0.0; 3],
                    ..ok()
                },
                "wall[1].servo.axis",
            ),
            (
                ServoConfig {
                    axis: [f64::NAN, 0.0, 1.0],
                    ..ok()
                },
                "wall[1].servo.axis",
            ),
            (
                ServoConfig {
                    max_velocity: 0.0,
                    ..ok()
                },
                "wall[1].servo.max_velocity",
            ),
            (ServoConfig { gain: -1.0, ..ok() }, "wall[1].servo.gain"),
        ];
        for (c, key) in cases {
            let e = validate("wall[1]", &c).unwrap_err().to_string();
            assert!(e.contains(key) && e.contains("allowed"), "{e}");
        }
    }
}
