//! The time loop of the bouncing particle, in two stepping modes.
//!
//! **Force discontinuity at contact onset.** Out of contact ẍ = −g exactly,
//! so the Nordsieck vector holds (x, v, −g, 0, 0, 0). At the onset the
//! contact force switches on and the higher derivatives jump; a Gear vector
//! carried across would hold stale free-flight values and the corrector
//! would need many steps to forget them. Both modes therefore *restart* the
//! integrator at the onset: the onset time and velocity are exact (flight is
//! a parabola), and the Nordsieck vector is seeded with the one-sided
//! derivatives of the contact solution at h = 0⁺ from the law
//! ([`NormalContactLaw::onset_derivatives`]). At the rebound the flight that
//! follows is again exact, so nothing of the contact's derivatives is carried
//! into it either.

use super::events::{locate, locate_where, time_to_surface, Crossing};
use super::limits;
use super::schedule::{GradedSteps, Grading, SingularMesh};
use super::tolerance;
use super::{
    BodyVelocities, ContactRecord, InputError, Observer, RunOutcome, Sample, Scenario, StepRule,
    Stepping, TwoBody,
};
use crate::contact::{with_model, LawVisitor, ModelError, NormalContactLaw, Onset};
use crate::integrate::{Gear5, Integrator, Kinematics, Scheme, Verlet};
use std::fmt;

/// Why a run could not finish.
#[derive(Debug, Clone, PartialEq)]
pub enum SimulationError {
    /// A scenario field is out of range.
    Input(InputError),
    /// The particle never reaches the boundary.
    NeverReachesBoundary,
    /// A contact did not end within its step budget.
    NoRebound { contact: u32, steps: u64 },
    /// The contact model could not be built (e.g. a restitution out of reach).
    Model(ModelError),
}

impl fmt::Display for SimulationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimulationError::Input(e) => e.fmt(f),
            SimulationError::NeverReachesBoundary => {
                f.write_str("the particle never reaches the boundary (check motion.velocity and motion.gravity)")
            }
            SimulationError::NoRebound { contact, steps } => write!(
                f,
                "contact {contact} did not end after {steps} steps (the particle came to rest on the boundary?)"
            ),
            SimulationError::Model(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for SimulationError {}

impl From<ModelError> for SimulationError {
    fn from(e: ModelError) -> Self {
        SimulationError::Model(e)
    }
}

impl From<InputError> for SimulationError {
    fn from(e: InputError) -> Self {
        SimulationError::Input(e)
    }
}

/// The numerical problem a run solves, resolved from a [`Scenario`] and its law.
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
    /// Gravity of the relative motion, m/s² ([`Scenario::relative_gravity`]).
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
    /// Resolves Δt for `law` (Δt = η T_c with the law's estimate at the
    /// first impact speed, Δt as given, or Δt for an accuracy target from
    /// pilot runs: [`super::tolerance`]).
    pub fn new(s: &Scenario, law: &impl NormalContactLaw) -> Result<Self, SimulationError> {
        let mass = s.reduced_mass();
        let g = s.relative_gravity();
        let mut speed = s.impact_speed();
        if speed <= 0.0 {
            // Dropped with no speed onto the surface: the gravity-driven
            // oscillation has the speed scale √(2 g h_eq), h_eq the static overlap.
            let (mut lo, mut hi) = (0.0, s.particle.radius);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if law.force(mid, 0.0, &Default::default()) < mass * g {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            speed = (2.0 * g * hi).sqrt();
        }
        let estimate = law.contact_time_estimate(mass, speed);
        check_gravity_share(s, law, mass)?;
        let dt = match s.step_rule() {
            StepRule::Fixed(dt) => dt,
            StepRule::Fraction(eta) => eta * estimate,
            StepRule::Tolerance(_) => tolerance::PILOT_ETAS[1] * estimate,
        };
        let mut problem = Problem {
            mass,
            gravity: g,
            gap: s.motion.gap,
            velocity: s.relative_velocity(),
            contacts: s.motion.contacts,
            dt,
            contact_time_estimate: estimate,
            stepping: s.integration.stepping,
            two_body: s.two_body(),
            error_estimate: None,
            pilot_steps: None,
        };
        if let StepRule::Tolerance(tol) = s.step_rule() {
            let chosen = tolerance::choose_step(s, law, tol, &problem)?;
            problem.dt = chosen.eta * estimate;
            problem.error_estimate = Some(chosen.error_estimate);
            problem.pilot_steps = Some(chosen.pilot_steps);
        }
        Ok(problem)
    }

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

/// Refuses a contact that gravity dominates: g T_c/|v_c| above
/// [`limits::MAX_GRAVITY_SHARE`] at the first impact, or at the last one
/// when a target restitution e < 1 slows the later impacts (|v_c| e^(n−1),
/// gravity-free). There e = v_r/|v_c| is ill-conditioned and the integrator
/// cannot resolve it (measurements in [`limits`]). The message names
/// `motion.gap` with the smallest gap that would do.
fn check_gravity_share(
    s: &Scenario,
    law: &impl NormalContactLaw,
    mass: f64,
) -> Result<(), InputError> {
    let g = s.relative_gravity();
    if g == 0.0 {
        return Ok(());
    }
    let slowing = match s.contact.restitution {
        Some(e) if e < 1.0 => e.powi(s.motion.contacts.saturating_sub(1).min(10_000) as i32),
        _ => 1.0,
    };
    let share = |v: f64| g * law.contact_time_estimate(mass, v) / v;
    let v_last = s.impact_speed() * slowing;
    let ratio = if v_last > 0.0 {
        share(v_last)
    } else {
        f64::INFINITY
    };
    if ratio <= limits::MAX_GRAVITY_SHARE {
        return Ok(());
    }
    // The smallest impact speed with an acceptable share (the share falls
    // with the speed for every law: T_c does not grow with it).
    let (mut lo, mut hi) = ((1e-30f64).ln(), (1e10f64).ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if share(mid.exp()) > limits::MAX_GRAVITY_SHARE {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let v_min = hi.exp();
    let v_first = s.impact_speed();
    if slowing < 1.0 && v_first >= v_min {
        // The first impact is fine, a later slower one is not.
        let e = s.contact.restitution.unwrap_or(1.0);
        let most = 1.0 + ((v_first / v_min).ln() / (1.0 / e).ln()).floor();
        return Err(InputError {
            field: "motion.contacts".into(),
            value: s.motion.contacts.to_string(),
            allowed: format!(
                "1 to {most} for this scenario: with e = {e} the impact speed falls to \
                 {v_last:.3e} m/s by contact {n}, where gravity dominates the contact \
                 (g T_c/|v_c| = {ratio:.3e} > {max}) and the rebound speed cannot be resolved",
                n = s.motion.contacts,
                max = limits::MAX_GRAVITY_SHARE,
            ),
        });
    }
    let v_needed = v_min / slowing;
    let v0 = s.relative_velocity();
    let gap_needed = (v_needed * v_needed - v0 * v0) / (2.0 * g);
    Err(InputError {
        field: "motion.gap".into(),
        value: format!("{} m", limits::show(s.motion.gap)),
        allowed: format!(
            "≥ {gap_needed:.3e} m for this particle, boundary and law: gravity dominates the \
             contact (g T_c/|v_c| = {ratio:.3e} > {max}: the impact speed {v:.3e} m/s is too \
             small against the velocity gravity adds during the contact, and the rebound speed \
             cannot be resolved); or a faster motion.velocity, a smaller particle.radius or a \
             stiffer particle",
            max = limits::MAX_GRAVITY_SHARE,
            v = v_first
        ),
    })
}

/// Refuses a step that does not resolve the contact: Δt above
/// [`limits::MAX_ETA`] times the contact-time estimate (`integration.dt`;
/// `integration.eta` is bounded by [`Scenario::validate`]), or a step count
/// that is not finite. Called by [`plan`], not by [`simulate`]: studies of
/// the integrator itself (the convergence study runs η = 0.2) may step
/// coarser.
pub fn check_step(s: &Scenario, problem: &Problem) -> Result<(), InputError> {
    let limit = limits::MAX_ETA * problem.contact_time_estimate;
    if let Some(dt) = s.integration.dt {
        if dt.is_nan() || dt > limit {
            return Err(InputError {
                field: "integration.dt".into(),
                value: format!("{} s", limits::show(dt)),
                allowed: format!(
                    "0 < Δt ≤ {limit:.4e} s, i.e. at most {} × the contact-time estimate \
                     T_c = {:.4e} s (a coarser step does not resolve the contact: errors of \
                     several % at 0.125 T_c, divergence beyond)",
                    limits::MAX_ETA,
                    problem.contact_time_estimate
                ),
            });
        }
    }
    let steps = problem.expected_steps();
    if !(steps.is_finite() && problem.dt > 0.0 && problem.contact_time_estimate > 0.0) {
        return Err(InputError {
            field: "integration.dt".into(),
            value: format!("{} s", problem.dt),
            allowed: format!(
                "a step giving a finite number of steps (the contact-time estimate is {} s and \
                 the expected end time {} s: check particle.radius, particle.youngs_modulus, \
                 motion.gap and motion.gravity)",
                problem.contact_time_estimate,
                problem.expected_end_time()
            ),
        });
    }
    Ok(())
}

/// [`plan`]'s checks without its cost: validation, the gravity share and
/// the step, with an `integration.tolerance` replaced by η = 1/50 (its
/// pilot runs are not needed to know that the contact can be resolved;
/// the step it chooses is finer still).
pub fn check_resolution(s: &Scenario) -> Result<(), SimulationError> {
    let mut s = *s;
    if s.integration.tolerance.take().is_some() {
        s.integration.eta = Some(super::DEFAULT_ETA);
    }
    plan(&s).map(|_| ())
}

/// Runs a scenario (validated first) and reports every contact.
pub fn simulate<O: Observer>(
    s: &Scenario,
    observer: &mut O,
) -> Result<RunOutcome, SimulationError> {
    s.validate()?;
    struct Visit<'a, O> {
        scenario: &'a Scenario,
        observer: &'a mut O,
    }
    impl<O: Observer> LawVisitor for Visit<'_, O> {
        type Output = Result<RunOutcome, SimulationError>;
        fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output {
            let problem = Problem::new(self.scenario, &law)?;
            match self.scenario.integration.scheme {
                Scheme::Gear5 => {
                    let gear = Gear5::for_force(law.depends_on_rate());
                    simulate_with(&law, gear, &problem, self.observer)
                }
                Scheme::Verlet => simulate_with(&law, Verlet, &problem, self.observer),
            }
        }
    }
    with_model(
        &s.contact.model(),
        &s.pair(),
        s.reduced_mass(),
        s.impact_speed(),
        Visit {
            scenario: s,
            observer,
        },
    )?
}

/// Resolves a scenario into its numerical problem (Δt, expected steps)
/// without running it: for step-count guards and progress bars. Refuses a
/// step that does not resolve the contact ([`check_step`]).
pub fn plan(s: &Scenario) -> Result<Problem, SimulationError> {
    s.validate()?;
    struct Plan<'a>(&'a Scenario);
    impl LawVisitor for Plan<'_> {
        type Output = Result<Problem, SimulationError>;
        fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output {
            let problem = Problem::new(self.0, &law)?;
            check_step(self.0, &problem)?;
            Ok(problem)
        }
    }
    with_model(
        &s.contact.model(),
        &s.pair(),
        s.reduced_mass(),
        s.impact_speed(),
        Plan(s),
    )?
}

const PROGRESS_EVERY: u64 = 1 << 16;

/// Runs `problem` with a concrete law and integrator.
pub fn simulate_with<L: NormalContactLaw, I: Integrator, O: Observer>(
    law: &L,
    integrator: I,
    problem: &Problem,
    observer: &mut O,
) -> Result<RunOutcome, SimulationError> {
    let mut run = Run {
        law,
        acceleration_law: law.scaled(1.0 / problem.mass),
        step_law: law.scaled(1.0 / problem.mass),
        integrator,
        problem,
        observer,
        inv_mass: 1.0 / problem.mass,
        steps: 0,
        t_end: problem.expected_end_time(),
        contact_budget: (100.0 * problem.contact_time_estimate / problem.dt) as u64 + 1_000_000,
        history: L::History::default(),
        released: false,
    };
    let mut contacts = match problem.stepping {
        Stepping::Event => run.event_stepping()?,
        Stepping::Fixed => run.fixed_stepping()?,
    };
    if let Some(bodies) = &problem.two_body {
        attach_bodies(&mut contacts, bodies);
    }
    Ok(RunOutcome {
        contacts,
        steps: run.steps,
        dt: problem.dt,
        contact_time_estimate: problem.contact_time_estimate,
        error_estimate: problem.error_estimate,
        pilot_steps: problem.pilot_steps,
    })
}

/// Each sphere's velocities of every contact, from the relative ones (kept
/// out of line: the fixed-boundary path never calls it).
#[inline(never)]
fn attach_bodies(contacts: &mut [ContactRecord], bodies: &TwoBody) {
    for c in contacts {
        c.bodies = Some(BodyVelocities::of(c, bodies));
    }
}

struct Run<'a, L: NormalContactLaw, I, O> {
    law: &'a L,
    /// `law` scaled by 1/m: gives accelerations (one multiplication fewer
    /// on the latency chain of every step).
    acceleration_law: L,
    /// `acceleration_law` scaled by the integrator's force gain for the
    /// current step size ([`Integrator::step_scaled`]); kept in step with
    /// the state by [`Self::scale_law_for`].
    step_law: L,
    integrator: I,
    problem: &'a Problem,
    observer: &'a mut O,
    inv_mass: f64,
    steps: u64,
    t_end: f64,
    contact_budget: u64,
    /// The law's memory of the current contact.
    history: L::History,
    /// The force of a non-attractive law has returned to zero in this contact.
    released: bool,
}

/// How the steps of a contact are laid out.
#[derive(Debug, Clone, Copy)]
enum Schedule {
    /// Fixed stepping: steps end on the grid t_n = `first_end` + (n − 1) Δt.
    Grid { first_end: f64 },
    /// Event stepping: Δt, graded at both ends for laws whose onset is not
    /// smooth (see [`super::schedule`]).
    Free,
}

/// Where the steps of a contact end, in τ = t − t_c.
enum StepEnds {
    Grid {
        /// τ of grid point 1, and Δt.
        first: f64,
        first_end: f64,
        dt: f64,
        /// Grid points reached.
        n: u64,
        /// Graded first step ends of a law with a singular onset
        /// ([`SingularMesh::onset_step`]), the last on grid point `pre_grid`.
        pre: Vec<f64>,
        pre_next: usize,
        pre_grid: u64,
        /// Graded steps toward the end of a law with a singular onset
        /// ([`SingularMesh::end_step`]).
        end: Option<SingularMesh>,
        /// The steps have left the grid for the graded end: from then on
        /// `n` is unused and the contact is closed by the first grid point
        /// after the rebound.
        off_grid: bool,
    },
    Free {
        graded: GradedSteps,
        j: u64,
    },
    /// Event stepping of a law with a singular onset: [`SingularMesh`] at
    /// the onset and toward the end.
    Singular {
        mesh: SingularMesh,
    },
}

impl StepEnds {
    fn new<L: NormalContactLaw>(schedule: Schedule, t_c: f64, problem: &Problem, law: &L) -> Self {
        let dt = problem.dt;
        // A singular law is graded at both ends: where h = 0 (attraction
        // allowed), or the force zero that precedes it (forbidden).
        let singular = law.onset() == Onset::Singular;
        let mesh = SingularMesh::new(dt, problem.contact_time_estimate);
        match schedule {
            Schedule::Free => {
                let grading = match law.onset() {
                    Onset::Singular => return StepEnds::Singular { mesh },
                    Onset::Smooth => Grading::Uniform,
                    Onset::NonSmooth => Grading::Power,
                };
                StepEnds::Free {
                    graded: GradedSteps::new(dt, problem.contact_time_estimate, grading),
                    j: 0,
                }
            }
            Schedule::Grid { first_end } => {
                let first = first_end - t_c;
                let grid_tau = |n: u64| first + (n as f64 - 1.0) * dt;
                let (mut pre, mut pre_grid) = (Vec::new(), 0);
                if singular {
                    // The onset mesh up to its first step of Δt, stretched to land on a grid point.
                    let mut sizes = Vec::new();
                    let mut total = 0.0;
                    loop {
                        let h = mesh.onset_step(total);
                        if h >= dt {
                            break;
                        }
                        sizes.push(h);
                        total += h;
                    }
                    let n = (((total - first) / dt).round() + 1.0).max(1.0) as u64;
                    let scale = grid_tau(n) / total;
                    let mut tau = 0.0;
                    for size in &sizes {
                        tau += size * scale;
                        pre.push(tau);
                    }
                    if let Some(last) = pre.last_mut() {
                        *last = grid_tau(n);
                    }
                    pre_grid = n;
                }
                StepEnds::Grid {
                    first,
                    first_end,
                    dt,
                    n: 0,
                    pre,
                    pre_next: 0,
                    pre_grid,
                    end: singular.then_some(mesh),
                    off_grid: false,
                }
            }
        }
    }

    /// True when the steps are graded toward a singular end: [`Self::next`]
    /// then wants the estimated time left to it after the maximum overlap.
    fn grades_end(&self) -> bool {
        matches!(
            self,
            StepEnds::Grid { end: Some(_), .. } | StepEnds::Singular { .. }
        )
    }

    /// τ at the end of the step that starts at `tau_start`; `remaining` is
    /// the estimated time from `tau_start` to a singular end (see
    /// [`Self::grades_end`]), `None` otherwise.
    fn next(&mut self, tau_start: f64, remaining: Option<f64>) -> f64 {
        match self {
            StepEnds::Grid {
                first,
                dt,
                n,
                pre,
                pre_next,
                pre_grid,
                end,
                off_grid,
                ..
            } => {
                if *pre_next < pre.len() {
                    *pre_next += 1;
                    if *pre_next == pre.len() {
                        *n = *pre_grid;
                    }
                    pre[*pre_next - 1]
                } else {
                    // Toward a singular end the steps follow the graded mesh
                    // alone, off the grid: a cut at a grid point followed by
                    // a regrowth to the mesh's step would amplify the poorly
                    // determined high Nordsieck components by ratio⁵ where
                    // the solution is nearly singular (measured: 4e−4 in e
                    // at η = 1/200).
                    let graded = match (end, remaining) {
                        (Some(mesh), Some(remaining)) => Some(mesh.end_step(remaining)),
                        _ => None,
                    };
                    if *off_grid || graded.is_some_and(|h| h < *dt) {
                        *off_grid = true;
                        return tau_start + graded.unwrap_or(*dt);
                    }
                    *n += 1;
                    *first + (*n as f64 - 1.0) * *dt
                }
            }
            StepEnds::Free { graded, j } => {
                *j += 1;
                tau_start + graded.next(*j - 1)
            }
            StepEnds::Singular { mesh } => {
                // A heavily damped contact can turn back while still in
                // the onset's graded region: both meshes then apply.
                let h = mesh.onset_step(tau_start);
                tau_start + remaining.map_or(h, |r| h.min(mesh.end_step(r)))
            }
        }
    }

    /// τ at the end of the step that restarts at an event at `tau_event`:
    /// the next grid point at least Δt/4 away, or the next planned step.
    fn after_event(&mut self, tau_event: f64) -> f64 {
        match self {
            StepEnds::Grid {
                first,
                dt,
                n,
                pre,
                pre_next,
                off_grid,
                ..
            } => {
                *pre_next = pre.len();
                *off_grid = false;
                *n = (((tau_event + 0.25 * *dt - *first) / *dt).ceil() + 1.0).max(1.0) as u64;
                *first + (*n as f64 - 1.0) * *dt
            }
            StepEnds::Free { .. } | StepEnds::Singular { .. } => self.next(tau_event, None),
        }
    }

    /// The maximum overlap was found at `tau_max` in the step ending at `tau`.
    fn max_overlap_found(&mut self, tau: f64, tau_max: f64) {
        if let StepEnds::Free { graded, .. } = self {
            graded.plan_end(tau, tau_max);
        }
    }

    /// Absolute time of the step end `tau_end`; in fixed stepping the grid
    /// point that closes the step containing the rebound at `tau_rebound`.
    fn absolute_end(&mut self, t_c: f64, tau_end: f64, tau_rebound: f64) -> f64 {
        match self {
            StepEnds::Grid {
                first,
                first_end,
                dt,
                n,
                off_grid,
                ..
            } => {
                if *off_grid {
                    // The first grid point at or after the rebound.
                    *n = (((tau_rebound - *first) / *dt).ceil() + 1.0).max(1.0) as u64;
                    if *first_end + (*n as f64 - 1.0) * *dt < t_c + tau_rebound {
                        *n += 1;
                    }
                }
                *first_end + (*n as f64 - 1.0) * *dt
            }
            StepEnds::Free { .. } | StepEnds::Singular { .. } => t_c + tau_end,
        }
    }

    /// Grid points spanned (fixed stepping).
    fn grid_steps(&self) -> u64 {
        match self {
            StepEnds::Grid { n, .. } => *n,
            StepEnds::Free { .. } | StepEnds::Singular { .. } => 0,
        }
    }
}

/// How a contact ended.
struct ContactEnd {
    record: ContactRecord,
    /// Time of the end of the step that contains the rebound, s.
    step_end: f64,
    /// Grid steps spanned by the contact (restarts inside a step do not count).
    steps: u64,
}

impl<L: NormalContactLaw, I: Integrator, O: Observer> Run<'_, L, I, O> {
    /// Contact part of the acceleration ẍ during a contact times the
    /// integrator's force gain (gravity, −g, is added by the step:
    /// [`Integrator::step_scaled`]): the law's force per unit mass, continued smoothly to x > 0 inside the step that contains
    /// the rebound (see [`NormalContactLaw::force`]).
    ///
    /// A non-attractive law is integrated with its unclamped force until the
    /// force has returned to zero (so that the step straddling that point
    /// sees a smooth force and locates it on its polynomial), and with the
    /// clamped force after. For other laws the test compiles away.
    #[inline(always)]
    fn contact_acceleration(&self, x: f64, v: f64) -> f64 {
        let law = &self.step_law;
        if L::NON_ATTRACTIVE && !self.released {
            law.unclamped_force(-x, -v, &self.history)
        } else {
            law.force(-x, -v, &self.history)
        }
    }

    /// Physical net acceleration ẍ at (x, v).
    fn acceleration(&self, x: f64, v: f64) -> f64 {
        let g = self.problem.gravity;
        if x < 0.0 {
            self.law.force(-x, -v, &self.history) * self.inv_mass - g
        } else {
            -g
        }
    }

    fn sample(&mut self, t: f64, x: f64, v: f64) {
        let in_contact = x < 0.0;
        let overlap = (-x).max(0.0);
        let force = if in_contact {
            self.law.force(overlap, -v, &self.history)
        } else {
            0.0
        };
        let a = self.acceleration(x, v);
        self.observer.sample(&Sample {
            t,
            x,
            v,
            a,
            overlap,
            force,
            in_contact,
        });
    }

    fn flight_samples(&mut self, t0: f64, x0: f64, v0: f64, duration: f64) {
        let n = self.observer.flight_samples();
        let g = self.problem.gravity;
        for i in 0..n {
            let tau = duration * i as f64 / n as f64;
            self.sample(t0 + tau, x0 + tau * (v0 - 0.5 * g * tau), v0 - g * tau);
        }
    }

    /// Free flight in closed form between contacts; only contacts integrated.
    fn event_stepping(&mut self) -> Result<Vec<ContactRecord>, SimulationError> {
        let g = self.problem.gravity;
        let (mut t, mut x, mut v) = (0.0, self.problem.gap, self.problem.velocity);
        let mut records = Vec::with_capacity(self.problem.contacts as usize);
        for n in 1..=self.problem.contacts {
            let tau = time_to_surface(x, v, g).ok_or(SimulationError::NeverReachesBoundary)?;
            if O::ACTIVE {
                self.flight_samples(t, x, v, tau);
            }
            let t_contact = t + tau;
            let impact_velocity = v - g * tau;
            self.check_gravity_share(n, impact_velocity)?;
            let end = self.contact(n, t_contact, impact_velocity, Schedule::Free)?;
            (t, x, v) = (end.record.t_rebound, 0.0, end.record.rebound_velocity);
            records.push(end.record);
        }
        if O::ACTIVE && g > 0.0 {
            self.flight_samples(t, x, v, 2.0 * v / g);
        }
        Ok(records)
    }

    /// One constant Δt on a fixed grid t_k = k Δt through the whole path.
    fn fixed_stepping(&mut self) -> Result<Vec<ContactRecord>, SimulationError> {
        let g = self.problem.gravity;
        let dt = self.problem.dt;
        let it = self.integrator;
        let mut records = Vec::with_capacity(self.problem.contacts as usize);
        let mut k: u64 = 0;
        let mut state = it.start(
            [self.problem.gap, self.problem.velocity, -g, 0.0, 0.0, 0.0],
            dt,
        );
        for n in 1..=self.problem.contacts {
            // Flight: the scheme integrates ẍ = −g exactly; step until the
            // step that crosses the surface, then place the onset exactly.
            let (t_contact, impact_velocity, first_end_index) = loop {
                let before = it.kinematics(&state);
                if before.position <= 0.0 && before.velocity <= 0.0 {
                    break (k as f64 * dt, before.velocity, None);
                }
                it.step(&mut state, |_, _| -g);
                self.steps += 1;
                let after = it.kinematics(&state);
                if O::ACTIVE {
                    self.sample((k + 1) as f64 * dt, after.position, after.velocity);
                    if self.steps.is_multiple_of(PROGRESS_EVERY) {
                        self.observer.progress((k + 1) as f64 * dt, self.t_end);
                    }
                }
                if after.position < 0.0 {
                    let tau = time_to_surface(before.position, before.velocity, g)
                        .ok_or(SimulationError::NeverReachesBoundary)?;
                    break (k as f64 * dt + tau, before.velocity - g * tau, Some(k + 1));
                }
                if g == 0.0 && after.velocity >= 0.0 {
                    return Err(SimulationError::NeverReachesBoundary);
                }
                k += 1;
            };
            // The contact restarts the scheme at the onset. Its first step
            // runs to the next grid point; a sliver shorter than Δt/4 is
            // merged with the following step (a tiny first step would
            // amplify the rounding of the Nordsieck vector when rescaled).
            self.check_gravity_share(n, impact_velocity)?;
            let mut end_index = first_end_index.unwrap_or(k + 1);
            if end_index as f64 * dt - t_contact < 0.25 * dt {
                end_index += 1;
            }
            let first_end = end_index as f64 * dt;
            let end = self.contact(n, t_contact, impact_velocity, Schedule::Grid { first_end })?;
            k = end_index + end.steps - 1;
            // Exact flight from the rebound to the grid point closing its step.
            let rest = end.step_end - end.record.t_rebound;
            let v_r = end.record.rebound_velocity;
            let (x, v) = (rest * (v_r - 0.5 * g * rest), v_r - g * rest);
            state = it.start([x.max(0.0), v, -g, 0.0, 0.0, 0.0], dt);
            records.push(end.record);
        }
        Ok(records)
    }

    /// Refuses contact `n` > 1 when the impacts have slowed (a dissipative
    /// law) until gravity dominates it: g T_c/|v_c| above
    /// [`limits::MAX_GRAVITY_SHARE`], where the rebound cannot be resolved
    /// (see [`limits`]; the first contact is checked before the run).
    fn check_gravity_share(&self, n: u32, v_c: f64) -> Result<(), SimulationError> {
        let g = self.problem.gravity;
        if n == 1 || g == 0.0 {
            return Ok(());
        }
        let speed = v_c.abs();
        let share = if speed > 0.0 {
            g * self.law.contact_time_estimate(self.problem.mass, speed) / speed
        } else {
            f64::INFINITY
        };
        if share <= limits::MAX_GRAVITY_SHARE {
            return Ok(());
        }
        Err(SimulationError::Input(InputError {
            field: "motion.contacts".into(),
            value: self.problem.contacts.to_string(),
            allowed: format!(
                "1 to {} for this scenario: the impact speed has fallen to {speed:.3e} m/s by \
                 contact {n}, where gravity dominates the contact (g T_c/|v_c| = {share:.3e} > \
                 {}) and the rebound cannot be resolved",
                n - 1,
                limits::MAX_GRAVITY_SHARE
            ),
        }))
    }

    /// Integrates one contact from its onset (h = 0, velocity `v_c`) to the
    /// rebound. Step ends come from [`StepEnds`]: the grid in fixed
    /// stepping, a mesh graded at both ends in event stepping. Times inside
    /// the contact are kept relative to the onset (τ = t − t_c), so that
    /// durations keep their relative precision.
    ///
    /// Events inside a step (maximum overlap, force zero, rebound) are
    /// located on the step's polynomial. Where the force has a kink at an
    /// event (the branch change of a hysteretic law at the maximum overlap;
    /// the clamp of a non-attractive law at the force zero) the integrator
    /// is restarted at the event with the derivatives of the new branch
    /// ([`Self::restart`]), so that no step straddles the kink.
    fn contact(
        &mut self,
        number: u32,
        t_c: f64,
        v_c: f64,
        schedule: Schedule,
    ) -> Result<ContactEnd, SimulationError> {
        let it = self.integrator;
        let m = self.problem.mass;
        let g = self.problem.gravity;
        let mut ends = StepEnds::new(schedule, t_c, self.problem, self.law);
        // Constant for the contact: only singular-onset laws grade their end.
        let grades_end = ends.grades_end();
        // One-sided derivatives at h = 0⁺ (see the module doc).
        let overlap_rate = -v_c;
        self.history = L::History::default();
        self.released = false;
        let onset_force = self.law.force(0.0, overlap_rate, &self.history);
        let overlap_accel = g - onset_force * self.inv_mass;
        let [h3, h4, h5] = self.law.onset_derivatives(m, overlap_rate, overlap_accel);
        let mut tau_start = 0.0;
        let mut tau_end = ends.next(tau_start, None);
        let mut state = it.start([0.0, v_c, -overlap_accel, -h3, -h4, -h5], tau_end);
        self.scale_law_for(&state);
        if O::ACTIVE {
            self.sample(t_c, 0.0, v_c);
        }
        let mut max_force = onset_force;
        let mut max_overlap: Option<(f64, f64)> = None;
        let mut tau_force_zero: Option<f64> = None;
        let mut steps: u64 = 0;
        loop {
            let len = tau_end - tau_start;
            if it.step_size(&state) != len {
                it.set_step(&mut state, len);
                self.scale_law_for(&state);
            }
            let mut before = state;
            self.contact_step(&mut state);
            steps += 1;
            let mut tau_step = tau_start;
            // Events of this step; a restart replaces (before, state, tau_step, tau_end).
            loop {
                let h = it.step_size(&state);
                let k = it.kinematics(&state);
                let mut restart_from: Option<(f64, [f64; 6])> = None;
                if max_overlap.is_none() && k.velocity >= 0.0 {
                    let (theta, at) = locate(&it.dense(&before, &state), Crossing::Velocity);
                    let overlap = -at.position;
                    let tau_max = tau_step + theta * h;
                    max_overlap = Some((tau_max, overlap));
                    max_force = max_force.max(self.law.force(overlap, -at.velocity, &self.history));
                    ends.max_overlap_found(tau_end, tau_max);
                    if self.law.at_max_overlap(overlap, &mut self.history) {
                        let accel =
                            g - self
                                .law
                                .unclamped_force(overlap, -at.velocity, &self.history)
                                * self.inv_mass;
                        let [h3, h4, h5] = self.law.branch_derivatives(
                            m,
                            overlap,
                            -at.velocity,
                            accel,
                            &self.history,
                        );
                        restart_from =
                            Some((tau_max, [at.position, at.velocity, -accel, -h3, -h4, -h5]));
                    }
                }
                if restart_from.is_none()
                    && L::NON_ATTRACTIVE
                    && max_overlap.is_some()
                    && !self.released
                {
                    let unclamped = |k: &Kinematics| {
                        self.law
                            .unclamped_force(-k.position, -k.velocity, &self.history)
                    };
                    if unclamped(&k) <= 0.0 {
                        let dense = it.dense(&before, &state);
                        let (theta, at) = locate_where(&dense, |k| -unclamped(k));
                        let tau_zero = tau_step + theta * h;
                        tau_force_zero = Some(tau_zero);
                        self.released = true;
                        if O::ACTIVE {
                            self.sample(t_c + tau_zero, at.position, at.velocity);
                        }
                        let a = self.acceleration(at.position, at.velocity);
                        restart_from =
                            Some((tau_zero, [at.position, at.velocity, a, 0.0, 0.0, 0.0]));
                    }
                }
                let Some((tau_event, d)) = restart_from else {
                    break;
                };
                tau_end = ends.after_event(tau_event);
                (before, state) = self.restart(d, tau_end - tau_event);
                steps += 1;
                tau_step = tau_event;
            }
            let h = it.step_size(&state);
            let k = it.kinematics(&state);
            self.law
                .update_history(-k.position, -k.velocity, &mut self.history);
            if k.position < 0.0 {
                max_force = max_force.max(self.law.force(-k.position, -k.velocity, &self.history));
            }
            if let (Some((tau_max, overlap)), true) = (max_overlap, k.position >= 0.0) {
                let (theta, at) = locate(&it.dense(&before, &state), Crossing::Position);
                let duration = tau_step + theta * h;
                let t_rebound = t_c + duration;
                let rebound_velocity = at.velocity;
                if O::ACTIVE {
                    self.sample(t_rebound, 0.0, rebound_velocity);
                }
                self.steps += steps;
                return Ok(ContactEnd {
                    record: ContactRecord {
                        t_contact: t_c,
                        t_max_overlap: t_c + tau_max,
                        t_rebound,
                        t_force_zero: tau_force_zero.map(|tau| t_c + tau),
                        duration,
                        max_overlap: overlap,
                        max_force,
                        max_acceleration: max_force * self.inv_mass - g,
                        impact_velocity: v_c,
                        rebound_velocity,
                        restitution: rebound_velocity / -v_c,
                        energy_dissipated: 0.5
                            * m
                            * (v_c * v_c - rebound_velocity * rebound_velocity),
                        apex_height: (g > 0.0)
                            .then(|| rebound_velocity * rebound_velocity / (2.0 * g)),
                        steps,
                        bodies: None,
                    },
                    step_end: ends.absolute_end(t_c, tau_end, duration),
                    steps: ends.grid_steps(),
                });
            }
            if O::ACTIVE {
                self.sample(t_c + tau_end, k.position, k.velocity);
            }
            if (self.steps + steps).is_multiple_of(PROGRESS_EVERY) {
                self.observer.progress(t_c + tau_end, self.t_end);
            }
            tau_start = tau_end;
            tau_end = if grades_end && max_overlap.is_some() && !self.released {
                ends.next(tau_start, Some(time_to_exit(&k)))
            } else {
                ends.next(tau_start, None)
            };
            if steps > self.contact_budget {
                self.steps += steps;
                return Err(SimulationError::NoRebound {
                    contact: number,
                    steps,
                });
            }
        }
    }

    /// Restarts the integrator from the derivatives `d` at an event and
    /// takes one step of length `span` (to a grid point); returns the states
    /// at the two ends of that step.
    fn restart(&mut self, d: [f64; 6], span: f64) -> (I::State, I::State) {
        let it = self.integrator;
        let start = it.start(d, span);
        self.scale_law_for(&start);
        let mut state = start;
        self.contact_step(&mut state);
        (start, state)
    }

    /// Scales the law for the step size of `state` (after every `start` or
    /// `set_step` inside a contact).
    #[inline(always)]
    fn scale_law_for(&mut self, state: &I::State) {
        self.step_law = self
            .acceleration_law
            .scaled(self.integrator.force_gain(state));
    }

    /// One step inside a contact, with the law scaled for the step size.
    #[inline(always)]
    fn contact_step(&self, state: &mut I::State) {
        let g = self.problem.gravity;
        self.integrator
            .step_scaled(state, -g, |x, v| self.contact_acceleration(x, v));
    }
}

/// Estimated time until the gap x (< 0 in contact, rising) returns to 0:
/// the first positive root of x + v s + a s²/2 = 0, written without
/// cancellation, or −x/v where that quadratic has no root (a strong
/// attraction decelerating the exit; it fades as h^(1/4) near h = 0, so the
/// exit comes anyway). Only shapes the step mesh: its error costs steps,
/// not accuracy.
fn time_to_exit(k: &Kinematics) -> f64 {
    let (x, v, a) = (k.position, k.velocity, k.acceleration);
    let disc = v * v - 2.0 * a * x;
    if disc >= 0.0 && v + disc.sqrt() > 0.0 {
        -2.0 * x / (v + disc.sqrt())
    } else if v > 0.0 {
        -x / v
    } else {
        f64::INFINITY
    }
}
