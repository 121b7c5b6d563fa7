//! The paper's estimates as published (eqs. 26–30), for comparison with the exact values.
//! These are NOT the reference; see [`super::linear`] and [`super::power`].

use super::{check_non_negative, check_positive, check_speed};
use crate::{Error, Result};

/// ERRATA 9: the paper's Hertz contact time from eqs. 30–31 cannot be reproduced.
pub const BRILLIANTOV_NOT_REPRODUCIBLE: &str =
    "The paper's T_cN = 4.29 µs (eqs. 30–31, Brilliantov et al.) is not reproducible: \
     n in eq. 31 b is undefined and no physical reading gives 4.29 µs; the exact Hertz contact \
     time of the validation case is 4.926 µs (ERRATA 9). Eq. 30 is fit for choosing a time \
     step, not for validation.";

fn check(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<(f64, f64, f64)> {
    Ok((
        check_positive("p_squared", p_squared)?,
        check_non_negative("gravity", gravity)?,
        check_speed(impact_speed)?,
    ))
}

/// Eq. 26 as printed: `T_c = 2/p · arctan(|v_c| p / g)`. It takes the wrong arctan branch
/// (gives `T_c < π/p`, while gravity lengthens the contact; ERRATA 6). `g = 0` gives `π/p`.
pub fn eq26_as_printed(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<f64> {
    let (p2, g, v) = check(p_squared, gravity, impact_speed)?;
    if v == 0.0 && g == 0.0 {
        return Err(Error::NoContactDynamics);
    }
    let p = p2.sqrt();
    Ok(2.0 * (v * p).atan2(g) / p)
}

/// Eq. 26 corrected (ERRATA 6): `T_c = (π + 2 arctan(g/(|v_c| p)))/p`, the exact linear value.
pub fn eq26_corrected(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<f64> {
    super::linear::duration(p_squared, gravity, impact_speed)
}

/// Eq. 27: `T_c = π/p` (linear, gravity-free).
pub fn eq27(p_squared: f64) -> Result<f64> {
    let p2 = check_positive("p_squared", p_squared)?;
    Ok(std::f64::consts::PI / p2.sqrt())
}

/// Eq. 28 as printed, as a magnitude: `h_max = (sqrt(v_c² p² − g²) + g)/p²` (the correct form
/// has `+g²`, ERRATA 6). Errors when `v_c² p² < g²` (square root of a negative number).
pub fn eq28_as_printed(p_squared: f64, gravity: f64, impact_speed: f64) -> Result<f64> {
    let (p2, g, v) = check(p_squared, gravity, impact_speed)?;
    let vp = v * p2.sqrt();
    let arg = (vp - g) * (vp + g);
    if arg < 0.0 {
        return Err(Error::InvalidParameter {
            name: "impact_speed",
            value: v,
            requirement: "such that v_c² p² ≥ g² for eq. 28 as printed",
        });
    }
    Ok((arg.sqrt() + g) / p2)
}

/// Eq. 29 (Džiugys et al.), as a magnitude: `h_max = |v_c|/p` (linear, gravity-free).
pub fn eq29(p_squared: f64, impact_speed: f64) -> Result<f64> {
    let p2 = check_positive("p_squared", p_squared)?;
    let v = check_speed(impact_speed)?;
    Ok(v / p2.sqrt())
}

/// Eq. 30 (Brilliantov et al.): `T_c = 2.94 (m_eff/k)^(2/5) |v_c|^(−1/5)`.
///
/// Reading used: `k` of eq. 31 a carries the factor `4/5` in front of the Hertz stiffness `K`
/// (`F = K h^(3/2)`, `K/m_eff = p²`), so `m_eff/k = 5/(4 p²)`. Then eq. 30 is the gravity-free
/// exact Hertz time with the coefficient `2·0.4·B(0.4, 1/2) = 2.9432…` rounded to 2.94 (see
/// [`super::power::duration_gravity_free`]); for the validation case it gives ≈ 4.92 µs, not
/// the paper's 4.29 µs ([`BRILLIANTOV_NOT_REPRODUCIBLE`]). `p_squared` is the Hertz `p²`.
pub fn eq30_brilliantov(p_squared: f64, impact_speed: f64) -> Result<f64> {
    let p2 = check_positive("p_squared", p_squared)?;
    let v = check_speed(impact_speed)?;
    if v == 0.0 {
        return Err(Error::NoContactDynamics);
    }
    let t = 2.94 * (1.25 / p2).powf(0.4) * v.powf(-0.2);
    if t.is_finite() {
        Ok(t)
    } else {
        Err(Error::Numerical("eq. 30 not representable"))
    }
}
