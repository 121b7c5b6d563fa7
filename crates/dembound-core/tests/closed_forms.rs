//! Cross-checks of the integrated bouncing particle against closed forms
//! written out here, independently of the code under test (ERRATA items 6–7).

use dembound_core::bounce::{simulate, ContactRecord, Scenario, Stepping};
use dembound_core::contact::ContactLawKind;
use dembound_core::integrate::Scheme;
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// p² = p̄² c² R^(−1−α), p̄² = ζ̄ r̄^(2−α)/(π(1−ν²)) (eqs 11–14), for the default scenario.
fn p_squared(s: &Scenario, alpha: f64) -> f64 {
    let bar = |x: f64| x / (x + 1.0);
    let nu = s.particle.poisson_ratio;
    let pbar2 = bar(s.boundary.modulus_ratio) * bar(s.boundary.radius_ratio).powf(2.0 - alpha)
        / (PI * (1.0 - nu * nu));
    pbar2 * s.particle.youngs_modulus / s.particle.density * s.particle.radius.powf(-1.0 - alpha)
}

fn run(s: &Scenario) -> Vec<ContactRecord> {
    simulate(s, &mut ()).expect("valid scenario").contacts
}

fn linear(stepping: Stepping, eta: f64, gravity: f64) -> Scenario {
    let mut s = Scenario::default();
    s.contact.law = ContactLawKind::Linear;
    s.integration.stepping = stepping;
    s.integration.eta = Some(eta);
    s.motion.gravity = gravity;
    if gravity == 0.0 {
        s.motion.velocity = -0.313;
        s.motion.contacts = 1;
    }
    s
}

#[test]
fn linear_without_gravity_matches_harmonic_half_period() {
    // h_max = |v_c|/p and T_c = π/p (eqs 27, 29 are exact when g = 0).
    //
    // The issue asks for 1e−9 at η = 1/50. That is below Gear5's own
    // truncation error there: on the bare oscillator x'' = −x started with
    // exact derivatives, 50 Gear5 steps per half period leave a velocity error
    // of 2.6e−8 and a phase error of 1.1e−8 (measured; the scheme converges
    // at order 5, so η = 1/100 gives 8.7e−10). So: at η = 1/50 the run must
    // reach the scheme's own accuracy (h_max 2e−8, T_c 5e−9, i.e. the event
    // handling adds nothing measurable), and 1e−9 at η = 1/100.
    for (eta, tol_h, tol_t) in [(0.02, 2e-8, 5e-9), (0.01, 1e-9, 1e-9)] {
        let s = linear(Stepping::Event, eta, 0.0);
        let p = p_squared(&s, 1.0).sqrt();
        let c = run(&s)[0];
        let (eh, et) = (rel(c.max_overlap, 0.313 / p), rel(c.duration, PI / p));
        assert!(
            eh < tol_h && et < tol_t,
            "eta {eta}: h_max {eh:e}, T_c {et:e}"
        );
    }
}

#[test]
fn symmetry_without_gravity() {
    // With g = 0 the contact is symmetric: t_mp − t_c = T_c/2.
    for law in [ContactLawKind::Linear, ContactLawKind::Hertz] {
        let mut s = linear(Stepping::Event, 0.02, 0.0);
        s.contact.law = law;
        let c = run(&s)[0];
        let half = c.t_max_overlap - c.t_contact;
        assert!(
            rel(half, c.duration / 2.0) < 1e-6,
            "{law:?}: {}",
            rel(half, c.duration / 2.0)
        );
    }
}

/// Exact values of the validation case, linear law with gravity (ERRATA 6–7).
struct LinearExact {
    t_rebound_2: f64,
    max_overlap: f64,
    max_acceleration: f64,
    rebound_velocity: f64,
}

fn linear_exact(s: &Scenario) -> LinearExact {
    let g = s.motion.gravity;
    let p2 = p_squared(s, 1.0);
    let p = p2.sqrt();
    let vc = (2.0 * g * s.motion.gap).sqrt();
    let tc = (PI + 2.0 * (g / (vc * p)).atan()) / p;
    let t1 = (2.0 * s.motion.gap / g).sqrt();
    LinearExact {
        t_rebound_2: t1 + (tc + 2.0 * vc / g) + tc,
        max_overlap: (g + (g * g + vc * vc * p2).sqrt()) / p2,
        max_acceleration: (g * g + vc * vc * p2).sqrt(),
        rebound_velocity: vc,
    }
}

fn check_linear_with_gravity(stepping: Stepping, tol: f64) {
    let s = linear(stepping, 0.02, 9.81);
    let e = linear_exact(&s);
    let c = run(&s)[1];
    let errs = [
        ("t_r", rel(c.t_rebound, e.t_rebound_2)),
        ("h_max", rel(c.max_overlap, e.max_overlap)),
        ("a_max", rel(c.max_acceleration, e.max_acceleration)),
        ("v_r", rel(c.rebound_velocity, e.rebound_velocity)),
    ];
    for (name, err) in errs {
        assert!(err < tol, "{stepping:?} {name}: {err:e}");
    }
}

#[test]
fn linear_validation_case_event_stepping() {
    check_linear_with_gravity(Stepping::Event, 1e-6);
}

#[test]
fn linear_validation_case_fixed_stepping() {
    // The paper's δ₂ was 0.2–0.56 %; the issue demands 0.05 %.
    check_linear_with_gravity(Stepping::Fixed, 5e-4);
}

#[test]
fn energy_is_conserved_by_the_rebound() {
    // The model is conservative: |v_r| = |v_c| (ERRATA 8).
    for (law, tol) in [
        (ContactLawKind::Hertz, 1e-4),
        (ContactLawKind::Linear, 1e-6),
    ] {
        for scheme in [Scheme::Gear5] {
            let mut s = Scenario::default();
            s.contact.law = law;
            s.integration.scheme = scheme;
            for c in run(&s) {
                let err = rel(c.rebound_velocity, -c.impact_velocity);
                assert!(err < tol, "{law:?}: {err:e}");
            }
        }
    }
}

#[test]
fn verlet_is_second_order_on_the_linear_case() {
    // Halving Δt divides Verlet's h_max error by ~4.
    let err = |eta: f64| {
        let mut s = linear(Stepping::Event, eta, 9.81);
        s.integration.scheme = Scheme::Verlet;
        rel(run(&s)[0].max_overlap, linear_exact(&s).max_overlap)
    };
    let ratio = err(0.02) / err(0.01);
    assert!((3.0..5.0).contains(&ratio), "{ratio}");
}
