//! The analytic cylinder wall (issue 25): a sphere rolling in a tube, a
//! radial impact against the curvature model's exact single contact, a
//! Janssen bed in a vertical tube.

mod common;

use common::grain;
use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{
    ContactHistory, ContactModel, Damping, DampingKind, Dissipation, NormalLaw, PairLaw,
};
use dembound_physics::material::{effective_modulus, PairProperties};
use dembound_scene::setup::{
    Cylinder, DomainSetup, FrictionSetup, NamedMaterial, Plane, RunLength, SphereInit, TimeStep,
    WallSetup,
};
use dembound_scene::{Partner, SceneSetup, Simulation};

const G: f64 = 9.81;

fn scene(lower: [f64; 3], upper: [f64; 3], contact: ContactModel, dt: f64, e: f64) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower,
            upper,
            periodic: [false; 3],
        },
        contact,
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: grain(e),
    });
    s
}

fn sphere(position: [f64; 3], velocity: [f64; 3], radius: f64) -> SphereInit {
    SphereInit {
        position,
        velocity,
        radius,
        material: 0,
        fixed: false,
        group: None,
    }
}

fn friction(mu: f64, mu_r: f64) -> Option<FrictionSetup> {
    Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: mu,
        rolling_friction: mu_r,
    }))
}

/// A sphere rolling without slip on the inside of a horizontal tube
/// (axis x, gravity −z) is a pendulum of length R_c − R with the rolling
/// sphere's inertia: ω² = 5 g/(7 (R_c − R)) for small amplitude.
///
/// Tolerance 1e-3 on the period. The measured period differs from the
/// formula by: the finite amplitude, T(θ0)/T(0) − 1 = θ0²/16 = 2.5e-5 at
/// θ0 = 0.02 rad; the Hertz sinking of the centre, δ/(R_c − R) ≈ 5e-6
/// (δ ≈ 4e-8 m at E = 1e9 Pa); the tangential spring's compliance,
/// (ω/ω_t)² ≈ (30/1.5e4)² ≈ 4e-6; the zero-crossing interpolation and
/// Verlet at Δt = 2 µs (≈ 1e5 steps per period), < 1e-6. All well inside
/// 1e-3, which a flat-wall (no rolling) or sliding pendulum (ω² = g/L,
/// 40 % off) would fail.
#[test]
fn sphere_rolling_in_a_tube_oscillates_at_the_rolling_pendulum_frequency() {
    let (r, rc, e): (f64, f64, f64) = (2.0e-3, 1.0e-2, 1.0e9);
    let theta0: f64 = 0.02;
    let contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
    );
    let mut s = scene([-0.02; 3], [0.02; 3], contact, 2.0e-6, e);
    s.gravity = [0.0, 0.0, -G];
    s.friction = friction(1.0, 0.0);
    // The Hertz overlap that carries the sphere's weight there: F = E_eff
    // √R_eff δ^{3/2} (E_eff with the 4/3, R_eff = R R_c/(R_c − R)).
    let m = grain(e);
    let mass = m.density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let r_eff = r * rc / (rc - r);
    let load = mass * G * theta0.cos();
    let delta = (load / (effective_modulus(&m, &m) * r_eff.sqrt())).powf(2.0 / 3.0);
    let arm = rc - r + delta;
    s.spheres.push(sphere(
        [0.0, arm * theta0.sin(), -arm * theta0.cos()],
        [0.0; 3],
        r,
    ));
    s.walls.push(WallSetup::Cylinder(Cylinder {
        point: [0.0; 3],
        axis: [1.0, 0.0, 0.0],
        radius: rc,
        inside: true,
        length: None,
        material: 0,
    }));
    let mut sim = Simulation::new(s, 1).unwrap();
    let omega = (5.0 * G / (7.0 * (rc - r))).sqrt();
    let period = 2.0 * std::f64::consts::PI / omega;
    let dt = sim.dt();
    // Upward zero crossings of the angle, interpolated in the step.
    let angle = |sim: &Simulation| {
        let x = sim.positions()[0];
        x[1].atan2(-x[2])
    };
    let mut crossings = Vec::new();
    let mut last = angle(&sim);
    let steps = (4.5 * period / dt) as u64;
    for k in 1..=steps {
        sim.step(1);
        let now = angle(&sim);
        if last < 0.0 && now >= 0.0 {
            crossings.push((k as f64 - 1.0 + last / (last - now)) * dt);
        }
        last = now;
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let n = crossings.len() - 1;
    let measured = (crossings[n] - crossings[0]) / n as f64;
    let error = measured / period - 1.0;
    println!(
        "rolling in a tube: period {measured:.9} s, 2π/ω = {period:.9} s, relative {error:.2e}"
    );
    assert!(error.abs() < 1e-3, "{measured} vs {period}: {error:e}");
    // It rolled: the contact point (R along the radius from the axis
    // through the centre) is at rest, v + ω × (R e) = 0, to 1e-3 of the
    // largest speed ω θ0 (R_c − R).
    let (x, v, w) = (
        sim.positions()[0],
        sim.velocities()[0],
        sim.angular_velocities()[0],
    );
    let rho = (x[1] * x[1] + x[2] * x[2]).sqrt();
    let arm = [0.0, r * x[1] / rho, r * x[2] / rho];
    let slip = [
        v[0] + w[1] * arm[2] - w[2] * arm[1],
        v[1] + w[2] * arm[0] - w[0] * arm[2],
        v[2] + w[0] * arm[1] - w[1] * arm[0],
    ];
    let slip = (slip[0] * slip[0] + slip[1] * slip[1] + slip[2] * slip[2]).sqrt();
    let vmax = omega * theta0 * (rc - r);
    assert!(slip < 1e-3 * vmax, "slip {slip} m/s, v_max {vmax} m/s");
}

/// h(t) of one sphere–wall contact with normal law `law` from contact
/// onset at speed `v` (m/s), by RK4 at `steps` per estimated contact time:
/// (contact time s, rebound speed m/s). An integration independent of the
/// engine's (its own stepping, its own end detection).
fn exact_contact(law: &PairLaw, mass: f64, v: f64, steps: usize) -> (f64, f64) {
    let dt = law.contact_time_estimate(v) / steps as f64;
    let history = ContactHistory::default();
    let accel = |h: f64, rate: f64| {
        if h > 0.0 {
            law.force(h, rate, &history) / mass
        } else {
            0.0
        }
    };
    let (mut h, mut rate, mut t) = (0.0f64, v, 0.0f64);
    loop {
        let (k1h, k1r) = (rate, -accel(h, rate));
        let (k2h, k2r) = (
            rate + 0.5 * dt * k1r,
            -accel(h + 0.5 * dt * k1h, rate + 0.5 * dt * k1r),
        );
        let (k3h, k3r) = (
            rate + 0.5 * dt * k2r,
            -accel(h + 0.5 * dt * k2h, rate + 0.5 * dt * k2r),
        );
        let (k4h, k4r) = (rate + dt * k3r, -accel(h + dt * k3h, rate + dt * k3r));
        let h1 = h + dt / 6.0 * (k1h + 2.0 * k2h + 2.0 * k3h + k4h);
        let r1 = rate + dt / 6.0 * (k1r + 2.0 * k2r + 2.0 * k3r + k4r);
        if h1 <= 0.0 && t > 0.0 {
            // The end inside the step, by linear interpolation (error
            // O(Δt²) relative: ~1e-9 at 2·10⁴ steps).
            let s = h / (h - h1);
            return (t + s * dt, -(rate + s * (r1 - rate)));
        }
        (h, rate, t) = (h1, r1, t + dt);
    }
}

/// A sphere thrown radially at the inside of a tube (no gravity, no
/// friction) rebounds along the radius with the contact time and the
/// restitution of the curvature model's single contact: Hertz with
/// R_eff = R R_c/(R_c − R) (LAMMPS `wall/gran zcylinder`), E_eff of the
/// two materials, m_eff = m. Elastic: e = 1 and the closed-form time
/// 2.9432 δ_max/v (δ_max = (5 m v²/(4 E_eff √R_eff))^{2/5}); Tsuji-damped:
/// the model's restitution, against the RK4 integration of its force.
///
/// Tolerance 1e-4: the engine runs Verlet at Δt = t_c/2000 (error
/// ~(π/2000)² ≈ 2.5e-6 in e and t_c), the collision log locates onset and
/// end inside a step (exact here: no force outside contact); the RK4
/// reference at 2·10⁴ steps per contact is good to ~1e-10. The flat-wall
/// model (R_eff = R) gives a contact time 4.4 % longer: the test tells
/// the models apart.
#[test]
fn radial_impact_inside_a_tube_matches_the_curvature_models_single_contact() {
    let (r, rc, e, v): (f64, f64, f64, f64) = (2.0e-3, 1.0e-2, 1.0e7, 0.5);
    let m = grain(e);
    let mass = m.density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let r_eff = r * rc / (rc - r);
    let props = PairProperties {
        radius: r_eff,
        modulus: effective_modulus(&m, &m),
        mass,
    };
    for damping in [
        None,
        Some(Damping::new(
            DampingKind::Tsuji,
            Dissipation::Restitution(0.7),
        )),
    ] {
        let contact = match damping {
            None => ContactModel::elastic(NormalLaw::Hertz),
            Some(d) => ContactModel::damped(NormalLaw::Hertz, d),
        };
        let law = contact.pair(&props);
        let (t_exact, rebound_exact) = exact_contact(&law, mass, v, 20_000);
        if damping.is_none() {
            // The RK4 reference against the closed form (I = ∫₀¹ (1 −
            // x^{5/2})^{-1/2} dx = (2/5) B(2/5, 1/2) = 1.4716376...).
            let dmax = (5.0 * mass * v * v / (4.0 * props.modulus * r_eff.sqrt())).powf(0.4);
            let closed = 2.0 * 1.471_637_592_162_352 * dmax / v;
            assert!((t_exact / closed - 1.0).abs() < 1e-6, "{t_exact} {closed}");
            assert!((rebound_exact / v - 1.0).abs() < 1e-9);
        }
        let dt = t_exact / 2000.0;
        let mut s = scene([-0.02; 3], [0.02; 3], contact, dt, e);
        s.gravity = [0.0; 3];
        s.collisions = true;
        // From 1 mm short of the wall along +y (a radius), axis z.
        s.spheres
            .push(sphere([0.0, rc - r - 1e-3, 0.0], [0.0, v, 0.0], r));
        s.walls.push(WallSetup::Cylinder(Cylinder {
            point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            radius: rc,
            inside: true,
            length: None,
            material: 0,
        }));
        let mut sim = Simulation::new(s, 1).unwrap();
        let steps = ((2e-3 / v + 2.0 * t_exact) / dt) as u64;
        sim.step(steps);
        let log = sim.collisions();
        assert_eq!(log.len(), 1, "{log:?}");
        let c = log[0];
        assert_eq!(c.j, Partner::Wall(0));
        let restitution = c.rebound_normal_velocity / c.impact_normal_velocity;
        let e_exact = rebound_exact / v;
        println!(
            "radial impact ({}): contact {:.9e} s (exact {t_exact:.9e}), e = {restitution:.9} \
             (exact {e_exact:.9})",
            if damping.is_some() {
                "tsuji"
            } else {
                "elastic"
            },
            c.duration
        );
        assert!(
            (c.duration / t_exact - 1.0).abs() < 1e-4,
            "{} {t_exact}",
            c.duration
        );
        assert!(
            (restitution - e_exact).abs() < 1e-4,
            "{restitution} {e_exact}"
        );
        // The flat-wall contact lasts (R_eff/R)^{1/5} = 1.0456 times longer.
        assert!((c.duration / t_exact - 1.0).abs() < 0.1 * (1.25f64.powf(0.2) - 1.0));
        // Along the radius: no velocity across it.
        let vel = sim.velocities()[0];
        assert!(
            vel[0].abs() < 1e-12 * v && vel[2].abs() < 1e-12 * v,
            "{vel:?}"
        );
        assert!(vel[1] < 0.0);
    }
}

/// A bed in a vertical tube on a floor, with wall friction, settles: the
/// floor's and the tube's vertical forces carry the weight, N m g, and the
/// tube carries part of it (Janssen): the floor less than N m g.
///
/// Poured, not dropped as a block: layers 6 R apart land one after the
/// other, each pushing the bed below down along the wall, which then holds
/// it up. (A dense block dropped at once overshoots on the floor, springs
/// back and leaves the wall friction pulling the bed down, −0.09 N m g
/// here: both are static states; the history decides.) Smooth grains
/// (μ = 0.1), a rough tube (its own μ = 1, 0.32 against a grain).
///
/// The forces the walls applied (the weight minus the net force on the
/// bed, `Simulation::forces`, averaged over the window) carry N m g to
/// 1e-6 (measured 1e-8; the bed's momentum changes by ~1e-8 N m g over the
/// window; 4e-9 when written): the 1e-5.
///
/// The observed wall forces (`Observation::wall_forces`) are what the
/// force stage applied to the walls (`pipeline::wall_loads`): floor plus
/// tube carry N m g to 1e-5 (the tolerance), and they equal the
/// applied forces of the bed's balance above to 1e-9 N m g (the same
/// forces summed in another order, the pair forces cancelling to
/// round-off: ~1e-16 of the ~N m g pair loads per step). (They were
/// re-evaluated at the end-of-step velocities before: 1 − 1.06e-5 N m g,
/// 0.99762 with rolling friction.) The same with rolling friction
/// (μ_r = 0.2 on grains and tube), whose torques do not enter the forces
/// but whose springs change the history.
#[test]
fn bed_in_a_vertical_tube_carries_its_weight_on_floor_and_wall() {
    let (floor, tube, weight) = tube_bed(0.0);
    assert!(
        floor < weight && tube > 0.01 * weight,
        "{floor} {tube} {weight}"
    );
}

/// With rolling friction this pour ends with the tube pulling the bed
/// down (floor 1.43 N m g, tube −0.43 N m g: the static state depends on
/// the history, see above); floor and tube still carry N m g.
#[test]
fn bed_in_a_vertical_tube_with_rolling_friction_carries_its_weight() {
    tube_bed(0.2);
}

/// The Janssen bed with rolling friction `mu_r` on grains and tube,
/// settled, then averaged over a window: asserts the balances above;
/// returns the floor's and the tube's vertical loads and N m g, N.
fn tube_bed(mu_r: f64) -> (f64, f64, f64) {
    let (r, rc, e): (f64, f64, f64) = (1.0e-3, 6.0e-3, 1.0e7);
    let contact = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.05)),
    );
    let mut s = scene([-0.01, -0.01, 0.0], [0.01, 0.01, 0.16], contact, 5.0e-6, e);
    s.gravity = [0.0, 0.0, -G];
    // Smooth grains (μ = 0.1), a rough tube (its own μ = 1: 0.32 against
    // a grain, the geometric mean).
    s.friction = friction(0.1, mu_r).map(|mut f| {
        f.walls = vec![None, Some((1.0, mu_r))];
        f
    });
    // A loose column poured at once: sites 2.4 R apart across the tube,
    // layers 3 R apart, small deterministic offsets. The layers land one
    // after the other, each pushing the bed below down along the wall, so
    // that the wall's friction ends up holding the bed up. (A dense block
    // dropped as one springs back at the end and leaves the friction
    // pulling down: the static state depends on the history.)
    let mut rng = common::Rng(7);
    let spacing = 2.4 * r;
    let mut z = 1.5 * r;
    while s.spheres.len() < 300 {
        let mut layer = Vec::new();
        let reach = rc - 1.2 * r;
        let k = (reach / spacing).floor() as i64;
        for i in -k..=k {
            for j in -k..=k {
                let (x, y) = (i as f64 * spacing, j as f64 * spacing);
                if (x * x + y * y).sqrt() <= reach - 0.1 * r {
                    layer.push([
                        x + 0.05 * r * rng.symmetric(),
                        y + 0.05 * r * rng.symmetric(),
                        z,
                    ]);
                }
            }
        }
        for p in layer {
            if s.spheres.len() < 300 {
                s.spheres.push(sphere(p, [0.0; 3], r));
            }
        }
        z += 6.0 * r;
    }
    s.walls.push(WallSetup::Plane(Plane {
        point: [0.0; 3],
        normal: [0.0, 0.0, 1.0],
        material: 0,
    }));
    s.walls.push(WallSetup::Cylinder(Cylinder {
        point: [0.0, 0.0, 0.08],
        axis: [0.0, 0.0, 1.0],
        radius: rc,
        inside: true,
        length: None,
        material: 0,
    }));
    let n = s.spheres.len();
    let m = grain(e);
    let weight = n as f64 * m.density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * G;
    let mut sim = Simulation::new(s, 1).unwrap();
    // At rest: below 1e-12 J of kinetic energy (of ~10 mJ of potential
    // energy released), after at least 1.5 s.
    sim.step(300_000);
    for _ in 0..200 {
        if sim.observe().kinetic_energy < 1e-12 {
            break;
        }
        sim.step(10_000);
    }
    let o = sim.observe();
    assert!(
        o.kinetic_energy < 1e-12,
        "not at rest: {} J",
        o.kinetic_energy
    );
    let window = 20_000;
    let pz = |sim: &Simulation| sim.velocities().iter().map(|v| v[2]).sum::<f64>();
    let p0 = pz(&sim);
    let (mut floor, mut tube, mut applied) = (0.0, 0.0, 0.0);
    for _ in 0..window {
        sim.step(1);
        // The pairs' forces cancel in the sum: what is left is the weight
        // plus the walls' forces on the bed.
        applied += weight + sim.forces().iter().map(|f| f[2]).sum::<f64>();
        let o = sim.observe();
        // The walls push up on the bed: the force on them is downward.
        floor -= o.wall_forces[0][2];
        tube -= o.wall_forces[1][2];
    }
    let (floor, tube) = (floor / window as f64, tube / window as f64);
    // The bed's acceleration over the window, ΔP/T, in N m g.
    let drift = (pz(&sim) - p0) * m.density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
        / (window as f64 * sim.dt())
        / weight;
    println!(
        "tube bed of {n}: at {:.3} s the floor carries {:.6} N m g, the tube {:.6} N m g \
         (sum − 1 = {:.2e}; applied − 1 = {:.2e}; N m g = {weight:.6e} N; ΔP/T = {drift:.1e} N m g)",
        sim.time(),
        floor / weight,
        tube / weight,
        (floor + tube) / weight - 1.0,
        applied / window as f64 / weight - 1.0
    );
    assert!(drift.abs() < 1e-6, "{drift}");
    let applied = applied / window as f64;
    assert!(
        (applied / weight - 1.0).abs() < 1e-6,
        "{applied} vs {weight}"
    );
    assert!(
        ((floor + tube) / weight - 1.0).abs() < 1e-5,
        "{floor} + {tube} vs {weight}"
    );
    assert!(
        ((floor + tube) - applied).abs() < 1e-9 * weight,
        "{floor} + {tube} vs applied {applied}"
    );
    (floor, tube, weight)
}
