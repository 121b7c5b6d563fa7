//! Friction and rotation against closed forms (issue 13).
//!
//! - Oblique impact on a plane in gross sliding: the tangential impulse is
//!   μ times the normal one throughout, so v_t' = v_t − μ (1 + e) v_n and
//!   ω' = (5/2) μ (1 + e) v_n/R (I = 2/5 m R², lever arm R); without
//!   friction the spin stays 0 and v_t is untouched.
//! - A sphere on an incline (gravity tilted by θ over a horizontal plane):
//!   μ < (2/7) tan θ slides at g (sin θ − μ cos θ); (2/7) tan θ ≤ μ rolls
//!   without slip at (5/7) g sin θ; with rolling resistance μ_r > tan θ
//!   (and μ > tan θ) it stays put.
//!
//! Each under velocity Verlet and under the paper's Gear5 (its spins by
//! `dynamics::gear5_rotation`), with the same bounds.

mod common;

use dembound_physics::contact::tangential::TangentialKind;
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_physics::material::Material;
use dembound_scene::setup::Scheme;
use dembound_scene::{SceneSetup, Simulation};

const R: f64 = 1.0e-3;

fn material() -> Material {
    Material {
        density: 2500.0,
        youngs_modulus: 1.0e8,
        poisson_ratio: 0.25,
    }
}

/// One sphere of radius R at `position` with `velocity` over the plane
/// z = 0 of its own material, Hertz with Tsuji damping of target e
/// (exact calibration, clamped), friction μ (`None`: no friction at all),
/// Δt given.
fn sphere_on_plane(
    position: [f64; 3],
    velocity: [f64; 3],
    e: f64,
    friction: Option<(TangentialKind, f64, f64)>,
    scheme: Scheme,
    dt: f64,
) -> SceneSetup {
    let contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(e)),
    );
    common::sphere_on_plane(
        R,
        material(),
        position,
        velocity,
        contact,
        friction,
        scheme,
        dt,
    )
}

/// Both schemes: every closed form below holds for each.
const SCHEMES: [Scheme; 2] = [Scheme::Verlet, Scheme::Gear5];

/// Hertz contact time of a sphere of radius R on a plane of its own
/// material at speed v (eq 29–30: T_c = 2.9432 h_max/v,
/// h_max = (5 m v²/(4 k))^(2/5), k = E_eff √R).
fn hertz_contact_time(v: f64) -> f64 {
    let m = material();
    let e_eff = 4.0 / 3.0 / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus);
    let k = e_eff * R.sqrt();
    let mass = m.sphere_mass(R);
    let h_max = (1.25 * mass * v * v / k).powf(0.4);
    2.943_275_184_3 * h_max / v
}

/// Runs an impact from just above the plane until well after it.
fn impact(
    vn: f64,
    vt: f64,
    e: f64,
    friction: Option<(TangentialKind, f64, f64)>,
    scheme: Scheme,
) -> Simulation {
    // Δt = T_c/20000: Verlet's error in e is then 3e-7 (measured: 1.5e-6
    // at T_c/4000, first order in Δt: the Tsuji damping h^(1/4) ḣ is not
    // smooth at onset); Gear5's 2.1e-9 (the normal force's kinks at onset
    // corrected).
    let per_contact = 20000;
    let tc = hertz_contact_time(vn);
    let dt = tc / per_contact as f64;
    let gap = 10.0 * dt * vn;
    let s = sphere_on_plane([0.0, 0.0, R + gap], [vt, 0.0, -vn], e, friction, scheme, dt);
    let mut sim = Simulation::new(s, 1).unwrap();
    sim.step(3 * per_contact);
    sim
}

#[test]
fn oblique_impact_in_gross_sliding_matches_the_closed_forms() {
    let (vn, vt, e, mu) = (0.5, 2.5, 0.8, 0.3);
    // Gross sliding throughout needs v_t > (7/2) μ (1 + e) v_n = 0.945 m/s
    // (the slip velocity falls by 7/2 of the centre's change): 2.5 m/s.
    for (kind, scheme) in [TangentialKind::Mindlin, TangentialKind::Linear]
        .into_iter()
        .flat_map(|k| SCHEMES.map(|s| (k, s)))
    {
        let sim = impact(vn, vt, e, Some((kind, mu, 0.0)), scheme);
        let v = sim.velocities()[0];
        let w = sim.angular_velocities()[0];
        assert!(v[2] > 0.0, "rebounding: {v:?}");
        // Closed forms with the nominal e. Error budget: the exact
        // calibration gives e for the continuous law; Verlet at
        // Δt = T_c/20000 misses it by a few 1e-7 (asserted here), which
        // enters v_t' and ω' scaled by μ v_n/v_t' and 1: inside 1e-6.
        // Gear5 gets e to 2.1e-9, but the tangential force μ F_n has the
        // normal force's kink at onset, which `kinks` does not correct:
        // v_t' 6.5e-8 and ω' 5.4e-7 off (measured; the spin takes 5/2 of
        // the relative change), inside the 1e-6.
        let measured_e = v[2] / vn;
        eprintln!(
            "{kind:?} {scheme:?}: e = {measured_e}, v_t' = {} m/s, ω' = {} rad/s",
            v[0], w[1]
        );
        assert!(
            (measured_e / e - 1.0).abs() < 5e-7,
            "{kind:?} {scheme:?}: e = {measured_e}"
        );
        let vt_expected = vt - mu * (1.0 + e) * vn;
        let w_expected = 2.5 * mu * (1.0 + e) * vn / R;
        assert!(
            (v[0] / vt_expected - 1.0).abs() < 1e-6,
            "{kind:?} {scheme:?}: v_t' = {} m/s, closed form {vt_expected} m/s",
            v[0]
        );
        // Spin about +y for motion along +x on a floor below.
        assert!(
            (w[1] / w_expected - 1.0).abs() < 1e-6,
            "{kind:?} {scheme:?}: ω' = {} rad/s, closed form {w_expected} rad/s",
            w[1]
        );
        // With the measured e the relations are those of the impulses
        // (Σ F_t Δt = μ Σ F_n Δt step by step in gross sliding): round-off.
        // Verlet only: Gear5's velocity is not a sum of force × Δt.
        if scheme == Scheme::Verlet {
            let vt_impulse = vt - mu * (vn + v[2]);
            assert!(
                (v[0] - vt_impulse).abs() < 1e-12 * vt,
                "{kind:?} {scheme:?}"
            );
            let w_impulse = 2.5 * mu * (vn + v[2]) / R;
            assert!(
                (w[1] / w_impulse - 1.0).abs() < 1e-12,
                "{kind:?} {scheme:?}"
            );
        }
        assert_eq!(v[1], 0.0);
        assert_eq!(w[0], 0.0);
        assert_eq!(w[2], 0.0);
    }
}

#[test]
fn without_friction_spin_is_untouched_and_vt_unchanged() {
    let (vn, vt, e) = (0.5, 2.5, 0.8);
    for scheme in SCHEMES {
        // The rotation machinery on, μ = 0: no tangential force, exactly
        // (Gear5's predictor carries a constant v_t, the corrector adds 0).
        let sim = impact(vn, vt, e, Some((TangentialKind::Mindlin, 0.0, 0.0)), scheme);
        assert_eq!(sim.velocities()[0][0], vt, "{scheme:?}");
        assert_eq!(sim.angular_velocities()[0], [0.0; 3], "{scheme:?}");
        // No friction at all: the same normal motion, bit for bit.
        let plain = impact(vn, vt, e, None, scheme);
        assert_eq!(plain.velocities()[0], sim.velocities()[0], "{scheme:?}");
        assert_eq!(plain.angular_velocities()[0], [0.0; 3], "{scheme:?}");
    }
}

/// A sphere resting on the plane z = 0 under gravity tilted by θ (the
/// incline's frame: x down the slope), started at its static overlap.
fn incline(theta: f64, mu: f64, roll: f64, scheme: Scheme) -> (Simulation, f64) {
    let g = 9.81;
    // Δt = T_c/50 at the speed √(g R), ample for resting contacts.
    let dt = hertz_contact_time((g * R).sqrt()) / 50.0;
    let m = material();
    let e_eff = 4.0 / 3.0 / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus);
    let weight = m.sphere_mass(R) * g * theta.cos();
    let h0 = (weight / (e_eff * R.sqrt())).powf(2.0 / 3.0);
    let mut s = sphere_on_plane(
        [0.0, 0.0, R - h0],
        [0.0; 3],
        0.5,
        Some((TangentialKind::Mindlin, mu, roll)),
        scheme,
        dt,
    );
    s.gravity = [g * theta.sin(), 0.0, -g * theta.cos()];
    (Simulation::new(s, 1).unwrap(), dt)
}

#[test]
fn incline_sliding_accelerates_at_g_sin_minus_mu_cos() {
    for scheme in SCHEMES {
        let theta = 20f64.to_radians();
        // Sliding needs μ < (2/7) tan θ = 0.104.
        let mu = 0.05;
        let (mut sim, dt) = incline(theta, mu, 0.0, scheme);
        // Let the normal transient die (damped, e = 0.5) and the slip start.
        let settle = (0.05 / dt) as u64;
        sim.step(settle);
        let v1 = sim.velocities()[0][0];
        let t1 = sim.time();
        sim.step(settle);
        let v2 = sim.velocities()[0][0];
        let a = (v2 - v1) / (sim.time() - t1);
        let expected = 9.81 * (theta.sin() - mu * theta.cos());
        eprintln!("{scheme:?} sliding: a = {a} m/s², closed form {expected} m/s²");
        // In steady sliding F_t = μ F_n with F_n = m g cos θ to the decay of
        // the normal transient (e^(-50 periods)): the velocity change is exact
        // to round-off over the interval; 1e-6 is the bound.
        assert!(
            (a / expected - 1.0).abs() < 1e-6,
            "{scheme:?}: a = {a} m/s², closed form {expected} m/s²"
        );
        assert!(sim.velocities()[0][0] > 0.0);
    }
}

#[test]
fn incline_rolling_without_slip_accelerates_at_five_sevenths_g_sin() {
    for scheme in SCHEMES {
        let theta = 20f64.to_radians();
        // μ = 0.5 > tan θ = 0.364: no slip; a free sphere rolls.
        let (mut sim, dt) = incline(theta, 0.5, 0.0, scheme);
        let settle = (0.05 / dt) as u64;
        sim.step(settle);
        let (x1, v1, w1, t1) = (
            sim.positions()[0][0],
            sim.velocities()[0][0],
            sim.angular_velocities()[0][1],
            sim.time(),
        );
        let steps = (1.0 / dt).round() as u64;
        sim.step(steps);
        let span = sim.time() - t1;
        let (x2, v2, w2) = (
            sim.positions()[0][0],
            sim.velocities()[0][0],
            sim.angular_velocities()[0][1],
        );
        let a = (v2 - v1) / span;
        let expected = 5.0 / 7.0 * 9.81 * theta.sin();
        eprintln!("{scheme:?} rolling: a = {a} m/s², closed form {expected} m/s²");
        // The tangential spring holds a constant (2/7) m g sin θ once its
        // damped transient is gone: the centre's acceleration is the rolling
        // closed form to the transient's remains, 1e-6.
        assert!(
            (a / expected - 1.0).abs() < 1e-6,
            "{scheme:?}: a = {a} m/s², rolling closed form {expected} m/s²"
        );
        // Slip of the contact point over 1 s: Δx − R Δθ (θ the rotation
        // angle, ∫ω dt = (ω₁ + ω₂)/2 · span for constant angular acceleration).
        let slip = (x2 - x1) - R * 0.5 * (w1 + w2) * span;
        eprintln!("{scheme:?} rolling: contact-point slip {slip} m over {span} s");
        assert!(slip.abs() < 1e-9, "{scheme:?}: slip {slip} m over {span} s");
    }
}

#[test]
fn incline_with_friction_and_rolling_resistance_above_tan_theta_holds() {
    for scheme in SCHEMES {
        let theta = 20f64.to_radians();
        let (mut sim, dt) = incline(theta, 0.5, 0.5, scheme);
        sim.step((0.05 / dt) as u64);
        let x1 = sim.positions()[0];
        let t1 = sim.time();
        sim.step((1.0 / dt).round() as u64);
        let x2 = sim.positions()[0];
        let d =
            ((x2[0] - x1[0]).powi(2) + (x2[1] - x1[1]).powi(2) + (x2[2] - x1[2]).powi(2)).sqrt();
        eprintln!(
            "{scheme:?} held: displacement {d} m over {} s",
            sim.time() - t1
        );
        assert!(
            d < 1e-9,
            "{scheme:?}: moved {d} m in {} s (spin {:?} rad/s)",
            sim.time() - t1,
            sim.angular_velocities()[0]
        );
    }
}
