//! The composer against the sub-models composed by hand, and against the
//! closed forms of gross sliding, gross rolling and rolling without slip.

use super::*;
use crate::contact::tangential::{effective_shear_modulus, FrictionModel, TangentialKind};
use crate::contact::{ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use crate::material::{Material, PairProperties};

const GLASS: Material = Material {
    density: 2500.0,
    youngs_modulus: 7.0e10,
    poisson_ratio: 0.25,
};

/// Radii of the two spheres, m.
const R1: f64 = 1.0e-3;
const R2: f64 = 1.5e-3;

fn law_of(model: ContactModel, kind: TangentialKind, mu: f64, mu_r: f64) -> ContactLaw {
    let (m1, m2) = (GLASS.sphere_mass(R1), GLASS.sphere_mass(R2));
    let pair = PairProperties::spheres(R1, m1, &GLASS, R2, m2, &GLASS);
    let law = model.pair(&pair);
    let friction = FrictionModel {
        tangential: kind,
        friction: mu,
        rolling_friction: mu_r,
    }
    .pair(
        &law,
        &pair,
        effective_shear_modulus(&GLASS, &GLASS),
        mu,
        mu_r,
    );
    ContactLaw {
        law,
        friction,
        torque_arm: TorqueArm::Radius,
    }
}

/// The laws the bit-for-bit comparison runs: Hertz–Mindlin with Tsuji
/// damping, a damped linear spring with the linear tangential spring,
/// Walton–Braun (a normal history), each with rolling friction.
fn laws() -> Vec<ContactLaw> {
    let tsuji = ContactModel::damped(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.6)),
    );
    let viscous = ContactModel::damped(
        NormalLaw::Linear,
        Damping::new(DampingKind::Viscous, Dissipation::Restitution(0.8)),
    );
    let walton = ContactModel::elastic(NormalLaw::WaltonBraun { restitution: 0.5 });
    vec![
        law_of(tsuji, TangentialKind::Mindlin, 0.4, 0.05),
        law_of(viscous, TangentialKind::Linear, 0.3, 0.1),
        law_of(walton, TangentialKind::Mindlin, 0.5, 0.02),
    ]
}

/// xorshift64*: reproducible inputs without a dependency.
struct Rng(u64);

impl Rng {
    /// Uniform in [−1, 1).
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    fn vector(&mut self, scale: f64) -> [f64; 3] {
        [
            scale * self.next(),
            scale * self.next(),
            scale * self.next(),
        ]
    }

    fn unit(&mut self) -> [f64; 3] {
        let v = self.vector(1.0);
        let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / r, v[1] / r, v[2] / r]
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn bits(v: [f64; 3]) -> [u64; 3] {
    v.map(f64::to_bits)
}

/// The contact as the engine's pair loop composed it from the sub-models
/// before the composer existed (force on body 2, torques on 1 and 2).
#[allow(clippy::too_many_arguments)]
fn by_hand(
    cl: &ContactLaw,
    g: &Geometry,
    a: &Side,
    b: &Side,
    history: &mut ContactHistory,
    shear: &mut [f64; 3],
    roll: Option<&mut [f64; 3]>,
    dt: f64,
) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let f = cl.law.force(g.overlap, g.overlap_rate, history);
    cl.law.update(g.overlap, g.overlap_rate, history);
    let n = g.normal;
    let arm = [
        a.arm * a.spin[0] + b.arm * b.spin[0],
        a.arm * a.spin[1] + b.arm * b.spin[1],
        a.arm * a.spin[2] + b.arm * b.spin[2],
    ];
    let spin = cross(arm, n);
    let slip = [
        a.velocity[0] - b.velocity[0] + spin[0],
        a.velocity[1] - b.velocity[1] + spin[1],
        a.velocity[2] - b.velocity[2] + spin[2],
    ];
    let s = dot(slip, n);
    let vt = [slip[0] - s * n[0], slip[1] - s * n[1], slip[2] - s * n[2]];
    let ft = cl.friction.tangential_force(g.overlap, f, n, vt, dt, shear);
    let nxf = cross(n, ft);
    let mut ti = nxf.map(|x| a.arm * x);
    let mut tj = nxf.map(|x| b.arm * x);
    if let Some(roll) = roll {
        let inv = a.inverse_inertia + b.inverse_inertia;
        let m = cl.friction.rolling_torque(
            &cl.law,
            g.overlap,
            f,
            n,
            [
                a.spin[0] - b.spin[0],
                a.spin[1] - b.spin[1],
                a.spin[2] - b.spin[2],
            ],
            if inv > 0.0 { 1.0 / inv } else { 0.0 },
            dt,
            roll,
        );
        for d in 0..3 {
            ti[d] += m[d];
            tj[d] -= m[d];
        }
    }
    let fj = [f * n[0] - ft[0], f * n[1] - ft[1], f * n[2] - ft[2]];
    (fj, ti, tj)
}

fn sphere(rng: &mut Rng, radius: f64) -> Side {
    let m = GLASS.sphere_mass(radius);
    Side {
        velocity: rng.vector(0.1),
        spin: rng.vector(100.0),
        arm: radius,
        inverse_inertia: 1.0 / (0.4 * m * radius * radius),
    }
}

/// The composer gives the hand-composed contact's forces, torques and
/// histories bit for bit (the composer is that composition moved, so any
/// difference is a changed operation), over random states: loading and
/// unloading, sticking and sliding, springs not yet in the tangent plane,
/// with and without a rolling spring, sphere pairs and a sphere on a
/// moving wall.
#[test]
fn calculate_forces_equals_the_sub_models_composed_by_hand_bit_for_bit() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let dt = 1.0e-6;
    let mut sliding = 0;
    for cl in laws() {
        for step in 0..2000 {
            let g = Geometry {
                overlap: 5.0e-6 * (1.0 + rng.next()) + 1e-9,
                overlap_rate: 0.1 * rng.next(),
                normal: rng.unit(),
            };
            let a = sphere(&mut rng, R1);
            let b = if step % 4 == 3 {
                Side::wall(rng.vector(0.05))
            } else {
                sphere(&mut rng, R2)
            };
            let history = ContactHistory {
                max_overlap: g.overlap * (1.0 + 0.5 * (1.0 + rng.next())),
                unloading: step % 2 == 0,
            };
            // ContactState from rest to beyond the Coulomb limit.
            let scale = 10f64.powf(-9.0 + 4.0 * rng.next().abs());
            let shear = rng.vector(scale);
            let scale = 1.0e-6 * rng.next().abs();
            let roll = rng.vector(scale);
            let rolling = step % 3 != 0;
            let (mut h1, mut s1, mut r1) = (history, shear, roll);
            let (mut h2, mut s2, mut r2) = (history, shear, roll);
            let c = cl.calculate_forces(
                &g,
                &a,
                &b,
                ContactState {
                    history: &mut h1,
                    tangential: &mut s1,
                    rolling: rolling.then_some(&mut r1),
                },
                dt,
            );
            let (fj, ti, tj) = by_hand(
                &cl,
                &g,
                &a,
                &b,
                &mut h2,
                &mut s2,
                rolling.then_some(&mut r2),
                dt,
            );
            assert_eq!(bits(c.on_body2(g.normal)), bits(fj), "step {step}");
            assert_eq!(bits(c.torque1()), bits(ti), "step {step}");
            assert_eq!(bits(c.torque2()), bits(tj), "step {step}");
            assert_eq!(h1, h2);
            assert_eq!(bits(s1), bits(s2));
            assert_eq!(bits(r1), bits(r2));
            // Action and reaction (== ignores the sign of an exact zero).
            let (f1, f2) = (c.on_body1(g.normal), c.on_body2(g.normal));
            assert!((0..3).all(|d| f1[d] == -f2[d]));
            let limit = cl.friction.friction() * c.normal;
            if norm(c.tangential) > 0.999 * limit {
                sliding += 1;
            }
        }
    }
    // Both regimes were compared (about half the random springs exceed
    // the limit; counted when written: several hundred of 6000).
    assert!(sliding > 300 && sliding < 5700, "{sliding}");
}

/// In gross sliding the tangential force is the Coulomb limit μ F_n,
/// against the slip, and body 1's torque is R₁ n × F_t: against a wall
/// at rest, a sphere sliding along x without spin.
#[test]
fn gross_sliding_transmits_the_coulomb_limit_against_the_slip() {
    let cl = laws()[0];
    let mu = cl.friction.friction();
    let n = [0.0, 0.0, -1.0];
    let g = Geometry {
        overlap: 2.0e-6,
        overlap_rate: 0.0,
        normal: n,
    };
    let a = Side {
        velocity: [0.5, 0.0, 0.0],
        spin: [0.0; 3],
        arm: R1,
        inverse_inertia: 1.0,
    };
    let (mut h, mut s) = (ContactHistory::default(), [0.0; 3]);
    let mut c = None;
    // 0.5 m/s for 1 ms moves the spring 0.5 mm, far beyond μ F_n/k_t.
    for _ in 0..1000 {
        c = Some(cl.calculate_forces(
            &g,
            &a,
            &Side::wall([0.0; 3]),
            ContactState {
                history: &mut h,
                tangential: &mut s,
                rolling: None,
            },
            1.0e-6,
        ));
    }
    let c = c.unwrap();
    // F_n: the elastic Hertz force at rest (ḣ = 0: no damping).
    assert_eq!(
        c.normal,
        cl.law.force(2.0e-6, 0.0, &ContactHistory::default())
    );
    // |F_t| = μ F_n to a few roundings (the spring's rescale: 1e-15).
    assert!((norm(c.tangential) / (mu * c.normal) - 1.0).abs() < 1e-15);
    assert!(c.tangential[0] < 0.0 && c.tangential[1] == 0.0 && c.tangential[2] == 0.0);
    // τ₁ = R₁ n × F_t: n = −z, F_t = −|F_t| x give +|F_t| R₁ about y
    // (a force along −x at the contact point below the centre).
    let expected = cross(n, c.tangential).map(|x| R1 * x);
    assert_eq!(c.torque1(), expected);
    assert!(c.torque1()[1] > 0.0);
    // The wall takes F_n n − F_t: F_n downward, μ F_n along the slip.
    let on_wall = c.on_body2(n);
    assert!(on_wall[2] < 0.0 && on_wall[0] > 0.0);
}

/// A sphere pair in gross sliding: the torque on each sphere is its arm
/// times n × F_t with |F_t| = μ F_n against the slip, the arm R for
/// `TorqueArm::Radius` and R − δ/2 for `TorqueArm::ContactPoint`
/// (LAMMPS's `dist_to_contact`), `TorqueArm::OverlapMiddle` (Yade's
/// contact point) and `TorqueArm::HalfOverlap` (LIGGGHTS's `cri`, `crj`);
/// against a wall the first two take R, the last two R − δ/2. Closed form:
/// n = +x, body 1 sliding along +y on body 2 at rest, so F_t = −μ F_n ŷ
/// and n × F_t = −μ F_n ẑ, τ_k = −A_k μ F_n ẑ.
#[test]
fn sliding_torque_is_the_arm_times_the_coulomb_force() {
    let h = 5.0e-6;
    let n = [1.0, 0.0, 0.0];
    let g = Geometry {
        overlap: h,
        overlap_rate: 0.0,
        normal: n,
    };
    let a = Side {
        velocity: [0.0, 0.5, 0.0],
        spin: [0.0; 3],
        arm: R1,
        inverse_inertia: 1.0,
    };
    let b = Side {
        velocity: [0.0; 3],
        spin: [0.0; 3],
        arm: R2,
        inverse_inertia: 1.0,
    };
    let sliding = |cl: &ContactLaw, other: &Side| {
        let (mut hist, mut s) = (ContactHistory::default(), [0.0; 3]);
        let mut c = None;
        // 0.5 m/s for 1 ms moves the spring 0.5 mm, far beyond μ F_n/k_t.
        for _ in 0..1000 {
            c = Some(cl.calculate_forces(
                &g,
                &a,
                other,
                ContactState {
                    history: &mut hist,
                    tangential: &mut s,
                    rolling: None,
                },
                1.0e-6,
            ));
        }
        c.unwrap()
    };
    for arm in [
        TorqueArm::Radius,
        TorqueArm::ContactPoint,
        TorqueArm::OverlapMiddle,
        TorqueArm::HalfOverlap,
    ] {
        let cl = ContactLaw {
            torque_arm: arm,
            ..laws()[0]
        };
        let mu = cl.friction.friction();
        let c = sliding(&cl, &b);
        // F_n: the elastic Hertz force at rest (ḣ = 0: no damping).
        let f_n = cl.law.force(h, 0.0, &ContactHistory::default());
        let (arm1, arm2) = match arm {
            TorqueArm::Radius => (R1, R2),
            TorqueArm::ContactPoint | TorqueArm::OverlapMiddle | TorqueArm::HalfOverlap => {
                (R1 - 0.5 * h, R2 - 0.5 * h)
            }
        };
        // The closed form to a few roundings: |F_t| is μ F_n after the
        // spring's rescale (1e-15 relative), times one product.
        let close = |got: f64, want: f64| (got / want - 1.0).abs() < 1e-14;
        let t1 = c.torque1();
        let t2 = c.torque2();
        assert!(close(t1[2], -arm1 * mu * f_n), "{arm:?}: {t1:?}");
        assert!(close(t2[2], -arm2 * mu * f_n), "{arm:?}: {t2:?}");
        assert!(t1[0] == 0.0 && t1[1] == 0.0 && t2[0] == 0.0 && t2[1] == 0.0);
        // Against a wall at rest LAMMPS (fix wall/gran) and the first two
        // arms take R, Yade's box face R − δ/2.
        let w = sliding(&cl, &Side::wall([0.0; 3]));
        let fw = cl.law.force(h, 0.0, &ContactHistory::default());
        let wall_arm = if matches!(arm, TorqueArm::OverlapMiddle | TorqueArm::HalfOverlap) {
            R1 - 0.5 * h
        } else {
            R1
        };
        assert!(close(w.torque1()[2], -wall_arm * mu * fw), "{arm:?}");
        assert_eq!(w.torque2(), [0.0; 3]);
    }
    // The two arms differ by the factor 1 − δ/(2R) (here 2.5e-3 on body 1),
    // far above the 1e-14 tolerance: the test tells them apart.
    assert!(0.5 * h / R1 > 1e-3);
}

/// In gross rolling the rolling torque is capped at μ_r R_eff F_n and
/// opposes the relative rolling spin; it enters τ₁ with + and τ₂ with −.
#[test]
fn rolling_torque_is_capped_at_mu_r_r_eff_f_n() {
    let cl = laws()[1];
    let mu_r = cl.friction.rolling_friction();
    let r_eff = R1 * R2 / (R1 + R2);
    let n = [1.0, 0.0, 0.0];
    let g = Geometry {
        overlap: 1.0e-6,
        overlap_rate: 0.0,
        normal: n,
    };
    // Rolling about z relative to each other, contact points moving
    // together (no slip: R₁ ω₁ = −R₂ ω₂ about z, equal velocities).
    let a = Side {
        velocity: [0.0; 3],
        spin: [0.0, 0.0, 30.0],
        arm: R1,
        inverse_inertia: 1.0e9,
    };
    let b = Side {
        spin: [0.0, 0.0, -30.0 * R1 / R2],
        arm: R2,
        ..a
    };
    let (mut h, mut s, mut m) = (ContactHistory::default(), [0.0; 3], [0.0; 3]);
    let mut c = None;
    for _ in 0..2000 {
        c = Some(cl.calculate_forces(
            &g,
            &a,
            &b,
            ContactState {
                history: &mut h,
                tangential: &mut s,
                rolling: Some(&mut m),
            },
            1.0e-5,
        ));
    }
    let c = c.unwrap();
    let limit = mu_r * r_eff * c.normal;
    // Capped: the spring's length is the limit to a few roundings.
    assert!((norm(m) / limit - 1.0).abs() < 1e-14, "{m:?} {limit}");
    // Against ω₁ − ω₂ (along +z).
    assert!(m[2] < 0.0 && m[0] == 0.0 && m[1] == 0.0);
    // The slip is R₁ω₁ + R₂ω₂ = 0 to rounding: tangential force tiny
    // against the rolling torque's lever.
    let nxf = cross(n, c.tangential);
    for d in 0..3 {
        assert_eq!(c.torque1()[d], R1 * nxf[d] + m[d]);
        assert_eq!(c.torque2()[d], R2 * nxf[d] - m[d]);
    }
}

/// A sphere rolling without slip on a moving wall (the wall as side 2
/// with its surface velocity): no tangential force, exactly; with μ = 0
/// the contact is the normal stage alone.
#[test]
fn a_wall_is_side_two_with_its_surface_velocity() {
    let cl = laws()[0];
    let n = [0.0, 0.0, -1.0];
    let g = Geometry {
        overlap: 1.0e-6,
        overlap_rate: 0.0,
        normal: n,
    };
    // v₁ − u + R ω × n = 0: ω = (0, 2, 0) rad/s, R = 0.5 m gives
    // R ω × n = (−1, 0, 0) m/s; u = (1, 0, 0) m/s, v₁ = (2, 0, 0) m/s.
    // Every product and sum is exact in binary.
    let a = Side {
        velocity: [2.0, 0.0, 0.0],
        spin: [0.0, 2.0, 0.0],
        arm: 0.5,
        inverse_inertia: 1.0,
    };
    let wall = Side::wall([1.0, 0.0, 0.0]);
    assert_eq!(slip_velocity(&a, &wall, n), [0.0; 3]);
    let (mut h, mut s) = (ContactHistory::default(), [0.0; 3]);
    let c = cl.calculate_forces(
        &g,
        &a,
        &wall,
        ContactState {
            history: &mut h,
            tangential: &mut s,
            rolling: None,
        },
        1.0e-6,
    );
    assert_eq!(c.tangential, [0.0; 3]);
    assert_eq!(s, [0.0; 3]);
    assert_eq!(c.torque1(), [0.0; 3]);
    // The wall pushes the sphere up with F_n.
    assert_eq!(c.on_body1(n), [0.0, 0.0, c.normal]);
    assert!(c.normal > 0.0);

    // μ = 0: sliding fast, still no tangential force, and F_n is the
    // normal stage's.
    let model = ContactModel::elastic(NormalLaw::Hertz);
    let frictionless = law_of(model, TangentialKind::Mindlin, 0.0, 0.0);
    let fast = Side {
        velocity: [3.0, -1.0, 0.0],
        ..a
    };
    let mut h2 = ContactHistory::default();
    let c = frictionless.calculate_forces(
        &g,
        &fast,
        &wall,
        ContactState {
            history: &mut h,
            tangential: &mut s,
            rolling: None,
        },
        1.0e-6,
    );
    assert_eq!(c.tangential, [0.0; 3]);
    assert_eq!(
        c.normal,
        frictionless.law.normal_stage(1.0e-6, 0.0, &mut h2)
    );
}

/// LIGGGHTS's arm (`TorqueArm::HalfOverlap`) at a known sticking state,
/// by LIGGGHTS's formulas (`surface_model_default.h`,
/// `tangential_model_history.h`): from an empty spring one step moves it
/// by v_t Δt, v_t the tangential part of v₁ − v₂ + ((R₁ − δ/2) ω₁ + (R₂
/// − δ/2) ω₂) × n, so F_t = −c v_t with c = k_t Δt + η_t the same scalar
/// as under the default arm (whose slip takes R: c read from that run),
/// and the torques are (R_k − δ/2) n × F_t. Against a wall the whole
/// contact is Yade's (`TorqueArm::OverlapMiddle`), bit for bit.
#[test]
fn half_overlap_sticking_step_is_liggghts_slip_and_torque() {
    let h = 1.0e-6;
    let n = [0.0, 0.0, 1.0];
    let g = Geometry {
        overlap: h,
        overlap_rate: 0.0,
        normal: n,
    };
    let a = Side {
        velocity: [0.02, -0.01, 0.005],
        spin: [30.0, -20.0, 5.0],
        arm: R1,
        inverse_inertia: 1.0,
    };
    let b = Side {
        velocity: [-0.01, 0.03, 0.0],
        spin: [-10.0, 40.0, 7.0],
        arm: R2,
        inverse_inertia: 1.0,
    };
    let step = |arm: TorqueArm, other: &Side| {
        let cl = ContactLaw {
            torque_arm: arm,
            ..laws()[0]
        };
        let (mut hist, mut s) = (ContactHistory::default(), [0.0; 3]);
        cl.calculate_forces(
            &g,
            &a,
            other,
            ContactState {
                history: &mut hist,
                tangential: &mut s,
                rolling: None,
            },
            1.0e-7,
        )
    };
    // The tangential slip of arms c1, c2, n = z: (v₁ − v₂)_xy + (w_y, −w_x)
    // with w = c1 ω₁ + c2 ω₂.
    let slip = |c1: f64, c2: f64| {
        let w = [
            c1 * a.spin[0] + c2 * b.spin[0],
            c1 * a.spin[1] + c2 * b.spin[1],
        ];
        [
            a.velocity[0] - b.velocity[0] + w[1],
            a.velocity[1] - b.velocity[1] - w[0],
            0.0,
        ]
    };
    let (c1, c2) = (R1 - 0.5 * h, R2 - 0.5 * h);
    let radius = step(TorqueArm::Radius, &b);
    let v_r = slip(R1, R2);
    let coefficient = -radius.tangential[0] / v_r[0];
    assert!(coefficient > 0.0);
    let half = step(TorqueArm::HalfOverlap, &b);
    let v_h = slip(c1, c2);
    // Sticking: under μ F_n (measured 0.12 N against 0.49 N, mostly the
    // tangential dashpot), or the cut would break F_t ∝ v_t.
    let mu = laws()[0].friction.friction();
    assert!(norm(half.tangential) < 0.5 * mu * half.normal);
    // A few roundings of the slip's sums and of one product (1e-13
    // relative); the arms R against R − δ/2 move the spin terms by
    // δ/(2R) = 5e-4 of 0.1 m/s, 1e6 times that.
    for (k, v) in v_h.iter().enumerate().take(2) {
        let want = -coefficient * v;
        assert!(
            (half.tangential[k] / want - 1.0).abs() < 1e-12,
            "F_t[{k}] {:?} against {want}",
            half.tangential
        );
        assert!((radius.tangential[k] / want - 1.0).abs() > 1e-6);
    }
    assert_eq!(half.tangential[2], 0.0);
    let t1 = cross(n, half.tangential).map(|x| c1 * x);
    let t2 = cross(n, half.tangential).map(|x| c2 * x);
    for k in 0..3 {
        assert!((half.torque1()[k] - t1[k]).abs() <= 1e-15 * norm(t1));
        assert!((half.torque2()[k] - t2[k]).abs() <= 1e-15 * norm(t2));
    }
    // The wall: every bit of Yade's.
    let wall = Side::wall([0.01, 0.0, 0.0]);
    let (w_half, w_yade) = (
        step(TorqueArm::HalfOverlap, &wall),
        step(TorqueArm::OverlapMiddle, &wall),
    );
    assert_eq!(w_half.normal.to_bits(), w_yade.normal.to_bits());
    assert_eq!(bits(w_half.tangential), bits(w_yade.tangential));
    assert_eq!(bits(w_half.torque1()), bits(w_yade.torque1()));
    assert_eq!(bits(w_half.torque2()), bits(w_yade.torque2()));
    assert_ne!(
        bits(w_half.torque1()),
        bits(step(TorqueArm::ContactPoint, &wall).torque1())
    );
}

/// An observation is the whole contact evaluated after a step of zero
/// length on copies of the history and springs: the same forces and
/// torques, bit for bit, as `calculate_forces` at dt = 0 given copies,
/// and nothing of the caller's moved (the history, read only; the springs,
/// passed by value). Random states as above, pairs and moving walls.
#[test]
fn observe_is_calculate_forces_at_zero_dt_on_copies() {
    let mut rng = Rng(0x2545_F491_4F6C_DD1D);
    for cl in laws() {
        for step in 0..500 {
            let g = Geometry {
                overlap: 5.0e-6 * (1.0 + rng.next()) + 1e-9,
                overlap_rate: 0.1 * rng.next(),
                normal: rng.unit(),
            };
            let a = sphere(&mut rng, R1);
            let b = if step % 2 == 1 {
                Side::wall(rng.vector(0.05))
            } else {
                sphere(&mut rng, R2)
            };
            let history = ContactHistory {
                max_overlap: g.overlap * (1.0 + 0.5 * (1.0 + rng.next())),
                unloading: step % 3 == 0,
            };
            let scale = 10f64.powf(-9.0 + 4.0 * rng.next().abs());
            let shear = rng.vector(scale);
            let scale = 1.0e-6 * rng.next().abs();
            let roll = rng.vector(scale);
            let seen = cl.observe(&g, &a, &b, &history, shear, Some(roll));
            let (mut h, mut s, mut r) = (history, shear, roll);
            let whole = cl.calculate_forces(
                &g,
                &a,
                &b,
                ContactState {
                    history: &mut h,
                    tangential: &mut s,
                    rolling: Some(&mut r),
                },
                0.0,
            );
            assert_eq!(seen.normal.to_bits(), whole.normal.to_bits());
            assert_eq!(bits(seen.tangential), bits(whole.tangential));
            assert_eq!(bits(seen.torque1()), bits(whole.torque1()));
            assert_eq!(bits(seen.torque2()), bits(whole.torque2()));
            // The force is the one before the history's update.
            assert_eq!(
                seen.normal.to_bits(),
                cl.law.force(g.overlap, g.overlap_rate, &history).to_bits()
            );
        }
    }
}
