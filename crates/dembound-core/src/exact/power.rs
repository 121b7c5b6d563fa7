//! Power-law contact `h'' = g − p² h^α` for any `α ≥ 1` (ERRATA 1, 8).
//!
//! Energy conservation gives `ḣ² = D(h) = v_c² + 2 g h − 2 p² h^(α+1)/(α+1)`. The maximum
//! overlap is the positive root of `p² h^(α+1)/(α+1) − g h − v_c²/2 = 0` and
//! `T_c/2 = ∫₀^h_max dh / sqrt(D(h))` (ERRATA 8); the motion is time-reversible, so the maximum
//! overlap is reached at `T_c/2` and `v_r = |v_c|`.
//!
//! Numerics. With `s = h/h_max`, `w = 1 − s` and the root identity
//! `2 p² h_max^(α+1)/(α+1) = 2 g h_max + v_c²`, the energy function factors without any
//! cancellation into a sum of non-negative terms,
//! `D = (h_max − h) G`, `G = (v_c²/h_max) Q_(α+1)(s) + 2 g s Q_α(s)`,
//! `Q_n(s) = (1 − s^n)/(1 − s) = −expm1(n ln s)/w` (limit `n` as `w → 0`; `ln s` is taken as
//! `ln_1p(−w)` for `w < 1/2`). The substitution `h = h_max sin²θ` removes the square-root
//! singularity at `h_max` (`cos θ` cancels) and, for `|v_c| → 0`, the one at `h = 0` (`sin θ`
//! cancels against `sqrt(G)`):
//! `t(h) = ∫₀^θ(h) 2 sqrt(h_max) dθ / sqrt(G/s)`, `T_c/2 = t(h_max)` (upper limit `π/2`).
//! The integrand is smooth inside `[0, π/2]`; for non-integer `α` it has only a weak algebraic
//! endpoint singularity, which double-exponential (tanh-sinh) quadrature handles.

use super::linear::clamp_tau;
use super::{
    check_non_negative, check_positive, check_problem, check_speed, ContactProblem, ContactShape,
};
use crate::{Error, Result};
use roots::{find_root_brent, Convergency};
use std::f64::consts::FRAC_PI_2;

/// Beta function `B(a, b) = Γ(a) Γ(b) / Γ(a + b)` from `libm::tgamma` (a few ulp).
pub fn beta(a: f64, b: f64) -> Result<f64> {
    check_positive("a", a)?;
    check_positive("b", b)?;
    let value = libm::tgamma(a) * libm::tgamma(b) / libm::tgamma(a + b);
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::Numerical("beta function overflow"))
    }
}

fn check_alpha(alpha: f64) -> Result<f64> {
    if alpha.is_finite() && alpha >= 1.0 {
        Ok(alpha)
    } else {
        Err(Error::InvalidParameter {
            name: "alpha",
            value: alpha,
            requirement: "finite and >= 1",
        })
    }
}

fn finite_positive(value: f64, what: &'static str) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::Numerical(what))
    }
}

/// Gravity-free maximum overlap `h_max = ((α+1) v²/(2p²))^(1/(α+1))`.
pub fn max_overlap_gravity_free(p_squared: f64, alpha: f64, impact_speed: f64) -> Result<f64> {
    let p2 = check_positive("p_squared", p_squared)?;
    let alpha = check_alpha(alpha)?;
    let v = check_speed(impact_speed)?;
    if v == 0.0 {
        return Err(Error::NoContactDynamics);
    }
    let base = 0.5 * (alpha + 1.0) * (v / p2.sqrt()).powi(2);
    finite_positive(
        base.powf(1.0 / (alpha + 1.0)),
        "gravity-free maximum overlap not representable",
    )
}

/// Gravity-free contact duration
/// `T_c = 2 (h_max/|v|) (1/(α+1)) B(1/(α+1), 1/2)` (from `∫₀¹ ds/sqrt(1 − s^n) = B(1/n, 1/2)/n`);
/// for Hertz `2·0.4·B(0.4, 0.5) ≈ 2.9432`, the coefficient of eq. 30.
pub fn duration_gravity_free(p_squared: f64, alpha: f64, impact_speed: f64) -> Result<f64> {
    let h = max_overlap_gravity_free(p_squared, alpha, impact_speed)?;
    let v = check_speed(impact_speed)?;
    let n = alpha + 1.0;
    let t = 2.0 * (h / v) * beta(1.0 / n, 0.5)? / n;
    finite_positive(t, "gravity-free duration not representable")
}

/// Gravity-free contact shape from the closed forms (`problem.gravity` is ignored).
pub fn gravity_free_shape(p_squared: f64, alpha: f64, impact_speed: f64) -> Result<ContactShape> {
    let t = duration_gravity_free(p_squared, alpha, impact_speed)?;
    Ok(ContactShape {
        duration: t,
        time_to_max_overlap: 0.5 * t,
        max_overlap: max_overlap_gravity_free(p_squared, alpha, impact_speed)?,
    })
}

/// Relative x-tolerance convergence for `roots::find_root_brent`.
struct RelTol {
    rel: f64,
    abs: f64,
    max_iter: usize,
}

impl Convergency<f64> for RelTol {
    fn is_root_found(&mut self, y: f64) -> bool {
        y == 0.0
    }
    fn is_converged(&mut self, x1: f64, x2: f64) -> bool {
        (x1 - x2).abs() <= self.rel * x1.abs().max(x2.abs()) + self.abs
    }
    fn is_iteration_limit_reached(&mut self, iter: usize) -> bool {
        iter >= self.max_iter
    }
}

/// Maximum overlap with gravity: the positive root of
/// `f(h) = p² h^(α+1)/(α+1) − g h − v_c²/2` (ERRATA 8). `f(0) ≤ 0` and `f` is convex, so the
/// root is unique; it is bracketed in `[0, 2 max(h_0, h_g)]` (`h_0` the gravity-free root,
/// `h_g = ((α+1) g/p²)^(1/α)` the root for `v_c = 0`), found with Brent (`roots`) and polished
/// with Newton to full precision.
pub fn max_overlap(problem: &ContactProblem, impact_speed: f64) -> Result<f64> {
    let (p2, alpha, g) = check_problem(problem)?;
    let v = check_speed(impact_speed)?;
    if g == 0.0 {
        return max_overlap_gravity_free(p2, alpha, v);
    }
    let n = alpha + 1.0;
    let h_g = finite_positive(
        (n * g / p2).powf(1.0 / alpha),
        "gravity overlap scale not representable",
    )?;
    if v == 0.0 {
        return Ok(h_g);
    }
    let h_0 = max_overlap_gravity_free(p2, alpha, v)?;
    let hi = 2.0 * h_0.max(h_g);
    let half_v2 = 0.5 * v * v;
    let f = |h: f64| h * (p2 * h.powf(alpha) / n - g) - half_v2;
    let df = |h: f64| p2 * h.powf(alpha) - g;
    let mut conv = RelTol {
        rel: 1e-14,
        abs: 0.0,
        max_iter: 400,
    };
    let mut h = find_root_brent(0.0, hi, f, &mut conv)
        .map_err(|_| Error::Numerical("maximum overlap root not bracketed"))?;
    // Newton polish, accepting a step only while the residual does not grow.
    let mut r = f(h).abs();
    for _ in 0..4 {
        let d = df(h);
        if d.is_nan() || d <= 0.0 {
            break;
        }
        let trial = h - f(h) / d;
        let rt = f(trial).abs();
        if trial > 0.0 && trial.is_finite() && rt <= r {
            let done = trial == h;
            h = trial;
            r = rt;
            if done {
                break;
            }
        } else {
            break;
        }
    }
    finite_positive(h, "maximum overlap not found")
}

/// `Q_n = (1 − s^n)/(1 − s)` from `w = 1 − s` and `ln s`, without cancellation.
fn q(n: f64, w: f64, ln_s: f64) -> f64 {
    if w == 0.0 {
        n
    } else {
        -(n * ln_s).exp_m1() / w
    }
}

/// Time integrand in the angle `θ` (`h = h_max sin²θ`), given `sin θ` and `cos θ`.
#[derive(Debug, Clone, Copy)]
struct Integrand {
    alpha: f64,
    h_max: f64,
    speed: f64,
    v2_over_h: f64,
    two_g: f64,
}

impl Integrand {
    fn new(alpha: f64, h_max: f64, speed: f64, g: f64) -> Self {
        Integrand {
            alpha,
            h_max,
            speed,
            v2_over_h: speed * speed / h_max,
            two_g: 2.0 * g,
        }
    }

    /// `G/s` with `G = D/(h_max − h)`; `+∞` at `s = 0` when `v > 0`.
    fn g_over_s(&self, sn: f64, cs: f64) -> f64 {
        let s = sn * sn;
        let w = cs * cs;
        let ln_s = if w < 0.5 { (-w).ln_1p() } else { 2.0 * sn.ln() };
        let mut gs = self.two_g * q(self.alpha, w, ln_s);
        if self.v2_over_h > 0.0 {
            gs += self.v2_over_h * q(self.alpha + 1.0, w, ln_s) / s;
        }
        gs
    }

    /// `dt/dθ = 2 sqrt(h_max) / sqrt(G/s)`.
    fn rate(&self, sn: f64, cs: f64) -> f64 {
        2.0 * self.h_max.sqrt() / self.g_over_s(sn, cs).sqrt()
    }

    /// `(h, ḣ)` on the loading branch: `h = h_max sin²θ`, `ḣ = sqrt(h_max) sinθ cosθ sqrt(G/s)`.
    fn state(&self, sn: f64, cs: f64) -> (f64, f64) {
        if sn == 0.0 {
            return (0.0, self.speed);
        }
        let h = self.h_max * sn * sn;
        let hd = self.h_max.sqrt() * sn * cs * self.g_over_s(sn, cs).sqrt();
        (h, hd)
    }

    /// Scale of the integrand (its value at `θ = π/2`), for quadrature tolerances.
    fn scale(&self) -> f64 {
        self.rate(1.0, 0.0)
    }

    /// `∫₀^angle rate dθ`, measured from the bottom (`from_top = false`, `θ = angle`) or from
    /// the top (`from_top = true`, `θ = π/2 − angle`, i.e. the time from `h(θ)` to `h_max`).
    fn integral(&self, angle: f64, from_top: bool) -> Result<f64> {
        if angle <= 0.0 {
            return Ok(0.0);
        }
        // The quadrature crate truncates the tanh-sinh sum at |t| = 3, which drops a relative
        // ~2e−14 of the mass next to each endpoint where the integrand does not vanish. The
        // smoothstep map θ = angle·(3ξ² − 2ξ³) makes the integrand vanish at both ends
        // (dθ/dξ = 6 angle ξ(1 − ξ)) and keeps it analytic, so that loss becomes ~1e−27.
        let f = |xi: f64| {
            let a = angle * xi * xi * (3.0 - 2.0 * xi);
            let (sn, cs) = a.sin_cos();
            let rate = if from_top {
                self.rate(cs, sn)
            } else {
                self.rate(sn, cs)
            };
            rate * 6.0 * angle * xi * (1.0 - xi)
        };
        let scale = self.scale() * angle;
        let out = quadrature::double_exponential::integrate(f, 0.0, 1.0, 1e-16 * scale);
        if out.integral.is_finite() && out.integral >= 0.0 && out.error_estimate <= 1e-9 * scale {
            Ok(out.integral)
        } else {
            Err(Error::Numerical("time quadrature did not converge"))
        }
    }

    /// Angle with `integral(angle, from_top) = target`, `0 ≤ target ≤ integral(π/2)`:
    /// Brent (`roots`) then Newton polish.
    fn invert(&self, target: f64, from_top: bool) -> Result<f64> {
        if target <= 0.0 {
            return Ok(0.0);
        }
        let rate = |a: f64| {
            let (sn, cs) = a.sin_cos();
            if from_top {
                self.rate(cs, sn)
            } else {
                self.rate(sn, cs)
            }
        };
        let mut failure = None;
        let residual = |a: f64| match self.integral(a, from_top) {
            Ok(t) => t - target,
            Err(e) => {
                failure = Some(e);
                0.0
            }
        };
        let mut conv = RelTol {
            rel: 1e-12,
            abs: 1e-300,
            max_iter: 200,
        };
        let found = find_root_brent(0.0, FRAC_PI_2, residual, &mut conv);
        if let Some(e) = failure {
            return Err(e);
        }
        let mut a = found.map_err(|_| Error::Numerical("time inversion failed to bracket"))?;
        let mut r = self.integral(a, from_top)? - target;
        for _ in 0..3 {
            let d = rate(a);
            if !(d > 0.0 && d.is_finite()) || r == 0.0 {
                break;
            }
            let trial = (a - r / d).clamp(0.0, FRAC_PI_2);
            let rt = self.integral(trial, from_top)? - target;
            if rt.abs() <= r.abs() {
                let done = trial == a;
                a = trial;
                r = rt;
                if done {
                    break;
                }
            } else {
                break;
            }
        }
        Ok(a)
    }
}

fn setup(problem: &ContactProblem, impact_speed: f64) -> Result<(Integrand, f64)> {
    let (_, alpha, g) = check_problem(problem)?;
    let v = check_speed(impact_speed)?;
    if v == 0.0 && g == 0.0 {
        return Err(Error::NoContactDynamics);
    }
    let h_max = max_overlap(problem, v)?;
    let integrand = Integrand::new(alpha, h_max, v, g);
    let half = integrand.integral(FRAC_PI_2, false)?;
    Ok((integrand, finite_positive(half, "contact duration")?))
}

/// Contact with gravity by quadrature, any `α ≥ 1` (also `α = 1`, to compare with
/// [`super::linear`]): `h_max` from [`max_overlap`], `T_c = 2 ∫₀^h_max dh/sqrt(D(h))`
/// (ERRATA 8), evaluated as described in the module documentation.
pub fn contact_shape(problem: &ContactProblem, impact_speed: f64) -> Result<ContactShape> {
    let (integrand, half) = setup(problem, impact_speed)?;
    Ok(ContactShape {
        duration: 2.0 * half,
        time_to_max_overlap: half,
        max_overlap: integrand.h_max,
    })
}

/// Loading-branch time to reach overlap `h ∈ [0, h_max]`, `t(h) = ∫₀^h dh'/sqrt(D(h'))`.
pub fn time_to_overlap(problem: &ContactProblem, impact_speed: f64, overlap: f64) -> Result<f64> {
    let (integrand, half) = setup(problem, impact_speed)?;
    let h = check_non_negative("overlap", overlap)?;
    let ratio = h / integrand.h_max;
    if ratio > 1.0 + 1e-12 {
        return Err(Error::InvalidParameter {
            name: "overlap",
            value: h,
            requirement: "at most the maximum overlap",
        });
    }
    if ratio >= 1.0 {
        return Ok(half);
    }
    if ratio <= 0.5 {
        integrand.integral(ratio.sqrt().asin(), false)
    } else {
        // θ measured from the top: cos²θ = 1 − ratio.
        let phi = (1.0 - ratio).sqrt().asin();
        Ok((half - integrand.integral(phi, true)?).max(0.0))
    }
}

/// Exact overlap history `(h, dh/dt)` at time `tau ∈ [0, T_c]` after contact start, for any
/// `α ≥ 1` with gravity: inversion of `t(h)` (Brent, then Newton). The first half of the
/// contact is inverted from the bottom (`τ ≤ T_c/4`) or from the top (remaining time to
/// `T_c/2`), so `h` and `ḣ` keep their relative precision at both ends; the second half follows
/// from time reversibility, `h(τ) = h(T_c − τ)`, `ḣ(τ) = −ḣ(T_c − τ)`. `tau` may exceed `T_c` by
/// a relative `1e−12` (clamped); `T_c` here is the quadrature value of [`contact_shape`].
pub fn overlap_at(problem: &ContactProblem, impact_speed: f64, tau: f64) -> Result<(f64, f64)> {
    let (integrand, half) = setup(problem, impact_speed)?;
    let duration = 2.0 * half;
    let tau = clamp_tau(tau, duration)?;
    let (t, sign) = if tau <= half {
        (tau, 1.0)
    } else {
        ((duration - tau).max(0.0), -1.0)
    };
    let (h, hd) = if t <= 0.5 * half {
        let a = integrand.invert(t, false)?;
        let (sn, cs) = a.sin_cos();
        integrand.state(sn, cs)
    } else {
        let a = integrand.invert((half - t).max(0.0), true)?;
        let (sn, cs) = a.sin_cos();
        integrand.state(cs, sn)
    };
    Ok((h, sign * hd))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beta_matches_known_values() {
        // B(1/2, 1/2) = π, B(1, 1) = 1, B(2, 3) = 1/12; libm tgamma is good to a few ulp.
        assert!((beta(0.5, 0.5).unwrap() - std::f64::consts::PI).abs() < 1e-14);
        assert!((beta(1.0, 1.0).unwrap() - 1.0).abs() < 1e-15);
        assert!((beta(2.0, 3.0).unwrap() - 1.0 / 12.0).abs() < 1e-15);
    }
}
