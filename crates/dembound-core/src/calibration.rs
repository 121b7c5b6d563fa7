//! From a configured contact model to the concrete law a run uses, with a
//! target restitution turned into the law's coefficient.
//!
//! The spring–dashpot and Tsuji laws invert closed forms (from the physics
//! crate); the viscoelastic law has none, so its exact calibration runs the
//! adaptive reference integrator ([`crate::reference::dissipative`]). This
//! module sits above both [`crate::contact`] and [`crate::reference`], so
//! that the laws never import the references that check them.

use crate::contact::{
    with_law, Calibration, ContactLawKind, ContactModel, DampingKind, Dissipation, HertzTsuji,
    HertzViscoelastic, LawVisitor, LinearDashpot, ModelError, NoAttraction, NormalContactLaw,
    WaltonBraun,
};
use crate::material::ContactPair;
use crate::reference::dissipative::{damped_hertz, DampedHertz};
use dembound_physics::contact::registry;

/// Calls `f` with the concrete law of `model` for `pair`, a body of `mass`
/// (kg; the particle's own mass against a fixed boundary) and first impact
/// speed `impact_speed` (m/s; used only to calibrate the viscoelastic law
/// to a target restitution). A target restitution becomes the law's
/// coefficient as `model.calibration` says.
///
/// Each dissipative law is its own type and the no-attraction clamp is the
/// wrapper [`NoAttraction`]; elastic models go through [`with_law`]
/// unchanged (their force is ≥ 0 for h ≥ 0, so the clamp would be a no-op).
pub fn with_model<R>(
    model: &ContactModel,
    pair: &ContactPair,
    mass: f64,
    impact_speed: f64,
    f: impl LawVisitor<Output = R>,
) -> Result<R, ModelError> {
    fn clamp<L: NormalContactLaw, R>(
        law: L,
        attractive: bool,
        f: impl LawVisitor<Output = R>,
    ) -> R {
        if attractive {
            f.visit(law)
        } else {
            f.visit(NoAttraction(law))
        }
    }
    let need = || {
        model.dissipation.ok_or_else(|| {
            ModelError(format!(
                "contact.damping = \"{}\" needs contact.restitution or contact.damping_coefficient",
                model.damping.name()
            ))
        })
    };
    let (attractive, calibration) = (model.attractive, model.calibration);
    match (model.law, model.damping) {
        (ContactLawKind::WaltonBraun, DampingKind::None) => match need() {
            Ok(Dissipation::Restitution(e)) => Ok(f.visit(pair.law::<WaltonBraun>(&[e]))),
            _ => Err(ModelError(
                "law = \"walton-braun\" needs contact.restitution (k2 = k1/e^2)".into(),
            )),
        },
        (law, DampingKind::None) => Ok(with_law(law, pair, f)),
        (ContactLawKind::Linear, DampingKind::Viscous) => Ok(clamp(
            LinearDashpot::calibrated(pair, mass, need()?, calibration, attractive),
            attractive,
            f,
        )),
        (ContactLawKind::Hertz, DampingKind::Tsuji) => Ok(clamp(
            HertzTsuji::calibrated(pair, mass, need()?, calibration, attractive),
            attractive,
            f,
        )),
        (ContactLawKind::Hertz, DampingKind::Viscoelastic) => Ok(clamp(
            HertzViscoelastic::calibrated(
                pair,
                mass,
                need()?,
                impact_speed,
                calibration,
                attractive,
            )?,
            attractive,
            f,
        )),
        (law, damping) => Err(ModelError(format!(
            "contact.damping = \"{}\" does not go with law = \"{}\" (allowed with it: {})",
            damping.name(),
            law.row().name,
            registry::dampings_for(law.row())
        ))),
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
) -> Result<f64, ModelError> {
    let model = DampedHertz::Viscoelastic { stiffness, a };
    damped_hertz(model, mass, speed, 0.0, attractive)
        .map(|r| r.restitution)
        .map_err(|e| ModelError(format!("viscoelastic calibration: {e}")))
}

impl HertzViscoelastic {
    /// As [`Self::for_pair`], calibrating for the law as run
    /// ([`Calibration::Exact`]) or for the unclamped law
    /// ([`Calibration::Formula`]).
    pub fn calibrated(
        pair: &ContactPair,
        mass: f64,
        dissipation: Dissipation,
        impact_speed: f64,
        calibration: Calibration,
        attractive: bool,
    ) -> Result<Self, ModelError> {
        let as_run = attractive || calibration == Calibration::Formula;
        Self::for_pair(pair, mass, dissipation, impact_speed, as_run)
    }

    /// A from a target restitution at `impact_speed` (see the module doc),
    /// or A given (s).
    pub fn for_pair(
        pair: &ContactPair,
        mass: f64,
        dissipation: Dissipation,
        impact_speed: f64,
        attractive: bool,
    ) -> Result<Self, ModelError> {
        let stiffness = pair.power_law_stiffness(1.5);
        let a = match dissipation {
            Dissipation::Coefficient(a) => a,
            Dissipation::Restitution(e) if e >= 1.0 => 0.0,
            Dissipation::Restitution(e) => {
                if impact_speed.is_nan() || impact_speed <= 0.0 || impact_speed.is_infinite() {
                    return Err(ModelError(
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
                if e_of(lo) < e || e_of(hi) > e {
                    return Err(ModelError(format!(
                        "contact.restitution = {e} is out of reach of the viscoelastic law (0 < δ ≤ 30)"
                    )));
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
        Ok(Self { stiffness, a })
    }
}
