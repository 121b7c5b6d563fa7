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

use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{
    Calibration, ContactModel, Damping, DampingKind, Dissipation, NormalLaw,
};
use dembound_physics::material::Material;
use dembound_scene::setup::{
    DomainSetup, FrictionSetup, NamedMaterial, RunLength, SphereInit, TimeStep, WallSetup,
};
use dembound_scene::{SceneSetup, Simulation};
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
    // Converged: T_c/200,000 changes e_t by < 2e-6 (measured).
    let dt = contact_time(vn0) / 20_000.0;
    // y = [h, ḣ, v_t, ω, δ]; ḣ > 0 approaching.
    let forces = |y: [f64; 5]| -> (f64, f64, f64) {
        let h = y[0].max(0.0);
        let fn_ = (k * h * h.sqrt() + gamma * h.sqrt().sqrt() * y[1]).max(0.0);
        let kt = 8.0 * g_star * (R * h).sqrt();
        let slip = y[2] - R * y[3];
        let limit = MU * fn_.abs();
        let mut delta = y[4];
        let ft = if kt * delta.abs() > limit {
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
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-1.0, -1.0, -0.01],
            upper: [1.0, 1.0, 1.0],
            periodic: [false; 3],
        },
        model,
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "alumina".into(),
        material: Material {
            density: RHO,
            youngs_modulus: E,
            poisson_ratio: NU,
        },
    });
    s.spheres.push(SphereInit {
        position: [0.0, 0.0, R + 3.0 * dt * vn],
        velocity: [vt, 0.0, -vn],
        radius: R,
        material: 0,
        fixed: false,
        group: None,
    });
    s.walls.push(WallSetup::Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    });
    s.friction = Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: MU,
        rolling_friction: 0.0,
    }));
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
        let (en, et, ew) = engine(theta, 2000.0);
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
        worst_w = worst_w.max((ew - rw).abs() / rw.abs());
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
    // The engine at Δt = T_c/2000 against the reference. Measured: the
    // engine converges (T_c/2000 → T_c/10,000 moves e_t by < 7e-5 except
    // at 2°, 7e-6 there) but not quite onto the reference where sticking
    // and sliding alternate: |Δe_t| = 1.3e-3 at 5°, 2.9e-4 at 30°, 2e-5
    // elsewhere; Δω'/ω' = 7.6e-3 at 5°, 2.6e-4 at 30°. The cause is not
    // found (doubtful: the order of the Coulomb cut within the step); the
    // bounds below are those measurements with a margin of 1.5.
    println!("worst |Δe_t| = {worst_et:e}, worst relative Δω' = {worst_w:e}");
    assert!(worst_et < 2e-3, "{worst_et}");
    assert!(worst_w < 1.2e-2, "{worst_w}");
}
