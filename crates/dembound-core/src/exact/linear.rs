//! Linear contact (`α = 1`) with gravity: closed forms (ERRATA 6, eqs. 20–22 b).
//!
//! With overlap `h = −x`, the contact equation `h'' = g − p² h`, `h(0) = 0`, `h'(0) = |v_c|`
//! (time `τ` from contact start) has the solution
//! `h(τ) = (|v_c|/p) sin pτ + (g/p²)(1 − cos pτ)`, which is eq. 20 b with `v_c = −|v_c|` and
//! `x = −h`. Then (ERRATA 6)
//! * `T_c = (π + 2 arctan(g / (|v_c| p))) / p` (eq. 26 as printed takes the other arctan branch),
//! * `t_mp = T_c / 2`,
//! * `h_max = (g + sqrt(g² + v_c² p²)) / p²` (eq. 28 as printed has `−g²`),
//! * `a_max = p² h_max − g = sqrt(g² + v_c² p²)` (eq. 25 with the corrected sign),
//! * `v_r = |v_c|`.

use super::{check_non_negative, check_positive, check_speed, ContactShape};
use crate::{Error, Result};
use std::f64::consts::PI;

/// State of the particle during a linear contact (eqs. 20–22 b), in the paper's signed
/// coordinates: `position = x = −h ≤ 0`, `velocity = ẋ`, `acceleration = ẍ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearState {
    /// `x(τ)`, eq. 20 b (m, ≤ 0 during contact).
    pub position: f64,
    /// `ẋ(τ)`, eq. 21 b (m/s).
    pub velocity: f64,
    /// `ẍ(τ) = −g − p² x(τ)`, eq. 22 b with `p² = p̄² c² R_m^(−1−α)` (m/s²). With the consistent
    /// force direction of ERRATA 1, this is `−g + p² h`.
    pub acceleration: f64,
}

fn check(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<(f64, f64, f64)> {
    let p2 = check_positive("p_squared", p_squared)?;
    let g = check_non_negative("gravity", gravity)?;
    let v = check_speed(impact_speed)?;
    if v == 0.0 && g == 0.0 {
        return Err(Error::NoContactDynamics);
    }
    Ok((p2, g, v))
}

/// Contact duration `T_c = (π + 2 arctan(g / (|v_c| p))) / p` (ERRATA 6, corrected eq. 26).
/// For `g = 0` it is `π/p` (eq. 27); for `|v_c| = 0` it is `2π/p`.
pub fn duration(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<f64> {
    let (p2, g, v) = check(p_squared, gravity, impact_speed)?;
    let p = p2.sqrt();
    Ok((PI + 2.0 * g.atan2(v * p)) / p)
}

/// Maximum overlap `h_max = (g + sqrt(g² + v_c² p²)) / p²` (ERRATA 6, corrected eq. 28).
pub fn max_overlap(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<f64> {
    let (p2, g, v) = check(p_squared, gravity, impact_speed)?;
    Ok((g + g.hypot(v * p2.sqrt())) / p2)
}

/// Maximum net upward acceleration `a_max = p² h_max − g = sqrt(g² + v_c² p²)`
/// (eq. 25 with the consistent sign, ERRATA 6).
pub fn max_acceleration(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<f64> {
    let (p2, g, v) = check(p_squared, gravity, impact_speed)?;
    Ok(g.hypot(v * p2.sqrt()))
}

/// Gravity-included linear contact (closed form, ERRATA 6), used by [`super::contacts`] for
/// `α = 1`: duration, time to maximum overlap (`T_c/2`) and `h_max`.
pub fn contact_shape(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<ContactShape> {
    let t = duration(p_squared, gravity, impact_speed)?;
    let h = max_overlap(p_squared, gravity, impact_speed)?;
    Ok(ContactShape {
        duration: t,
        time_to_max_overlap: 0.5 * t,
        max_overlap: h,
    })
}

/// In-contact history at time `tau ∈ [0, T_c]` after contact start (eqs. 20–22 b with
/// `v_c = −|impact_speed|`):
/// `x = p⁻² (v_c p sin pτ + g (cos pτ − 1))`, `ẋ = v_c cos pτ − (g/p) sin pτ`,
/// `ẍ = −g − p² x`. As printed these are consistent with the corrected force direction
/// (ERRATA 1) because `x ≤ 0` in contact; `cos pτ − 1` is evaluated as `−2 sin²(pτ/2)`.
/// `tau` may exceed `T_c` by a relative `1e−12` (clamped); the position is clamped to `≤ 0`.
pub fn state_at(p_squared: f64, gravity: f64, impact_speed: f64, tau: f64) -> Result<LinearState> {
    let (p2, g, v) = check(p_squared, gravity, impact_speed)?;
    let t_c = duration(p2, g, v)?;
    let tau = clamp_tau(tau, t_c)?;
    let p = p2.sqrt();
    let vc = -v;
    let (s, c) = (p * tau).sin_cos();
    let half = (0.5 * p * tau).sin();
    let x = ((vc * p * s - 2.0 * g * half * half) / p2).min(0.0);
    let xd = vc * c - (g / p) * s;
    let xdd = -g - p2 * x;
    Ok(LinearState {
        position: x,
        velocity: xd,
        acceleration: xdd,
    })
}

/// Checks `tau ∈ [0, duration]`, tolerating a relative `1e−12` overshoot, and clamps.
pub(crate) fn clamp_tau(tau: f64, duration: f64) -> Result<f64> {
    if !tau.is_finite() {
        return Err(Error::InvalidParameter {
            name: "tau",
            value: tau,
            requirement: "finite",
        });
    }
    if tau < 0.0 || tau > duration * (1.0 + 1e-12) {
        return Err(Error::TimeOutOfContact { tau, duration });
    }
    Ok(tau.min(duration))
}

#[cfg(test)]
mod tests {
    use super::*;

    // Independent check of the closed forms: the ODE h'' = g − p² h itself. At τ = T_c/2 the
    // velocity vanishes and h = h_max; at τ = T_c, h = 0 and ẋ = |v_c|. The only error is the
    // rounding of sin/cos of arguments of size ≤ 2π (a few ulp), so 1e−13 (relative to the
    // natural scales h_max and |v_c|) is a safe bound.
    #[test]
    fn closed_forms_are_consistent() {
        for &(p2, g, v) in &[
            (1.0, 1.0, 1.0),
            (1.3716e13, 9.81, 0.313209),
            (4.0, 10.0, 0.1),
            (2.5, 0.0, 3.0),
            (9.0, 2.0, 0.0),
        ] {
            let s = contact_shape(p2, g, v).unwrap();
            let mid = state_at(p2, g, v, s.time_to_max_overlap).unwrap();
            assert!((-mid.position - s.max_overlap).abs() <= 1e-13 * s.max_overlap);
            let vs = v.max(g / p2.sqrt());
            assert!(mid.velocity.abs() <= 1e-13 * vs);
            let end = state_at(p2, g, v, s.duration).unwrap();
            assert!(end.position.abs() <= 1e-13 * s.max_overlap);
            assert!((end.velocity - v).abs() <= 1e-13 * vs);
            let a = max_acceleration(p2, g, v).unwrap();
            assert!((mid.acceleration - a).abs() <= 1e-13 * a);
        }
    }

    #[test]
    fn rejects_bad_input() {
        assert!(duration(0.0, 1.0, 1.0).is_err());
        assert!(duration(f64::NAN, 1.0, 1.0).is_err());
        assert!(duration(1.0, -1.0, 1.0).is_err());
        assert!(duration(1.0, 0.0, 0.0).is_err());
        assert!(duration(1.0, 1.0, f64::INFINITY).is_err());
        assert!(state_at(1.0, 1.0, 1.0, -1e-3).is_err());
        assert!(state_at(1.0, 1.0, 1.0, 10.0).is_err());
        assert!(state_at(1.0, 1.0, 1.0, f64::NAN).is_err());
    }
}
