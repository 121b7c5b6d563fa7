//! `integration.tolerance`: the chosen Δt meets the target against the
//! exact reference.
use dembound_core::bounce::{simulate, Scenario, Stepping};
use dembound_core::contact::ContactLawKind;
use dembound_core::exact::scenario_contacts;
use dembound_core::integrate::Scheme;

fn errors(s: &Scenario) -> (Vec<[f64; 3]>, Vec<u64>, Option<f64>) {
    let out = simulate(s, &mut ()).unwrap();
    let exact = scenario_contacts(s).unwrap();
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    let errs = out
        .contacts
        .iter()
        .zip(&exact)
        .map(|(c, e)| {
            [
                rel(c.max_overlap, e.max_overlap),
                rel(c.duration, e.duration),
                rel(c.rebound_velocity, e.rebound_velocity),
            ]
        })
        .collect();
    let steps = out.contacts.iter().map(|c| c.steps).collect();
    (errs, steps, out.error_estimate)
}

#[test]
fn hertz_at_1e_minus_8_meets_the_target_within_300_steps_per_contact() {
    let mut s = Scenario::default();
    s.integration.tolerance = Some(1e-8);
    let (errs, steps, estimate) = errors(&s);
    let estimate = estimate.expect("an error estimate");
    assert!(estimate <= 1e-8, "{estimate}");
    for (e, n) in errs.iter().zip(&steps) {
        assert!(e.iter().all(|&x| x <= 1e-8), "{e:?}");
        assert!(*n <= 300, "{n} steps");
    }
}

#[test]
fn the_estimate_tracks_the_measured_error_and_tightens_with_the_target() {
    // Gear5 Hertz and linear (event stepping, 5th order) and Verlet Hertz
    // (2nd order): measured ≤ tolerance at every target.
    for (law, scheme) in [
        (ContactLawKind::Hertz, Scheme::Gear5),
        (ContactLawKind::Linear, Scheme::Gear5),
        (ContactLawKind::Hertz, Scheme::Verlet),
    ] {
        let mut last_steps = 0;
        for tol in [1e-4, 1e-6, 1e-8] {
            let mut s = Scenario::default();
            s.contact.law = law;
            s.integration.scheme = scheme;
            s.integration.tolerance = Some(tol);
            let (errs, steps, estimate) = errors(&s);
            let worst = errs.iter().flatten().fold(0.0_f64, |a, &b| a.max(b));
            assert!(
                worst <= tol,
                "{law:?} {scheme:?} tol {tol}: measured {worst}"
            );
            assert!(estimate.unwrap() <= tol);
            assert!(steps[0] >= last_steps, "{law:?} {scheme:?} tol {tol}");
            last_steps = steps[0];
        }
    }
}

#[test]
fn fixed_stepping_meets_a_loose_target() {
    let mut s = Scenario::default();
    s.integration.stepping = Stepping::Fixed;
    s.motion.gap = 1e-5;
    s.integration.tolerance = Some(1e-6);
    let (errs, _, _) = errors(&s);
    let worst = errs.iter().flatten().fold(0.0_f64, |a, &b| a.max(b));
    assert!(worst <= 1e-6, "{worst}");
}

#[test]
fn tolerance_excludes_eta_and_dt() {
    let mut s = Scenario::default();
    s.integration.tolerance = Some(1e-8);
    s.integration.eta = Some(0.01);
    assert_eq!(
        s.validate().unwrap_err().field(),
        Some("integration.tolerance")
    );
}

#[test]
fn the_pilot_runs_are_counted_apart() {
    // The pilots: the first contact alone, from its onset at the first
    // impact speed, at η = 1/50 and 1/100 of the contact-time estimate.
    let mut s = Scenario::default();
    s.integration.tolerance = Some(1e-8);
    let out = simulate(&s, &mut ()).unwrap();
    let pilot_steps = |eta: f64| {
        let mut p = Scenario::default();
        p.integration.eta = Some(eta);
        p.motion.gap = 0.0;
        p.motion.velocity = -s.impact_speed();
        p.motion.contacts = 1;
        simulate(&p, &mut ()).unwrap().steps
    };
    let pilots = pilot_steps(0.02) + pilot_steps(0.01);
    assert!(pilots > 100, "{pilots}");
    assert_eq!(out.pilot_steps, Some(pilots));
    assert_eq!(out.total_steps(), out.steps + pilots);
    assert_eq!(out.steps, out.contacts.iter().map(|c| c.steps).sum::<u64>());
    // Without a tolerance there are none.
    let plain = simulate(&Scenario::default(), &mut ()).unwrap();
    assert_eq!(plain.pilot_steps, None);
    assert_eq!(plain.total_steps(), plain.steps);
}
