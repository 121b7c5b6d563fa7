//! The numerical problem a run solves (one degree of freedom, its mass,
//! gravity, Δt and contact-time estimate): the data
//! shared by the time loop ([`super::simulate`]), the step choice for an
//! accuracy target ([`super::tolerance`]) and the resolution of a scenario
//! ([`super::run`]), which sit above it.

use super::events::time_to_surface;
use super::{Stepping, TwoBody};

/// The numerical problem a run solves, resolved from a [`Scenario`](super::Scenario) and its law.
///
/// It has one degree of freedom, the gap x between the surfaces: against a
/// fixed boundary the particle's position, against a free one the relative
/// coordinate, with the reduced mass m* and the difference of the two
/// spheres' gravity (the time loop does not know which).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Problem {
    /// Mass of the relative motion, kg: the particle's against a fixed
    /// boundary, m* = m_m m_b/(m_m + m_b) against a free one.
    pub mass: f64,
    /// Gravity of the relative motion, m/s² ([`Scenario::relative_gravity`](super::Scenario::relative_gravity)).
    pub gravity: f64,
    /// Initial gap, m.
    pub gap: f64,
    /// Initial (relative) velocity, m/s, upward positive.
    pub velocity: f64,
    /// Rebounds to run.
    pub contacts: u32,
    /// Time step, s.
    pub dt: f64,
    /// The contact-time estimate Δt came from, s.
    pub contact_time_estimate: f64,
    pub stepping: Stepping,
    /// The two spheres, with a free boundary: each sphere's velocities are
    /// recovered from the relative ones after the run.
    pub two_body: Option<TwoBody>,
    /// With `integration.tolerance`: the estimated largest relative error of
    /// T_c, h_max and v_r at the chosen Δt (see [`super::tolerance`]).
    pub error_estimate: Option<f64>,
    /// With `integration.tolerance`: the steps of the pilot runs that chose Δt.
    pub pilot_steps: Option<u64>,
}

impl Problem {
    /// Expected end time of the run, s (flight exact, contacts estimated).
    pub fn expected_end_time(&self) -> f64 {
        let g = self.gravity;
        let first = time_to_surface(self.gap, self.velocity, g).unwrap_or(0.0);
        let speed = (self.velocity * self.velocity + 2.0 * g * self.gap).sqrt();
        let flight = if g > 0.0 { 2.0 * speed / g } else { 0.0 };
        let n = f64::from(self.contacts);
        first + n * self.contact_time_estimate + (n - 1.0) * flight
    }

    /// Expected number of integration steps.
    pub fn expected_steps(&self) -> f64 {
        match self.stepping {
            Stepping::Event => f64::from(self.contacts) * self.contact_time_estimate / self.dt,
            Stepping::Fixed => self.expected_end_time() / self.dt,
        }
    }
}
