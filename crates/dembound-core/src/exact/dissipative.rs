//! The reference of a whole dissipative [`Scenario`] (`contact.damping` or
//! `law = "walton-braun"`), in the per-contact record of the integrator:
//! each contact from [`crate::reference::dissipative`] (closed forms for the
//! spring–dashpot and Walton–Braun, the adaptive Dormand–Prince integration
//! at a relative tolerance of 1e−13 per step for the damped Hertz laws), the
//! flights between contacts in closed form (ERRATA 7).
//!
//! The law's coefficients (c, γ, A, k₂) come from the same calibration the
//! run uses ([`crate::contact`]); the contact itself is integrated by code
//! that shares nothing with the Gear/Verlet time loop or the law types.

use super::first_contact_time;
use crate::calibration::damping_coefficient as calibrated_coefficient;
use crate::contact::{ContactLawKind, DampingKind, Dissipation, Hertz, LinearSpring, WaltonBraun};
use crate::record::{BodyVelocities, ContactRecord};
use crate::reference::dissipative::{
    damped_hertz, damped_hertz_max_force, spring_dashpot, spring_dashpot_max_force, walton_braun,
    ContactReference, DampedHertz,
};
use crate::scenario::Scenario;
use crate::{Error, Result};

/// True when `s` has a dissipative contact (damping, or Walton–Braun).
pub fn is_dissipative(s: &Scenario) -> bool {
    s.contact.law == ContactLawKind::WaltonBraun || s.contact.damping != DampingKind::None
}

/// One contact at impact speed `v` > 0: the reference and the peak force.
type ContactFn<'a> = dyn Fn(f64) -> Result<(ContactReference, f64)> + 'a;

/// The reference values of every contact of a dissipative scenario
/// (`steps` = 0: nothing was integrated by the time loop).
pub fn dissipative_contacts(s: &Scenario) -> Result<Vec<ContactRecord>> {
    dissipative_contacts_with(s, None)
}

/// As [`dissipative_contacts`], with the damping's raw coefficient already
/// resolved (by [`crate::bounce::resolve`]: no second calibration).
pub fn dissipative_contacts_with(
    s: &Scenario,
    damping_coefficient: Option<f64>,
) -> Result<Vec<ContactRecord>> {
    let mass = s.reduced_mass();
    let g = s.relative_gravity();
    let pair = s.pair();
    let c = &s.contact;
    let model = c.model();
    let dissipation = model.dissipation.ok_or(Error::InvalidParameter {
        name: "contact.restitution",
        value: f64::NAN,
        requirement: "given (or contact.damping_coefficient) for a dissipative law",
    })?;
    let attractive = c.attractive;
    // The damping's raw coefficient, calibrated as the run calibrates it
    // (only the viscoelastic calibration, a root solve, can fail).
    let coefficient = || match damping_coefficient {
        Some(c) => Ok(c),
        None => calibrated_coefficient(&model, &pair, mass, s.impact_speed())
            .map_err(|_| Error::Numerical("viscoelastic calibration failed")),
    };
    let contact: Box<ContactFn> = match (c.law, c.damping) {
        (ContactLawKind::WaltonBraun, DampingKind::None) => {
            let Dissipation::Restitution(e) = dissipation else {
                return Err(Error::InvalidParameter {
                    name: "contact.restitution",
                    value: f64::NAN,
                    requirement: "given for law = \"walton-braun\"",
                });
            };
            let law = pair.law::<WaltonBraun>(&[e]);
            Box::new(move |v| {
                let r = walton_braun(law.loading, law.unloading, mass, v, g)?;
                Ok((r, law.loading * r.max_overlap))
            })
        }
        (ContactLawKind::Linear, DampingKind::Viscous) => {
            let (k, c) = (pair.law::<LinearSpring>(&[]).stiffness, coefficient()?);
            Box::new(move |v| {
                let r = spring_dashpot(k, c, mass, v, g, attractive)?;
                let f = spring_dashpot_max_force(k, c, mass, v, g)?;
                Ok((r, f))
            })
        }
        (ContactLawKind::Hertz, DampingKind::Tsuji) => {
            let model = DampedHertz::Tsuji {
                stiffness: pair.law::<Hertz>(&[]).stiffness,
                damping: coefficient()?,
            };
            Box::new(move |v| damped(model, mass, v, g, attractive))
        }
        (ContactLawKind::Hertz, DampingKind::Viscoelastic) => {
            let model = DampedHertz::Viscoelastic {
                stiffness: pair.law::<Hertz>(&[]).stiffness,
                a: coefficient()?,
            };
            Box::new(move |v| damped(model, mass, v, g, attractive))
        }
        _ => {
            return Err(Error::InvalidParameter {
                name: "contact.damping",
                value: f64::NAN,
                requirement: "\"viscous\" with law = \"linear\", \"tsuji\" or \"viscoelastic\" \
                              with \"hertz\", or law = \"walton-braun\" without damping",
            })
        }
    };
    let reference_error = |e: Error| match e {
        // The value the user gave (not ξ, which the message states).
        Error::Overdamped(xi) => {
            let (field, value) = match (c.restitution, c.damping_coefficient) {
                (Some(e), _) => ("contact.restitution", crate::scenario::limits::show(e)),
                (None, Some(d)) => (
                    "contact.damping_coefficient",
                    format!("{} N s/m", crate::scenario::limits::show(d)),
                ),
                (None, None) => ("contact.restitution", "missing".into()),
            };
            Error::Input {
                field: field.into(),
                value,
                allowed: format!(
                    "a damping ratio ξ < 1 for an exact reference (this gives ξ = {xi:.4}, \
                     overdamped): the closed-form reference of the spring–dashpot is for \
                     ξ < 1; `dembound run` integrates the overdamped contact"
                ),
            }
        }
        Error::NoReferenceRebound => Error::NoExactRebound { contact: 0 },
        // Error::Integration: the only other failure of a reference.
        _ => Error::Numerical("the adaptive reference integration failed"),
    };

    let mut t_contact = first_contact_time(&super::scenario::flight(s))?;
    let mut speed = s.impact_speed();
    let bodies = s.two_body();
    let mut out = Vec::with_capacity(s.motion.contacts as usize);
    for n in 0..s.motion.contacts {
        if n > 0 && g == 0.0 {
            return Err(Error::NoFurtherContact {
                requested: s.motion.contacts as usize,
            });
        }
        let (r, max_force) = contact(speed).map_err(|e| match e {
            Error::NoReferenceRebound => Error::NoExactRebound {
                contact: n as usize + 1,
            },
            e => reference_error(e),
        })?;
        let v_r = r.rebound_speed;
        let mut record = ContactRecord {
            t_contact,
            t_max_overlap: t_contact + r.t_max_overlap,
            t_rebound: t_contact + r.duration,
            t_force_zero: r.t_force_zero.map(|t| t_contact + t),
            duration: r.duration,
            max_overlap: r.max_overlap,
            max_force,
            max_acceleration: max_force / mass - g,
            impact_velocity: -speed,
            rebound_velocity: v_r,
            restitution: r.restitution,
            energy_dissipated: 0.5 * mass * (speed * speed - v_r * v_r),
            apex_height: (g > 0.0).then(|| v_r * v_r / (2.0 * g)),
            steps: 0,
            bodies: None,
        };
        record.bodies = bodies.map(|b| BodyVelocities::of(&record, &b));
        out.push(record);
        // The flight back: up and down again at the same speed (ERRATA 7).
        if g > 0.0 {
            t_contact = record.t_rebound + 2.0 * v_r / g;
        }
        speed = v_r;
    }
    Ok(out)
}

fn damped(
    model: DampedHertz,
    mass: f64,
    v: f64,
    g: f64,
    attractive: bool,
) -> Result<(ContactReference, f64)> {
    let r = damped_hertz(model, mass, v, g, attractive)?;
    Ok((r, damped_hertz_max_force(model, mass, v, g)?))
}
