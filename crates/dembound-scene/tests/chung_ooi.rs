//! Chung & Ooi (2011), Granular Matter 13, 643, Test 4: oblique impacts of
//! an aluminium-oxide sphere (R = 2.5 mm, ρ = 4000 kg/m³, E = 380 GPa,
//! ν = 0.23) at 3.9 m/s on a plane of the same material, μ = 0.092,
//! e = 0.98, over incidence angles θ (from the normal): the tangential
//! restitution of the contact point, e_t = (v_t' − R ω')/v_t, and the
//! rebound spin ω' against θ, with the Hertz–Mindlin no-slip model.
//!
//! The reference is derived two ways, independently of the engine:
//! - Thornton's analytical limit (Wu, Thornton & Li 2003; Maw, Barber &
//!   Fawcett 1976): for tan θ > (7/2) μ (1 + e) the contact slides
//!   throughout, ω' = (5/2) μ (1 + e) v_n/R and
//!   e_t = 1 − (7/2) μ (1 + e)/tan θ, exactly.
//! - Over the whole range (sticking at small angles, where the tangential
//!   spring makes e_t negative), the same model integrated here in its
//!   continuous form by classical RK4 at Δt = T_c/20,000 (state: overlap,
//!   normal and tangential velocity, spin, tangential displacement δ with
//!   dδ/dt = slip velocity, cut back to μ|F_n|/k_t when the spring exceeds
//!   the Coulomb limit, LIGGGHTS's rule), written from the formulas below
//!   without the engine or the physics crate: F_n = k h^(3/2) + γ h^(1/4) ḣ
//!   (k = E_eff √R, E_eff = (4/3) E/(2(1 − ν²)), γ = √5 ξ √(k m),
//!   ξ = −ln e/√(π² + ln² e), LIGGGHTS's mapping; F_n ≥ 0, the clamp,
//!   so that the normal impulse is ∫|F_n| dt, which the sliding limit
//!   assumes), k_t = 8 G* √(R h) (G* = E/(2(1+ν))/(2(2 − ν))), tangential
//!   damping η_t = 2 √(5/6) ξ √(k_t m).
//!
//! **The Coulomb boundary with a dashpot** (the 1.4e-3 gap of session 4,
//! found in session 5). While the contact unloads, μ F_n can fall faster
//! than the spring relaxes, so the spring rides on the limit, cut back at
//! every instant. The engine (LIGGGHTS `tangential_model_history`) moves
//! the spring by the slip first and then compares, so there it slides:
//! F_t = μ F_n, no dashpot. A reference that cuts δ after each step and
//! then tests the cut spring with `k_t |δ| > μ F_n` finds equality, calls
//! it sticking and adds −η_t v_slip (capped): a different selection on the
//! boundary of the same differential inclusion. The two agree exactly
//! without damping (e = 1: 1e-8 at every angle) and differ by 1.3e-3 in e_t
//! at 5° and 2.9e-4 at 30° with e = 0.98, both converged; the trace at 5°
//! parts at 78 % of the contact, where the spring first meets the falling
//! limit. The reference now takes the engine's selection in its continuous
//! form: on the boundary it slides while d(k_t |δ|)/dt > d(μ F_n)/dt under
//! dδ/dt = v_slip, with dF_n/dt = (3/2) k h^(1/2) ḣ + γ (ḣ²/(4 h^(3/4)) +
//! h^(1/4) ḧ) and dk_t/dt = 4 G* √R ḣ/√h. Neither selection is "the"
//! Mindlin theory, which has no dashpot: this is LIGGGHTS's (and EDEM's)
//! damped Hertz–Mindlin, the model the engine claims.

mod common;

use dembound_physics::contact::tangential::TangentialKind;
use dembound_physics::contact::{
    Calibration, ContactModel, Damping, DampingKind, Dissipation, NormalLaw,
};
use dembound_physics::material::Material;
use dembound_scene::setup::Scheme;
use dembound_scene::Simulation;
use std::f64::consts::PI;

const R: f64 = 2.5e-3;
const RHO: f64 = 4000.0;
const E: f64 = 380.0e9;
const NU: f64 = 0.23;
const MU: f64 = 0.092;
const REST: f64 = 0.98;
const SPEED: f64 = 3.9;

fn mass() -> f64 {
    4.0 / 3.0 * PI * RHO * R * R * R
}

fn e_eff() -> f64 {
    4.0 / 3.0 * E / (2.0 * (1.0 - NU * NU))
}

fn xi() -> f64 {
    let l = REST.ln();
    -l / (PI * PI + l * l).sqrt()
}

/// Hertz contact time at the normal speed v (eqs 29–30).
fn contact_time(v: f64) -> f64 {
    let k = e_eff() * R.sqrt();
    let h_max = (1.25 * mass() * v * v / k).powf(0.4);
    2.943_275_184_3 * h_max / v
}

/// (v_n', v_t', ω') from the independent RK4 integration.
fn reference(theta: f64) -> (f64, f64, f64) {
    let m = mass();
    let inertia = 0.4 * m * R * R;
    let k = e_eff() * R.sqrt();
    let gamma = 5f64.sqrt() * xi() * (k * m).sqrt();
    let g_star = E / (2.0 * (1.0 + NU)) / (2.0 * (2.0 - NU));
    let vn0 = SPEED * theta.cos();
    let vt0 = SPEED * theta.sin();
    // Converged: T_c/200,000 changes e_t by < 1e-6 (measured, 7e-7 at 5°).
    let dt = contact_time(vn0) / 20_000.0;
    // y = [h, ḣ, v_t, ω, δ]; ḣ > 0 approaching.
    let forces = |y: [f64; 5]| -> (f64, f64, f64) {
        let h = y[0].max(0.0);
        let fn_ = (k * h * h.sqrt() + gamma * h.sqrt().sqrt() * y[1]).max(0.0);
        let kt = 8.0 * g_star * (R * h).sqrt();
        let slip = y[2] - R * y[3];
        let limit = MU * fn_.abs();
        let mut delta = y[4];
        // On the Coulomb boundary (the spring was cut to it after the last
        // step), sliding goes on if the spring would outgrow the limit
        // under sticking, d(k_t |δ|)/dt > d(μ F_n)/dt with dδ/dt = slip:
        // the continuous form of the engine's (LIGGGHTS's) order, which
        // moves the spring by the slip first and then compares. Testing
        // the cut spring alone (`>`) would call it sticking and add the
        // dashpot there (module doc).
        let on_boundary = delta != 0.0 && h > 0.0 && kt * delta.abs() >= limit * (1.0 - 1e-12);
        let outgrows = on_boundary && {
            let rate_n = y[1];
            let elastic_damped = k * h * h.sqrt() + gamma * h.sqrt().sqrt() * rate_n;
            let limit_rate = if elastic_damped > 0.0 {
                let accel_n = -elastic_damped / m;
                MU * (1.5 * k * h.sqrt() * rate_n
                    + gamma * (0.25 * rate_n * rate_n / h.powf(0.75) + h.sqrt().sqrt() * accel_n))
            } else {
                0.0
            };
            let kt_rate = 4.0 * g_star * R.sqrt() * rate_n / h.sqrt();
            kt_rate * delta.abs() + kt * delta.signum() * slip > limit_rate
        };
        let ft = if kt * delta.abs() > limit || outgrows {
            delta = delta.signum() * limit / kt;
            -kt * delta
        } else {
            let eta = 2.0 * (5.0f64 / 6.0).sqrt() * xi() * (kt * m).sqrt();
            (-kt * delta - eta * slip).clamp(-limit, limit)
        };
        (fn_, ft, slip)
    };
    let rate = |y: [f64; 5]| -> [f64; 5] {
        let (fn_, ft, slip) = forces(y);
        [y[1], -fn_ / m, ft / m, -R * ft / inertia, slip]
    };
    let mut y = [0.0, vn0, vt0, 0.0, 0.0];
    loop {
        let k1 = rate(y);
        let at = |k: [f64; 5], s: f64| {
            let mut z = y;
            for i in 0..5 {
                z[i] += s * k[i];
            }
            z
        };
        let k2 = rate(at(k1, 0.5 * dt));
        let k3 = rate(at(k2, 0.5 * dt));
        let k4 = rate(at(k3, dt));
        for i in 0..5 {
            y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        // The spring cut back to the Coulomb limit after the step.
        let h = y[0].max(0.0);
        let kt = 8.0 * g_star * (R * h).sqrt();
        let fn_ = (k * h * h.sqrt() + gamma * h.sqrt().sqrt() * y[1]).max(0.0);
        if kt * y[4].abs() > MU * fn_.abs() {
            y[4] = y[4].signum() * MU * fn_.abs() / kt;
        }
        if y[0] < 0.0 && y[1] < 0.0 {
            return (-y[1], y[2], y[3]);
        }
    }
}

/// (v_n', v_t', ω') from the engine at Δt = T_c/`per_contact`.
fn engine(theta: f64, per_contact: f64) -> (f64, f64, f64) {
    let vn = SPEED * theta.cos();
    let vt = SPEED * theta.sin();
    let dt = contact_time(vn) / per_contact;
    let model = ContactModel {
        calibration: Calibration::Formula,
        attractive: false,
        ..ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(REST)),
        )
    };
    let s = common::sphere_on_plane(
        R,
        Material {
            density: RHO,
            youngs_modulus: E,
            poisson_ratio: NU,
        },
        [0.0, 0.0, R + 3.0 * dt * vn],
        [vt, 0.0, -vn],
        model,
        Some((TangentialKind::Mindlin, MU, 0.0)),
        Scheme::Verlet,
        dt,
    );
    let mut sim = Simulation::new(s, 1).unwrap();
    sim.step((1.5 * per_contact) as u64 + 10);
    let v = sim.velocities()[0];
    let w = sim.angular_velocities()[0];
    (v[2], v[0], w[1])
}

fn tangential_restitution(vt0: f64, vt: f64, w: f64) -> f64 {
    (vt - R * w) / vt0
}

#[test]
fn test4_against_the_independent_integration_and_the_sliding_limit() {
    println!("theta_deg,e_t_engine,e_t_reference,omega_engine_rad_s,omega_reference_rad_s");
    let mut worst_et = 0.0f64;
    let mut worst_w = 0.0f64;
    for deg in [
        2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 60.0, 70.0, 80.0,
    ] {
        let theta = f64::to_radians(deg);
        let vt0 = SPEED * theta.sin();
        let (rn, rt, rw) = reference(theta);
        let (en, et, ew) = engine(theta, 100_000.0);
        let et_ref = tangential_restitution(vt0, rt, rw);
        let et_eng = tangential_restitution(vt0, et, ew);
        println!("{deg},{et_eng},{et_ref},{ew},{rw}");
        // Normal restitution: both near e (LIGGGHTS's β is exact only for
        // the linear spring: ±2 % for Hertz).
        assert!((rn / (SPEED * theta.cos()) - REST).abs() < 0.02);
        assert!(
            (en / rn - 1.0).abs() < 1e-3,
            "{deg}°: v_n' {en} vs {rn} m/s"
        );
        worst_et = worst_et.max((et_eng - et_ref).abs());
        worst_w = worst_w.max(R * (ew - rw).abs() / vt0);
        // Gross sliding (tan θ > 3.5 μ (1 + e) = 0.638, θ > 32.5°, with a
        // margin for the spring's build-up): the analytical limit, with the
        // run's own normal restitution; the engine transmits exactly μ F_n
        // at every step of sliding, so round-off: 1e-6 is the bound.
        if deg >= 40.0 {
            let e_run = en / (SPEED * theta.cos());
            let vn = SPEED * theta.cos();
            let w_limit = 2.5 * MU * (1.0 + e_run) * vn / R;
            assert!(
                (ew / w_limit - 1.0).abs() < 1e-6,
                "{deg}°: ω' {ew} vs {w_limit}"
            );
            let et_limit = 1.0 - 3.5 * MU * (1.0 + e_run) / theta.tan();
            assert!(
                (et_eng - et_limit).abs() < 1e-6,
                "{deg}°: e_t {et_eng} vs {et_limit}"
            );
        }
    }
    // The engine at Δt = T_c/100,000 against the reference, 1e-6 of the
    // incident tangential speed, the bound, on e_t and on R ω'.
    // Measured: |Δe_t| ≤ 4.8e-7 (2°), R |Δω'|/v_t ≤ 3.4e-7. What is left is
    // the engine's time step: it converges at first order (the dashpots
    // see the half-step velocity, and η_t ∝ h^(1/4) has an unbounded slope
    // at the onset), e_t at 5° moving by 6.9e-5 from T_c/2000 to /20,000,
    // 5e-6 from there to /100,000, and /200,000 is 3.7e-7 from /4,000,000;
    // the reference moves by 7e-7 from T_c/20,000 to /200,000.
    println!("worst |Δe_t| = {worst_et:e}, worst R|Δω'|/v_t = {worst_w:e}");
    assert!(worst_et < 1e-6, "{worst_et}");
    assert!(worst_w < 1e-6, "{worst_w}");
}
