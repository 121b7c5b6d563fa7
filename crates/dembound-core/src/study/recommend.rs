//! Recommended boundary parameters: how far a quantity q (h_max, T_c, a_max)
//! departs from its rigid half-space value, `|q(r, ζ)/q(∞, ∞) − 1|`, and the
//! smallest ζ (or r) that keeps that deviation within a tolerance T.
//!
//! The deviation is monotone in each of r and ζ (p² = k/m grows with both
//! for α < 2, and h_max, T_c fall and a_max grows with p², with or without
//! gravity), so the limit is the single root of `deviation − T`, found on
//! the exact model with Brent's method (`roots`) in u = 1/x, and then
//! checked by the integrator at the point found.
//!
//! Closed forms. Without gravity q/q∞ = s^(−1/(α+1)) for h_max and T_c and
//! s^(1/(α+1)) for a_max, with s = ζ̄ r̄^(2−α) (ERRATA 16), so the limit is
//! s* = (1+T)^(−(α+1)) (resp. (1−T)^(α+1)): with r = ∞, 1/ζ = (1+T)^(α+1) − 1,
//! and with ζ = ∞, 1/r = (1+T)^((α+1)/(2−α)) − 1 (h_max, T_c). With gravity
//! h_max has a closed form too: from p² h^(α+1)/(α+1) = g h + v_c²/2 at
//! h = (1+T) h∞ and at h∞, s* = (1+T)^(−(α+1)) (1 + γ(1+T))/(1 + γ) with
//! γ = 2 g h∞/v_c² (h∞ the exact rigid half-space overlap with gravity).

use super::{bar, first_contact, Axis, Model, Quantity, StudyError};
use crate::bounce::{InputError, Scenario};
use crate::contact::ContactLawKind;
use roots::{find_root_brent, Convergency};
use serde::Serialize;
use std::fmt;

/// Why a recommendation could not be computed.
#[derive(Debug, Clone, PartialEq)]
pub enum RecommendError {
    /// A value out of range (names the argument, the value and the range).
    Input(InputError),
    /// The exact model or the integrator failed.
    Study(StudyError),
    /// Root finding failed.
    Numerical(&'static str),
}

impl fmt::Display for RecommendError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RecommendError::Input(e) => e.fmt(f),
            RecommendError::Study(e) => e.fmt(f),
            RecommendError::Numerical(what) => write!(f, "root finding failed: {what}"),
        }
    }
}

impl std::error::Error for RecommendError {}

impl From<StudyError> for RecommendError {
    fn from(e: StudyError) -> Self {
        RecommendError::Study(e)
    }
}

impl From<InputError> for RecommendError {
    fn from(e: InputError) -> Self {
        RecommendError::Input(e)
    }
}

fn input(field: &str, value: f64, allowed: &str) -> RecommendError {
    RecommendError::Input(InputError {
        field: field.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    })
}

fn scenario_for(base: &Scenario, law: ContactLawKind, r: f64, zeta: f64) -> Scenario {
    let mut s = *base;
    s.contact.law = law;
    s.boundary.radius_ratio = r;
    s.boundary.modulus_ratio = zeta;
    s.motion.contacts = 1;
    s
}

/// `|q(r, ζ)/q(∞, ∞) − 1|` for one model.
pub fn deviation(
    base: &Scenario,
    law: ContactLawKind,
    r: f64,
    zeta: f64,
    quantity: Quantity,
    model: Model,
) -> Result<f64, StudyError> {
    let q = |r, z| first_contact(&scenario_for(base, law, r, z), model).map(|c| quantity.of(&c));
    Ok((q(r, zeta)? / q(f64::INFINITY, f64::INFINITY)? - 1.0).abs())
}

/// The deviation of one quantity, exact and integrated.
#[derive(Debug, Clone, Serialize)]
pub struct QuantityDeviation {
    pub quantity: Quantity,
    /// Exact model, fraction (not %).
    pub exact: f64,
    /// Integrator, fraction.
    pub simulated: f64,
}

/// The deviations of h_max, T_c and a_max at one (r, ζ).
#[derive(Debug, Clone, Serialize)]
pub struct Deviations {
    pub law: ContactLawKind,
    #[serde(with = "crate::serde_inf")]
    pub radius_ratio: f64,
    #[serde(with = "crate::serde_inf")]
    pub modulus_ratio: f64,
    pub quantities: Vec<QuantityDeviation>,
}

fn check_ratio(field: &str, x: f64) -> Result<(), RecommendError> {
    if x > 0.0 && !x.is_nan() {
        Ok(())
    } else {
        Err(input(field, x, "> 0, or inf"))
    }
}

/// Deviations of every quantity at (r, ζ), exact and by the integrator.
pub fn deviations(
    base: &Scenario,
    law: ContactLawKind,
    r: f64,
    zeta: f64,
) -> Result<Deviations, RecommendError> {
    check_ratio("r", r)?;
    check_ratio("zeta", zeta)?;
    scenario_for(base, law, r, zeta).validate()?;
    let quantities = Quantity::ALL
        .iter()
        .map(|&q| {
            Ok(QuantityDeviation {
                quantity: q,
                exact: deviation(base, law, r, zeta, q, Model::Exact)?,
                simulated: deviation(base, law, r, zeta, q, Model::Simulated)?,
            })
        })
        .collect::<Result<_, StudyError>>()?;
    Ok(Deviations {
        law,
        radius_ratio: r,
        modulus_ratio: zeta,
        quantities,
    })
}

/// What the search found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Outcome {
    /// The smallest value that keeps the deviation within T.
    Found { value: f64 },
    /// No value does: the other parameter alone already gives `floor` ≥ T.
    Unreachable { floor: f64 },
    /// Every value does (down to 1e−12): e.g. a_max with T ≥ 1.
    AnyValue,
}

/// The smallest ζ (or r) within tolerance.
#[derive(Debug, Clone, Serialize)]
pub struct Limit {
    pub law: ContactLawKind,
    pub quantity: Quantity,
    /// T, a fraction (0.01 = 1 %).
    pub tolerance: f64,
    /// The parameter solved for.
    pub solved: Axis,
    /// The other parameter's value (∞ when not given).
    #[serde(with = "crate::serde_inf")]
    pub other: f64,
    pub outcome: Outcome,
    /// Exact deviation at the limit (= T to root-finding accuracy).
    pub exact_deviation: Option<f64>,
    /// The integrator's deviation at the limit (its own rigid half-space run as reference).
    pub simulated_deviation: Option<f64>,
    /// The gravity-free closed form of the limit (see the module doc).
    pub gravity_free: Option<f64>,
    /// For h_max with gravity: the closed form with gravity (module doc).
    pub closed_form: Option<f64>,
}

impl Limit {
    /// The value found, if any.
    pub fn value(&self) -> Option<f64> {
        match self.outcome {
            Outcome::Found { value } => Some(value),
            _ => None,
        }
    }
}

/// The barred value x̄ = x/(x+1) back to x.
fn unbar(xb: f64) -> f64 {
    xb / (1.0 - xb)
}

/// Solves s* = ζ̄ r̄^(2−α) for the `solved` parameter given the other.
fn solve_s(s_target: f64, alpha: f64, solved: Axis, other: f64) -> Option<f64> {
    let xb = match solved {
        Axis::Modulus => s_target / bar(other).powf(2.0 - alpha),
        Axis::Radius => (s_target / bar(other)).powf(1.0 / (2.0 - alpha)),
    };
    (xb > 0.0 && xb < 1.0).then(|| unbar(xb))
}

/// The gravity-free limit (closed form): `None` when no value (or every
/// value) satisfies T.
pub fn gravity_free_limit(
    alpha: f64,
    quantity: Quantity,
    tolerance: f64,
    solved: Axis,
    other: f64,
) -> Option<f64> {
    let n = alpha + 1.0;
    let s = match quantity {
        Quantity::MaxAcceleration if tolerance >= 1.0 => return None,
        Quantity::MaxAcceleration => (1.0 - tolerance).powf(n),
        _ => (1.0 + tolerance).powf(-n),
    };
    solve_s(s, alpha, solved, other)
}

/// The h_max limit with gravity in closed form (module doc), from the exact
/// rigid half-space overlap h∞ with gravity.
pub fn max_overlap_limit_with_gravity(
    base: &Scenario,
    law: ContactLawKind,
    tolerance: f64,
    solved: Axis,
    other: f64,
) -> Result<Option<f64>, StudyError> {
    let alpha = law.exponent();
    let s = scenario_for(base, law, f64::INFINITY, f64::INFINITY);
    let h_inf = first_contact(&s, Model::Exact)?.max_overlap;
    let v = s.impact_speed();
    let gamma = 2.0 * s.motion.gravity * h_inf / (v * v);
    let t1 = 1.0 + tolerance;
    let s_target = t1.powf(-(alpha + 1.0)) * (1.0 + gamma * t1) / (1.0 + gamma);
    Ok(solve_s(s_target, alpha, solved, other))
}

struct RelTol(f64);

impl Convergency<f64> for RelTol {
    fn is_root_found(&mut self, y: f64) -> bool {
        y == 0.0
    }
    fn is_converged(&mut self, a: f64, b: f64) -> bool {
        (a - b).abs() <= self.0 * a.abs().max(b.abs())
    }
    fn is_iteration_limit_reached(&mut self, iter: usize) -> bool {
        iter >= 500
    }
}

/// The smallest value of `solved` (the other parameter at `other`, ∞ for
/// "not given") that keeps `|q/q∞ − 1| ≤ tolerance` on the exact model,
/// checked by the integrator at that value.
pub fn smallest(
    base: &Scenario,
    law: ContactLawKind,
    quantity: Quantity,
    tolerance: f64,
    solved: Axis,
    other: f64,
) -> Result<Limit, RecommendError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(input(
            "tolerance",
            tolerance,
            "finite and > 0 (a fraction: 0.01 = 1 %)",
        ));
    }
    let other_name = match solved.other() {
        Axis::Radius => "r",
        Axis::Modulus => "zeta",
    };
    check_ratio(other_name, other)?;
    let alpha = law.exponent();
    if solved == Axis::Radius && alpha >= 2.0 {
        return Err(input(
            "law",
            alpha,
            "α < 2 when solving for r (r̄^(2−α): r has no effect at α = 2 and the opposite one above)",
        ));
    }
    let at = |x: f64| -> (f64, f64) {
        match solved {
            Axis::Modulus => (other, x),
            Axis::Radius => (x, other),
        }
    };
    {
        let (r, z) = at(1.0);
        scenario_for(base, law, r, z).validate()?;
    }
    let dev = |x: f64, model| {
        let (r, z) = at(x);
        deviation(base, law, r, z, quantity, model)
    };
    let gravity_free = gravity_free_limit(alpha, quantity, tolerance, solved, other);
    let closed_form = if quantity == Quantity::MaxOverlap && base.motion.gravity > 0.0 {
        max_overlap_limit_with_gravity(base, law, tolerance, solved, other)?
    } else {
        None
    };
    let mut limit = Limit {
        law,
        quantity,
        tolerance,
        solved,
        other,
        outcome: Outcome::AnyValue,
        exact_deviation: None,
        simulated_deviation: None,
        gravity_free,
        closed_form,
    };
    let floor = dev(f64::INFINITY, Model::Exact)?;
    if floor >= tolerance {
        limit.outcome = Outcome::Unreachable { floor };
        return Ok(limit);
    }
    // u = 1/x: the deviation grows with u from `floor` at u = 0.
    let mut u_hi = 1.0;
    loop {
        if dev(1.0 / u_hi, Model::Exact)? > tolerance {
            break;
        }
        if u_hi > 1e12 {
            return Ok(limit);
        }
        u_hi *= 4.0;
    }
    let mut error: Option<StudyError> = None;
    let f = |u: f64| match dev(1.0 / u, Model::Exact) {
        Ok(d) => d - tolerance,
        Err(e) => {
            error.get_or_insert(e);
            f64::NAN
        }
    };
    let root = find_root_brent(0.0, u_hi, f, &mut RelTol(1e-14));
    if let Some(e) = error {
        return Err(e.into());
    }
    let u = root.map_err(|_| RecommendError::Numerical("Brent did not converge"))?;
    let value = 1.0 / u;
    limit.outcome = Outcome::Found { value };
    limit.exact_deviation = Some(dev(value, Model::Exact)?);
    limit.simulated_deviation = Some(dev(value, Model::Simulated)?);
    Ok(limit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::gravity_free;

    const INF: f64 = f64::INFINITY;

    fn rel(a: f64, b: f64) -> f64 {
        (a / b - 1.0).abs()
    }

    #[test]
    fn hertz_max_overlap_limits_match_the_closed_forms() {
        // ζ = 1/((1+T)^(α+1) − 1) with r = ∞, r = 1/((1+T)^((α+1)/(2−α)) − 1)
        // with ζ = ∞: exact without gravity; with gravity, against the
        // closed form derived with gravity (module doc), both to 1e−6.
        let t: f64 = 0.01;
        let zeta0 = 1.0 / (1.01f64.powf(2.5) - 1.0);
        let r0 = 1.0 / (1.01f64.powf(5.0) - 1.0);
        let hertz = ContactLawKind::Hertz;
        let q = Quantity::MaxOverlap;
        let free = gravity_free(&Scenario::default());
        let z = smallest(&free, hertz, q, t, Axis::Modulus, INF).unwrap();
        let r = smallest(&free, hertz, q, t, Axis::Radius, INF).unwrap();
        assert!(rel(z.value().unwrap(), zeta0) < 1e-6, "{z:?}");
        assert!(rel(r.value().unwrap(), r0) < 1e-6, "{r:?}");
        assert!(rel(z.gravity_free.unwrap(), zeta0) < 1e-12);

        let g = Scenario::default();
        let z = smallest(&g, hertz, q, t, Axis::Modulus, INF).unwrap();
        let r = smallest(&g, hertz, q, t, Axis::Radius, INF).unwrap();
        assert!(
            rel(z.value().unwrap(), z.closed_form.unwrap()) < 1e-6,
            "{z:?}"
        );
        assert!(
            rel(r.value().unwrap(), r.closed_form.unwrap()) < 1e-6,
            "{r:?}"
        );
        // Gravity matters only at the 1e−4 level here.
        assert!(rel(z.value().unwrap(), zeta0) < 1e-3);
        assert!(rel(z.value().unwrap(), zeta0) > 1e-7);
        // The exact deviation at the limit is T; the integrator's agrees closely.
        assert!((z.exact_deviation.unwrap() - t).abs() < 1e-9);
        assert!((z.simulated_deviation.unwrap() - t).abs() < 1e-4);
    }

    #[test]
    fn given_one_parameter_and_unreachable_cases() {
        let g = Scenario::default();
        let hertz = ContactLawKind::Hertz;
        // r = 100 alone already costs 0.18 % of h_max: within 1 %, ζ has a limit
        // larger than with r = ∞.
        let z_inf = smallest(&g, hertz, Quantity::MaxOverlap, 0.01, Axis::Modulus, INF).unwrap();
        let z_100 = smallest(&g, hertz, Quantity::MaxOverlap, 0.01, Axis::Modulus, 100.0).unwrap();
        assert!(z_100.value().unwrap() > z_inf.value().unwrap());
        assert!(rel(z_100.value().unwrap(), z_100.closed_form.unwrap()) < 1e-6);
        // r = 10 alone costs 1.9 %: no ζ keeps h_max within 1 %.
        let none = smallest(&g, hertz, Quantity::MaxOverlap, 0.01, Axis::Modulus, 10.0).unwrap();
        match none.outcome {
            Outcome::Unreachable { floor } => assert!((floor - 0.019).abs() < 1e-3),
            other => panic!("{other:?}"),
        }
        assert!(none.closed_form.is_none());
        // a_max can at most fall by 100 %: with T = 2 every ζ will do.
        let any = smallest(
            &g,
            hertz,
            Quantity::MaxAcceleration,
            2.0,
            Axis::Modulus,
            INF,
        )
        .unwrap();
        assert_eq!(any.outcome, Outcome::AnyValue);
        // Bad input names the argument.
        let e = smallest(&g, hertz, Quantity::Duration, -0.1, Axis::Modulus, INF).unwrap_err();
        assert!(matches!(e, RecommendError::Input(ref i) if i.field == "tolerance"));
        let e = smallest(&g, hertz, Quantity::Duration, 0.1, Axis::Modulus, 0.0).unwrap_err();
        assert!(matches!(e, RecommendError::Input(ref i) if i.field == "r"));
    }

    #[test]
    fn other_quantities_match_their_gravity_free_forms() {
        let free = gravity_free(&Scenario::default());
        for law in [ContactLawKind::Linear, ContactLawKind::Hertz] {
            for q in Quantity::ALL {
                for axis in [Axis::Modulus, Axis::Radius] {
                    let l = smallest(&free, law, q, 0.02, axis, INF).unwrap();
                    let v = l.value().unwrap();
                    assert!(rel(v, l.gravity_free.unwrap()) < 1e-6, "{l:?}");
                }
            }
        }
        let d = deviations(&Scenario::default(), ContactLawKind::Hertz, 100.0, 100.0).unwrap();
        for q in &d.quantities {
            assert!(q.exact > 0.003 && q.exact < 0.006, "{q:?}");
            assert!((q.simulated - q.exact).abs() < 1e-4, "{q:?}");
        }
    }
}
