//! The exact reference of a whole [`Scenario`], in the same per-contact
//! record the integrator produces, so that the two compare field by field.

use super::{contacts, ContactProblem, Flight};
use crate::contact::ContactLawKind;
use crate::record::{BodyVelocities, ContactRecord};
use crate::scenario::Scenario;
use crate::{Error, Result};
use dembound_physics::contact::registry::Family;

/// The exact problem of a scenario's pair and law (p² from eqs 10–14).
pub fn problem(s: &Scenario) -> ContactProblem {
    let alpha = s.contact.law.exponent();
    // p = √(k/m) with the mass of the relative motion (eq 10; the particle's
    // own against a fixed boundary, m* against a free one).
    // The paper's laws: k = E_eff R_eff^(2−α) (eq 4); another registry law
    // of F = k h^α (`hooke`, `hertz-kn`): its own k for the pair.
    let k = match s.contact.law {
        ContactLawKind::Registry(_) => s.contact.model().normal().map_or(f64::NAN, |law| {
            law.resolve(&s.pair().properties()).stiffness()
        }),
        _ => s.pair().power_law_stiffness(alpha),
    };
    let p = (k / s.reduced_mass()).sqrt();
    ContactProblem {
        p_squared: p * p,
        alpha,
        gravity: s.relative_gravity(),
    }
}

/// Initial conditions of a scenario's first flight (of the relative motion).
pub fn flight(s: &Scenario) -> Flight {
    Flight {
        gap: s.motion.gap,
        velocity: s.relative_velocity(),
        gravity: s.relative_gravity(),
    }
}

/// Exact values of every contact of `s` (`steps` = 0: nothing was integrated).
///
/// A dissipative scenario (`contact.damping`, or Walton–Braun) gets the
/// reference of its own law ([`super::dissipative`]), never the elastic one.
pub fn scenario_contacts(s: &Scenario) -> Result<Vec<ContactRecord>> {
    scenario_contacts_with(s, None)
}

/// As [`scenario_contacts`], with a damped law's raw coefficient already
/// resolved (by [`crate::bounce::resolve`]: no second calibration).
pub fn scenario_contacts_with(
    s: &Scenario,
    damping_coefficient: Option<f64>,
) -> Result<Vec<ContactRecord>> {
    if super::dissipative::is_dissipative(s) {
        return super::dissipative::dissipative_contacts_with(s, damping_coefficient);
    }
    // The elastic reference is that of F = k h^α: a registry law has it
    // only when its family fixes α (linear 1, Hertzian 3/2).
    if let ContactLawKind::Registry(row) = s.contact.law {
        if !matches!(row.family, Family::Linear | Family::Hertzian) {
            return Err(Error::InvalidParameter {
                name: "contact.law",
                value: f64::NAN,
                requirement: "a law of the linear or Hertzian family (F = k h or k h^(3/2)) \
                              for the exact elastic reference",
            });
        }
    }
    let mass = s.reduced_mass();
    let bodies = s.two_body();
    let exact = contacts(&problem(s), &flight(s), s.motion.contacts as usize)?;
    Ok(exact
        .into_iter()
        .map(|c| {
            let mut record = ContactRecord {
                t_contact: c.t_contact,
                t_max_overlap: c.t_max_overlap,
                t_rebound: c.t_rebound,
                duration: c.duration,
                max_overlap: c.max_overlap,
                max_force: c.max_force_per_mass * mass,
                max_acceleration: c.max_acceleration,
                impact_velocity: c.impact_velocity,
                rebound_velocity: c.rebound_velocity,
                // Elastic: e = 1 and nothing is dissipated; the force returns to
                // zero exactly with the overlap.
                restitution: c.rebound_velocity / -c.impact_velocity,
                energy_dissipated: 0.0,
                t_force_zero: None,
                apex_height: c.apex_height.is_finite().then_some(c.apex_height),
                steps: 0,
                bodies: None,
            };
            record.bodies = bodies.map(|b| BodyVelocities::of(&record, &b));
            record
        })
        .collect())
}
