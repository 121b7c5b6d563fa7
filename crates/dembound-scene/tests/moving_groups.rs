//! Moving groups of fixed spheres (issue 27 item 1,
//! `pipeline::moving_groups`) against closed forms: a head-on elastic
//! collision with an infinitely heavy moving sphere (the free one leaves
//! at 2V, and exactly as in the frame where the wall is still), a
//! turning ring whose spheres sit where the exact rotation puts them, a
//! sphere in a hollow of a lined plate that ends up moving with it, an
//! undamped lined drum whose energy balance closes at second order in
//! Δt, and threads and restarts with the same bits.

mod common;

use common::grain;
use dembound_physics::contact::tangential::{FrictionModel, TangentialKind};
use dembound_physics::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use dembound_scene::setup::{
    DomainSetup, FrictionSetup, GroupMotion, NamedMaterial, RunLength, Scheme, SphereInit, TimeStep,
};
use dembound_scene::walls::motion::WallMotion;
use dembound_scene::{SceneSetup, Simulation};

const R: f64 = 1.0e-3;
const G: f64 = 9.81;

fn motion(velocity: [f64; 3], angular_velocity: [f64; 3], center: [f64; 3]) -> WallMotion {
    WallMotion {
        velocity,
        angular_velocity,
        center,
        start: 0.0,
        end: f64::INFINITY,
        oscillation: None,
    }
}

fn scene(half: f64, dt: f64, model: ContactModel) -> SceneSetup {
    let mut s = SceneSetup::new(
        DomainSetup {
            lower: [-half; 3],
            upper: [half; 3],
            periodic: [false; 3],
        },
        model,
        TimeStep::Fixed(dt),
        RunLength::Steps(0),
    );
    s.materials.push(NamedMaterial {
        name: "grain".into(),
        material: grain(1.0e7),
    });
    s
}

fn sphere(position: [f64; 3], velocity: [f64; 3], fixed: bool) -> SphereInit {
    SphereInit {
        position,
        velocity,
        radius: R,
        material: 0,
        fixed,
        group: None,
    }
}

/// The x velocity of a free sphere after a head-on elastic collision with
/// a fixed sphere 1 mm apart: the free one starts at `free` (m/s along x)
/// and the fixed one moves at `wall` (none: it stays).
fn head_on(scheme: Scheme, free: f64, wall: Option<f64>, dt: f64) -> f64 {
    let mut s = scene(0.02, dt, ContactModel::elastic(NormalLaw::Hertz));
    s.integration.scheme = scheme;
    s.spheres.push(sphere([0.0; 3], [free, 0.0, 0.0], false));
    s.spheres.push(sphere([-3.0 * R, 0.0, 0.0], [0.0; 3], true));
    if let Some(v) = wall {
        s.group_motions.push(GroupMotion {
            group: 1,
            spheres: 1..2,
            motion: motion([v, 0.0, 0.0], [0.0; 3], [-3.0 * R, 0.0, 0.0]),
        });
    }
    let mut sim = Simulation::new(s, 1).unwrap();
    // Contact at t = 1 mm / 0.1 m/s = 10 ms, ~0.3 ms long.
    sim.step((0.012 / dt).round() as u64);
    let v = sim.velocities()[0];
    assert!(v[1] == 0.0 && v[2] == 0.0, "{v:?}");
    v[0]
}

/// An elastic, frictionless sphere at rest hit head-on by an infinitely
/// heavy sphere moving at V leaves at 2V (in the wall's frame it comes in
/// at −V and leaves at +V). Two checks:
///
/// - against the frame where the wall stands still: the same run with
///   the free sphere thrown at −V onto a fixed sphere rebounds at v_r,
///   and the moving wall's run must give V + v_r. The two runs are the
///   same arithmetic up to rounding (the positions differ by V t, so
///   their last bits differ, ~1e-16 of 3 mm in a gap of ~1e-5 m: 1e-14
///   relative per force, summed over ~300 contact steps): 1e-10 of V.
///   (Verlet; Gear5's onset correction integrates the first part of the
///   contact along the free sphere's predicted path, which is not the
///   same arithmetic in the two frames: they differ by 1.5e-7 of V,
///   measured, within its truncation error below.)
/// - against 2V itself: the rebound of an elastic contact is off by
///   O((Δt/T_c)²) under velocity Verlet; at Δt = T_c/300 that is
///   ≤ 1.1e-5 (measured 3.0e-7 under Verlet, 2.9e-7 under Gear5).
#[test]
fn head_on_collision_with_a_moving_sphere_leaves_at_twice_its_speed() {
    let v = 0.1;
    for scheme in [Scheme::Verlet, Scheme::Gear5] {
        let dt = 1.0e-6;
        let moving = head_on(scheme, 0.0, Some(v), dt);
        let still = head_on(scheme, -v, None, dt);
        println!(
            "{scheme:?}: moving {moving:.17e}, V + v_r {:.17e}, (v − 2V)/2V {:.2e}",
            v + still,
            (moving - 2.0 * v) / (2.0 * v)
        );
        if scheme == Scheme::Verlet {
            assert!(
                (moving - (v + still)).abs() <= 1e-10 * v,
                "{moving} vs {}",
                v + still
            );
        }
        assert!((moving - 2.0 * v).abs() <= 1.1e-5 * 2.0 * v, "{moving}");
    }
}

/// A ring of 12 fixed spheres turning at ω = 3 rad/s about z through
/// c = (1, 2, 0) mm, a free sphere bouncing inside it: after each stretch
/// every ring sphere is at the exact rotation of its initial position,
/// c + Rot(θ)(X − c) with θ = ω t (written out here with cos and sin),
/// to 1e-15 of its distance from the axis plus one rounding of the
/// centre (Rodrigues' I + sin θ K + (1 − cos θ) K² and the
/// cos/sin matrix differ by a few ulp), and moves at ω × (x − c); no
/// drift from the steps.
#[test]
fn a_turning_ring_sits_at_the_exact_rotation() {
    let dt = 1.0e-5;
    let mut s = scene(0.02, dt, ContactModel::elastic(NormalLaw::Hertz));
    let c = [1.0e-3, 2.0e-3, 0.0];
    let w = 3.0;
    s.spheres
        .push(sphere([c[0] + 1e-3, c[1], 0.0], [0.05, 0.03, 0.0], false));
    let ring = 12;
    let radius = 5.0e-3;
    for k in 0..ring {
        let a = 2.0 * std::f64::consts::PI * k as f64 / ring as f64;
        s.spheres.push(sphere(
            [c[0] + radius * a.cos(), c[1] + radius * a.sin(), 0.0],
            [0.0; 3],
            true,
        ));
    }
    let initial: Vec<[f64; 3]> = s.spheres.iter().map(|s| s.position).collect();
    s.group_motions.push(GroupMotion {
        group: 1,
        spheres: 1..1 + ring,
        motion: motion([0.0; 3], [0.0, 0.0, w], c),
    });
    let mut sim = Simulation::new(s, 1).unwrap();
    let mut steps = 0u64;
    let mut contacts = 0usize;
    for stretch in [1u64, 999, 9000, 40000] {
        sim.step(stretch);
        steps += stretch;
        contacts = contacts.max(sim.wall_contacts());
        let theta = w * (steps as f64 * dt);
        let (sn, cs) = theta.sin_cos();
        let (x, v) = (sim.positions(), sim.velocities());
        for k in 1..=ring {
            let d = [initial[k][0] - c[0], initial[k][1] - c[1]];
            let exact = [
                c[0] + cs * d[0] - sn * d[1],
                c[1] + sn * d[0] + cs * d[1],
                0.0,
            ];
            let tol = 1e-15 * radius + f64::EPSILON * 2e-3;
            for a in 0..3 {
                assert!(
                    (x[k][a] - exact[a]).abs() <= tol,
                    "step {steps}, sphere {k}, axis {a}: {:?} vs {exact:?}",
                    x[k]
                );
            }
            let vel = [-w * (x[k][1] - c[1]), w * (x[k][0] - c[0]), 0.0];
            for a in 0..3 {
                assert!((v[k][a] - vel[a]).abs() <= 1e-15 * w * radius + 1e-18);
            }
        }
    }
    // The free sphere met the ring (its pair forces ran with the spheres
    // where they are).
    assert!(sim.observe().work_by_walls.unwrap() != 0.0);
}

/// Fixed spheres of a square plate (2 R apart) under gravity, a free
/// sphere in one of its hollows, Hertz + Tsuji e = 0.5, Mindlin μ = 0.5.
/// The plate starts moving along x at V = 1 cm/s at t = 20 ms (the sphere
/// has settled). A sphere held by friction in a hollow of a translating
/// plate moves with it: once the jolt has died out v = V, ω = 0, and it
/// keeps its place in the hollow (the plate's frame is inertial after
/// the start). Measured over the last 40 ms of 200 ms: the mean velocity
/// within 1e-4 V (the jolt's ringing is damped by e = 0.5 in a few
/// contact times, ~0.1 ms), the spin below 1e-4 V/R, and the sphere
/// within 1 µm of the hollow's moving centre (its settling depth).
#[test]
fn a_sphere_in_a_hollow_of_a_lined_plate_moves_with_it() {
    let dt = 1.0e-6;
    let v_plate = 0.01;
    let start = 0.02;
    let mut s = scene(
        0.02,
        dt,
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        ),
    );
    s.gravity = [0.0, 0.0, -G];
    s.friction = Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.5,
        rolling_friction: 0.0,
    }));
    // The hollow above (0, 0): its four spheres at (±R, ±R), the free
    // sphere's centre √2 R above the plate's centres when just touching.
    let top = 2f64.sqrt() * R;
    s.spheres
        .push(sphere([0.0, 0.0, top + 1e-7], [0.0; 3], false));
    let n = 6;
    for i in 0..n {
        for j in 0..n {
            let x = (2 * i as i64 - n as i64 + 1) as f64 * R;
            let y = (2 * j as i64 - n as i64 + 1) as f64 * R;
            s.spheres.push(sphere([x, y, 0.0], [0.0; 3], true));
        }
    }
    s.group_motions.push(GroupMotion {
        group: 1,
        spheres: 1..1 + n * n,
        motion: WallMotion {
            start,
            ..motion([v_plate, 0.0, 0.0], [0.0; 3], [0.0; 3])
        },
    });
    let mut sim = Simulation::new(s, 1).unwrap();
    let total = (0.2 / dt).round() as u64;
    let last = (0.04 / dt).round() as u64;
    sim.step(total - last);
    let (mut sum, mut spin) = (0.0, 0.0f64);
    let chunk = 100;
    for _ in 0..last / chunk {
        sim.step(chunk);
        sum += sim.velocities()[0][0];
        let w = sim.angular_velocities()[0];
        spin = spin.max(w.iter().map(|x| x.abs()).fold(0.0, f64::max));
    }
    let mean = sum / (last / chunk) as f64;
    println!(
        "mean v/V − 1 = {:.2e}, |ω| R/V = {:.2e}",
        mean / v_plate - 1.0,
        spin * R / v_plate
    );
    assert!((mean - v_plate).abs() <= 1e-4 * v_plate, "{mean}");
    assert!(spin * R <= 1e-4 * v_plate, "{spin}");
    let x = sim.positions()[0];
    let hollow = v_plate * (sim.time() - start);
    assert!(
        (x[0] - hollow).abs() <= 1e-6 && x[1].abs() <= 1e-6,
        "{x:?} vs {hollow}"
    );
}

/// A ring of 24 touching fixed spheres (radius 2R/sin(π/24) about the y
/// axis) turning at `omega` rad/s, with 6 free spheres inside (two rows of three) under
/// gravity, all at y = 0 (a flat drum).
fn flat_drum(dt: f64, model: ContactModel, omega: f64) -> SceneSetup {
    let mut s = scene(0.02, dt, model);
    s.gravity = [0.0, 0.0, -G];
    let count = 24;
    let ring = R / (std::f64::consts::PI / count as f64).sin();
    for k in 0..6 {
        let x = ((k % 3) as f64 - 1.0) * 2.2 * R;
        let z = -ring + (3.0 + 2.2 * (k / 3) as f64) * R;
        s.spheres.push(sphere([x, 0.0, z], [0.0; 3], false));
    }
    for k in 0..count {
        let a = 2.0 * std::f64::consts::PI * k as f64 / count as f64;
        s.spheres.push(sphere(
            [ring * a.cos(), 0.0, ring * a.sin()],
            [0.0; 3],
            true,
        ));
    }
    s.group_motions.push(GroupMotion {
        group: 1,
        spheres: 6..6 + count,
        motion: motion([0.0; 3], [0.0, omega, 0.0], [0.0; 3]),
    });
    s
}

/// An undamped, frictionless drum lined with spheres: nothing dissipates,
/// so D = E₀ + W − (K + E + P) is the integration error alone. Velocity
/// Verlet keeps a shadow energy within O((Δt/T_c)²) of the energy (T_c
/// ≈ 0.3 ms here, Δt/T_c ≈ 1/150 and 1/300); the trapezoidal W is of the
/// same order (measured: |D| 4e-7 and 7e-7 of the scale). Asserted:
/// |D| ≤ 1e-5 of the energy scale (K + E + |P − P₀| + |W|, the largest
/// over the run) at both steps, and below 1e-4 of the work the drum did.
/// A W counted where the surface walls' is, before the pair forces, would
/// read the group's forces as the step's first half leaves them (zero):
/// W = 0 and D = −(the energy the drum put in) fails both.
#[test]
fn undamped_lined_drum_balance_closes() {
    let run = |dt: f64| {
        let mut sim = Simulation::new(
            flat_drum(dt, ContactModel::elastic(NormalLaw::Hertz), 5.0),
            1,
        )
        .unwrap();
        let p0 = sim.observe().potential_energy;
        let mut scale = 0.0f64;
        let stretch = (0.002 / dt).round() as u64;
        for _ in 0..50 {
            sim.step(stretch);
            let o = sim.observe();
            let w = o.work_by_walls.unwrap();
            scale = scale.max(
                o.kinetic_energy + o.elastic_energy + (o.potential_energy - p0).abs() + w.abs(),
            );
        }
        let o = sim.observe();
        (o.dissipated_energy, o.work_by_walls.unwrap(), scale)
    };
    for dt in [2.0e-6, 1.0e-6] {
        let (d, w, scale) = run(dt);
        println!(
            "Δt {dt:e} s: D {d:.3e} J, W {w:.3e} J, scale {scale:.3e} J, D/scale {:.2e}",
            d / scale
        );
        assert!(w > 0.0);
        assert!(d.abs() <= 1e-5 * scale, "{d} vs scale {scale}");
        assert!(d.abs() <= 1e-4 * w, "{d} vs W {w}");
    }
}

/// A damped frictional lined drum: friction and damping only take energy
/// out, so the dissipated energy never falls between observations, but
/// for Verlet's energy error in the contacts open at the time: (Δt/T_c)²
/// ≈ 1e-5 of their elastic energy (≤ 1e-10 J here), ~3e-9 of the energy
/// scale K + E + |P − P₀| + |W| (measured: a fall of 2.5e-10 of it once
/// in 100 looks); 1e-8 allowed. The drum puts
/// energy in (W > 0), and the balance K + E + P + D − W = E₀ holds to the
/// rounding of the terms (1e-12 of their scale).
#[test]
fn damped_frictional_lined_drum_only_dissipates() {
    let dt = 1.0e-6;
    let mut s = flat_drum(
        dt,
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        ),
        5.0,
    );
    s.friction = Some(FrictionSetup::uniform(FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.5,
        rolling_friction: 0.01,
    }));
    let mut sim = Simulation::new(s, 1).unwrap();
    let first = sim.observe();
    let (p0, mut last) = (first.potential_energy, first.dissipated_energy);
    let mut scale = 0.0f64;
    for _ in 0..100 {
        sim.step(1000);
        let o = sim.observe();
        let w = o.work_by_walls.unwrap();
        scale = scale
            .max(o.kinetic_energy + o.elastic_energy + (o.potential_energy - p0).abs() + w.abs());
        assert!(o.dissipated_energy >= last - 1e-8 * scale, "{o:?}");
        let b = sim.energy_balance(&o);
        assert!((b.total - b.total_initial).abs() <= 1e-12 * scale, "{b:?}");
        last = o.dissipated_energy;
    }
    assert!(sim.observe().work_by_walls.unwrap() > 0.0);
}

/// The damped frictional drum on 1 and 2 threads and restarted from a
/// checkpoint halfway, Verlet and Gear5: the same bits (the pose is a
/// function of the step; the list build's step, the work and the group's
/// last power are in the checkpoint).
#[test]
fn threads_and_restarts_give_the_same_bits() {
    for scheme in [Scheme::Verlet, Scheme::Gear5] {
        let mut s = flat_drum(
            1.0e-6,
            ContactModel::damped(
                NormalLaw::Hertz,
                Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
            ),
            5.0,
        );
        s.integration.scheme = scheme;
        s.friction = Some(FrictionSetup::uniform(FrictionModel {
            tangential: TangentialKind::Mindlin,
            friction: 0.5,
            rolling_friction: 0.01,
        }));
        let (first, second) = (8000, 6000);
        let mut straight = Simulation::new(s.clone(), 1).unwrap();
        straight.step(first + second);
        let mut two = Simulation::new(s.clone(), 2).unwrap();
        two.step(first + second);
        assert_eq!(common::state(&straight), common::state(&two), "{scheme:?}");
        let mut a = Simulation::new(s.clone(), 2).unwrap();
        a.step(first);
        let cp = a.checkpoint();
        let mut b = Simulation::restore(s, &cp, 1).unwrap();
        b.step(second);
        assert_eq!(common::state(&straight), common::state(&b), "{scheme:?}");
        assert!(straight.observe().work_by_walls.unwrap() > 0.0);
    }
}
