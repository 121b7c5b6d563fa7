//! The crate's one error type: every fallible public function returns
//! [`Result`]. The variants are grouped by concern (bad input, the model,
//! a run, the exact reference, the independent reference and its ODE
//! solver, root finding); a failure inside a larger computation (a study, a
//! sweep case) is wrapped once in a variant that says where it happened, so
//! a caller can tell bad input (the outermost variant is one of the input
//! ones, or, for the exact reference, anything but [`Error::Numerical`])
//! from a computation that failed.
//!
//! The messages are the ones users see (the CLI prints them, the Python
//! bindings raise them): keep their text when changing a variant. None of
//! the variants reports a [`source`](std::error::Error::source): the wrapped
//! error is already part of the message, and `anyhow`'s `{:#}` would print
//! it twice.

use crate::study::restitution::DissipativeLaw;

/// `Result` with the crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Why a computation of the crate failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    // ---- Bad input ----
    /// A value outside its allowed range.
    #[error("invalid value for `{field}`: {value} (allowed: {allowed})")]
    Input {
        /// The key, `section.key` (or the argument's name).
        field: String,
        /// The offending value as the user wrote it.
        value: String,
        /// The allowed range or set, with units.
        allowed: String,
    },
    /// A request a study cannot take (a target, a ratio, its base
    /// scenario), with a message naming what is wrong.
    #[error("{0}")]
    Request(String),
    /// The requested rebound cannot be reached (restitution study's
    /// reverse question), with the reachable range.
    #[error("{0}")]
    OutOfReach(String),
    /// Nothing to sweep: an empty list (names it).
    #[error("nothing to sweep: no {0} given")]
    NothingToSweep(&'static str),

    // ---- The contact model ----
    /// The contact model could not be built (e.g. a restitution out of
    /// reach, a missing parameter), with a message naming the keys.
    #[error("{0}")]
    Model(String),

    // ---- A run (the integrator) ----
    /// The particle never reaches the boundary.
    #[error("the particle never reaches the boundary (check motion.velocity and motion.gravity)")]
    NeverReachesBoundary,
    /// A contact did not end within its step budget.
    #[error(
        "contact {contact} did not end after {steps} steps (the particle came to rest on the boundary?)"
    )]
    NoRebound {
        /// The contact (1-based).
        contact: u32,
        /// The steps spent on it.
        steps: u64,
    },

    // ---- The exact reference ([`crate::exact`]) ----
    /// A parameter is NaN, infinite or outside its domain.
    #[error("invalid parameter {name} = {value}: must be {requirement}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// What is required.
        requirement: &'static str,
    },
    /// The particle never reaches the boundary (e.g. `g = 0` and it does
    /// not move towards it): the exact reference's wording of
    /// [`Error::NeverReachesBoundary`].
    #[error("the particle never reaches the boundary")]
    NoImpact,
    /// Zero impact speed and zero gravity: the particle rests on the boundary without force.
    #[error("zero impact speed and zero gravity: no contact motion to describe")]
    NoContactDynamics,
    /// Without gravity the particle leaves after its first contact: there is no `n`-th contact.
    #[error("without gravity there is only one contact, {requested} were requested")]
    NoFurtherContact {
        /// The number of contacts asked for.
        requested: usize,
    },
    /// `ContactProblem::gravity` and `Flight::gravity` differ.
    #[error("contact problem gravity {problem} differs from flight gravity {flight}")]
    InconsistentGravity {
        /// Gravity of the contact problem.
        problem: f64,
        /// Gravity of the flight.
        flight: f64,
    },
    /// The time inside a contact is outside `[0, T_c]`.
    #[error("time {tau} s since contact start is outside the contact [0, {duration}] s")]
    TimeOutOfContact {
        /// Requested time since contact start.
        tau: f64,
        /// Contact duration.
        duration: f64,
    },
    /// A numerical step of the exact reference (root bracketing,
    /// quadrature, inversion) failed.
    #[error("numerical failure: {0}")]
    Numerical(&'static str),
    /// A dissipative contact that does not end: after the force returns to
    /// zero gravity pulls the particle back before the overlap closes.
    #[error("contact {contact} does not end: gravity holds the particle on the boundary")]
    NoExactRebound {
        /// The contact (1-based).
        contact: usize,
    },

    // ---- The independent reference ([`crate::reference`]) and its ODE solver ----
    /// ξ ≥ 1: the closed form is for the underdamped oscillator.
    #[error("overdamped (ξ = {0} ≥ 1)")]
    Overdamped(f64),
    /// The body never leaves the boundary (gravity wins).
    #[error("the body does not rebound")]
    NoReferenceRebound,
    /// The reference's adaptive integration failed (the solver's error).
    #[error("integration failed: {0}")]
    Integration(Box<Error>),
    /// The ODE solver found no event within its step budget.
    #[error("no event after {0} steps")]
    TooManySteps(usize),
    /// The ODE solver's step size underflowed or its state became non-finite.
    #[error("step size underflow at t = {0:e}")]
    StepUnderflow(f64),

    // ---- Root finding in the studies ----
    /// A root search of a study (e.g. Brent's method) failed.
    #[error("root finding failed: {0}")]
    RootFinding(&'static str),

    // ---- Where a failure happened inside a larger computation ----
    /// A study's run failed.
    #[error("simulation failed: {0}")]
    Simulation(Box<Error>),
    /// A study's exact reference failed.
    #[error("exact reference failed: {0}")]
    Exact(Box<Error>),
    /// A sweep case's scenario is invalid (the wrapped error is an
    /// [`Error::Input`]).
    #[error("{case}: {error}")]
    CaseInput {
        /// The case's label.
        case: String,
        /// What is wrong with it.
        error: Box<Error>,
    },
    /// A sweep case's run failed.
    #[error("{case}: the run failed: {error}")]
    CaseRun {
        /// The case's label.
        case: String,
        /// Why the run failed.
        error: Box<Error>,
    },
    /// A sweep case's exact reference failed.
    #[error("{case}: the exact reference failed: {error}")]
    CaseExact {
        /// The case's label.
        case: String,
        /// Why the reference failed.
        error: Box<Error>,
    },
    /// A run of the restitution study failed at one (law, r, ζ).
    #[error("{law} at r = {radius_ratio}, ζ = {modulus_ratio}: {error}")]
    StudyRun {
        /// The dissipative law.
        law: DissipativeLaw,
        /// The pair's radius ratio r.
        radius_ratio: f64,
        /// The pair's modulus ratio ζ.
        modulus_ratio: f64,
        /// Why the run failed.
        error: Box<Error>,
    },
}

impl Error {
    /// A bad value: the key, the value and the allowed range.
    pub fn input(
        field: impl Into<String>,
        value: impl Into<String>,
        allowed: impl Into<String>,
    ) -> Self {
        Error::Input {
            field: field.into(),
            value: value.into(),
            allowed: allowed.into(),
        }
    }

    /// The key of an [`Error::Input`] (`section.key` or the argument's
    /// name); `None` for every other variant.
    pub fn field(&self) -> Option<&str> {
        match self {
            Error::Input { field, .. } => Some(field),
            _ => None,
        }
    }

    /// A study's run failed with `e` ([`Error::Simulation`]).
    pub fn simulation(e: Error) -> Self {
        Error::Simulation(Box::new(e))
    }

    /// A study's exact reference failed with `e` ([`Error::Exact`]).
    pub fn exact(e: Error) -> Self {
        Error::Exact(Box::new(e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The wrappers keep the wrapped message (the texts users saw before
    /// the crate had one error type).
    #[test]
    fn wrapped_messages_keep_their_text() {
        let run = Error::NoRebound {
            contact: 2,
            steps: 10,
        };
        assert_eq!(
            Error::simulation(run.clone()).to_string(),
            "simulation failed: contact 2 did not end after 10 steps \
             (the particle came to rest on the boundary?)"
        );
        let case = Error::CaseRun {
            case: "r = 1".into(),
            error: Box::new(run),
        };
        assert!(case
            .to_string()
            .starts_with("r = 1: the run failed: contact 2"));
        let input = Error::input("motion.gap", "-1", "> 0 m");
        assert_eq!(
            input.to_string(),
            "invalid value for `motion.gap`: -1 (allowed: > 0 m)"
        );
        assert_eq!(
            Error::Integration(Box::new(Error::TooManySteps(7))).to_string(),
            "integration failed: no event after 7 steps"
        );
    }
}
