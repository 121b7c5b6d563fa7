//! The paper's scenario: an elastic sphere dropped under gravity on a fixed
//! boundary sphere, integrated contact by contact, with every event (contact
//! onset, maximum overlap, rebound) located inside the time step.

pub mod batch;
pub mod events;
pub mod limits;
mod problem;
mod run;
mod scenario;
pub mod schedule;
mod simulate;
pub mod tolerance;

pub use batch::simulate_batch;
pub use problem::{Problem, SimulationError};
pub use run::{check_resolution, check_step, plan, resolve, simulate, simulate_resolved, Resolved};
pub use scenario::{
    BoundarySection, ContactSection, GravityOn, InputError, Integration, Motion, ParticleSection,
    Scenario, StepRule, Stepping, TwoBody, DEFAULT_ETA, MAX_TOLERANCE, MIN_TOLERANCE,
};
pub use simulate::simulate_with;

use serde::{Deserialize, Serialize};

/// Everything measured for one contact. SI units; times from t = 0; x
/// upward positive.
///
/// Against a free boundary (`boundary.fixed = false`) every kinematic
/// field is of the *relative* motion: x is the gap, velocities are
/// v_m − v_b, accelerations ẍ_m − ẍ_b, and `restitution` is the ratio of
/// relative velocities; each sphere's own velocities are in `bodies`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    /// Contact onset t_c, s.
    pub t_contact: f64,
    /// Time of maximum overlap t_mp, s.
    pub t_max_overlap: f64,
    /// Rebound t_r (overlap back to zero), s.
    pub t_rebound: f64,
    /// When attraction is forbidden: the time the force first returns to
    /// zero after the maximum overlap, s — the physical end of the contact
    /// (the particle then flies free while the overlap closes, until
    /// `t_rebound`). `None` for laws that may pull (or never do).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_force_zero: Option<f64>,
    /// T_c = t_r − t_c, s.
    pub duration: f64,
    /// h_max > 0, m.
    pub max_overlap: f64,
    /// Peak contact force, N.
    pub max_force: f64,
    /// Peak net acceleration ẍ (upward positive, gravity included), m/s²
    /// (F_max/m* − g for the relative motion with a free boundary).
    pub max_acceleration: f64,
    /// v_c < 0, m/s.
    pub impact_velocity: f64,
    /// v_r > 0, m/s (at `t_rebound`).
    pub rebound_velocity: f64,
    /// Coefficient of restitution v_r/|v_c|.
    pub restitution: f64,
    /// Kinetic energy lost in the contact, ½ m (v_c² − v_r²), J (with
    /// gravity this includes the tiny work of gravity over the overlap).
    pub energy_dissipated: f64,
    /// Apex of the flight after the rebound, above the contact point, m
    /// (`None` without gravity).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub apex_height: Option<f64>,
    /// Integration steps spent in this contact.
    pub steps: u64,
    /// Each sphere's velocity before and after the contact, with a free
    /// boundary (`None` against a fixed one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bodies: Option<BodyVelocities>,
}

/// The two spheres' velocities at the onset and at the rebound of a contact
/// with a free boundary, m/s, upward positive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyVelocities {
    /// v_m at `t_contact`.
    pub particle_before: f64,
    /// v_m at `t_rebound`.
    pub particle_after: f64,
    /// v_b at `t_contact`.
    pub boundary_before: f64,
    /// v_b at `t_rebound`.
    pub boundary_after: f64,
}

impl BodyVelocities {
    /// Both spheres' velocities for `record`, recovered from the
    /// centre-of-mass motion of `bodies`.
    pub fn of(record: &ContactRecord, bodies: &TwoBody) -> Self {
        let (particle_before, boundary_before) =
            bodies.velocities(record.t_contact, record.impact_velocity);
        let (particle_after, boundary_after) =
            bodies.velocities(record.t_rebound, record.rebound_velocity);
        BodyVelocities {
            particle_before,
            particle_after,
            boundary_before,
            boundary_after,
        }
    }
}

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
