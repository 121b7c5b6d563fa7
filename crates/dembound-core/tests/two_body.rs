//! A free boundary sphere (`boundary.fixed = false`): the head-on collision
//! of two spheres, integrated in the relative coordinate with the reduced
//! mass m* and recovered body by body from the ballistic centre of mass.
//!
//! The comparisons are against a *fixed* boundary whose particle has the
//! mass m* — built independently, by scaling the particle's density by
//! m*/m_m (which changes neither the effective radius nor the modulus).

use dembound_core::bounce::{simulate, ContactRecord, GravityOn, Scenario};
use dembound_core::contact::{ContactLawKind, DampingKind};
use dembound_core::exact::scenario_contacts;
use std::f64::consts::PI;

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn mass(density: f64, radius: f64) -> f64 {
    4.0 / 3.0 * PI * density * radius.powi(3)
}

/// Two spheres approaching head-on without gravity.
fn free(
    law: ContactLawKind,
    r: f64,
    zeta: f64,
    boundary_density: f64,
    v_m: f64,
    v_b: f64,
) -> Scenario {
    let mut s = Scenario::default();
    s.contact.law = law;
    s.boundary.radius_ratio = r;
    s.boundary.modulus_ratio = zeta;
    s.boundary.fixed = false;
    s.boundary.density = Some(boundary_density);
    s.boundary.velocity = Some(v_b);
    s.motion.gap = 1e-4;
    s.motion.velocity = v_m;
    s.motion.gravity_on = GravityOn::None;
    s.motion.contacts = 1;
    s
}

/// The same relative motion against a fixed boundary, the particle's mass
/// replaced by m* through its density.
fn fixed_equivalent(s: &Scenario) -> Scenario {
    let m_m = mass(s.particle.density, s.particle.radius);
    let r_b = s.boundary.radius_ratio * s.particle.radius;
    let m_b = mass(s.boundary.density.unwrap(), r_b);
    let reduced = m_m * m_b / (m_m + m_b);
    let mut f = *s;
    f.boundary.fixed = true;
    f.boundary.density = None;
    f.boundary.velocity = None;
    f.motion.velocity = s.motion.velocity - s.boundary.velocity.unwrap();
    f.motion.gravity_on = GravityOn::Particle;
    f.motion.gravity = 0.0;
    f.particle.density *= reduced / m_m;
    f
}

fn one(s: &Scenario) -> ContactRecord {
    simulate(s, &mut ()).expect("valid scenario").contacts[0]
}

fn check_momentum(s: &Scenario, c: &ContactRecord) {
    let m_m = mass(s.particle.density, s.particle.radius);
    let m_b = mass(
        s.boundary.density.unwrap(),
        s.boundary.radius_ratio * s.particle.radius,
    );
    let b = c.bodies.expect("a free boundary reports both spheres");
    let before = m_m * b.particle_before + m_b * b.boundary_before;
    let after = m_m * b.particle_after + m_b * b.boundary_after;
    // Without gravity the total momentum is that of t = 0.
    let initial = m_m * s.motion.velocity + m_b * s.boundary.velocity.unwrap();
    let scale = m_m * s.motion.velocity.abs() + m_b * s.boundary.velocity.unwrap().abs();
    assert!(((after - before) / scale).abs() < 1e-12, "{before} {after}");
    assert!(((before - initial) / scale).abs() < 1e-12);
    // Relative velocities are the record's.
    assert!((b.particle_before - b.boundary_before - c.impact_velocity).abs() < 1e-12);
    assert!((b.particle_after - b.boundary_after - c.rebound_velocity).abs() < 1e-12);
}

#[test]
fn equal_spheres_head_on_conserve_momentum_and_match_the_reduced_mass() {
    for law in [ContactLawKind::Hertz, ContactLawKind::Linear] {
        let s = free(law, 1.0, 1.0, 1000.0, -0.3, 0.2);
        let c = one(&s);
        check_momentum(&s, &c);
        let f = one(&fixed_equivalent(&s));
        assert!(f.bodies.is_none());
        assert!(rel(c.max_overlap, f.max_overlap) < 1e-12, "{law:?}");
        assert!(rel(c.duration, f.duration) < 1e-12, "{law:?}");
        assert!(rel(c.rebound_velocity, f.rebound_velocity) < 1e-12);
        // Equal elastic spheres exchange their velocities.
        let b = c.bodies.unwrap();
        assert!((b.particle_after - 0.2).abs() < 1e-7, "{b:?}");
        assert!((b.boundary_after + 0.3).abs() < 1e-7, "{b:?}");
        // The exact reference of the free scenario agrees too.
        let exact = scenario_contacts(&s).unwrap()[0];
        assert!(rel(c.max_overlap, exact.max_overlap) < 1e-6, "{law:?}");
        assert!(rel(c.duration, exact.duration) < 1e-6, "{law:?}");
    }
}

#[test]
fn unequal_spheres_match_the_reduced_mass_for_elastic_and_dissipative_laws() {
    let mut cases = Vec::new();
    for law in [ContactLawKind::Hertz, ContactLawKind::Linear] {
        cases.push(free(law, 2.0, 0.5, 3000.0, -0.4, 0.1));
        cases.push(free(law, 0.5, 10.0, 500.0, 0.05, 0.35));
    }
    let mut tsuji = free(ContactLawKind::Hertz, 3.0, 2.0, 2500.0, -0.2, 0.1);
    tsuji.contact.damping = DampingKind::Tsuji;
    tsuji.contact.restitution = Some(0.6);
    cases.push(tsuji);
    let mut wb = free(ContactLawKind::WaltonBraun, 0.7, 1.5, 4000.0, -0.2, 0.0);
    wb.contact.restitution = Some(0.8);
    cases.push(wb);
    for s in cases {
        let c = one(&s);
        check_momentum(&s, &c);
        let f = one(&fixed_equivalent(&s));
        let what = format!("{:?} r = {}", s.contact, s.boundary.radius_ratio);
        assert!(rel(c.max_overlap, f.max_overlap) < 1e-12, "{what}");
        assert!(rel(c.duration, f.duration) < 1e-12, "{what}");
        assert!(rel(c.restitution, f.restitution) < 1e-12, "{what}");
        // Kinetic energy: lost exactly as ½ m* (v_c² − v_r²).
        let b = c.bodies.unwrap();
        let m_m = s.particle.mass();
        let m_b = mass(
            s.boundary.density.unwrap(),
            s.boundary.radius_ratio * s.particle.radius,
        );
        let ke = |vm: f64, vb: f64| 0.5 * m_m * vm * vm + 0.5 * m_b * vb * vb;
        let lost =
            ke(b.particle_before, b.boundary_before) - ke(b.particle_after, b.boundary_after);
        let scale = ke(b.particle_before, b.boundary_before);
        assert!(
            ((lost - c.energy_dissipated) / scale).abs() < 1e-12,
            "{what}"
        );
    }
}

#[test]
fn gravity_on_both_spheres_leaves_the_relative_motion_free_of_gravity() {
    let mut both = free(ContactLawKind::Hertz, 5.0, 3.0, 2000.0, -0.3, 0.0);
    both.motion.gravity_on = GravityOn::Both;
    both.motion.gravity = 9.81;
    let mut none = both;
    none.motion.gravity_on = GravityOn::None;
    let (cb, cn) = (one(&both), one(&none));
    // The relative motion is the same problem: identical records.
    assert_eq!(cb.max_overlap, cn.max_overlap);
    assert_eq!(cb.duration, cn.duration);
    assert_eq!(cb.rebound_velocity, cn.rebound_velocity);
    assert_eq!(cb.apex_height, None);
    // Each sphere has fallen by g t more.
    let (bb, bn) = (cb.bodies.unwrap(), cn.bodies.unwrap());
    let g = 9.81;
    assert!((bb.particle_before - bn.particle_before + g * cb.t_contact).abs() < 1e-12);
    assert!((bb.boundary_after - bn.boundary_after + g * cb.t_rebound).abs() < 1e-12);
}

#[test]
fn a_very_heavy_free_boundary_is_a_fixed_one() {
    let mut heavy = Scenario::default();
    heavy.boundary.fixed = false;
    heavy.boundary.density = Some(1e6 * heavy.particle.density);
    let fixed = Scenario::default();
    let (a, b) = (
        simulate(&heavy, &mut ()).unwrap(),
        simulate(&fixed, &mut ()).unwrap(),
    );
    // m_m/m_b = 1e−12: the two differ at that level only.
    for (x, y) in a.contacts.iter().zip(&b.contacts) {
        assert!(rel(x.max_overlap, y.max_overlap) < 1e-9);
        assert!(rel(x.t_rebound, y.t_rebound) < 1e-9);
        let bodies = x.bodies.unwrap();
        assert!((bodies.particle_after - y.rebound_velocity).abs() < 1e-9);
        assert!(bodies.boundary_after.abs() < 1e-9);
    }
    assert!(b.contacts.iter().all(|c| c.bodies.is_none()));
}
