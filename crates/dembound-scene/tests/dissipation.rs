//! The dissipated energy summed contact by contact (`output.dissipation`,
//! `pipeline::dissipation`) against closed forms.

mod common;

use common::{grain, sphere_on_plane};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::setup::Scheme;
use dembound_scene::Simulation;

const R: f64 = 1e-3;
const V: f64 = 0.1;

fn mass() -> f64 {
    grain(1.0e7).density * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3)
}

/// A sphere thrown head-on at the plane at V (no gravity) with `model`,
/// run until well after it rebounds: (D_c, residual D, kinetic energy).
fn head_on(model: ContactModel, dt: f64) -> (f64, f64, f64) {
    let mut s = sphere_on_plane(
        R,
        grain(1.0e7),
        [0.0, 0.0, 1.5 * R],
        [0.0, 0.0, -V],
        model,
        None,
        Scheme::Verlet,
        dt,
    );
    s.gravity = [0.0; 3];
    s.dissipation = true;
    let mut sim = Simulation::new(s, 1).unwrap();
    // 0.5 R of flight each way at ≤ V, and the contact (≪ 1 ms here).
    let steps = (2.0 * R / V / dt).ceil() as u64;
    sim.step(steps);
    let o = sim.observe();
    (
        o.dissipated_by_contacts.unwrap(),
        o.dissipated_energy,
        o.kinetic_energy,
    )
}

#[test]
fn an_undamped_contact_dissipates_nothing() {
    let (dc, d, k) = head_on(ContactModel::elastic(NormalLaw::Linear), 1e-7);
    // No dashpot, no friction: every term is exactly 0.
    assert_eq!(dc, 0.0);
    // The residual D is Verlet's energy error only.
    assert!(d.abs() < 1e-3 * 0.5 * mass() * V * V, "{d} {k}");
}

#[test]
fn a_damped_linear_contact_dissipates_the_closed_form() {
    // Linear damped oscillator (Hooke + viscous calibrated to e): the
    // rebound speed is e V exactly, so D = ½ m V² (1 − e²) (m* = m
    // against a wall).
    let e = 0.5;
    let model = ContactModel::damped(
        NormalLaw::Linear,
        Damping::new(DampingKind::Viscous, Dissipation::Restitution(e)),
    );
    let exact = 0.5 * mass() * V * V * (1.0 - e * e);
    let mut errors = Vec::new();
    for dt in [4e-7, 2e-7, 1e-7] {
        let (dc, d, _) = head_on(model, dt);
        // D_c against the closed form: Verlet's trajectory loses e by
        // O(Δt/T_c) (the dashpot reads the half-step velocity), T_c ≈ 60 µs
        // here: within 1 %.
        assert!(
            (dc - exact).abs() < 1e-2 * exact,
            "dt {dt}: {dc} vs {exact}"
        );
        errors.push((d - dc).abs() / exact);
    }
    // The balance error D − D_c once the contact is over is the
    // integration error of the spring (the contact starts and ends
    // between steps), not a missing term: it falls as Δt² (measured 2.3e-5,
    // 4.7e-6, 2.2e-7 of D: each halving ≥ 3×, second order being 4×).
    assert!(
        errors[0] > 3.0 * errors[1] && errors[1] > 3.0 * errors[2],
        "{errors:?}"
    );
    assert!(errors[2] < 1e-6, "{errors:?}");
}
