//! Event location inside a step: roots of the integrator's own interpolating
//! polynomial.
//!
//! Written by hand (rather than with a root-finding crate) because locating
//! events inside the step is one of the numerics this project is about, and
//! the polynomial gives its derivative for free: a safeguarded Newton
//! iteration on a bracket converges to the last bit in a few iterations.

use crate::integrate::{DenseOutput, Kinematics};

/// What to find the zero of on the step's polynomial.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Crossing {
    /// Position x(θ) = 0 (contact onset or rebound), rising through zero.
    Position,
    /// Velocity ẋ(θ) = 0 (maximum overlap), rising through zero.
    Velocity,
}

fn value(k: &Kinematics, c: Crossing, dt: f64) -> (f64, f64) {
    match c {
        Crossing::Position => (k.position, k.velocity * dt),
        Crossing::Velocity => (k.velocity, k.acceleration * dt),
    }
}

/// Step fraction θ where the chosen quantity rises through zero on `dense`.
///
/// The quantity is < 0 at some θ ≤ 0 and ≥ 0 at θ = 1. The interpolant of a
/// step need not reproduce the start value exactly (Gear's is anchored at the
/// end), so when the quantity is already ≥ 0 at θ = 0 the bracket is
/// extended back into the previous step (θ down to −1), where the
/// polynomial is still of the scheme's order.
pub fn locate(dense: &impl DenseOutput, crossing: Crossing) -> (f64, Kinematics) {
    let dt = dense.step_size();
    let f = |t: f64| value(&dense.at(t), crossing, dt);
    let mut hi = 1.0;
    let mut lo = 0.0;
    if f(lo).0 >= 0.0 {
        lo = -1.0;
        if f(lo).0 >= 0.0 {
            // No sign change on the polynomial (cannot happen for a
            // detected event unless Δt is absurdly large): take the step end.
            return (1.0, dense.at(1.0));
        }
    }
    let mut theta = 0.5 * (lo + hi);
    // Initial guess by linear interpolation of the bracket values.
    let (f_lo, f_hi) = (f(lo).0, f(hi).0);
    if f_hi > f_lo {
        theta = lo - f_lo * (hi - lo) / (f_hi - f_lo);
    }
    for _ in 0..100 {
        let (y, dy) = f(theta);
        if y == 0.0 {
            break;
        }
        if y < 0.0 {
            lo = theta;
        } else {
            hi = theta;
        }
        let newton = theta - y / dy;
        let next = if dy > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - theta).abs() <= 4.0 * f64::EPSILON * theta.abs().max(1e-300)
            || hi - lo <= f64::EPSILON
        {
            theta = next;
            break;
        }
        theta = next;
    }
    (theta, dense.at(theta))
}

/// Step fraction θ where `f(kinematics)` rises through zero on `dense`,
/// for quantities without a cheap derivative (the force of a law along the
/// step's polynomial). Same bracket as [`locate`] (θ down to −1 when the
/// quantity is already ≥ 0 at θ = 0); Illinois-modified regula falsi, which
/// converges superlinearly and keeps the bracket, to the last bit.
pub fn locate_where(dense: &impl DenseOutput, f: impl Fn(&Kinematics) -> f64) -> (f64, Kinematics) {
    let q = |t: f64| f(&dense.at(t));
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut f_lo = q(lo);
    let mut f_hi = q(hi);
    if f_lo >= 0.0 {
        lo = -1.0;
        f_lo = q(lo);
        if f_lo >= 0.0 {
            return (1.0, dense.at(1.0));
        }
    }
    if f_hi < 0.0 {
        return (1.0, dense.at(1.0));
    }
    // Illinois: halve the retained end's value when the same end is kept twice.
    let mut side = 0;
    for _ in 0..200 {
        let theta = if f_hi > f_lo {
            (lo - f_lo * (hi - lo) / (f_hi - f_lo)).clamp(lo, hi)
        } else {
            0.5 * (lo + hi)
        };
        if theta <= lo || theta >= hi || hi - lo <= 2.0 * f64::EPSILON {
            break;
        }
        let y = q(theta);
        if y == 0.0 {
            return (theta, dense.at(theta));
        }
        if y < 0.0 {
            lo = theta;
            f_lo = y;
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            hi = theta;
            f_hi = y;
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    // The upper end of the bracket: the first point with the quantity ≥ 0.
    (hi, dense.at(hi))
}

/// Smallest τ ≥ 0 at which a body in free flight at height x ≥ 0 with
/// velocity v (upward positive) under gravity g reaches x = 0:
/// x + v τ − g τ²/2 = 0. Written in the cancellation-free form for both
/// signs of v. `None` if it never does (g = 0 and v ≥ 0 with x > 0).
pub fn time_to_surface(x: f64, v: f64, g: f64) -> Option<f64> {
    if x <= 0.0 && v <= 0.0 {
        return Some(0.0);
    }
    if g == 0.0 {
        return (v < 0.0).then(|| -x / v);
    }
    let root = (v * v + 2.0 * g * x.max(0.0)).sqrt();
    Some(if v > 0.0 {
        (v + root) / g
    } else {
        2.0 * x / (root - v)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::{Gear5, Integrator, Verlet};

    #[test]
    fn locates_sine_zero_to_rounding() {
        // x = sin t crosses zero rising at t = 2π; a step from 6.2 to 6.35.
        for (name, theta) in [("gear", 0), ("verlet", 1)] {
            let (t0, dt) = (6.2_f64, 0.15);
            let d = [t0.sin(), t0.cos(), -t0.sin(), -t0.cos(), t0.sin(), t0.cos()];
            let t = if theta == 0 {
                let g = Gear5::POSITION_DEPENDENT;
                let before = g.start(d, dt);
                let mut after = before;
                g.step(&mut after, |x, _| -x);
                let (th, _) = locate(&g.dense(&before, &after), Crossing::Position);
                t0 + th * dt
            } else {
                let before = Verlet.start(d, dt);
                let after =
                    Verlet.start([(t0 + dt).sin(), (t0 + dt).cos(), 0.0, 0.0, 0.0, 0.0], dt);
                let (th, _) = locate(&Verlet.dense(&before, &after), Crossing::Position);
                t0 + th * dt
            };
            // Gear: local error O(Δt⁶)~1e−8·C; Hermite: O(Δt⁴)/384 ≈ 1e−6.
            let tol = if theta == 0 { 1e-8 } else { 2e-6 };
            assert!((t - 2.0 * std::f64::consts::PI).abs() < tol, "{name}: {t}");
        }
    }

    #[test]
    fn time_to_surface_both_directions() {
        let g = 9.81;
        // dropped from rest from 5 mm: √(2H/g)
        let t = time_to_surface(5e-3, 0.0, g).unwrap();
        assert!((t - (2.0 * 5e-3 / g).sqrt()).abs() < 1e-16);
        // thrown up from the surface at v: 2v/g
        let t = time_to_surface(0.0, 0.3, g).unwrap();
        assert!((t - 0.6 / g).abs() < 1e-16);
        assert_eq!(time_to_surface(1.0, 1.0, 0.0), None);
        assert_eq!(time_to_surface(1.0, -2.0, 0.0), Some(0.5));
    }
}
