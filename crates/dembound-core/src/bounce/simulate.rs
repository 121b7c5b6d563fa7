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
use super::{
    ContactRecord, InputError, Observer, RunOutcome, Sample, Scenario, StepRule, Stepping,
};
use crate::contact::{with_model, LawVisitor, ModelError, NormalContactLaw};
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
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Problem {
    /// Particle mass, kg.
    pub mass: f64,
    /// g, m/s².
    pub gravity: f64,
    /// Initial gap, m.
    pub gap: f64,
    /// Initial velocity, m/s, upward positive.
    pub velocity: f64,
    /// Rebounds to run.
    pub contacts: u32,
    /// Time step, s.
    pub dt: f64,
    /// The contact-time estimate Δt came from, s.
    pub contact_time_estimate: f64,
    pub stepping: Stepping,
}

impl Problem {
    /// Resolves Δt for `law` (Δt = η T_c with the law's estimate at the
    /// first impact speed, or Δt as given).
    pub fn new(s: &Scenario, law: &impl NormalContactLaw) -> Self {
        let mass = s.particle.mass();
        let g = s.motion.gravity;
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
        let dt = match s.step_rule() {
            StepRule::Fixed(dt) => dt,
            StepRule::Fraction(eta) => eta * estimate,
        };
        Problem {
            mass,
            gravity: g,
            gap: s.motion.gap,
            velocity: s.motion.velocity,
            contacts: s.motion.contacts,
            dt,
            contact_time_estimate: estimate,
            stepping: s.integration.stepping,
        }
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
            let problem = Problem::new(self.scenario, &law);
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
        s.particle.mass(),
        s.impact_speed(),
        Visit {
            scenario: s,
            observer,
        },
    )?
}

/// Resolves a scenario into its numerical problem (Δt, expected steps)
/// without running it: for step-count guards and progress bars.
pub fn plan(s: &Scenario) -> Result<Problem, SimulationError> {
    s.validate()?;
    struct Plan<'a>(&'a Scenario);
    impl LawVisitor for Plan<'_> {
        type Output = Problem;
        fn visit<L: NormalContactLaw>(self, law: L) -> Problem {
            Problem::new(self.0, &law)
        }
    }
    Ok(with_model(
        &s.contact.model(),
        &s.pair(),
        s.particle.mass(),
        s.impact_speed(),
        Plan(s),
    )?)
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
    let contacts = match problem.stepping {
        Stepping::Event => run.event_stepping()?,
        Stepping::Fixed => run.fixed_stepping()?,
    };
    Ok(RunOutcome {
        contacts,
        steps: run.steps,
        dt: problem.dt,
        contact_time_estimate: problem.contact_time_estimate,
    })
}

struct Run<'a, L: NormalContactLaw, I, O> {
    law: &'a L,
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

/// How a contact ended.
struct ContactEnd {
    record: ContactRecord,
    /// Time of the end of the step that contains the rebound, s.
    step_end: f64,
    /// Grid steps spanned by the contact (restarts inside a step do not count).
    steps: u64,
}

impl<L: NormalContactLaw, I: Integrator, O: Observer> Run<'_, L, I, O> {
    /// Net acceleration ẍ during a contact: the law's force, continued
    /// smoothly to x > 0 inside the step that contains the rebound (see
    /// [`NormalContactLaw::force`]).
    ///
    /// A non-attractive law is integrated with its unclamped force until the
    /// force has returned to zero (so that the step straddling that point
    /// sees a smooth force and locates it on its polynomial), and with the
    /// clamped force after. For other laws the test compiles away.
    #[inline(always)]
    fn contact_acceleration(&self, x: f64, v: f64) -> f64 {
        let force = if L::NON_ATTRACTIVE && !self.released {
            self.law.unclamped_force(-x, -v, &self.history)
        } else {
            self.law.force(-x, -v, &self.history)
        };
        force * self.inv_mass - self.problem.gravity
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
            let dt = self.problem.dt;
            let end = self.contact(n, t_contact, impact_velocity, dt, t_contact + dt)?;
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
                    if self.steps % PROGRESS_EVERY == 0 {
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
            let mut end_index = first_end_index.unwrap_or(k + 1);
            let mut first = end_index as f64 * dt - t_contact;
            if first < 0.25 * dt {
                end_index += 1;
                first += dt;
            }
            let end = self.contact(n, t_contact, impact_velocity, first, end_index as f64 * dt)?;
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

    /// Integrates one contact from its onset (h = 0, velocity `v_c`) to the
    /// rebound. Steps end on the grid t_n = `first_end` + (n − 1) Δt (the
    /// first one has length `first`), except that a law with a singular
    /// onset ([`NormalContactLaw::singular_onset`]) first takes geometrically
    /// graded steps (ratio 1.4, from ~Δt/200) that land on a grid point.
    ///
    /// Events inside a step (maximum overlap, force zero, rebound) are
    /// located on the step's polynomial. Where the force has a kink at an
    /// event (the branch change of a hysteretic law at the maximum overlap;
    /// the clamp of a non-attractive law at the force zero) the integrator
    /// is restarted at the event with the derivatives of the new branch and
    /// integrated from there to the next grid point at least Δt/4 away
    /// ([`Self::restart`]), so that no step straddles the kink.
    fn contact(
        &mut self,
        number: u32,
        t_c: f64,
        v_c: f64,
        first: f64,
        first_end: f64,
    ) -> Result<ContactEnd, SimulationError> {
        let it = self.integrator;
        let dt = self.problem.dt;
        let m = self.problem.mass;
        let g = self.problem.gravity;
        let grid_time = |n: u64| first_end + (n as f64 - 1.0) * dt;
        // Graded onset: step ends (absolute times) and the grid index of the last.
        let mut graded: Vec<f64> = Vec::new();
        let mut graded_grid = 0;
        if self.law.singular_onset() {
            const RATIO: f64 = 1.4;
            const STEPS: i32 = 16;
            let sizes: Vec<f64> = (0..STEPS)
                .map(|j| dt / RATIO * RATIO.powi(j - STEPS + 1))
                .collect();
            let total: f64 = sizes.iter().sum();
            let n = (((t_c + total - first_end) / dt).round() + 1.0).max(1.0) as u64;
            let scale = (grid_time(n) - t_c) / total;
            let mut t = t_c;
            for size in &sizes {
                t += size * scale;
                graded.push(t);
            }
            if let Some(last) = graded.last_mut() {
                *last = grid_time(n);
            }
            graded_grid = n;
        }
        // One-sided derivatives at h = 0⁺ (see the module doc).
        let overlap_rate = -v_c;
        self.history = L::History::default();
        self.released = false;
        let onset_force = self.law.force(0.0, overlap_rate, &self.history);
        let overlap_accel = g - onset_force * self.inv_mass;
        let [h3, h4, h5] = self.law.onset_derivatives(m, overlap_rate, overlap_accel);
        let first_len = graded.first().map_or(first, |end| end - t_c);
        let mut state = it.start([0.0, v_c, -overlap_accel, -h3, -h4, -h5], first_len);
        if O::ACTIVE {
            self.sample(t_c, 0.0, v_c);
        }
        let mut max_force = onset_force;
        let mut max_overlap: Option<(f64, f64)> = None;
        let mut t_force_zero: Option<f64> = None;
        // Grid points reached (time bookkeeping) and integrator steps (work).
        let mut grid: u64 = 0;
        let mut steps: u64 = 0;
        let mut next_graded = 0;
        let mut t_start = t_c;
        loop {
            // The end of the next step, and its length.
            let (t_end, len) = if next_graded < graded.len() {
                next_graded += 1;
                if next_graded == graded.len() {
                    grid = graded_grid;
                }
                let end = graded[next_graded - 1];
                (end, end - t_start)
            } else {
                grid += 1;
                // Every step but the first starts on a grid point: exactly Δt.
                (grid_time(grid), if steps == 0 { first } else { dt })
            };
            let len = if steps == 0 { first_len } else { len };
            if it.step_size(&state) != len {
                it.set_step(&mut state, len);
            }
            let mut before = state;
            it.step(&mut state, |x, v| self.contact_acceleration(x, v));
            steps += 1;
            let mut t_step = t_start;
            let mut t_end = t_end;
            // Events of this step; a restart replaces (before, state, t_step, t_end).
            loop {
                let h = it.step_size(&state);
                let k = it.kinematics(&state);
                let mut restart_from: Option<(f64, [f64; 6])> = None;
                if max_overlap.is_none() && k.velocity >= 0.0 {
                    let (theta, at) = locate(&it.dense(&before, &state), Crossing::Velocity);
                    let overlap = -at.position;
                    let t_mp = t_step + theta * h;
                    max_overlap = Some((t_mp, overlap));
                    max_force = max_force.max(self.law.force(overlap, -at.velocity, &self.history));
                    if self.law.at_max_overlap(overlap, &mut self.history) {
                        let a = self
                            .law
                            .unclamped_force(overlap, -at.velocity, &self.history)
                            * self.inv_mass;
                        let accel = g - a;
                        let [h3, h4, h5] = self.law.branch_derivatives(
                            m,
                            overlap,
                            -at.velocity,
                            accel,
                            &self.history,
                        );
                        restart_from =
                            Some((t_mp, [at.position, at.velocity, -accel, -h3, -h4, -h5]));
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
                        let t_fz = t_step + theta * h;
                        t_force_zero = Some(t_fz);
                        self.released = true;
                        if O::ACTIVE {
                            self.sample(t_fz, at.position, at.velocity);
                        }
                        let a = self.acceleration(at.position, at.velocity);
                        restart_from = Some((t_fz, [at.position, at.velocity, a, 0.0, 0.0, 0.0]));
                    }
                }
                let Some((t_event, d)) = restart_from else {
                    break;
                };
                // Restart to the first grid point ≥ Δt/4 away; the graded
                // onset, if still running, is abandoned.
                next_graded = graded.len();
                let n = (((t_event + 0.25 * dt - first_end) / dt).ceil() + 1.0).max(1.0) as u64;
                grid = n;
                t_end = grid_time(n);
                (before, state) = self.restart(d, t_end - t_event);
                steps += 1;
                t_step = t_event;
            }
            let h = it.step_size(&state);
            let k = it.kinematics(&state);
            self.law
                .update_history(-k.position, -k.velocity, &mut self.history);
            if k.position < 0.0 {
                max_force = max_force.max(self.law.force(-k.position, -k.velocity, &self.history));
            }
            if let (Some((t_max_overlap, overlap)), true) = (max_overlap, k.position >= 0.0) {
                let (theta, at) = locate(&it.dense(&before, &state), Crossing::Position);
                let t_rebound = t_step + theta * h;
                let rebound_velocity = at.velocity;
                if O::ACTIVE {
                    self.sample(t_rebound, 0.0, rebound_velocity);
                }
                self.steps += steps;
                return Ok(ContactEnd {
                    record: ContactRecord {
                        t_contact: t_c,
                        t_max_overlap,
                        t_rebound,
                        t_force_zero,
                        duration: t_rebound - t_c,
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
                    },
                    step_end: t_end,
                    steps: grid,
                });
            }
            if O::ACTIVE {
                self.sample(t_end, k.position, k.velocity);
                if (self.steps + steps) % PROGRESS_EVERY == 0 {
                    self.observer.progress(t_end, self.t_end);
                }
            }
            t_start = t_end;
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
        let mut state = start;
        it.step(&mut state, |x, v| self.contact_acceleration(x, v));
        (start, state)
    }
}
