//! Exact reference solution for an elastic sphere bouncing under gravity on a DEM boundary
//! sphere (Jasevičius & Kačianauskas 2007, sections 3–4), in the consistent reading of
//! `ERRATA.md`.
//!
//! Conventions (all SI): `x` is the gap between the surfaces (upward positive), the overlap is
//! `h = −x ≥ 0` during contact. During contact the equation of motion is (ERRATA 1, corrected
//! eq. 9) `h'' = g − p² h^α`, i.e. `ẍ = −g + p² (−x)^α`, with `α ≥ 1` (`α = 1` linear,
//! `α = 1.5` Hertz) and `p² = k/m` (eq. 10). Out of contact `ẍ = −g`.
//!
//! The model is conservative and time-reversible, so every contact has the same impact speed
//! `|v_c| = sqrt(v0² + 2 g H0)`, the rebound speed equals the impact speed, and the maximum
//! overlap is reached at exactly half the contact duration (ERRATA 6, 8).
//!
//! * [`linear`]: closed forms for `α = 1` with gravity (ERRATA 6, eqs. 20–22 b).
//! * [`power`]: any `α ≥ 1` with gravity through a cancellation-free quadrature (ERRATA 8), and
//!   the gravity-free closed forms.
//! * [`paper`]: the paper's estimates as printed (eqs. 26–30), for comparison only.
//!
//! Nothing here panics, prints or performs I/O; every fallible function returns
//! [`crate::Result`] (the crate's [`Error`]).

pub mod dissipative;
pub mod linear;
pub mod paper;
pub mod power;
mod scenario;

pub use scenario::{flight, problem, scenario_contacts, scenario_contacts_with};

use crate::{Error, Result};

/// Parameters of the contact law `h'' = g − p² h^α` (ERRATA 1, corrected eq. 9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactProblem {
    /// `p² = k/m` (eqs. 10–11), s⁻² m^(1−α). Must be finite and positive.
    pub p_squared: f64,
    /// Force exponent `α` (eq. 4): 1 linear, 1.5 Hertz. Must be finite and `≥ 1`.
    pub alpha: f64,
    /// Gravitational acceleration `g ≥ 0`, m/s² (pointing towards the boundary).
    pub gravity: f64,
}

/// Initial conditions of the free flight (eq. 15).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flight {
    /// Initial gap `H0 ≥ 0` between the surfaces, m.
    pub gap: f64,
    /// Initial velocity `v0`, m/s, upward positive.
    pub velocity: f64,
    /// Gravitational acceleration `g ≥ 0`, m/s².
    pub gravity: f64,
}

/// Exact per-contact values (all SI; times absolute from `t = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactContact {
    /// Start of the contact `t_c` (ERRATA 7).
    pub t_contact: f64,
    /// Time of maximum overlap `t_mp = t_c + T_c/2` (ERRATA 6, 8).
    pub t_max_overlap: f64,
    /// Rebound time `t_r = t_c + T_c`.
    pub t_rebound: f64,
    /// Contact duration `T_c = t_r − t_c`.
    pub duration: f64,
    /// Maximum overlap `h_max > 0` (the paper prints the signed position, ERRATA 10).
    pub max_overlap: f64,
    /// Contact force per unit mass at maximum overlap, `p² h_max^α`, m/s².
    pub max_force_per_mass: f64,
    /// Net upward acceleration at maximum overlap, `p² h_max^α − g` (eq. 25 corrected, ERRATA 6).
    pub max_acceleration: f64,
    /// Velocity at contact start, `v_c = −|v_c| ≤ 0` (eq. 24 generalised).
    pub impact_velocity: f64,
    /// Velocity at rebound, `v_r = +|v_c| ≥ 0` (conservative model, ERRATA 8).
    pub rebound_velocity: f64,
    /// Height of the apex of the following flight, `v_r²/(2g)`; `+∞` when `g = 0`.
    pub apex_height: f64,
}

/// A single contact that starts at `h = 0` with speed `|v_c|`; times relative to contact start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactShape {
    /// Contact duration `T_c`.
    pub duration: f64,
    /// Time from contact start to maximum overlap (`= T_c/2`).
    pub time_to_max_overlap: f64,
    /// Maximum overlap `h_max > 0`.
    pub max_overlap: f64,
}

pub(crate) fn check_finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            requirement: "finite",
        })
    }
}

pub(crate) fn check_non_negative(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            requirement: "finite and >= 0",
        })
    }
}

pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            requirement: "finite and > 0",
        })
    }
}

/// Validated `(p², α, g)`.
pub(crate) fn check_problem(problem: &ContactProblem) -> Result<(f64, f64, f64)> {
    let p2 = check_positive("p_squared", problem.p_squared)?;
    let alpha = problem.alpha;
    if !(alpha.is_finite() && alpha >= 1.0) {
        return Err(Error::InvalidParameter {
            name: "alpha",
            value: alpha,
            requirement: "finite and >= 1",
        });
    }
    let g = check_non_negative("gravity", problem.gravity)?;
    Ok((p2, alpha, g))
}

/// Validated `(H0, v0, g)`.
fn check_flight(flight: &Flight) -> Result<(f64, f64, f64)> {
    let h0 = check_non_negative("gap", flight.gap)?;
    let v0 = check_finite("velocity", flight.velocity)?;
    let g = check_non_negative("gravity", flight.gravity)?;
    Ok((h0, v0, g))
}

/// Validated impact speed: the sign is ignored (`|v_c|` is used), it must be finite.
pub(crate) fn check_speed(impact_speed: f64) -> Result<f64> {
    check_finite("impact_speed", impact_speed).map(f64::abs)
}

/// Impact speed `|v_c| = sqrt(v0² + 2 g H0)` (eq. 24 generalised to `v0 ≠ 0`); the same for every
/// contact because the model is conservative (ERRATA 7, 8).
///
/// Errors if the particle never reaches the boundary (`g = 0` with `v0 ≥ 0`, unless
/// `H0 = 0` and `v0 = 0`, which is rejected too as it gives no motion).
pub fn impact_speed(flight: &Flight) -> Result<f64> {
    // Validates reachability as well.
    first_contact_time(flight)?;
    let (h0, v0, g) = check_flight(flight)?;
    let speed = v0.hypot((2.0 * g * h0).sqrt());
    check_finite("impact speed", speed)
}

/// Time of the first contact (ERRATA 7):
/// `t_c(1) = (v0 + sqrt(v0² + 2 g H0)) / g` for `v0 ≥ 0`, and the cancellation-free
/// `2 H0 / (sqrt(v0² + 2 g H0) − v0)` for `v0 < 0` (also valid for `g = 0`).
///
/// `H0 = 0` with `v0 ≤ 0` gives `0` (`g > 0`, or `v0 < 0`); `g = 0` with `v0 ≥ 0` is an error
/// (the particle never arrives, or rests on the boundary without force).
pub fn first_contact_time(flight: &Flight) -> Result<f64> {
    let (h0, v0, g) = check_flight(flight)?;
    let s = v0.hypot((2.0 * g * h0).sqrt());
    let t = if v0 < 0.0 {
        2.0 * h0 / (s - v0)
    } else if g > 0.0 {
        (v0 + s) / g
    } else {
        return Err(Error::NoImpact);
    };
    if t.is_finite() && t >= 0.0 {
        Ok(t)
    } else {
        Err(Error::Numerical("first contact time is not finite"))
    }
}

/// Shape of one contact starting at `h = 0` with speed `|impact_speed|` (sign ignored).
///
/// `α = 1` uses the closed forms of [`linear`] (ERRATA 6); any other `α` the quadrature of
/// [`power::contact_shape`] (ERRATA 8; for `g = 0` it agrees with the closed forms of
/// [`power::gravity_free_shape`] to ~1e−16).
pub fn contact_shape(problem: &ContactProblem, impact_speed: f64) -> Result<ContactShape> {
    let (p2, alpha, g) = check_problem(problem)?;
    if alpha == 1.0 {
        linear::contact_shape(p2, g, impact_speed)
    } else {
        power::contact_shape(problem, impact_speed)
    }
}

/// Largest `n` accepted by [`contacts`] (guards against huge allocations).
pub const MAX_CONTACTS: usize = 10_000_000;

/// The first `n` contacts of the bouncing particle. The `k`-th contact (1-based) starts at
/// `t_c(1) + (k−1)(T_c + 2|v_c|/g)` (ERRATA 7; eq. 23's `T_f` is the fall time only, the flight
/// between two contacts lasts `2|v_c|/g`).
///
/// Errors: invalid parameters, different gravities in `problem` and `flight`, a particle that
/// never reaches the boundary, `n > 1` with `g = 0` (only one contact happens), and
/// `n >` [`MAX_CONTACTS`].
pub fn contacts(problem: &ContactProblem, flight: &Flight, n: usize) -> Result<Vec<ExactContact>> {
    if n > MAX_CONTACTS {
        return Err(Error::InvalidParameter {
            name: "n",
            value: n as f64,
            requirement: "at most MAX_CONTACTS",
        });
    }
    let (p2, alpha, g) = check_problem(problem)?;
    let (_, _, gf) = check_flight(flight)?;
    if g != gf {
        return Err(Error::InconsistentGravity {
            problem: g,
            flight: gf,
        });
    }
    let t1 = first_contact_time(flight)?;
    let v = impact_speed(flight)?;
    if g == 0.0 && n > 1 {
        return Err(Error::NoFurtherContact { requested: n });
    }
    let shape = contact_shape(problem, v)?;
    let hm = shape.max_overlap;
    // p² h_max^α from the root identity (ERRATA 8) `p² h^(α+1)/(α+1) = g h + v²/2`:
    // p² h_max^α = (α+1)(g + v²/(2 h_max)), a sum of non-negative terms (no cancellation), and
    // a_max = p² h_max^α − g = α g + (α+1) v²/(2 h_max). For α = 1 this is sqrt(g² + v²p²).
    let (force, accel) = if alpha == 1.0 {
        let a = linear::max_acceleration(p2, g, v)?;
        (a + g, a)
    } else {
        let q = v * v / (2.0 * hm);
        ((alpha + 1.0) * (g + q), alpha * g + (alpha + 1.0) * q)
    };
    let period = if g > 0.0 {
        shape.duration + 2.0 * v / g
    } else {
        0.0
    };
    let apex = if g > 0.0 {
        v * v / (2.0 * g)
    } else {
        f64::INFINITY
    };
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let tc = t1 + (k as f64) * period;
        out.push(ExactContact {
            t_contact: tc,
            t_max_overlap: tc + shape.time_to_max_overlap,
            t_rebound: tc + shape.duration,
            duration: shape.duration,
            max_overlap: hm,
            max_force_per_mass: force,
            max_acceleration: accel,
            impact_velocity: -v,
            rebound_velocity: v,
            apex_height: apex,
        });
    }
    Ok(out)
}

/// Overlap history of one contact: `(h, dh/dt)` at time `tau ∈ [0, T_c]` after contact start
/// with speed `|impact_speed|`. Exact curve: the closed form (eqs. 20–21 b, `h = −x`) for
/// `α = 1`, otherwise the inversion of `t(h)` of [`power::overlap_at`] (ERRATA 8).
pub fn overlap_at(problem: &ContactProblem, impact_speed: f64, tau: f64) -> Result<(f64, f64)> {
    let (p2, alpha, g) = check_problem(problem)?;
    if alpha == 1.0 {
        let st = linear::state_at(p2, g, impact_speed, tau)?;
        Ok((-st.position, -st.velocity))
    } else {
        power::overlap_at(problem, impact_speed, tau)
    }
}

#[cfg(test)]
mod tests;
