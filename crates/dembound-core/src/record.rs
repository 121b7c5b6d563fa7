//! What a run measures of each contact ([`ContactRecord`]), shared by the
//! bounce simulator, the exact references and the studies.

use crate::scenario::TwoBody;
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
