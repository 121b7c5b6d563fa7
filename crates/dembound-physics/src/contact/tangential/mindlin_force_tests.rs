//! The incremental spring against LAMMPS's `mindlin/force` recurrence
//! written out by hand, and against the total spring ([`super::super::mindlin`]).

use crate::contact::tangential::{
    effective_shear_modulus, FrictionModel, FrictionPair, TangentialKind,
};
use crate::contact::{Calibration, ContactModel, Damping, DampingKind, Dissipation, NormalLaw};
use crate::material::{Material, PairProperties};

const GLASS: Material = Material {
    density: 2500.0,
    youngs_modulus: 7.0e10,
    poisson_ratio: 0.25,
};

/// Sphere radius (m): a 1 mm glass sphere on a glass plane, R_eff = R.
const R: f64 = 1.0e-3;

/// The scripted contacts' time step (s).
const DT: f64 = 5.0e-8;

fn friction(damping: Damping, kind: TangentialKind, mu: f64) -> FrictionPair {
    let pair = PairProperties::sphere_plane(R, GLASS.sphere_mass(R), &GLASS, &GLASS);
    let model = ContactModel {
        calibration: Calibration::Formula,
        ..ContactModel::damped(NormalLaw::Hertz, damping)
    };
    let law = model.pair(&pair);
    let g = effective_shear_modulus(&GLASS, &GLASS);
    FrictionModel {
        tangential: kind,
        friction: mu,
        rolling_friction: 0.0,
    }
    .pair(&law, &pair, g, mu, 0.0)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A scripted contact: overlap h_k (m), normal force F_n,k (N, Hertz-like,
/// only its size matters here) and slip v_k (m/s, in the plane z = 0) at
/// step k = 1..=n. The slip turns through a full circle and back, so the
/// spring loads, reaches the Coulomb limit, slides and unloads.
fn script(n: usize, growing: bool) -> Vec<(f64, f64, [f64; 3])> {
    (1..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let h = if growing {
                1.0e-7 * (1.0 + 4.0 * t)
            } else {
                3.0e-7
            };
            let fn_ = 1.0e9 * h.powf(1.5);
            let angle = 2.0 * std::f64::consts::PI * t;
            let v = 2.0e-2 * if t < 0.7 { 1.0 } else { -1.5 };
            (h, fn_, [v * angle.cos(), v * angle.sin(), 0.0])
        })
        .collect()
}

#[test]
fn undamped_it_is_lammps_mindlin_force_step_by_step() {
    // LAMMPS GranSubModTangentialMindlin::calculate_forces with
    // mindlin_force = 1 (src/GRANULAR/gran_sub_mod_tangential.cpp), the
    // normal fixed (no frame turn), x_γ,t = 0 (damp = 0):
    //   k_scaled = k · contact_radius, k = 8 G*, contact_radius = √(R h)
    //   history += (−k_scaled dt) vtr
    //   fs = history + (−damp) vtr
    //   if |fs| > Fscrit = μ |F_n|: fs *= Fscrit/|fs|; history = fs − fdamp
    // Ours takes k_t as (8 G* √R) √h, LAMMPS as 8 G* √(R h): the two k_t
    // differ by a few ulp each step and the force is a sum of up to 400
    // increments (and their cuts), so 400 × 4 ulp ≈ 4e-13 relative bounds
    // the drift; 1e-12 of the Coulomb limit's size is far below any step's
    // increment (≥ 1e-4 of it).
    let mu = 0.3;
    let f = friction(Damping::NONE, TangentialKind::MindlinForce, mu);
    let k = 8.0 * effective_shear_modulus(&GLASS, &GLASS);
    let dt = DT;
    let n = [0.0, 0.0, 1.0];
    let mut ours = [0.0; 3];
    let mut history = [0.0f64; 3];
    let mut slid = 0;
    for (h, fn_, vtr) in script(400, true) {
        let got = f.tangential_force(h, fn_, n, vtr, dt, &mut ours);
        let k_scaled = k * (R * h).sqrt();
        for a in 0..3 {
            history[a] += -k_scaled * dt * vtr[a];
        }
        let fdamp = [-0.0 * vtr[0], -0.0 * vtr[1], -0.0 * vtr[2]];
        let mut fs = [
            history[0] + fdamp[0],
            history[1] + fdamp[1],
            history[2] + fdamp[2],
        ];
        let fscrit = mu * fn_;
        let magfs = dot(fs, fs).sqrt();
        if magfs > fscrit {
            slid += 1;
            for x in &mut fs {
                *x *= fscrit / magfs;
            }
            history = [fs[0] - fdamp[0], fs[1] - fdamp[1], fs[2] - fdamp[2]];
        }
        for a in 0..3 {
            assert!(
                (got[a] - fs[a]).abs() <= 1e-12 * fscrit,
                "{a}: {got:?} {fs:?}"
            );
            assert!((ours[a] - history[a]).abs() <= 1e-12 * fscrit);
        }
    }
    // The script both sticks and slides.
    assert!(slid > 20 && slid < 380, "{slid}");
}

#[test]
fn at_a_constant_overlap_the_incremental_and_total_springs_agree() {
    // At a fixed h, k_t is fixed: F_s = −k_t Σ v Δt = −k_t δ, sticking, and
    // both cut the spring to the limit along itself when sliding (the same
    // order of Coulomb and dashpot): the same force throughout, to the
    // rounding of a sum of 400 increments taken in two orders (k_t (Σ v Δt)
    // against Σ (k_t v Δt): 400 × 2 ulp ≈ 2e-13 of the limit; 1e-12).
    // With and without the tangential dashpot.
    for damping in [
        Damping::NONE,
        Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.7)),
    ] {
        let incremental = friction(damping, TangentialKind::MindlinForce, 0.3);
        let total = friction(damping, TangentialKind::Mindlin, 0.3);
        let n = [0.0, 0.0, 1.0];
        let (mut fs, mut delta) = ([0.0; 3], [0.0; 3]);
        let mut slid = 0;
        for (h, fn_, v) in script(400, false) {
            let a = incremental.tangential_force(h, fn_, n, v, DT, &mut fs);
            let b = total.tangential_force(h, fn_, n, v, DT, &mut delta);
            let limit = 0.3 * fn_;
            if (dot(a, a).sqrt() - limit).abs() < 1e-9 * limit {
                slid += 1;
            }
            let k_t = total.tangential().stiffness(h);
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= 1e-12 * limit,
                    "{damping:?} {a:?} {b:?}"
                );
                // The stored force is the total spring's −k_t δ.
                assert!((fs[c] + k_t * delta[c]).abs() <= 1e-12 * limit);
            }
            // Its energy ½ |F_s|²/k_t is the total spring's ½ k_t |δ|².
            let (ea, eb) = (
                incremental.spring_energy(&law_of(damping), h, &fs, &[0.0; 3]),
                total.spring_energy(&law_of(damping), h, &delta, &[0.0; 3]),
            );
            assert!((ea - eb).abs() <= 1e-11 * eb.max(1e-300), "{ea} {eb}");
        }
        assert!(slid > 20 && slid < 380, "{slid}");
    }
}

fn law_of(damping: Damping) -> crate::contact::PairLaw {
    let pair = PairProperties::sphere_plane(R, GLASS.sphere_mass(R), &GLASS, &GLASS);
    ContactModel {
        calibration: Calibration::Formula,
        ..ContactModel::damped(NormalLaw::Hertz, damping)
    }
    .pair(&pair)
}

#[test]
fn under_a_growing_overlap_they_differ_by_the_stiffness_history() {
    // Constant slip v along x, h_j growing, sticking (μ large): the
    // incremental force is −v Δt Σ_j k_t(h_j), the total spring's
    // −k_t(h_m) m v Δt; their difference after m steps is
    // v Δt Σ_j (k_t(h_m) − k_t(h_j)) (> 0: the total spring stiffens the
    // whole displacement). Each side a sum of m = 300 terms: 1e-12.
    let incremental = friction(Damping::NONE, TangentialKind::MindlinForce, 1.0e6);
    let total = friction(Damping::NONE, TangentialKind::Mindlin, 1.0e6);
    let k = |h: f64| 8.0 * effective_shear_modulus(&GLASS, &GLASS) * (R * h).sqrt();
    let (v, dt) = (1.0e-2, 1.0e-8);
    let n = [0.0, 0.0, 1.0];
    let (mut fs, mut delta) = ([0.0; 3], [0.0; 3]);
    let mut hs = Vec::new();
    for j in 1..=300 {
        let h = 1.0e-7 * (1.0 + j as f64 / 100.0);
        hs.push(h);
        let a = incremental.tangential_force(h, 1.0, n, [v, 0.0, 0.0], dt, &mut fs);
        let b = total.tangential_force(h, 1.0, n, [v, 0.0, 0.0], dt, &mut delta);
        let expected: f64 = hs.iter().map(|&hj| v * dt * (k(h) - k(hj))).sum();
        let scale = b[0].abs();
        assert!(((a[0] - b[0]) - expected).abs() <= 1e-12 * scale, "{j}");
    }
    // Not a rounding: at the end the total spring is 1.3 times larger
    // (k_t(4e-7)/mean k_t over the loading, √4/((2/3)(4^1.5 − 1)/3) ≈ 1.29).
    let a = incremental.tangential_force(hs[299], 1.0, n, [0.0; 3], 0.0, &mut fs);
    let b = total.tangential_force(hs[299], 1.0, n, [0.0; 3], 0.0, &mut delta);
    assert!((b[0] / a[0] - 1.29).abs() < 0.01, "{}", b[0] / a[0]);
}

#[test]
fn the_applied_force_is_the_stored_force_when_sliding() {
    // After a sliding step the stored force is the applied one, of size
    // μ |F_n| (to the cut's rounding); re-evaluated through a step of zero
    // length a sticking one gives the same force as the step did.
    let damping = Damping::new(DampingKind::Tsuji, Dissipation::Restitution(0.7));
    let f = friction(damping, TangentialKind::MindlinForce, 0.3);
    let n = [0.0, 0.0, 1.0];
    let (h, fn_) = (3.0e-7, 0.4);
    let mut fs = [0.0; 3];
    let v = [1.0, 0.5, 0.0];
    let applied = f.tangential_force(h, fn_, n, v, 1.0e-6, &mut fs);
    assert!((dot(applied, applied).sqrt() / (0.3 * fn_) - 1.0).abs() < 1e-15);
    assert_eq!(f.applied_tangential_force(h, fn_, n, v, fs), applied);
    // The cut lands within a few ulp of the limit, either side: a spring
    // 1e-14 below it is still the sliding force (re-evaluated it would get
    // the dashpot and turn).
    let below = fs.map(|x| x * (1.0 - 1.0e-14));
    assert_eq!(f.applied_tangential_force(h, fn_, n, v, below), below);
    let mut fs = [0.0; 3];
    let v = [1.0e-4, 0.0, 0.0];
    let applied = f.tangential_force(h, fn_, n, v, DT, &mut fs);
    assert!(dot(applied, applied).sqrt() < 0.3 * fn_);
    assert_eq!(f.applied_tangential_force(h, fn_, n, v, fs), applied);
}
