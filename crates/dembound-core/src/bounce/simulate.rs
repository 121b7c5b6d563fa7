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
use super::problem::Problem;
use super::schedule::{GradedSteps, Grading, SingularMesh};
use super::{BodyVelocities, ContactRecord, Observer, RunOutcome, Sample, Stepping, TwoBody};
use crate::contact::{NormalContactLaw, Onset};
use crate::integrate::{FreeFall, Integrator, Kinematics};
use crate::{Error, Result};

const PROGRESS_EVERY: u64 = 1 << 16;

/// Runs `problem` with a concrete law and integrator.
pub fn simulate_with<L: NormalContactLaw, I: Integrator, O: Observer>(
    law: &L,
    integrator: I,
    problem: &Problem,
    observer: &mut O,
) -> Result<RunOutcome> {
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
    ///
    /// `#[inline]`, like the other per-step helpers of the contact loop
    /// ([`time_to_exit`], `GradedSteps::next`, `SingularMesh::onset_step` and
    /// `end_step`): `Run::contact` is generic, so the crate that runs a
    /// scenario (the CLI) compiles its own instance, and a call into this
    /// crate's code each step clobbers every XMM register of the loop
    /// (−8 … −18 % instructions per damped step, BENCHMARKS.md "#11 rest,
    /// session 7").
    #[inline]
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
    fn event_stepping(&mut self) -> Result<Vec<ContactRecord>> {
        let g = self.problem.gravity;
        let (mut t, mut x, mut v) = (0.0, self.problem.gap, self.problem.velocity);
        let mut records = Vec::with_capacity(self.problem.contacts as usize);
        for n in 1..=self.problem.contacts {
            let tau = time_to_surface(x, v, g).ok_or(Error::NeverReachesBoundary)?;
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
    fn fixed_stepping(&mut self) -> Result<Vec<ContactRecord>> {
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
            // (`free_fall`: the same states as `it.step(&mut state, |_, _| -g)`.)
            let mut flight = it.free_fall(state, -g);
            let (t_contact, impact_velocity, first_end_index) = loop {
                let before = flight.kinematics();
                if before.position <= 0.0 && before.velocity <= 0.0 {
                    break (k as f64 * dt, before.velocity, None);
                }
                flight.step();
                self.steps += 1;
                let after = flight.kinematics();
                if O::ACTIVE {
                    self.sample((k + 1) as f64 * dt, after.position, after.velocity);
                    if self.steps.is_multiple_of(PROGRESS_EVERY) {
                        self.observer.progress((k + 1) as f64 * dt, self.t_end);
                    }
                }
                if after.position < 0.0 {
                    let tau = time_to_surface(before.position, before.velocity, g)
                        .ok_or(Error::NeverReachesBoundary)?;
                    break (k as f64 * dt + tau, before.velocity - g * tau, Some(k + 1));
                }
                if g == 0.0 && after.velocity >= 0.0 {
                    return Err(Error::NeverReachesBoundary);
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
    fn check_gravity_share(&self, n: u32, v_c: f64) -> Result<()> {
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
        Err(Error::Input {
            field: "motion.contacts".into(),
            value: self.problem.contacts.to_string(),
            allowed: format!(
                "1 to {} for this scenario: the impact speed has fallen to {speed:.3e} m/s by \
                 contact {n}, where gravity dominates the contact (g T_c/|v_c| = {share:.3e} > \
                 {}) and the rebound cannot be resolved",
                n - 1,
                limits::MAX_GRAVITY_SHARE
            ),
        })
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
    ) -> Result<ContactEnd> {
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
                return Err(Error::NoRebound {
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
#[inline]
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
