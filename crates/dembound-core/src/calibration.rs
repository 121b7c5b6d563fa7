//! From a configured contact model to the concrete law a run uses, with a
//! target restitution turned into the law's coefficient.
//!
//! The spring–dashpot and Tsuji laws invert closed forms (from the physics
//! crate); the viscoelastic law has none, so its exact calibration runs the
//! adaptive reference integrator ([`crate::reference::dissipative`]). This
//! module sits above both [`crate::contact`] and [`crate::reference`], so
//! that the laws never import the references that check them.

use crate::contact::registered::missing;
use crate::contact::{
    with_law, BounceDamping, Calibration, ContactLawKind, ContactModel, Damped, DampingKind,
    Dissipation, Hertz, Hooke, LawVisitor, LinearSpring, NormalContactLaw, Registered, Tsuji,
    Viscoelastic, Viscous, WaltonBraun,
};
use crate::material::ContactPair;
use crate::reference::dissipative::{damped_hertz, DampedHertz};
use crate::{Error, Result};
use dembound_physics::contact::damping::{DampingSetup, DampingSubModel};
use dembound_physics::contact::normal::NormalSubModel;
use dembound_physics::contact::registry::NormalLaw;
use dembound_physics::contact::{damping_ratio_for, registry};

/// Calls `f` with the concrete law of `model` for `pair`, a body of `mass`
/// (kg; the particle's own mass against a fixed boundary) and first impact
/// speed `impact_speed` (m/s; used only to calibrate the viscoelastic law
/// to a target restitution). A target restitution becomes the law's
/// coefficient as `model.calibration` says ([`damping_coefficient`]).
///
/// A damped model is the physics crate's normal and damping sub-models
/// combined by [`Damped`], which applies the no-attraction clamp; elastic
/// models go through [`with_law`] unchanged (their force is ≥ 0 for h ≥ 0,
/// so the clamp would be a no-op).
pub fn with_model<R>(
    model: &ContactModel,
    pair: &ContactPair,
    mass: f64,
    impact_speed: f64,
    f: impl LawVisitor<Output = R>,
) -> Result<R> {
    match (model.law, model.damping) {
        (ContactLawKind::WaltonBraun, DampingKind::None) => match model.dissipation {
            Some(Dissipation::Restitution(e)) => Ok(f.visit(pair.law::<WaltonBraun>(&[e]))),
            _ => Err(Error::Model(
                "law = \"walton-braun\" needs contact.restitution (k2 = k1/e^2)".into(),
            )),
        },
        (_, DampingKind::None) => {
            let normal = model.normal().ok_or_else(|| missing(model))?;
            Ok(with_law(&normal, pair, mass, f))
        }
        _ => {
            let coefficient = damping_coefficient(model, pair, mass, impact_speed)?;
            with_damped(model, pair, mass, coefficient, f)
        }
    }
}

/// Calls `f` with the damped law of `model` (its normal law and damping)
/// for `pair` and `mass` (kg), with the damping's raw `coefficient` (c in
/// N s/m, γ in N s/m^(5/4) or A in s, [`damping_coefficient`]), clamped
/// unless `model.attractive`. The paper's damped laws are [`Damped`]
/// (monomorphised, with their exact onset extras); any other combination
/// the registry allows runs as [`Registered`].
pub fn with_damped<R>(
    model: &ContactModel,
    pair: &ContactPair,
    mass: f64,
    coefficient: f64,
    f: impl LawVisitor<Output = R>,
) -> Result<R> {
    fn combine<N, D, R>(
        normal: N,
        mass: f64,
        coefficient: f64,
        attractive: bool,
        f: impl LawVisitor<Output = R>,
    ) -> R
    where
        N: NormalContactLaw + NormalSubModel,
        D: BounceDamping,
    {
        let damping = D::new(&setup(
            NormalSubModel::stiffness(&normal),
            mass,
            Dissipation::Coefficient(coefficient),
            Calibration::Exact,
            attractive,
        ));
        if attractive {
            f.visit(Damped::<N, D, false> { normal, damping })
        } else {
            f.visit(Damped::<N, D, true> { normal, damping })
        }
    }
    let attractive = model.attractive;
    if !model.damping.combines_with(model.law) {
        return Err(incompatible(model.law, model.damping));
    }
    let hooke = match model.normal() {
        Some(NormalLaw::Hooke { stiffness }) => Some(stiffness),
        _ => None,
    };
    match (model.law, model.damping) {
        (ContactLawKind::Linear, DampingKind::Viscous) => Ok(combine::<_, Viscous, _>(
            pair.law::<LinearSpring>(&[]),
            mass,
            coefficient,
            attractive,
            f,
        )),
        (ContactLawKind::Hertz, DampingKind::Tsuji) => Ok(combine::<_, Tsuji, _>(
            pair.law::<Hertz>(&[]),
            mass,
            coefficient,
            attractive,
            f,
        )),
        (ContactLawKind::Hertz, DampingKind::Viscoelastic) => Ok(combine::<_, Viscoelastic, _>(
            pair.law::<Hertz>(&[]),
            mass,
            coefficient,
            attractive,
            f,
        )),
        // `hooke` is the linear spring with k_n given: the spring–dashpot's
        // exact onset extras apply.
        (ContactLawKind::Registry(_), DampingKind::Viscous) if hooke.is_some() => {
            Ok(combine::<_, Viscous, _>(
                pair.law::<Hooke>(&[hooke.unwrap_or(f64::NAN)]),
                mass,
                coefficient,
                attractive,
                f,
            ))
        }
        _ if attractive => {
            Ok(f.visit(Registered::<false>::damped(model, pair, mass, coefficient)?))
        }
        _ => Ok(f.visit(Registered::<true>::damped(model, pair, mass, coefficient)?)),
    }
}

fn incompatible(law: ContactLawKind, damping: DampingKind) -> Error {
    Error::Model(format!(
        "contact.damping = \"{}\" does not go with law = \"{}\" (allowed with it: {})",
        damping.name(),
        law.row().name,
        registry::dampings_for(law.row())
    ))
}

/// The physics crate's damping setup for a normal law of stiffness
/// `stiffness` (N/m^α) and `mass` (kg).
fn setup(
    stiffness: f64,
    mass: f64,
    dissipation: Dissipation,
    calibration: Calibration,
    attractive: bool,
) -> DampingSetup {
    let clamped_ratio = match (dissipation, calibration, attractive) {
        (Dissipation::Restitution(e), Calibration::Exact, false) if e > 0.0 && e <= 1.0 => {
            damping_ratio_for(e, false)
        }
        _ => f64::NAN,
    };
    DampingSetup {
        stiffness,
        mass,
        dissipation,
        calibration,
        attractive,
        reference_speed: None,
        clamped_ratio,
    }
}

/// The damping's raw coefficient of a damped `model` for `pair` and `mass`
/// (kg): c (N s/m) of the spring–dashpot, γ (N s/m^(5/4)) of Tsuji's, A
/// (s) of the viscoelastic law. Given as `contact.damping_coefficient`, or
/// solved for a target restitution as `model.calibration` says: the closed
/// forms of the physics sub-models for the spring–dashpot and Tsuji, the
/// adaptive reference integration at `impact_speed` (m/s) for the
/// viscoelastic law ([`viscoelastic_coefficient`]).
pub fn damping_coefficient(
    model: &ContactModel,
    pair: &ContactPair,
    mass: f64,
    impact_speed: f64,
) -> Result<f64> {
    let dissipation = model.dissipation.ok_or_else(|| {
        Error::Model(format!(
            "contact.damping = \"{}\" needs contact.restitution or contact.damping_coefficient",
            model.damping.name()
        ))
    })?;
    let (calibration, attractive) = (model.calibration, model.attractive);
    if !model.damping.combines_with(model.law) {
        return Err(incompatible(model.law, model.damping));
    }
    // The stiffness k of F = k h^α the damping scales with: the normal
    // law's own for this pair.
    let normal = model.normal().ok_or_else(|| missing(model))?;
    let k = normal.resolve(&pair.properties()).stiffness();
    let physics = setup(k, mass, dissipation, calibration, attractive);
    match model.damping {
        DampingKind::Viscous => Ok(Viscous::new(&physics).coefficient),
        DampingKind::Tsuji => Ok(Tsuji::new(&physics).coefficient),
        DampingKind::Viscoelastic => {
            let as_run = attractive || calibration == Calibration::Formula;
            viscoelastic_coefficient(k, mass, dissipation, impact_speed, as_run)
        }
        DampingKind::None => Ok(0.0),
    }
}

/// Restitution of a gravity-free impact at `speed` of a body of `mass` under
/// F = k (h^(3/2) + (3/2) A h^(1/2) ḣ), by the adaptive reference integrator.
pub fn viscoelastic_restitution(
    stiffness: f64,
    a: f64,
    mass: f64,
    speed: f64,
    attractive: bool,
) -> Result<f64> {
    let model = DampedHertz::Viscoelastic { stiffness, a };
    damped_hertz(model, mass, speed, 0.0, attractive)
        .map(|r| r.restitution)
        .map_err(|e| Error::Model(format!("viscoelastic calibration: {e}")))
}

/// The viscoelastic law's A (s) for Hertz stiffness `stiffness`
/// (N/m^(3/2)) and `mass` (kg): given, or solved for a target restitution
/// at `impact_speed` (m/s) for the law clamped unless `attractive` (see
/// `reference::dissipative`): e(δ) by the adaptive reference integrator,
/// inverted by bisection in ln δ, δ = A (k/m)^(2/5) v^(1/5).
pub fn viscoelastic_coefficient(
    stiffness: f64,
    mass: f64,
    dissipation: Dissipation,
    impact_speed: f64,
    attractive: bool,
) -> Result<f64> {
    let a = match dissipation {
        Dissipation::Coefficient(a) => a,
        Dissipation::Restitution(e) if e >= 1.0 => 0.0,
        Dissipation::Restitution(e) => {
            if impact_speed.is_nan() || impact_speed <= 0.0 || impact_speed.is_infinite() {
                return Err(Error::Model(
                        "contact.restitution with damping = \"viscoelastic\" needs a first impact speed > 0"
                            .into(),
                    ));
            }
            let t = (mass / stiffness).powf(0.4) * impact_speed.powf(-0.2);
            // A contact that never ends (creeping back under heavy
            // damping) counts as e = 0: the damping is too strong.
            let e_of = |ln_delta: f64| {
                viscoelastic_restitution(
                    stiffness,
                    ln_delta.exp() * t,
                    mass,
                    impact_speed,
                    attractive,
                )
                .unwrap_or(0.0)
            };
            // e decreases with δ: e(1e−9) ≈ 1, e(30) ≈ 0.
            let (mut lo, mut hi) = ((1e-9_f64).ln(), (30.0_f64).ln());
            let (e_low, e_high) = (e_of(hi), e_of(lo));
            if e_high < e || e_low > e {
                // Bad input (exit 2), with the reachable range: a target
                // the law cannot rebound with is not a failed run.
                return Err(Error::Input {
                    field: "contact.restitution".into(),
                    value: crate::scenario::limits::show(e),
                    allowed: format!(
                        "{e_low:.4e} to {e_high:.9} (or 1) with damping = \"viscoelastic\" at \
                         this impact speed ({impact_speed:.4e} m/s): the rest is out of reach of \
                         the viscoelastic law (0 < δ ≤ 30, δ = A (k/m)^(2/5) v^(1/5)); a smaller \
                         e needs damping = \"tsuji\" or \"viscous\""
                    ),
                });
            }
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if e_of(mid) > e {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo < 1e-13 {
                    break;
                }
            }
            (0.5 * (lo + hi)).exp() * t
        }
    };
    Ok(a)
}
