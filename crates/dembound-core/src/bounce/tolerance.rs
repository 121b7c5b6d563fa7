//! Δt for an accuracy target (`integration.tolerance`).
//!
//! The first contact is run alone (from its onset, at the first impact
//! speed) at two step sizes, η₁ = 1/50 and η₂ = 1/100 of the contact-time
//! estimate (coarser pilots are not yet in the asymptotic range for Hertz
//! and overestimate its error several-fold). With the scheme's order p, the
//! error of the finer run is about e₂ = d/(2^p − 1), where d is the largest
//! relative difference between the two runs in T_c, h_max and v_r
//! (Richardson). With e(η) ≈ e₂ (η/η₂)^p, the run uses
//! η = η₂ (s·tol/(N e₂))^(1/p) with the safety factor s = 1/2 and N the
//! number of contacts, never coarser than η₁ (no extrapolation beyond the
//! pilots), and reports N e₂ (η/η₂)^p as its error estimate.
//!
//! Why N: the rebound speed of one contact is the impact speed of the next
//! (the flight between is exact), so the per-contact errors of v_r, and
//! with it of h_max and T_c, add up from contact to contact (for an elastic
//! law; a dissipative one damps them by e each contact). The tolerance
//! holds for every contact of the run, so each may use 1/N of it.
//!
//! Orders: Gear5 with event stepping is of 5th order for every law (meshed
//! uniformly or graded at both ends: smooth onsets, Hertz and power laws,
//! and the singular-onset damping laws), and so is Gear5 with fixed
//! stepping on a smooth or singular-onset law (the latter graded between
//! grid points, [`super::schedule::SingularMesh`]); everything else
//! (Verlet; Gear5 with fixed stepping on a non-smooth law) is taken as 2nd
//! order, which is conservative where the true order is higher: a lower p
//! inflates e₂ and shrinks the extrapolated η.
//!
//! Caveats: the pilots cost about as many steps as the run they plan (they
//! are counted apart, in `RunOutcome::pilot_steps`; `RunOutcome::total_steps`
//! adds both); the estimate is for the first
//! contact (later contacts of a dissipative law are slower and usually more
//! accurate); in fixed stepping the pilot's onset lies on a grid point,
//! while the run's lies anywhere in a step.

use super::problem::Problem;
use super::simulate::simulate_with;
use super::{ContactRecord, Scenario, Stepping};
use crate::contact::{NormalContactLaw, Onset};
use crate::integrate::{Gear5, Scheme, Verlet};
use crate::Result;

/// η₁ and η₂ of the pilot runs.
pub const PILOT_ETAS: [f64; 2] = [0.02, 0.01];
/// Safety factor s: the run aims at s·tolerance.
pub const SAFETY: f64 = 0.5;
/// Smallest η the rule will choose.
pub const MIN_ETA: f64 = 1e-7;

/// The step a tolerance resolves to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToleranceStep {
    /// Chosen η (Δt = η T_c estimate).
    pub eta: f64,
    /// Order p assumed for the scheme.
    pub order: f64,
    /// Largest relative difference d between the two pilot runs.
    pub pilot_difference: f64,
    /// Estimated largest relative error of T_c, h_max, v_r of any contact
    /// at `eta` (N times the per-contact estimate).
    pub error_estimate: f64,
    /// Integration steps of the two pilot runs.
    pub pilot_steps: u64,
}

/// Order of convergence assumed for `scheme` and `stepping` with `law`.
pub fn assumed_order(scheme: Scheme, stepping: Stepping, law: &impl NormalContactLaw) -> f64 {
    match (scheme, stepping, law.onset()) {
        (Scheme::Gear5, Stepping::Event, _) => 5.0,
        (Scheme::Gear5, Stepping::Fixed, Onset::Smooth | Onset::Singular) => 5.0,
        _ => 2.0,
    }
}

/// Largest relative difference of T_c, h_max and v_r between two records.
fn difference(a: &ContactRecord, b: &ContactRecord) -> f64 {
    [
        (a.duration, b.duration),
        (a.max_overlap, b.max_overlap),
        (a.rebound_velocity, b.rebound_velocity),
    ]
    .iter()
    .filter(|(_, y)| *y != 0.0)
    .map(|(x, y)| ((x - y) / y).abs())
    .fold(0.0, f64::max)
}

/// Chooses η for `tolerance`; `base` is the scenario's problem with any Δt.
pub(crate) fn choose_step<L: NormalContactLaw>(
    s: &Scenario,
    law: &L,
    tolerance: f64,
    base: &Problem,
) -> Result<ToleranceStep> {
    let scheme = s.integration.scheme;
    let pilot = |eta: f64| -> Result<(ContactRecord, u64)> {
        let p = Problem {
            gap: 0.0,
            velocity: -s.impact_speed(),
            contacts: 1,
            dt: eta * base.contact_time_estimate,
            error_estimate: None,
            pilot_steps: None,
            ..*base
        };
        let out = match scheme {
            Scheme::Gear5 => {
                simulate_with(law, Gear5::for_force(law.depends_on_rate()), &p, &mut ())?
            }
            Scheme::Verlet => simulate_with(law, Verlet, &p, &mut ())?,
        };
        Ok((out.contacts[0], out.steps))
    };
    let [eta1, eta2] = PILOT_ETAS;
    let ((coarse, coarse_steps), (fine, fine_steps)) = (pilot(eta1)?, pilot(eta2)?);
    let order = assumed_order(scheme, s.integration.stepping, law);
    let d = difference(&coarse, &fine);
    let e2 = d / ((eta1 / eta2).powf(order) - 1.0);
    let contacts = f64::from(s.motion.contacts);
    let eta = if e2 > 0.0 {
        (eta2 * (SAFETY * tolerance / (contacts * e2)).powf(1.0 / order)).clamp(MIN_ETA, eta1)
    } else {
        eta1
    };
    Ok(ToleranceStep {
        eta,
        order,
        pilot_difference: d,
        error_estimate: contacts * e2 * (eta / eta2).powf(order),
        pilot_steps: coarse_steps + fine_steps,
    })
}
