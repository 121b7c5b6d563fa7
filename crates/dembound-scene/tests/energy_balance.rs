//! The energy balance with the dissipation summed contact by contact
//! (`output.dissipation`, `pipeline::dissipation`) on closed forms with
//! friction and moving walls (issue 27's energy balance): a sphere sliding
//! to rolling on a fixed plane, a sphere set rolling by a conveyor plate,
//! and a damped frictional sphere bouncing in a turning drum. Each case
//! checks D_c against its closed form where one exists, and that the
//! balance error D − D_c falls as a power of Δt (an integration error,
//! not a missing or biased term).

mod common;

use common::grain;
use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_physics::material::Material;
use dembound_scene::setup::{
    Cylinder, DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, Scheme, SphereInit,
    TimeStep, WallSetup,
};
use dembound_scene::walls::motion::WallMotion;
use dembound_scene::{SceneSetup, Simulation};

const G: f64 = 9.81;
const R: f64 = 1.0e-3;
const E: f64 = 1.0e9;
const MU: f64 = 0.5;

fn material() -> Material {
    grain(E)
}

fn mass() -> f64 {
    material().sphere_mass(R)
}

/// The code's sphere–plane modulus of one material, E_eff = (4/3) E* with
/// 1/E* = 2 (1 − ν²)/E (`material::effective_modulus`), written out.
fn e_eff() -> f64 {
    let m = material();
    4.0 / 3.0 / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio) / m.youngs_modulus)
}

/// A Hertz + Tsuji (e = 0.5) scene with Mindlin friction μ on everything,
/// gravity −g z, `output.dissipation` on.
fn scene(half_width: f64, scheme: Scheme, dt: f64) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-half_width, -half_width, -half_width],
            upper: [half_width, half_width, half_width],
            periodic: [false; 3],
        },
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        ),
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.integration.scheme = scheme;
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: material(),
    });
    s.gravity = [0.0, 0.0, -G];
    s.friction = Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: MU,
        rolling_friction: 0.0,
    }));
    s.dissipation = true;
    s
}

fn sphere(position: [f64; 3], velocity: [f64; 3]) -> SphereInit {
    SphereInit {
        position,
        velocity,
        radius: R,
        material: 0,
        fixed: false,
        group: None,
    }
}

/// The height of a sphere's centre at rest on the plane z = 0:
/// m g = E_eff √R δ^{3/2}.
fn resting_height() -> f64 {
    R - (mass() * G / (e_eff() * R.sqrt())).powf(2.0 / 3.0)
}

fn floor() -> WallSetup {
    WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    })
}

fn translation(v: [f64; 3]) -> WallMotion {
    WallMotion {
        velocity: v,
        angular_velocity: [0.0; 3],
        center: [0.0; 3],
        start: 0.0,
        end: f64::INFINITY,
        oscillation: None,
    }
}

/// Runs `steps` and returns (D_c, the balance error D − D_c), J.
fn run(s: SceneSetup, steps: u64) -> (f64, f64) {
    let mut sim = Simulation::new(s, 1).unwrap();
    sim.step(steps);
    let o = sim.observe();
    let dc = o.dissipated_by_contacts.expect("dissipation is on");
    (dc, o.dissipated_energy - dc)
}

/// A sphere at rest on a fixed plane (at its equilibrium overlap) thrown
/// along x at v₀, or at rest on a plate that starts moving at v₀: the
/// Coulomb force μ m g at the contact point keeps m R v + I ω about the
/// contact line, so the sphere rolls once v = 5v₀/7 (fixed plane) or
/// 2v₀/7 (plate), at t* = 2v₀/(7 μ g) either way. (D_c, balance error), J,
/// after 3 t*.
fn slide_to_roll(plate: bool, scheme: Scheme, dt: f64) -> (f64, f64) {
    let v0 = 0.1;
    let mut s = scene(0.02, scheme, dt);
    // The box's top 4R above the plane, not 2 cm: the step bound takes the
    // fastest approach from a fall through the box's height, √(2 g H), and
    // at 2 µs a 4 cm box puts Gear5's damped bound
    // (`setup_checks::check_damped_gear5`) at 1.006 for a sphere that
    // never falls (at 2.4 cm: 0.93).
    s.domain.upper[2] = 4.0 * R;
    let v = if plate { [0.0; 3] } else { [v0, 0.0, 0.0] };
    // Starts 5 mm back so that 3 t* of sliding and rolling stay on the plane.
    s.spheres.push(sphere([-5e-3, 0.0, resting_height()], v));
    s.walls.push(floor());
    if plate {
        s.wall_motions = vec![Some(translation([v0, 0.0, 0.0]))];
    }
    let t_star = 2.0 * v0 / (7.0 * MU * G);
    run(s, (3.0 * t_star / dt).ceil() as u64)
}

/// The kinetic energy the slide takes out: on the fixed plane ½ m v₀² −
/// ½ m v² − ½ I ω² with v = 5v₀/7, ω = v/R, I = 2/5 m R²: ½ m v₀² (1 −
/// 25/49 · 7/5) = m v₀²/7. On the plate the sphere ends at v = 2v₀/7 with
/// R ω = 5v₀/7 (its contact point moves with the plate), kinetic energy
/// ½ m v₀² (4/49 + 2/5 · 25/49) = m v₀²/7, and the plate's work is μ m g
/// v₀ t* = 2/7 m v₀²: it dissipates m v₀²/7 too (the plate's frame is the
/// fixed plane's case, Galilean invariance).
///
/// What else the closed form leaves out: at the stick the tangential
/// spring holds at most μ F_n/k_t of stretch, energy ½ μ² F_n²/k_t (k_t =
/// 8 G* a ≈ 2.5e4 N/m here, F_n = m g ≈ 1e-4 N: ≈ 5e-14 J, 1e-8 of D),
/// and its ringing is damped by the same dashpot (in D_c either way). The
/// normal dashpot stays still (the sphere starts at its resting overlap).
/// The stick comes within a step of t*: a lag of ≤ Δt of sliding,
/// μ m g v₀ Δt ≈ 5e-13 J at Δt = 1 µs, 4e-7 of D. Held to 1e-5.
fn closed_form() -> f64 {
    let v0: f64 = 0.1;
    mass() * v0 * v0 / 7.0
}

fn check_slide(plate: bool, scheme: Scheme) {
    let exact = closed_form();
    let mut errors = Vec::new();
    for dt in [2e-6, 1e-6, 5e-7] {
        let (dc, error) = slide_to_roll(plate, scheme, dt);
        println!(
            "{scheme:?} plate {plate} dt {dt:e}: D_c/closed − 1 = {:.2e}, (D − D_c)/D = {:.2e}",
            dc / exact - 1.0,
            error / exact
        );
        assert!(
            (dc - exact).abs() <= 1e-5 * exact,
            "dt {dt}: {dc} vs {exact}"
        );
        errors.push(error.abs() / exact);
    }
    // The balance error is the spring's and the stick's integration error
    // only: below 1e-6 of D here, and not growing as Δt falls (a missing
    // term would stay put or grow with the run's step count).
    assert!(errors.iter().all(|&e| e < 1e-6), "{errors:?}");
}

#[test]
fn a_sphere_sliding_on_a_plane_dissipates_a_seventh_of_m_v0_squared_verlet() {
    check_slide(false, Scheme::Verlet);
}

#[test]
fn a_sphere_sliding_on_a_plane_dissipates_a_seventh_of_m_v0_squared_gear5() {
    check_slide(false, Scheme::Gear5);
}

#[test]
fn a_conveyor_plate_dissipates_a_seventh_of_m_v_squared_verlet() {
    check_slide(true, Scheme::Verlet);
}

#[test]
fn a_conveyor_plate_dissipates_a_seventh_of_m_v_squared_gear5() {
    check_slide(true, Scheme::Gear5);
}

/// A damped frictional sphere thrown down at 0.3 m/s from 2R beside the
/// axis of a drum (cylinder of radius 10 R about y) turning at 20 rad/s
/// (its wall at 0.2 m/s): it meets the wall at t = 22.05 ms (z(t) = −0.3 t
/// − g t²/2 = −9 R), slides on it while the wall drags it along, and
/// leaves it (the contact lasts ≈ 10 µs); the run stops at 25 ms, in the
/// free flight after the first bounce, so that every Δt runs the same
/// single contact. (D_c, balance error, W), J.
fn drum_bounce(scheme: Scheme, dt: f64) -> (f64, f64, f64) {
    let rc = 10.0 * R;
    let mut s = scene(0.02, scheme, dt);
    s.spheres
        .push(sphere([2.0 * R, 0.0, 0.0], [0.0, 0.0, -0.3]));
    s.walls.push(WallSetup::Cylinder(Cylinder {
        point: [0.0; 3],
        axis: [0.0, 1.0, 0.0],
        radius: rc,
        inside: true,
        length: None,
        material: 0,
    }));
    s.wall_motions = vec![Some(WallMotion {
        angular_velocity: [0.0, 20.0, 0.0],
        ..translation([0.0; 3])
    })];
    let mut sim = Simulation::new(s, 1).unwrap();
    sim.step((0.025 / dt).round() as u64);
    let o = sim.observe();
    assert_eq!(o.wall_contacts, 0, "in flight after the bounce");
    let dc = o.dissipated_by_contacts.expect("dissipation is on");
    (
        dc,
        o.dissipated_energy - dc,
        o.work_by_walls.expect("a moving wall"),
    )
}

/// Verlet: halving Δt divides the balance error by ≥ 3 (second order is
/// 4×; measured 6.04e-3, 1.65e-3, 3.75e-4 of W at Δt = 0.4, 0.2, 0.1 µs):
/// integration error, nothing missing. (Gear5 on the same bounce gives
/// 8.2e-2, 1.07e-2, −1.61e-2 of W, not falling: its trapezoid of the
/// corrected states' powers at a contact's onset and end is not settled;
/// not asserted.)
#[test]
fn a_sphere_in_a_turning_drum_closes_the_balance_as_dt_falls_verlet() {
    drum_errors(Scheme::Verlet);
}

fn drum_errors(scheme: Scheme) {
    let mut errors = Vec::new();
    for dt in [4e-7, 2e-7, 1e-7] {
        let (dc, error, work) = drum_bounce(scheme, dt);
        println!(
            "dt {dt:e}: D_c {dc:.6e} J, W {work:.6e} J, (D − D_c)/W = {:.2e}",
            error / work
        );
        errors.push(error.abs() / work);
    }
    assert!(
        errors[0] > 3.0 * errors[1] && errors[1] > 3.0 * errors[2],
        "{errors:?}"
    );
}

/// The frictional bed of `friction_bed.rs` (6 × 6 × 4 spheres falling
/// onto the floor, Hertz + Tsuji e = 0.3, Mindlin μ = 0.5 with the
/// tangential dashpot, rolling resistance μ_r = 0.05) with its floor
/// moving along x at 1 cm/s (`moving`), `steps` at Δt: (D_c, D, W).
fn bed(scheme: Scheme, dt: f64, steps: u64, threads: usize) -> (f64, f64, Option<f64>) {
    let mut s = common::frictional_bed(6, 4, dt);
    s.integration.scheme = scheme;
    s.dissipation = true;
    // Wall 4 is the floor (lattice_drop: −x, +x, −y, +y, −z, +z).
    s.wall_motions = vec![
        None,
        None,
        None,
        None,
        Some(translation([0.01, 0.0, 0.0])),
        None,
    ];
    let mut sim = Simulation::new(s, threads).unwrap();
    sim.step(steps);
    let o = sim.observe();
    let dc = o.dissipated_by_contacts.expect("dissipation is on");
    (dc, o.dissipated_energy, o.work_by_walls)
}

/// A bed landing on a conveyor floor with sliding, rolling resistance at
/// its limit and tangential dashpots: the balance error falls as Δt²
/// (Verlet, 8 ms). Before the tangential work was taken from the applied
/// forces (a spring cut to its Coulomb or rolling limit re-read as
/// sticking gained its dashpot), it was −20 % of D at Δt = 2 µs and did
/// not fall with Δt.
#[test]
fn a_bed_with_rolling_resistance_on_a_conveyor_closes_the_balance_as_dt_falls() {
    let mut errors = Vec::new();
    for (dt, steps) in [(2e-6, 4000), (1e-6, 8000)] {
        let (dc, d, _) = bed(Scheme::Verlet, dt, steps, 1);
        println!(
            "dt {dt:e}: D_c {dc:.6e} J, (D − D_c)/D {:.2e}",
            (d - dc) / d
        );
        errors.push(((d - dc) / d).abs());
    }
    // Second order is 4× (measured 5.1e-4 → 1.2e-4 of D).
    assert!(errors[0] > 3.0 * errors[1], "{errors:?}");
    assert!(errors[0] < 2e-3, "{errors:?}");
}

/// D_c sums per body in body order, each body's contacts in list order:
/// the same bits on 1 and 2 threads (Verlet 8 ms at 2 µs; Gear5 3 ms at
/// 1 µs: its closed-form bound on the damped contact, `setup_checks::
/// check_damped_gear5`, allows at most 1.10 µs on this bed).
#[test]
fn dissipation_has_the_same_bits_on_one_and_two_threads() {
    for (scheme, dt, steps) in [(Scheme::Verlet, 2e-6, 4000), (Scheme::Gear5, 1e-6, 3000)] {
        let bits = |threads| {
            let (dc, d, w) = bed(scheme, dt, steps, threads);
            assert!(dc > 0.0 && dc.is_finite(), "{scheme:?}: D_c {dc}");
            [dc.to_bits(), d.to_bits(), w.unwrap_or(f64::NAN).to_bits()]
        };
        assert_eq!(bits(1), bits(2), "{scheme:?}");
    }
}
