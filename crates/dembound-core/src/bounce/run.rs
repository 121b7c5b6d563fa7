//! From a scenario to a run: validate, build the law, resolve the
//! numerical problem (Δt = η T_c, a given Δt, or the Δt of an accuracy
//! target from pilot runs, [`super::tolerance`]), check that the step
//! resolves the contact, then hand the problem to the time loop
//! ([`super::simulate`]). Above both the loop and the step choice, so that
//! neither imports the other's caller.

use super::limits;
use super::problem::Problem;
use super::simulate::simulate_with;
use super::tolerance;
use super::{Observer, RunOutcome, Scenario, StepRule};
use crate::calibration::{damping_coefficient, with_damped, with_model};
use crate::contact::{DampingKind, LawVisitor, NormalContactLaw};
use crate::integrate::{Gear5, Scheme, Verlet};
use crate::{Error, Result};

impl Problem {
    /// Resolves Δt for `law` (Δt = η T_c with the law's estimate at the
    /// first impact speed, Δt as given, or Δt for an accuracy target from
    /// pilot runs: [`super::tolerance`]).
    pub fn new(s: &Scenario, law: &impl NormalContactLaw) -> Result<Self> {
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
}

/// Refuses a contact that gravity dominates: g T_c/|v_c| above
/// [`limits::MAX_GRAVITY_SHARE`] at the first impact, or at the last one
/// when a target restitution e < 1 slows the later impacts (|v_c| e^(n−1),
/// gravity-free). There e = v_r/|v_c| is ill-conditioned and the integrator
/// cannot resolve it (measurements in [`limits`]). The message names
/// `motion.gap` with the smallest gap that would do.
fn check_gravity_share(s: &Scenario, law: &impl NormalContactLaw, mass: f64) -> Result<()> {
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
        return Err(Error::Input {
            field: "motion.contacts".into(),
            value: s.motion.contacts.to_string(),
            allowed: format!(
                "1 to {most} for this scenario: with e = {e} the impact speed falls to \
                 {v_last:.3e} m/s by contact {n}, where gravity dominates the contact \
                 (g T_c/|v_c| = {ratio:.3e} > {max}) and the rebound speed cannot be resolved",
                e = limits::show(e),
                n = s.motion.contacts,
                max = limits::MAX_GRAVITY_SHARE,
            ),
        });
    }
    let v_needed = v_min / slowing;
    let v0 = s.relative_velocity();
    let gap_needed = (v_needed * v_needed - v0 * v0) / (2.0 * g);
    Err(Error::Input {
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
pub fn check_step(s: &Scenario, problem: &Problem) -> Result<()> {
    let limit = limits::MAX_ETA * problem.contact_time_estimate;
    if let Some(dt) = s.integration.dt {
        if dt.is_nan() || dt > limit {
            return Err(Error::Input {
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
        return Err(Error::Input {
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

/// Refuses a step that does not resolve a stiff unloading branch
/// ([`NormalContactLaw::loading_unloading`], Walton–Braun's k₂ = k₁/e²):
/// ω₂ Δt above the scheme's bound ([`limits::MAX_UNLOADING_STEP_GEAR5`],
/// [`limits::MAX_UNLOADING_STEP_VERLET`]), ω₂ = √(k₂/m). There the
/// rebound is wrong by far more than the step's error elsewhere (e = 2.09
/// for a target 0.001 at the default step: energy created; measurements in
/// [`limits`]). The message names `contact.restitution`, with the smallest
/// e this step resolves and the step this e needs.
pub fn check_unloading(s: &Scenario, law: &impl NormalContactLaw, problem: &Problem) -> Result<()> {
    let Some([k1, k2]) = law.loading_unloading() else {
        return Ok(());
    };
    let omega2 = (k2 / problem.mass).sqrt();
    let limit = match s.integration.scheme {
        Scheme::Gear5 => limits::MAX_UNLOADING_STEP_GEAR5,
        Scheme::Verlet => limits::MAX_UNLOADING_STEP_VERLET,
    };
    if omega2 * problem.dt <= limit {
        return Ok(());
    }
    // The e the user gave, else the law's own √(k₁/k₂) (a study's raw
    // coefficient k₂).
    let e = s.contact.restitution.unwrap_or((k1 / k2).sqrt());
    let w = omega2 * problem.dt;
    // The smallest e this step rule resolves. Walton–Braun's ω₂ = ω₁/e
    // with ω₁ set by the loading line: a fixed Δt needs ω₁Δt/e ≤ limit;
    // Δt = η T_c with T_c = (π/2)(1 + e)/ω₁ (its estimate) needs
    // η (π/2)(1 + e)/e ≤ limit, e ≥ a/(limit − a) with a = η π/2.
    let (e_min, step) = match s.step_rule() {
        StepRule::Fraction(eta) => {
            let a = eta * std::f64::consts::FRAC_PI_2;
            (
                a / (limit - a),
                format!("integration.eta = {}", limits::show(eta)),
            )
        }
        StepRule::Fixed(dt) => (
            e * w / limit,
            format!("integration.dt = {} s", limits::show(dt)),
        ),
        StepRule::Tolerance(_) => (
            e * w / limit,
            format!(
                "the step integration.tolerance chose (Δt = {:.4e} s)",
                problem.dt
            ),
        ),
    };
    let dt_max = limit / omega2;
    let eta_max = dt_max / problem.contact_time_estimate;
    let smaller = match s.step_rule() {
        _ if eta_max < limits::ETA.0 => String::new(),
        StepRule::Fixed(_) => format!("; or keep e with integration.dt ≤ {dt_max:.4e} s"),
        _ => format!(
            "; or keep e with a smaller step, integration.eta ≤ {eta_max:.3e} (Δt ≤ {dt_max:.4e} s)"
        ),
    };
    Err(Error::Input {
        field: "contact.restitution".into(),
        value: limits::show(e),
        allowed: format!(
            "{e_min:.3e} to 1 with {step}: Walton–Braun's unloading line k₂ = k₁/e² \
             oscillates at ω₂ = {omega2:.4e} rad/s, and ω₂Δt = {w:.3e} above {limit} leaves it \
             unresolved (the rebound would be wrong, with energy created){smaller}"
        ),
    })
}

/// Refuses a Gear5 step that a damped contact makes unstable: the contact
/// linearised at its largest overlap ([`NormalContactLaw::damped_peak`]:
/// stiffness ω², damping rate β) must satisfy Gear5's closed-form bound
/// (ωΔt/W)² + βΔt/B ≤ 1 ([`dembound_physics::integrate::gear5_stability`];
/// W = 0.840, B = 0.163). Beyond it a parasitic root of the
/// predictor–corrector passes −1 and the rebound is wrong by far more
/// than the step's error elsewhere (e = 0.59 for a target 0.01 at
/// η = 0.1 printed with exit 0 before; measurements in [`limits`]).
/// Velocity Verlet is not refused: its error grows smoothly with the
/// step. The message names the step key with the largest step this
/// contact accepts, and the damping key.
pub fn check_damped_step(
    s: &Scenario,
    law: &impl NormalContactLaw,
    problem: &Problem,
) -> Result<()> {
    if s.integration.scheme != Scheme::Gear5 {
        return Ok(());
    }
    let Some(peak) = law.damped_peak(problem.mass, s.impact_speed().max(0.0), problem.gravity)
    else {
        return Ok(());
    };
    let stability = Gear5::for_force(law.depends_on_rate()).damped_stability();
    let Err(unstable) = stability.check(peak, problem.dt) else {
        return Ok(());
    };
    let dt_max = unstable.dt_max;
    let eta_max = dt_max / problem.contact_time_estimate;
    let damping = match (s.contact.restitution, s.contact.damping_coefficient) {
        (Some(e), _) => format!("contact.restitution = {}", limits::show(e)),
        (None, Some(c)) => format!("contact.damping_coefficient = {}", limits::show(c)),
        (None, None) => "the damping".to_string(),
    };
    let why = format!(
        "a damped contact under gear5: {}; or a weaker damping (a larger \
         contact.restitution or a smaller contact.damping_coefficient), or \
         integration.scheme = \"verlet\" (first order, its error grows smoothly)",
        unstable.describe(&damping)
    );
    let (field, value, allowed) = match s.step_rule() {
        StepRule::Fraction(eta) => (
            "integration.eta",
            limits::show(eta),
            format!(
                "≤ {eta_max:.3e} (Δt ≤ {dt_max:.4e} s, T_c ≈ {tc:.4e} s) for {why}",
                tc = problem.contact_time_estimate
            ),
        ),
        StepRule::Fixed(dt) => (
            "integration.dt",
            format!("{} s", limits::show(dt)),
            format!("0 < Δt ≤ {dt_max:.4e} s (integration.eta ≤ {eta_max:.3e}) for {why}"),
        ),
        StepRule::Tolerance(tol) => (
            "integration.tolerance",
            limits::show(tol),
            format!(
                "a tolerance whose step is ≤ {dt_max:.4e} s, or integration.eta ≤ {eta_max:.3e}, \
                 for {why}"
            ),
        ),
    };
    Err(Error::Input {
        field: field.into(),
        value,
        allowed,
    })
}

/// [`plan`]'s checks without its cost: validation, the gravity share and
/// the step, with an `integration.tolerance` replaced by η = 1/50 (its
/// pilot runs are not needed to know that the contact can be resolved;
/// the step it chooses is finer still).
pub fn check_resolution(s: &Scenario) -> Result<()> {
    let mut s = *s;
    if s.integration.tolerance.take().is_some() {
        s.integration.eta = Some(super::DEFAULT_ETA);
    }
    plan(&s).map(|_| ())
}

/// A scenario resolved once: validated, its damping calibrated (a target
/// restitution turned into the raw coefficient; for the viscoelastic law
/// an adaptive root solve) and its numerical problem chosen (Δt, with an
/// `integration.tolerance` the pilot runs). [`simulate_resolved`] runs it
/// without redoing any of this.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    /// The numerical problem (Δt, contact-time estimate, expected steps).
    pub problem: Problem,
    /// The damping's raw coefficient (c, γ or A), for a damped law.
    pub damping_coefficient: Option<f64>,
}

/// Calls `f` with the law of `s`, the damping's coefficient as resolved
/// (no calibration when it is given).
fn with_resolved_law<R>(
    s: &Scenario,
    damping_coefficient: Option<f64>,
    f: impl LawVisitor<Output = R>,
) -> Result<R> {
    let (model, pair) = (s.contact.model(), s.pair());
    Ok(match damping_coefficient {
        Some(c) => with_damped(&model, &pair, s.reduced_mass(), c, f)?,
        None => with_model(&model, &pair, s.reduced_mass(), s.impact_speed(), f)?,
    })
}

/// Resolves `s` once ([`Resolved`]), refusing a step that does not resolve
/// the contact ([`check_step`]).
pub fn resolve(s: &Scenario) -> Result<Resolved> {
    s.validate()?;
    let model = s.contact.model();
    let damping_coefficient = if model.damping == DampingKind::None {
        None
    } else {
        Some(damping_coefficient(
            &model,
            &s.pair(),
            s.reduced_mass(),
            s.impact_speed(),
        )?)
    };
    struct Plan<'a>(&'a Scenario);
    impl LawVisitor for Plan<'_> {
        type Output = Result<Problem>;
        fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output {
            let problem = Problem::new(self.0, &law)?;
            check_step(self.0, &problem)?;
            check_unloading(self.0, &law, &problem)?;
            check_damped_step(self.0, &law, &problem)?;
            Ok(problem)
        }
    }
    let problem = with_resolved_law(s, damping_coefficient, Plan(s))??;
    Ok(Resolved {
        problem,
        damping_coefficient,
    })
}

/// Runs a scenario resolved by [`resolve`] and reports every contact: the
/// same run as [`simulate`], without validating, calibrating or choosing
/// the step again.
pub fn simulate_resolved<O: Observer>(
    s: &Scenario,
    resolved: &Resolved,
    observer: &mut O,
) -> Result<RunOutcome> {
    struct Visit<'a, O> {
        scenario: &'a Scenario,
        problem: &'a Problem,
        observer: &'a mut O,
    }
    impl<O: Observer> LawVisitor for Visit<'_, O> {
        type Output = Result<RunOutcome>;
        fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output {
            run_problem(self.scenario, &law, self.problem, self.observer)
        }
    }
    with_resolved_law(
        s,
        resolved.damping_coefficient,
        Visit {
            scenario: s,
            problem: &resolved.problem,
            observer,
        },
    )?
}

/// The time loop of `law` on `problem`, with the scenario's scheme.
fn run_problem<L: NormalContactLaw, O: Observer>(
    s: &Scenario,
    law: &L,
    problem: &Problem,
    observer: &mut O,
) -> Result<RunOutcome> {
    match s.integration.scheme {
        Scheme::Gear5 => {
            let gear = Gear5::for_force(law.depends_on_rate());
            simulate_with(law, gear, problem, observer)
        }
        Scheme::Verlet => simulate_with(law, Verlet, problem, observer),
    }
}

/// Runs a scenario (validated first, a stiff unloading line and a damped
/// contact's Gear5 step checked: [`check_unloading`],
/// [`check_damped_step`]) and reports every contact.
pub fn simulate<O: Observer>(s: &Scenario, observer: &mut O) -> Result<RunOutcome> {
    s.validate()?;
    struct Visit<'a, O> {
        scenario: &'a Scenario,
        observer: &'a mut O,
    }
    impl<O: Observer> LawVisitor for Visit<'_, O> {
        type Output = Result<RunOutcome>;
        fn visit<L: NormalContactLaw>(self, law: L) -> Self::Output {
            let problem = Problem::new(self.scenario, &law)?;
            // Not `check_step`: studies of the integrator may step coarser
            // than a run should; but no step makes an unresolved unloading
            // line's rebound right.
            check_unloading(self.scenario, &law, &problem)?;
            check_damped_step(self.scenario, &law, &problem)?;
            run_problem(self.scenario, &law, &problem, self.observer)
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
pub fn plan(s: &Scenario) -> Result<Problem> {
    resolve(s).map(|r| r.problem)
}
