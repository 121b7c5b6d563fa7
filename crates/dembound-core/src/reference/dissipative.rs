//! Independent references for the dissipative contact laws: closed forms
//! for the linear spring–dashpot and Walton–Braun (gravity included), the
//! exact phase-space restitution of the Tsuji-type Hertz dashpot, and an
//! adaptive error-controlled integration ([`super::ode`]) of the contact
//! alone for the damped Hertz laws. Nothing here uses the Gear/Verlet time
//! loop or the law types of [`crate::contact`]: each force is written out
//! again below.
//!
//! Convention: a body of mass m hits the boundary at speed v > 0 (t = 0 at
//! the onset, h = 0, ḣ = v); gravity g ≥ 0 pushes it further in
//! (h'' = g − F/m). Times are measured from the onset.

use super::ode::{integrate_to_event, State, Tolerance};
use crate::{Error, Result};
use std::f64::consts::PI;

/// One contact, from the onset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactReference {
    /// Time of maximum overlap after the onset, s.
    pub t_max_overlap: f64,
    /// h_max, m.
    pub max_overlap: f64,
    /// Time after the onset at which the force first returns to zero
    /// (only when attraction is forbidden), s.
    pub t_force_zero: Option<f64>,
    /// Time after the onset at which the overlap returns to zero, s.
    pub duration: f64,
    /// Speed when the overlap returns to zero, m/s (> 0).
    pub rebound_speed: f64,
    /// rebound_speed / v.
    pub restitution: f64,
}

/// Root of `f` on [a, b] (f(a), f(b) of opposite signs) to the last bit.
fn bisect(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let fa_neg = f(a) < 0.0;
    for _ in 0..300 {
        let mid = 0.5 * (a + b);
        if mid <= a.min(b) || mid >= a.max(b) {
            break;
        }
        if (f(mid) < 0.0) == fa_neg {
            a = mid;
        } else {
            b = mid;
        }
    }
    0.5 * (a + b)
}

/// Free flight from overlap `h` > 0 moving out at ḣ < 0 under gravity:
/// time to h = 0 and the speed there (h + ḣτ + gτ²/2 = 0, smaller root,
/// cancellation-free).
fn flight_out(h: f64, hd: f64, g: f64) -> Option<(f64, f64)> {
    if h <= 0.0 {
        return Some((0.0, -hd));
    }
    let disc = hd * hd - 2.0 * g * h;
    if hd >= 0.0 || disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    Some((2.0 * h / (root - hd), root))
}

/// The underdamped oscillator h'' + 2ξω ḣ + ω² h = g started at h = 0,
/// ḣ = v (the spring–dashpot F = k h + c ḣ of mass m, ω² = k/m,
/// ξ = c/(2√(k m))): h = h_eq + e^(−σt)(a cos φ + b sin φ) and
/// ḣ = e^(−σt)(p cos φ + q sin φ), φ = ω_d t, ω_d = ω√(1 − ξ²), σ = ξω.
struct DampedOscillator {
    wd: f64,
    sigma: f64,
    h_eq: f64,
    a: f64,
    b: f64,
    p: f64,
    q: f64,
}

impl DampedOscillator {
    fn new(k: f64, c: f64, m: f64, v: f64, g: f64) -> Result<Self> {
        let omega = (k / m).sqrt();
        let xi = c / (2.0 * (k * m).sqrt());
        if xi >= 1.0 {
            return Err(Error::Overdamped(xi));
        }
        let wd = omega * (1.0 - xi * xi).sqrt();
        let sigma = xi * omega;
        let h_eq = g / (omega * omega);
        let (a, b) = (-h_eq, (v - sigma * h_eq) / wd);
        let (p, q) = (wd * b - sigma * a, -wd * a - sigma * b);
        Ok(Self {
            wd,
            sigma,
            h_eq,
            a,
            b,
            p,
            q,
        })
    }
}

/// Linear spring–dashpot F = k h + c ḣ in closed form (the damped
/// oscillator h'' + 2ξω ḣ + ω² h = g), with or without attraction. Events
/// other than the maximum are roots of the closed form found by bisection
/// (to rounding). Underdamped only (ξ < 1).
pub fn spring_dashpot(
    k: f64,
    c: f64,
    m: f64,
    v: f64,
    g: f64,
    attractive: bool,
) -> Result<ContactReference> {
    let DampedOscillator {
        wd,
        sigma,
        h_eq,
        a,
        b,
        p,
        q,
    } = DampedOscillator::new(k, c, m, v, g)?;
    let h = |phi: f64| h_eq + (-sigma * phi / wd).exp() * (a * phi.cos() + b * phi.sin());
    let hd = |phi: f64| (-sigma * phi / wd).exp() * (p * phi.cos() + q * phi.sin());
    let force = |phi: f64| k * h(phi) + c * hd(phi);
    let phi_mp = p.atan2(-q);
    // ḣ < 0 on (φ_mp, φ_mp + π): h falls monotonically there.
    let phi_end = phi_mp + PI;
    let h_root = (h(phi_end) < 0.0).then(|| bisect(h, phi_mp, phi_end));
    let (t_force_zero, duration, speed) = if attractive {
        let phi_r = h_root.ok_or(Error::NoReferenceRebound)?;
        (None, phi_r / wd, -hd(phi_r))
    } else {
        // First sign change of F after the maximum, scanning to the h root.
        let stop = h_root.unwrap_or(phi_end);
        let n = 4096;
        let mut lo = phi_mp;
        let mut found = None;
        for i in 1..=n {
            let hi = phi_mp + (stop - phi_mp) * i as f64 / n as f64;
            if force(hi) <= 0.0 {
                found = Some(bisect(force, lo, hi));
                break;
            }
            lo = hi;
        }
        let phi_f = found.ok_or(Error::NoReferenceRebound)?;
        let (tau, speed) = flight_out(h(phi_f), hd(phi_f), g).ok_or(Error::NoReferenceRebound)?;
        (Some(phi_f / wd), phi_f / wd + tau, speed)
    };
    Ok(ContactReference {
        t_max_overlap: phi_mp / wd,
        max_overlap: h(phi_mp),
        t_force_zero,
        duration,
        rebound_speed: speed,
        restitution: speed / v,
    })
}

/// Peak force of the linear spring–dashpot contact of [`spring_dashpot`]
/// (underdamped, ξ < 1), N, in closed form: F = k h + c ḣ is itself
/// F = k h_eq + e^(−σt)(α cos φ + β sin φ) with φ = ω_d t, whose first
/// stationary point after the onset is a maximum when F rises at the onset
/// (else the maximum is the onset's c v). The maximum comes before the
/// maximum overlap (there dF/dt = c ḧ < 0), so the clamp F ≥ 0 does not
/// touch it.
pub fn spring_dashpot_max_force(k: f64, c: f64, m: f64, v: f64, g: f64) -> Result<f64> {
    let DampedOscillator {
        wd,
        sigma,
        h_eq,
        a,
        b,
        p,
        q,
    } = DampedOscillator::new(k, c, m, v, g)?;
    // F − k h_eq = e^(−σt)(α cos φ + β sin φ); its time derivative is
    // e^(−σt)(P cos φ + Q sin φ).
    let (alpha, beta) = (k * a + c * p, k * b + c * q);
    let (pp, qq) = (-sigma * alpha + wd * beta, -sigma * beta - wd * alpha);
    let force =
        |phi: f64| k * h_eq + (-sigma * phi / wd).exp() * (alpha * phi.cos() + beta * phi.sin());
    let onset = force(0.0);
    if pp <= 0.0 {
        return Ok(onset);
    }
    // First φ > 0 with P cos φ + Q sin φ = 0.
    let phi = (pp.atan2(-qq)).rem_euclid(PI);
    Ok(force(phi).max(onset))
}

/// Peak force of a damped Hertz contact of [`damped_hertz`], N: the
/// adaptive integration from the onset to the first zero of dF/dt (F rises
/// from the onset, where dF/dt = +∞, and falls at the maximum overlap, so
/// the peak lies between and the clamp F ≥ 0 does not touch it). dF/dt is
/// written out (ḧ = g − F/m) and multiplied by h^(3/4) (Tsuji) or h^(1/2)
/// (viscoelastic) to stay finite at h = 0 with the same sign.
pub fn damped_hertz_max_force(model: DampedHertz, m: f64, v: f64, g: f64) -> Result<f64> {
    let k = model.stiffness();
    let h_s = (1.25 * m * v * v / k).powf(0.4);
    let t_s = h_s / v;
    let tol = Tolerance {
        rtol: DAMPED_HERTZ_RTOL,
        atol: [1e-15 * h_s, 1e-15 * v],
    };
    let free = |y: &State| [y[1], g - model.force(y[0], y[1]) / m];
    let falling = |y: &State| {
        let (h, hd) = (y[0].abs(), y[1]);
        let hdd = g - model.force(y[0], y[1]) / m;
        let scaled_rate = match model {
            // h^(3/4) dF/dt for F = k h^(3/2) + γ h^(1/4) ḣ.
            DampedHertz::Tsuji { stiffness, damping } => {
                1.5 * stiffness * h.powf(1.25) * hd + damping * (0.25 * hd * hd + h * hdd)
            }
            // h^(1/2) dF/dt / k for F = k (h^(3/2) + (3/2) A h^(1/2) ḣ).
            DampedHertz::Viscoelastic { a, .. } => {
                1.5 * h * hd + 1.5 * a * (0.5 * hd * hd + h * hdd)
            }
        };
        -scaled_rate
    };
    let peak = integrate_to_event(free, [0.0, v], &[&falling], tol, 1e-6 * t_s, 2_000_000)
        .map_err(|e| Error::Integration(Box::new(e)))?;
    Ok(model.force(peak.y[0], peak.y[1]))
}

/// Gravity-free spring–dashpot restitution for damping ratio ξ < 1:
/// exp(−πξ/√(1−ξ²)) with attraction; with F = max(F, 0)
/// exp(−ξ(π − 2 asin ξ)/√(1−ξ²)) (the force vanishes at ω_d t = π − 2 asin ξ
/// and the body leaves at the speed it has there; Schwager & Pöschel,
/// Granular Matter 9, 465 (2007)).
pub fn spring_dashpot_free_restitution(xi: f64, attractive: bool) -> f64 {
    let s = (1.0 - xi * xi).sqrt();
    if attractive {
        (-PI * xi / s).exp()
    } else {
        (-xi * (PI - 2.0 * xi.asin()) / s).exp()
    }
}

/// Walton–Braun in closed form, with gravity: loading h'' = g − ω₁² h to
/// h_max, unloading h'' = g − ω₂² (h − h₀) to the force zero h = h₀, then
/// free flight to h = 0. With g = 0: e = √(k₁/k₂), h_max = v/ω₁,
/// t(F = 0) = π/2 (1/ω₁ + 1/ω₂).
pub fn walton_braun(k1: f64, k2: f64, m: f64, v: f64, g: f64) -> Result<ContactReference> {
    let (w1, w2) = ((k1 / m).sqrt(), (k2 / m).sqrt());
    let h1 = g / (w1 * w1);
    let h_max = h1 + (h1 * h1 + (v / w1).powi(2)).sqrt();
    let t_mp = v.atan2(-w1 * h1) / w1;
    let h0 = h_max * (1.0 - k1 / k2);
    let g2 = g / (w2 * w2);
    let amplitude = h_max - (h0 + g2);
    if amplitude < g2 || amplitude <= 0.0 {
        return Err(Error::NoReferenceRebound);
    }
    let tau_f = (-g2 / amplitude).acos() / w2;
    let hd_f = -amplitude * w2 * (w2 * tau_f).sin();
    let (tau, speed) = flight_out(h0, hd_f, g).ok_or(Error::NoReferenceRebound)?;
    Ok(ContactReference {
        t_max_overlap: t_mp,
        max_overlap: h_max,
        t_force_zero: Some(t_mp + tau_f),
        duration: t_mp + tau_f + tau,
        rebound_speed: speed,
        restitution: speed / v,
    })
}

/// A damped Hertz law, written out independently of `crate::contact`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DampedHertz {
    /// F = k h^(3/2) + γ h^(1/4) ḣ.
    Tsuji { stiffness: f64, damping: f64 },
    /// F = k (h^(3/2) + (3/2) A h^(1/2) ḣ).
    Viscoelastic { stiffness: f64, a: f64 },
}

impl DampedHertz {
    fn stiffness(&self) -> f64 {
        match *self {
            DampedHertz::Tsuji { stiffness, .. } | DampedHertz::Viscoelastic { stiffness, .. } => {
                stiffness
            }
        }
    }

    /// No damping (γ = 0 or A = 0, e.g. a target e = 1): elastic Hertz.
    fn undamped(&self) -> bool {
        match *self {
            DampedHertz::Tsuji { damping, .. } => damping == 0.0,
            DampedHertz::Viscoelastic { a, .. } => a == 0.0,
        }
    }

    /// Unclamped force; fractional powers of |h| (the integration stops at
    /// h = 0, so h < 0 is met only inside rejected or bisected trial steps).
    fn force(&self, h: f64, hd: f64) -> f64 {
        let ah = h.abs();
        match *self {
            DampedHertz::Tsuji { stiffness, damping } => {
                stiffness * h * ah.powf(0.5) + damping * ah.powf(0.25) * hd
            }
            DampedHertz::Viscoelastic { stiffness, a } => {
                stiffness * (h * ah.powf(0.5) + 1.5 * a * ah.powf(0.5) * hd)
            }
        }
    }
}

/// Relative tolerance of [`damped_hertz`] (per step; the events come out
/// to ~1e−11 relative, checked against the exact Tsuji relations).
pub const DAMPED_HERTZ_RTOL: f64 = 1e-13;

/// A damped Hertz contact by adaptive Dormand–Prince integration of
/// h'' = g − F(h, ḣ)/m alone, from the onset (h = 0, ḣ = v), with events
/// located to the tolerance: maximum overlap, then (attraction forbidden)
/// the force zero followed by the clamped flight to h = 0, or (attraction
/// allowed) h = 0.
pub fn damped_hertz(
    model: DampedHertz,
    m: f64,
    v: f64,
    g: f64,
    attractive: bool,
) -> Result<ContactReference> {
    let k = model.stiffness();
    // Scales: the elastic Hertz h_max and its time h_max/v.
    let h_s = (1.25 * m * v * v / k).powf(0.4);
    let t_s = h_s / v;
    let tol = Tolerance {
        rtol: DAMPED_HERTZ_RTOL,
        atol: [1e-15 * h_s, 1e-15 * v],
    };
    let budget = 2_000_000;
    let ode = |e: Error| Error::Integration(Box::new(e));
    // After the maximum overlap, no event within the budget means the body
    // settles on the boundary (gravity against a spent rebound): no rebound.
    let settles = |e: Error| match e {
        Error::TooManySteps(_) => Error::NoReferenceRebound,
        e => Error::Integration(Box::new(e)),
    };
    let free = |y: &State| [y[1], g - model.force(y[0], y[1]) / m];
    let clamped = |y: &State| [y[1], g - model.force(y[0], y[1]).max(0.0) / m];
    let top = integrate_to_event(
        free,
        [0.0, v],
        &[&|y: &State| -y[1]],
        tol,
        1e-6 * t_s,
        budget,
    )
    .map_err(ode)?;
    let h_out = |y: &State| -y[0];
    let f_zero = |y: &State| -model.force(y[0], y[1]);
    let (t_force_zero, end) = if model.undamped() {
        // Elastic: the force returns to zero at the separation itself, so
        // the force-zero and separation events would coincide at h = 0,
        // where F ∝ h^(3/2) has a zero of order 3/2 (the event search
        // failed there gravity-free). The run reports the force zero at
        // the separation unless attraction is allowed.
        let end =
            integrate_to_event(free, top.y, &[&h_out], tol, 1e-3 * t_s, budget).map_err(settles)?;
        let t_end = top.t + end.t;
        ((!attractive).then_some(t_end), (t_end, end.y))
    } else if attractive {
        let end =
            integrate_to_event(free, top.y, &[&h_out], tol, 1e-3 * t_s, budget).map_err(settles)?;
        (None, (top.t + end.t, end.y))
    } else {
        let rel = integrate_to_event(free, top.y, &[&f_zero, &h_out], tol, 1e-3 * t_s, budget)
            .map_err(settles)?;
        let t_f = top.t + rel.t;
        if rel.index == 1 {
            (None, (t_f, rel.y))
        } else {
            let fly = integrate_to_event(clamped, rel.y, &[&h_out], tol, 1e-3 * t_s, budget)
                .map_err(settles)?;
            (Some(t_f), (t_f + fly.t, fly.y))
        }
    };
    let speed = -end.1[1];
    if speed <= 0.0 {
        return Err(Error::NoReferenceRebound);
    }
    Ok(ContactReference {
        t_max_overlap: top.t,
        max_overlap: top.y[0],
        t_force_zero,
        duration: end.0,
        rebound_speed: speed,
        restitution: speed / v,
    })
}

/// Exact gravity-free restitution and maximum overlap of the Tsuji-type law
/// F = k h^(3/2) + γ h^(1/4) ḣ: the phase-space substitution w ∝ h^(5/4)
/// turns v dv/dh = −(γ/m) h^(1/4) v − (k/m) h^(3/2) into a linear
/// spring–dashpot with damping ratio ξ = γ/√(5 k m) (derived here; the same
/// result as Antypov & Elliott, EPL 94, 50004 (2011)). Returns (e, h_max);
/// e follows [`spring_dashpot_free_restitution`] (the force zero
/// k h^(5/4) + γ ḣ = 0 is the dashpot's force zero in w as well) and
/// h_max = (5 m v²/(4k))^(2/5) exp(−ξ acos ξ/√(1−ξ²))^(4/5).
pub fn tsuji_free_exact(k: f64, gamma: f64, m: f64, v: f64, attractive: bool) -> (f64, f64) {
    let xi = gamma / (5.0 * k * m).sqrt();
    let e = spring_dashpot_free_restitution(xi, attractive);
    let decay = (-xi * xi.acos() / (1.0 - xi * xi).sqrt()).exp();
    let h_max = (1.25 * m * v * v / k).powf(0.4) * decay.powf(0.8);
    (e, h_max)
}

/// Tsuji's α(e) as a polynomial: α = 1.2728 − 4.2783 e + 11.087 e² −
/// 22.348 e³ + 27.467 e⁴ − 18.022 e⁵ + 4.8218 e⁶, the fit of J. S. Marshall,
/// J. Comput. Phys. 228, 1541 (2009), eq 53, to the chart of Tsuji, Tanaka
/// & Ishida (Powder Technol. 71, 239 (1992)), as LAMMPS `pair_style
/// granular ... damping tsuji` states it (doc/src/pair_granular.rst and
/// src/GRANULAR/gran_sub_mod_damping.cpp; read there, not in the papers).
/// The damping coefficient is η = α √(m k_n), with k_n = F/h = k h^(1/2)
/// the secant stiffness (so η ∝ h^(1/4)) and m the *particle* mass of Tsuji's
/// equal-sphere collisions, m = 2 m* (LAMMPS multiplies α by √2 since its
/// 2026 versions for that reason): in this crate's terms
/// γ = √2 α √(k m*), i.e. ξ = γ/√(5 k m*) = √2 α/√5. So read, it fits the
/// law *with attraction allowed* (checked against the exact relation in
/// the test below: within 5.2e−3 in e for 0.1 ≤ e ≤ 0.99; off by 4 % at
/// e = 0.05 and 100 % at 0.01, presumably outside Tsuji's chart).
pub fn tsuji_polynomial_alpha(e: f64) -> f64 {
    let c = [1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218];
    c.iter().rev().fold(0.0, |acc, &ci| acc * e + ci)
}

/// Thornton, Cummins & Cleary, Powder Technol. 233, 30 (2013), eqs B6–B7
/// with the coefficients h₁…h₁₀ of their Table 2, for Hertz with a damping
/// force 2γ√(m* k_n) ḣ, k_n = (3/2) k h^(1/2) the tangent stiffness, and no
/// attractive force: γ = √(1/(1 − (1+e)² exp α) − 1), α = Σ hᵢ eⁱ. Read in
/// Yade's `pkg/dem/HertzMindlin.cpp` (which names eqs B6, B7 and Table 2,
/// and notes the symbol γ) and Kratos' `GammaForHertzThornton` (the same
/// coefficients); the paper itself was not available to us, nor the
/// accuracy it claims for the fit. In this crate's terms the damping is
/// γ_law = 2γ√(3/2) √(k m*), i.e. ξ = γ_law/√(5 k m*) = √(6/5) γ, and the
/// relation is a fit of the *clamped* law's exact e(ξ)
/// ([`spring_dashpot_free_restitution`]`(ξ, false)` through the phase-space
/// map): measured within 1.3e−3 in e for 0.2 ≤ e ≤ 0.9 (test below; down
/// to e = 0.01 with the overdamped branch of `contact::free_restitution`),
/// 2e−3 at 0.95 and 1.1e−2 at 0.99.
pub fn thornton_b6_gamma(e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    let h = [
        -6.918798, -16.41105, 146.8049, -796.4559, 2928.711, -7206.864, 11494.29, -11342.18,
        6276.757, -1489.915,
    ];
    let alpha = e * h.iter().rev().fold(0.0, |acc, &hi| acc * e + hi);
    (1.0 / (1.0 - (1.0 + e) * (1.0 + e) * alpha.exp()) - 1.0).sqrt()
}

/// C₁ = Γ(3/5)√π/(2^(1/5) 5^(2/5) Γ(21/10)) ≈ 1.15345 of the viscoelastic
/// restitution e = 1 − C₁ δ' + (3/5) C₁² δ'² + O(δ'³) (Schwager & Pöschel,
/// Phys. Rev. E 57, 650 (1998); Ramírez et al., Phys. Rev. E 60, 4465
/// (1999)), with δ' = (3/2) A (k/m)^(2/5) v^(1/5) for F = k (h^(3/2) +
/// (3/2) A h^(1/2) ḣ) — the 3/2 placement checked numerically here, not
/// taken from the papers' notation.
pub fn viscoelastic_c1() -> f64 {
    libm::tgamma(0.6) * PI.sqrt() / (2f64.powf(0.2) * 5f64.powf(0.4) * libm::tgamma(2.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dashpot_closed_form_matches_schwager_poeschel() {
        // g = 0: the bisected closed form against the explicit formulas.
        let (k, m, v): (f64, f64, f64) = (3.0e4, 2.0e-6, 0.3);
        for xi in [0.05_f64, 0.2, 0.6] {
            let c = 2.0 * xi * (k * m).sqrt();
            for attractive in [true, false] {
                let r = spring_dashpot(k, c, m, v, 0.0, attractive).unwrap();
                let e = spring_dashpot_free_restitution(xi, attractive);
                assert!((r.restitution / e - 1.0).abs() < 1e-13, "{xi} {attractive}");
                let wd = (k / m).sqrt() * (1.0 - xi * xi).sqrt();
                if attractive {
                    assert!((r.duration * wd / PI - 1.0).abs() < 1e-14);
                } else {
                    let t_f = (PI - 2.0 * xi.asin()) / wd;
                    assert!((r.t_force_zero.unwrap() / t_f - 1.0).abs() < 1e-13);
                    let t_r = t_f + 2.0 * xi / (k / m).sqrt();
                    assert!((r.duration / t_r - 1.0).abs() < 1e-13);
                }
                let h_max = v / (k / m).sqrt() * (-xi * xi.acos() / (1.0 - xi * xi).sqrt()).exp();
                assert!((r.max_overlap / h_max - 1.0).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn dashpot_without_damping_is_the_papers_linear_contact() {
        // ξ = 0 with gravity: ERRATA item 6.
        let (k, m, v, g): (f64, f64, f64, f64) = (3.0e4, 2.0e-6, 0.3, 9.81);
        let r = spring_dashpot(k, 0.0, m, v, g, true).unwrap();
        let p = (k / m).sqrt();
        let t_c = (PI + 2.0 * (g / (v * p)).atan()) / p;
        assert!((r.duration / t_c - 1.0).abs() < 1e-14);
        assert!(
            (r.max_overlap / ((g + (g * g + v * v * p * p).sqrt()) / (p * p)) - 1.0).abs() < 1e-14
        );
        assert!((r.restitution - 1.0).abs() < 1e-13);
    }

    #[test]
    fn walton_braun_gravity_free_closed_form() {
        let (k1, m, v, e): (f64, f64, f64, f64) = (3.0e4, 2.0e-6, 0.3, 0.7);
        let k2 = k1 / (e * e);
        let r = walton_braun(k1, k2, m, v, 0.0).unwrap();
        let (w1, w2) = ((k1 / m).sqrt(), (k2 / m).sqrt());
        assert!((r.restitution / e - 1.0).abs() < 1e-14);
        assert!((r.max_overlap / (v / w1) - 1.0).abs() < 1e-15);
        let t_f = 0.5 * PI * (1.0 / w1 + 1.0 / w2);
        assert!((r.t_force_zero.unwrap() / t_f - 1.0).abs() < 1e-14);
    }

    #[test]
    fn adaptive_reference_meets_the_exact_tsuji_relations() {
        // The integration against the phase-space closed form: 1e−10.
        let (k, m, v): (f64, f64, f64) = (1.2e7, 5.2e-7, 0.313);
        for xi in [0.02_f64, 0.2, 0.5] {
            let gamma = xi * (5.0 * k * m).sqrt();
            for attractive in [true, false] {
                let model = DampedHertz::Tsuji {
                    stiffness: k,
                    damping: gamma,
                };
                let r = damped_hertz(model, m, v, 0.0, attractive).unwrap();
                let (e, h_max) = tsuji_free_exact(k, gamma, m, v, attractive);
                let (de, dh) = (
                    (r.restitution / e - 1.0).abs(),
                    (r.max_overlap / h_max - 1.0).abs(),
                );
                assert!(
                    de < 1e-10 && dh < 1e-10,
                    "ξ {xi} {attractive}: e {de:e}, h {dh:e}"
                );
            }
        }
    }

    #[test]
    fn published_fits_against_the_exact_relations() {
        // Tsuji's polynomial (ξ = √2 α/√5) against e(ξ) with attraction,
        // 0.1 ≤ e ≤ 0.99: measured ≤ 5.16e−3 (at e = 0.1). Thornton's B6
        // (ξ = √(6/5) γ) against the clamped e(ξ), 0.2 ≤ e ≤ 0.9 (ξ < 1,
        // where this closed form holds): measured ≤ 1.26e−3. Both fits are
        // of unknown published accuracy (see their docs).
        let (mut poly, mut b6): (f64, f64) = (0.0, 0.0);
        for i in 10..=99 {
            let e = f64::from(i) / 100.0;
            let xi = 2f64.sqrt() * tsuji_polynomial_alpha(e) / 5f64.sqrt();
            poly = poly.max((spring_dashpot_free_restitution(xi, true) / e - 1.0).abs());
            if (20..=90).contains(&i) {
                let xi = (1.2f64).sqrt() * thornton_b6_gamma(e);
                b6 = b6.max((spring_dashpot_free_restitution(xi, false) / e - 1.0).abs());
            }
        }
        assert!(poly < 5.2e-3 && poly > 5e-3, "{poly:e}");
        assert!(b6 < 1.3e-3 && b6 > 1.2e-3, "{b6:e}");
        assert_eq!(thornton_b6_gamma(1.0), 0.0);
    }

    #[test]
    fn viscoelastic_small_damping_follows_the_series() {
        // e = 1 − C₁ δ' + (3/5) C₁² δ'² + O(δ'³), δ' = (3/2) A (k/m)^(2/5) v^(1/5).
        // Measured on this integrator, the factor 3/2 of the law's damping
        // term belongs in δ' (without it the slope is off by exactly 3/2).
        let (k, m, v): (f64, f64, f64) = (1.2e7, 5.2e-7, 0.313);
        let c1 = viscoelastic_c1();
        assert!((c1 - 1.15345).abs() < 1e-5, "{c1}");
        for delta in [1e-3, 3e-3] {
            let a = delta / 1.5 * (m / k).powf(0.4) * v.powf(-0.2);
            let model = DampedHertz::Viscoelastic { stiffness: k, a };
            let r = damped_hertz(model, m, v, 0.0, true).unwrap();
            let series = 1.0 - c1 * delta + 0.6 * c1 * c1 * delta * delta;
            let err = (r.restitution - series).abs();
            assert!(err < 2.0 * delta.powi(3), "δ' {delta}: {err:e}");
        }
    }
}
