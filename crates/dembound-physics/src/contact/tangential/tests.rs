//! The tangential sub-models against closed forms.

use super::*;
use crate::contact::{Calibration, ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use crate::material::{effective_modulus, Material, PairProperties};

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

const GLASS: Material = Material {
    density: 2500.0,
    youngs_modulus: 7.0e10,
    poisson_ratio: 0.25,
};

fn setup(
    law: NormalLaw,
    damping: Damping,
    kind: TangentialKind,
    mu: f64,
) -> (PairLaw, FrictionPair) {
    let r = 1.0e-3;
    let m = GLASS.sphere_mass(r);
    let pair = PairProperties::sphere_plane(r, m, &GLASS, &GLASS);
    let model = ContactModel {
        calibration: Calibration::Formula,
        attractive: true,
        ..ContactModel::damped(law, damping)
    };
    let law = model.pair(&pair);
    let friction = FrictionModel {
        tangential: kind,
        friction: mu,
        rolling_friction: 0.0,
    };
    let g = effective_shear_modulus(&GLASS, &GLASS);
    (law, friction.pair(&law, &pair, g, mu, 0.0))
}

#[test]
fn shear_modulus_mixing_closed_forms() {
    // Equal materials: G* = G/(2(2 − ν)), G = E/(2(1 + ν)); against a rigid
    // body G* = G/(2 − ν). A few roundings: 1e-15.
    let g = 7.0e10 / (2.0 * 1.25);
    let same = effective_shear_modulus(&GLASS, &GLASS);
    assert!((same / (g / (2.0 * 1.75)) - 1.0).abs() < 1e-15);
    let rigid = effective_shear_modulus(&GLASS, &Material::rigid(1.0));
    assert!((rigid / (g / 1.75) - 1.0).abs() < 1e-15);
    assert_eq!(mix_friction(0.3, 0.3), 0.3);
    assert!((mix_friction(0.2, 0.8) - 0.4).abs() < 1e-16);
    assert_eq!(mix_friction(0.5, 0.0), 0.0);
}

#[test]
fn stiffnesses_closed_forms() {
    let (_, f) = setup(
        NormalLaw::Hertz,
        Damping::NONE,
        TangentialKind::Mindlin,
        0.5,
    );
    let g = effective_shear_modulus(&GLASS, &GLASS);
    let h: f64 = 1.0e-6;
    let expected = 8.0 * g * (1.0e-3 * h).sqrt();
    assert!((f.tangential().stiffness(h) / expected - 1.0).abs() < 1e-15);
    let (_, f) = setup(NormalLaw::Hertz, Damping::NONE, TangentialKind::Linear, 0.5);
    let e_eff = effective_modulus(&GLASS, &GLASS);
    assert!((f.tangential().stiffness(h) / (2.0 / 7.0 * e_eff * 1.0e-3) - 1.0).abs() < 1e-15);
    assert_eq!(f.tangential().stiffness(0.0), f.tangential().stiffness(1.0));
}

#[test]
fn sticks_elastically_then_slides_at_the_coulomb_limit() {
    // Constant tangential velocity v along x, constant normal force F_n:
    // the spring force is −k_t v t (k_t constant for the linear model)
    // until it reaches μ F_n, then exactly μ F_n against v, with the
    // spring stretched to μ F_n/k_t. Sums of equal increments: 1e-12.
    let mu = 0.3;
    let (_, f) = setup(NormalLaw::Linear, Damping::NONE, TangentialKind::Linear, mu);
    let (h, fn_, v, dt) = (1.0e-6, 2.0, 1.0e-3, 1.0e-7);
    let k = f.tangential().stiffness(h);
    let n = [0.0, 0.0, 1.0];
    let mut shear = [0.0; 3];
    let stick_steps = (mu * fn_ / (k * v * dt)).floor() as usize;
    assert!(stick_steps > 10, "{stick_steps}");
    for step in 1..=stick_steps + 20 {
        let force = f.tangential_force(h, fn_, n, [v, 0.0, 0.0], dt, &mut shear);
        assert_eq!(force[1], 0.0);
        assert_eq!(force[2], 0.0);
        if step <= stick_steps {
            let expected = -k * v * dt * step as f64;
            assert!((force[0] / expected - 1.0).abs() < 1e-12, "{step}");
        } else {
            assert!((force[0] / (-mu * fn_) - 1.0).abs() < 1e-15, "{step}");
            assert!((shear[0] / (mu * fn_ / k) - 1.0).abs() < 1e-15);
        }
    }
    // Reversal: the spring unloads from the limit at the elastic slope,
    // 2 μ F_n of force swing before sliding the other way.
    let force = f.tangential_force(h, fn_, n, [-v, 0.0, 0.0], dt, &mut shear);
    assert!((force[0] - (-mu * fn_ + k * v * dt)).abs() < 1e-12 * mu * fn_);
    // No friction: no force, whatever the spring.
    let (_, g) = setup(
        NormalLaw::Linear,
        Damping::NONE,
        TangentialKind::Linear,
        0.0,
    );
    let mut s = [1.0e-6, 0.0, 0.0];
    assert_eq!(
        g.tangential_force(h, fn_, n, [v, 0.0, 0.0], dt, &mut s),
        [0.0; 3]
    );
}

#[test]
fn history_is_rotated_into_the_new_tangent_plane() {
    // The normal turns by 0.1 rad about y; the stored displacement keeps
    // its length and becomes tangent (elastic, below the limit, dt = 0):
    // |F| = k_t |δ| and F·n = 0 to rounding.
    let (_, f) = setup(
        NormalLaw::Linear,
        Damping::NONE,
        TangentialKind::Linear,
        1.0,
    );
    let h = 1.0e-6;
    let k = f.tangential().stiffness(h);
    let mut shear = [1.0e-9, 2.0e-9, 0.0];
    let len = (5.0f64).sqrt() * 1.0e-9;
    let th = 0.1f64;
    let n = [th.sin(), 0.0, th.cos()];
    let force = f.tangential_force(h, 10.0, n, [0.0; 3], 0.0, &mut shear);
    let along = shear[0] * n[0] + shear[1] * n[1] + shear[2] * n[2];
    assert!(along.abs() < 1e-24, "{along}");
    assert!((norm(shear) / len - 1.0).abs() < 1e-15);
    assert!((norm(force) / (k * len) - 1.0).abs() < 1e-15);
}

/// The same turn under `contact.spring_rotation = "project"`
/// ([`FrictionPair::with_spring_rotation`]): the spring projected and not
/// rescaled. δ = (1, 2, 0) nm and n turned by θ = 0.1 rad about y: δ·n =
/// 1 nm · sin θ, so the projection's length is √(|δ|² − (δ·n)²) = √(5 −
/// sin²θ) nm (closed form), 0.1 % shorter than the rescaled spring's
/// √5 nm; the force k_t times it (elastic, below the limit, dt = 0), in
/// the tangent plane. Tolerance 1e-15: a few roundings; a rescale (or no
/// turn) is off by 1e-3.
#[test]
fn a_projecting_pair_leaves_the_turned_spring_shorter() {
    let (_, f) = setup(
        NormalLaw::Linear,
        Damping::NONE,
        TangentialKind::Linear,
        1.0,
    );
    let f = f.with_spring_rotation(SpringRotation::Project);
    assert_eq!(f.spring_rotation(), SpringRotation::Project);
    let h = 1.0e-6;
    let k = f.tangential().stiffness(h);
    let mut shear = [1.0e-9, 2.0e-9, 0.0];
    let th = 0.1f64;
    let len = (5.0 - th.sin().powi(2)).sqrt() * 1.0e-9;
    let n = [th.sin(), 0.0, th.cos()];
    let force = f.tangential_force(h, 10.0, n, [0.0; 3], 0.0, &mut shear);
    let along = shear[0] * n[0] + shear[1] * n[1] + shear[2] * n[2];
    assert!(along.abs() < 1e-24, "{along}");
    assert!((norm(shear) / len - 1.0).abs() < 1e-15, "{shear:?}");
    assert!((norm(force) / (k * len) - 1.0).abs() < 1e-15);
    // tangential_force_known turns the same way.
    let mut known = [1.0e-9, 2.0e-9, 0.0];
    let again = f.tangential_force_known(false, h, 10.0, n, [0.0; 3], 0.0, &mut known);
    assert_eq!((again, known), (force, shear));
}

#[test]
fn turn_spring_rotates_the_spring_with_the_frame() {
    // δ = a x̂ and a normal turned by θ about y from ẑ, n = (sin θ, 0,
    // cos θ): the projection δ − (δ·n) n = a cos θ (cos θ, 0, −sin θ)
    // rescaled to length a is a (cos θ, 0, −sin θ), the spring turned
    // with the frame (closed form). θ = 1e-5 takes the small-turn branch
    // (sin²θ = 1e-10 < 1e-8; its series 1 + x/2 is off by 3x²/8 ≈ 4e-21),
    // θ = 0.3 the root. Tolerance 1e-15 of a: a few roundings of values
    // ≤ a (2.2e-16 each).
    let a = 3.0e-7;
    for th in [1.0e-5f64, 0.3] {
        let mut shear = [a, 0.0, 0.0];
        FrictionPair::turn_spring(&mut shear, [th.sin(), 0.0, th.cos()]);
        let expected = [a * th.cos(), 0.0, -a * th.sin()];
        for c in 0..3 {
            assert!(
                (shear[c] - expected[c]).abs() < 1e-15 * a,
                "θ = {th}: {shear:?} against {expected:?}"
            );
        }
    }
    // A spring already in the plane is kept bit for bit; one along the
    // normal has no tangent part and becomes zero.
    let mut flat = [a, -2.0 * a, 0.0];
    FrictionPair::turn_spring(&mut flat, [0.0, 0.0, 1.0]);
    assert_eq!(flat, [a, -2.0 * a, 0.0]);
    let mut upright = [0.0, 0.0, a];
    FrictionPair::turn_spring(&mut upright, [0.0, 0.0, 1.0]);
    assert_eq!(upright, [0.0; 3]);
}

/// A spring whose |δ|² is subnormal (round-off slips of spheres at rest:
/// a touching FCC bed with Mindlin friction blew up to NaN this way) turns
/// like any other: δ = a x̂ with a = 1e-155 m (a² = 1e-310 < 2.2e-308) and
/// the normal turned by θ = 1e-5 (the small-turn test holds, and there
/// 1/|δ|² = ∞). The closed form of the test above, a (cos θ, 0, −sin θ);
/// tolerance 1e-6 of a: a² and (δ·n)² = 1e-320 are subnormals, kept to
/// ~1e-2 and ~1e-4 of themselves (the factor |δ|/|p| is 1 + 5e-11, so
/// the result is the projection to that precision: 1e-6 is loose).
#[test]
fn a_spring_with_a_subnormal_square_turns_to_a_finite_spring() {
    let a = 1.0e-155;
    let th = 1.0e-5f64;
    let mut shear = [a, 0.0, 0.0];
    FrictionPair::turn_spring(&mut shear, [th.sin(), 0.0, th.cos()]);
    let expected = [a * th.cos(), 0.0, -a * th.sin()];
    for c in 0..3 {
        assert!(
            (shear[c] - expected[c]).abs() < 1e-6 * a,
            "{shear:?} against {expected:?}"
        );
    }
}

#[test]
fn tangential_damping_has_the_normal_damping_ratio() {
    // Linear + viscous (formula, attractive: ξ = −ln e/√(π² + ln² e)):
    // η_t = 2 ξ √(k_t m*).
    let e: f64 = 0.7;
    let xi = -e.ln() / (std::f64::consts::PI.powi(2) + e.ln().powi(2)).sqrt();
    let r = 1.0e-3;
    let m = GLASS.sphere_mass(r);
    let (_, f) = setup(
        NormalLaw::Linear,
        Damping::new(DampingKind::Viscous, Dissipation::Restitution(e)),
        TangentialKind::Linear,
        0.5,
    );
    let h = 1.0e-6;
    let k_t = f.tangential().stiffness(h);
    let expected = 2.0 * xi * (k_t * m).sqrt();
    assert!((f.damping_coefficient(h, k_t) / expected - 1.0).abs() < 1e-14);
    // Hertz + Tsuji (formula): LIGGGHTS's γ_t = 2 √(5/6) |β| √(S_t m*),
    // S_t = 8 G* √(R h), β = ln e/√(ln² e + π²).
    let (_, f) = setup(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(e)),
        TangentialKind::Mindlin,
        0.5,
    );
    let s_t = 8.0 * effective_shear_modulus(&GLASS, &GLASS) * (r * h).sqrt();
    let expected = 2.0 * (5.0f64 / 6.0).sqrt() * xi * (s_t * m).sqrt();
    let k_t = f.tangential().stiffness(h);
    assert!((f.damping_coefficient(h, k_t) / expected - 1.0).abs() < 1e-14);
    // Undamped: none.
    let (_, f) = setup(
        NormalLaw::Hertz,
        Damping::NONE,
        TangentialKind::Mindlin,
        0.5,
    );
    assert_eq!(f.damping_coefficient(h, k_t), 0.0);
}

#[test]
fn without_tangential_damping_a_sticking_contact_is_the_spring_alone() {
    // Hertz + Tsuji (e = 0.5), μ = 0.3: with the dashpot the sticking force
    // is −k_t δ − η_t v_t; without it exactly −k_t δ (LIGGGHTS
    // `tangential_damping off`), the rolling damping ratio unchanged.
    let (law, f) = setup(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        TangentialKind::Mindlin,
        0.3,
    );
    let off = f.without_tangential_damping();
    let h = 1.0e-6;
    let k_t = f.tangential().stiffness(h);
    assert!(f.damping_coefficient(h, k_t) > 0.0);
    assert_eq!(off.damping_coefficient(h, k_t), 0.0);
    // A small slip under a large normal force: sticking in both.
    let (n, v, dt) = ([0.0, 0.0, 1.0], [1.0e-3, 0.0, 0.0], 1.0e-7);
    let (mut s_on, mut s_off) = ([0.0; 3], [0.0; 3]);
    let on = f.tangential_force(h, 10.0, n, v, dt, &mut s_on);
    let spring = off.tangential_force(h, 10.0, n, v, dt, &mut s_off);
    assert_eq!(s_on, s_off, "the same spring");
    assert_eq!(spring, [-k_t * s_off[0], 0.0, 0.0]);
    let eta = f.damping_coefficient(h, k_t);
    assert!((on[0] / (-k_t * s_on[0] - eta * v[0]) - 1.0).abs() < 1e-15);
    // The rolling spring keeps its dashpot: the same torque with μ_r > 0.
    let r = 1.0e-3;
    let m = GLASS.sphere_mass(r);
    let pair = PairProperties::sphere_plane(r, m, &GLASS, &GLASS);
    let model = FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.3,
        rolling_friction: 0.1,
    };
    let rolling = model.pair(
        &law,
        &pair,
        effective_shear_modulus(&GLASS, &GLASS),
        0.3,
        0.1,
    );
    let spin = [0.0, 50.0, 0.0];
    let (mut h_on, mut h_off) = ([0.0; 3], [0.0; 3]);
    let t_on = rolling.rolling_torque(&law, h, 10.0, n, spin, 1e-12, dt, &mut h_on);
    let t_off = rolling
        .without_tangential_damping()
        .rolling_torque(&law, h, 10.0, n, spin, 1e-12, dt, &mut h_off);
    assert_eq!(t_on, t_off);
    assert!(norm(t_on) > 0.0);
    // Undamped: nothing to remove.
    let (_, undamped) = setup(
        NormalLaw::Hertz,
        Damping::NONE,
        TangentialKind::Mindlin,
        0.3,
    );
    assert_eq!(undamped.without_tangential_damping(), undamped);
}

#[test]
fn tangentially_undamped_says_whether_the_dashpot_acts() {
    // The accessor against η_t itself (`damping_coefficient`, the
    // closed forms of `tangential_damping_has_the_normal_damping_ratio`):
    // undamped exactly when η_t = 0 at a contact's overlap.
    let (h, e) = (1.0e-6, 0.5);
    let laws = [
        (
            NormalLaw::Hertz,
            Damping::NONE,
            TangentialKind::Mindlin,
            false,
        ),
        (
            NormalLaw::Linear,
            Damping::NONE,
            TangentialKind::Linear,
            false,
        ),
        (
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(e)),
            TangentialKind::Mindlin,
            true,
        ),
        (
            NormalLaw::Linear,
            Damping::new(DampingKind::Viscous, Dissipation::Restitution(e)),
            TangentialKind::Linear,
            true,
        ),
    ];
    for (law, damping, kind, damped) in laws {
        let (_, f) = setup(law, damping, kind, 0.3);
        let k_t = f.tangential().stiffness(h);
        assert_eq!(f.tangentially_undamped(), !damped, "{law:?} {damping:?}");
        assert_eq!(f.damping_coefficient(h, k_t) == 0.0, !damped);
        // Without the dashpot: undamped, whatever the normal damping.
        let off = f.without_tangential_damping();
        assert!(off.tangentially_undamped(), "{law:?} {damping:?} off");
        assert_eq!(off.damping_coefficient(h, k_t), 0.0);
    }
}

#[test]
fn registry_names_and_checks() {
    assert_eq!(
        TangentialKind::from_name("mindlin"),
        Some(TangentialKind::Mindlin)
    );
    assert_eq!(
        TangentialKind::from_name("linear"),
        Some(TangentialKind::Linear)
    );
    assert_eq!(
        TangentialKind::from_name("mindlin_force"),
        Some(TangentialKind::MindlinForce)
    );
    assert_eq!(TangentialKind::from_name("hooke"), None);
    assert_eq!(
        tangential_names(),
        "\"mindlin\", \"linear\", \"mindlin_force\""
    );
    let m = FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: -0.1,
        rolling_friction: 0.0,
    };
    let err = m.validate().unwrap_err();
    assert_eq!(err.key, "contact.friction");
    let m = FrictionModel {
        friction: 0.3,
        rolling_friction: f64::NAN,
        ..m
    };
    assert_eq!(m.validate().unwrap_err().key, "contact.rolling_friction");
}

#[test]
fn sliding_with_damping_transmits_exactly_the_limit_along_the_slip() {
    // Near onset the damping η_t v_t exceeds the tiny limit μ F_n; the
    // force must still be μ F_n against the slip (not a spring turned
    // against it), at every step of a growing normal force.
    let e: f64 = 0.5;
    let (_, f) = setup(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(e)),
        TangentialKind::Mindlin,
        0.3,
    );
    let n = [0.0, 0.0, 1.0];
    let mut shear = [0.0; 3];
    for k in 1..200 {
        let h = 1.0e-9 * k as f64;
        let fn_ = 1.0e-4 * k as f64;
        let force = f.tangential_force(h, fn_, n, [5.0, 0.0, 0.0], 1.0e-7, &mut shear);
        assert!(
            (force[0] / (-0.3 * fn_) - 1.0).abs() < 1e-14,
            "step {k}: {force:?}"
        );
        assert!(shear[0] > 0.0);
    }
}

/// A spring exactly at the Coulomb limit sticks: sliding is k_t |δ| > μ |F_n|,
/// strictly (LIGGGHTS `tangential_model_history`'s `Ft_shear >
/// Ft_friction`, LAMMPS mindlin's `magfs > Fscrit`). k_t = 4 N/m, δ =
/// (1.5, 2, 0) m (|δ|² = 6.25, |δ| = 2.5) and μ |F_n| = 10 N are exact in
/// binary, so k_t² |δ|² = 100 = limit² exactly. Sticking with the
/// dashpot, the force is spring plus dashpot capped at the limit:
/// 10 (−k_t δ − η_t v)/|−k_t δ − η_t v| with v ⊥ δ; sliding would give
/// −k_t δ alone. A few roundings of numbers of order 10: 1e-14 N.
#[test]
fn a_spring_exactly_at_the_limit_sticks() {
    let moved = MovedSpring {
        stiffness: 4.0,
        limit: 10.0,
        stretch: 6.25,
    };
    assert_eq!(moved.cut(), (false, 1.0));
    let (_, f) = setup(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        TangentialKind::Mindlin,
        0.3,
    );
    let h = 1.0e-6;
    let eta = f.damping_coefficient(h, 4.0);
    assert!(eta > 0.0);
    let v = [2.0, -1.5, 0.0];
    let mut shear = [1.5, 2.0, 0.0];
    let (sliding, s) = moved.cut();
    let force = f.cut_spring_force(&moved, sliding, s, h, v, &mut shear);
    assert_eq!(shear, [1.5, 2.0, 0.0], "the spring is not cut");
    let sum = [-6.0 - eta * 2.0, -8.0 + eta * 1.5, 0.0];
    let magnitude = norm(sum);
    for (f, s) in force.iter().zip(sum) {
        assert!((f - 10.0 * s / magnitude).abs() < 1e-14, "{force:?}");
    }
}

#[test]
fn spring_energy_closed_forms() {
    // Tangential: ½ k_t(h) |δ|² (Mindlin k_t = 8 G* √(R h)); rolling:
    // ½ |M_r|²/k_r, k_r = 2.25 (F_n(h)/h) μ_r² R² with Hertz F_n = k h^(3/2),
    // k = E_eff √R. A few roundings: 1e-14.
    let (law, f) = setup(
        NormalLaw::Hertz,
        Damping::NONE,
        TangentialKind::Mindlin,
        0.5,
    );
    let h: f64 = 2.0e-6;
    let r = 1.0e-3;
    let shear = [3.0e-7, -4.0e-7, 0.0];
    let k_t = 8.0 * effective_shear_modulus(&GLASS, &GLASS) * (r * h).sqrt();
    let expected = 0.5 * k_t * 25.0e-14;
    let e = f.spring_energy(&law, h, &shear, &[0.0; 3]);
    assert!((e / expected - 1.0).abs() < 1e-14, "{e} vs {expected}");
    // Apart: nothing stored.
    assert_eq!(f.spring_energy(&law, -1.0e-9, &shear, &[0.0; 3]), 0.0);
    // Rolling spring.
    let m = GLASS.sphere_mass(r);
    let pair = PairProperties::sphere_plane(r, m, &GLASS, &GLASS);
    let mu_r = 0.2;
    let f = FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.5,
        rolling_friction: mu_r,
    }
    .pair(
        &law,
        &pair,
        effective_shear_modulus(&GLASS, &GLASS),
        0.5,
        mu_r,
    );
    let k = effective_modulus(&GLASS, &GLASS) * r.sqrt();
    let k_r = 2.25 * (k * h.sqrt()) * mu_r * mu_r * r * r;
    let torque = [0.0, 2.0e-6, 0.0];
    let e = f.spring_energy(&law, h, &[0.0; 3], &torque);
    let expected = 0.5 * 4.0e-12 / k_r;
    assert!((e / expected - 1.0).abs() < 1e-14, "{e} vs {expected}");
}

#[test]
fn the_applied_force_is_recovered_from_the_stored_spring() {
    // A damped Mindlin contact whose slip turns by 0.3 rad a step,
    // alternating between sliding (5 m/s at F_n = 1e-2 N) and sticking
    // (1e-6 m/s at 1e-1 N): from the spring each step stored, the applied
    // force is
    // what the step returned, bit for bit. (A re-evaluation through a
    // zero-length step would see a spring cut to the limit at, or a
    // rounding below, the limit and add the dashpot, turning the force
    // toward the slip.)
    let (_, f) = setup(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        TangentialKind::Mindlin,
        0.3,
    );
    let n = [0.0, 0.0, 1.0];
    let h = 1.0e-7;
    let mut shear = [0.0; 3];
    let mut sliding = 0;
    for k in 0..200 {
        let (speed, fn_) = if k % 7 < 4 {
            (5.0, 1.0e-2)
        } else {
            (1.0e-6, 1.0e-1)
        };
        let a = 0.3 * k as f64;
        let v = [speed * a.cos(), speed * a.sin(), 0.0];
        let applied = f.tangential_force(h, fn_, n, v, 1.0e-7, &mut shear);
        if (norm(applied) / (0.3 * fn_) - 1.0).abs() < 1e-12 {
            sliding += 1;
        }
        let recovered = f.applied_tangential_force(h, fn_, n, v, shear);
        assert_eq!(applied, recovered, "step {k}");
    }
    // Both branches were exercised.
    assert!(sliding > 50 && sliding < 200, "{sliding}");
}

#[test]
fn the_applied_rolling_torque_is_recovered_from_the_stored_spring() {
    // As above for the rolling spring (μ_r = 0.2, the rolling dashpot of
    // the Tsuji ratio): a relative spin that turns and alternates between
    // rolling at the limit (1e4 rad/s at F_n = 1e-2 N) and holding
    // (1e-6 rad/s at 1e-1 N).
    let (law, _) = setup(
        NormalLaw::Hertz,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.5)),
        TangentialKind::Mindlin,
        0.5,
    );
    let r = 1.0e-3;
    let pair = PairProperties::sphere_plane(r, GLASS.sphere_mass(r), &GLASS, &GLASS);
    let f = FrictionModel {
        tangential: TangentialKind::Mindlin,
        friction: 0.5,
        rolling_friction: 0.2,
    }
    .pair(
        &law,
        &pair,
        effective_shear_modulus(&GLASS, &GLASS),
        0.5,
        0.2,
    );
    let n = [0.0, 0.0, 1.0];
    let (h, inertia) = (1.0e-7, 1.0e-12);
    let mut spring = [0.0; 3];
    let mut limited = 0;
    for k in 0..200 {
        let (speed, fn_) = if k % 7 < 4 {
            (1.0e4, 1.0e-2)
        } else {
            (1.0e-6, 1.0e-1)
        };
        let a = 0.3 * k as f64;
        let w = [speed * a.cos(), speed * a.sin(), 0.0];
        let applied = f.rolling_torque(&law, h, fn_, n, w, inertia, 1.0e-7, &mut spring);
        if (norm(applied) / (0.2 * r * fn_) - 1.0).abs() < 1e-12 {
            limited += 1;
        }
        let recovered = f.applied_rolling_torque(&law, h, fn_, n, w, inertia, spring);
        assert_eq!(applied, recovered, "step {k}");
    }
    assert!(limited > 50 && limited < 200, "{limited}");
}
