//! The paper's scenario: an elastic sphere dropped under gravity on a fixed
//! boundary sphere, integrated contact by contact, with every event (contact
//! onset, maximum overlap, rebound) located inside the time step.

pub mod batch;
pub mod events;
/// The scenario's input ranges (moved to [`crate::scenario::limits`]).
pub use crate::scenario::limits;
mod problem;
mod run;
pub mod schedule;
mod simulate;
pub mod tolerance;

pub use crate::record::{BodyVelocities, ContactRecord};
pub use crate::scenario::{
    BoundarySection, ContactSection, GravityOn, Integration, Motion, ParticleSection, Scenario,
    StepRule, Stepping, TwoBody, DEFAULT_ETA, MAX_TOLERANCE, MIN_TOLERANCE,
};
pub use batch::simulate_batch;
pub use problem::Problem;
pub use run::{
    check_damped_step, check_resolution, check_step, check_unloading, plan, resolve, simulate,
    simulate_resolved, Resolved,
};
pub use simulate::simulate_with;

use serde::{Deserialize, Serialize};

/// The result of one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunOutcome {
    pub contacts: Vec<ContactRecord>,
    /// Integration steps taken in all (flight and contact) by the run; the
    /// pilot runs of `integration.tolerance` are in `pilot_steps`.
    pub steps: u64,
    /// Δt used, s.
    pub dt: f64,
    /// The law's contact-time estimate Δt was derived from, s.
    pub contact_time_estimate: f64,
    /// With `integration.tolerance`: the estimated largest relative error of
    /// T_c, h_max and v_r at the Δt chosen ([`tolerance`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error_estimate: Option<f64>,
    /// With `integration.tolerance`: the steps of the two pilot runs that
    /// chose Δt ([`tolerance`]), not included in `steps`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pilot_steps: Option<u64>,
}

impl RunOutcome {
    /// Every integration step the run cost: `steps` plus the pilot runs'.
    pub fn total_steps(&self) -> u64 {
        self.steps + self.pilot_steps.unwrap_or(0)
    }
}

/// One point of the trajectory, for histories and plots (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    pub t: f64,
    pub x: f64,
    pub v: f64,
    pub a: f64,
    pub overlap: f64,
    pub force: f64,
    pub in_contact: bool,
}

/// Watches a run: trajectory samples and progress. The unit type `()`
/// watches nothing and costs nothing (the calls compile away).
pub trait Observer {
    /// False for observers that ignore samples; the run then skips computing
    /// them (`progress` is still called).
    const ACTIVE: bool = true;
    /// A trajectory point (every step in contact and in fixed-step flight;
    /// `flight_samples()` points per flight arc in event stepping).
    fn sample(&mut self, _sample: &Sample) {}
    /// Points per free-flight arc in event stepping.
    fn flight_samples(&self) -> usize {
        0
    }
    /// Called now and then with the simulated time and the expected end time, s.
    fn progress(&mut self, _t: f64, _t_end: f64) {}
}

impl Observer for () {
    const ACTIVE: bool = false;
}
