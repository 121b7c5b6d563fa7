//! The exact reference of a whole [`Scenario`], in the same per-contact
//! record the integrator produces, so that the two compare field by field.

use super::{contacts, ContactProblem, ExactError, Flight};
use crate::bounce::{ContactRecord, Scenario};

/// The exact problem of a scenario's pair and law (p² from eqs 10–14).
pub fn problem(s: &Scenario) -> ContactProblem {
    let alpha = s.contact.law.exponent();
    let p = s.pair().p(alpha);
    ContactProblem {
        p_squared: p * p,
        alpha,
        gravity: s.motion.gravity,
    }
}

/// Initial conditions of a scenario's first flight.
pub fn flight(s: &Scenario) -> Flight {
    Flight {
        gap: s.motion.gap,
        velocity: s.motion.velocity,
        gravity: s.motion.gravity,
    }
}

/// Exact values of every contact of `s` (`steps` = 0: nothing was integrated).
pub fn scenario_contacts(s: &Scenario) -> Result<Vec<ContactRecord>, ExactError> {
    let mass = s.particle.mass();
    let exact = contacts(&problem(s), &flight(s), s.motion.contacts as usize)?;
    Ok(exact
        .into_iter()
        .map(|c| ContactRecord {
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
        })
        .collect())
}
