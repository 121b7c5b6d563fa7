//! The value checks of the scene file's validation: each error names the
//! key, the value and the allowed range ([`SceneError::Input`], exit 2).

use crate::{limits, SceneError};

pub(crate) fn invalid(key: &str, value: impl std::fmt::Display, allowed: &str) -> SceneError {
    SceneError::input(format!(
        "invalid value for `{key}`: {value} (allowed: {allowed})"
    ))
}

pub(crate) fn check(
    ok: bool,
    key: &str,
    value: impl std::fmt::Display,
    allowed: &str,
) -> Result<(), SceneError> {
    if ok {
        Ok(())
    } else {
        Err(invalid(key, value, allowed))
    }
}

pub(crate) fn positive(key: &str, x: f64, unit: &str) -> Result<(), SceneError> {
    check(
        x > 0.0 && x.is_finite(),
        key,
        x,
        &format!("finite and > 0, in {unit}"),
    )
}

pub(crate) fn finite3(key: &str, v: [f64; 3], unit: &str) -> Result<(), SceneError> {
    check(
        v.iter().all(|x| x.is_finite()),
        key,
        format!("{v:?}"),
        &format!("three finite numbers, in {unit}"),
    )
}

/// `x` in `range` (both ends included), in `unit`; the ranges are
/// [`crate::limits`]'s.
pub(crate) fn ranged(key: &str, x: f64, range: (f64, f64), unit: &str) -> Result<(), SceneError> {
    check(
        limits::within(x, range),
        key,
        limits::show(x),
        &limits::describe(range, unit),
    )
}

/// A velocity of at most [`limits::MAX_SPEED`].
pub(crate) fn speed(key: &str, v: [f64; 3]) -> Result<(), SceneError> {
    finite3(key, v, "m/s")?;
    let s = limits::norm(v);
    check(
        s <= limits::MAX_SPEED,
        key,
        format!("{v:?} (|v| = {} m/s)", limits::show(s)),
        &format!("|v| ≤ {} m/s", limits::show(limits::MAX_SPEED)),
    )
}

pub(crate) fn nonzero3(key: &str, v: [f64; 3]) -> Result<(), SceneError> {
    check(
        v.iter().all(|x| x.is_finite()) && v.iter().any(|x| *x != 0.0),
        key,
        format!("{v:?}"),
        "a finite non-zero vector",
    )
}
