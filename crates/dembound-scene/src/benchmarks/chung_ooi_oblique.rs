//! Chung & Ooi (2011) Tests 4–8: oblique and spinning impacts with
//! friction, Hertz–Mindlin as the engine runs it (LIGGGHTS's
//! `tangential_model history`: k_t = 8 G* √(R* h), the spring cut back to
//! μ F_n, a tangential dashpot beside the Tsuji normal one). That is not
//! Mindlin–Deresiewicz (no load-history dependence of the tangential
//! stiffness, no micro-slip annulus): the codes of the paper mostly ran
//! the same simplification, which is why their curves agree.
//!
//! References: the rigid-body limit for an impact that slides throughout
//! ([`super::closed_form`], exact for this model up to round-off, with the
//! run's own normal restitution), checked where the incident slip exceeds
//! the threshold (7/2) μ (1 + e) v_n by 30 % (the spring reaches the
//! Coulomb limit at the onset there); the paper's curves as digitised
//! ([`super::digitised`]) over the whole range, where the sticking regime
//! depends on the tangential law.

use super::chung_ooi::{describe, named, steps_per_contact, Named, SOURCE};
use super::closed_form::{hertz_impact, sliding_threshold, Body};
use super::digitised::{self, interpolate};
use super::impact::{Ball, Impact, Target};
use super::peer::{LAMMPS_T5_STEEL, LAMMPS_T6_ALLOY};
use super::{Band, Check, Curve, Outcome, Plot, Style};
use crate::SceneError;
use dembound_physics::contact::{
    ContactModel, Damping, DampingKind, Dissipation, NormalLaw, HERTZ_CONTACT_TIME_FACTOR,
};
use dembound_physics::material::Material;

const YADE4: &str = "Yade Test4.py";
const ASSUMED: &str = "assumed: not found in a source; E and ρ scale out of the normalised results";

/// Round-off band of the sliding closed form, in the normalised unit.
const SLIDING_BAND: f64 = 1e-6;
/// Margin over the sliding threshold for the closed-form checks.
const MARGIN: f64 = 1.3;
/// Two spheres: the line of centres turns while they slide past each
/// other, by φ ≈ v_cp T_c/(R₁ + R₂) (≈ 7e-3 rad at 85°: 2 mm on 0.3 m),
/// while the rigid-body theory and the plane keep the normal fixed; the
/// turn mixes normal and tangential components by sin φ, so the
/// deviations are of order φ times the ratio of the components. 1e-3
/// (a seventh of φ at the largest angle); measured 3.7e-5 against the
/// closed form and 3.6e-4 against the plane (the recoil tangent, ≈ 18.7
/// at 85°), at T_c/4000 and T_c/20,000 alike: geometry, not integration.
const TURNING_BAND: f64 = 1e-3;

fn contact(e: f64) -> ContactModel {
    if e < 1.0 {
        ContactModel::damped(
            NormalLaw::Hertz,
            Damping::new(DampingKind::Tsuji, Dissipation::Restitution(e)),
        )
    } else {
        ContactModel::elastic(NormalLaw::Hertz)
    }
}

fn body(n: &Named, r: f64) -> Body {
    Body {
        youngs_modulus: n.material.youngs_modulus,
        poisson_ratio: n.material.poisson_ratio,
        radius: r,
        mass: n.material.sphere_mass(r),
    }
}

const RIGID: Body = Body {
    youngs_modulus: f64::INFINITY,
    poisson_ratio: 0.0,
    radius: f64::INFINITY,
    mass: f64::INFINITY,
};

/// A sphere on the rigid plane z = 0 with centre tangential velocity
/// `vt` along x, normal approach `vn` and spin ω_y = `spin`; returns
/// (v_x', v_z', ω_y'). In this frame the contact point moves at
/// v_x − R ω_y.
#[allow(clippy::too_many_arguments)]
fn on_plane(
    m: &Named,
    r: f64,
    vn: f64,
    vt: f64,
    spin: f64,
    e: f64,
    mu: f64,
    quick: bool,
) -> Result<(f64, f64, f64), SceneError> {
    let h = hertz_impact(body(m, r), RIGID, vn);
    let dt = HERTZ_CONTACT_TIME_FACTOR * h.max_overlap / vn / steps_per_contact(quick);
    let out = Impact {
        ball: Ball {
            material: m.material,
            radius: r,
            velocity: [vt, 0.0, -vn],
            spin: [0.0, spin, 0.0],
        },
        target: Target::Plane(Material::rigid(m.material.density)),
        contact: contact(e),
        friction: Some(mu),
        dt,
        approach_speed: vn,
        contact_time: h.duration,
    }
    .run()?;
    Ok((out.velocity[0][0], out.velocity[0][2], out.spin[0][1]))
}

/// Largest |ours − digitised| over the digitised range, and the count.
fn worst_against(ours: &[(f64, f64)], published: &[(f64, f64)]) -> (f64, usize) {
    let mut worst = 0.0f64;
    let mut n = 0;
    for &(x, y) in ours {
        if let Some(p) = interpolate(published, x) {
            worst = worst.max((y - p).abs());
            n += 1;
        }
    }
    (worst, n)
}

fn angles(quick: bool) -> Vec<f64> {
    if quick {
        // One sticking, one near the minimum, two sliding (Tests 4, 6, 8).
        vec![10.0, 25.0, 60.0, 80.0]
    } else {
        (1..=17).map(|k| 5.0 * k as f64).collect()
    }
}

pub(super) fn test4(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let oxide = named("aluminium oxide", 3.8e11, 0.23, 4000.0, YADE4);
    let alloy = named("aluminium alloy", 7.0e10, 0.33, 2700.0, YADE4);
    let (r, v, mu, e) = (0.0025, 3.9, 0.092, 0.98);
    let mut checks = Vec::new();
    let mut et_curves = Vec::new();
    let mut w_curves = Vec::new();
    let mut a_curves = Vec::new();
    let materials: Vec<Named> = if quick {
        vec![oxide]
    } else {
        vec![oxide, alloy]
    };
    for (g, m) in materials.iter().enumerate() {
        let (mut et_pts, mut w_pts, mut a_pts) = (Vec::new(), Vec::new(), Vec::new());
        let mut worst_slide = 0.0f64;
        for deg in angles(quick) {
            progress(&format!("chung-ooi-4: {} at {deg}°", m.name));
            let th = f64::to_radians(deg);
            let (vn, vt) = (v * th.cos(), v * th.sin());
            let (vx, vz, wy) = on_plane(m, r, vn, vt, 0.0, e, mu, quick)?;
            let et = vx / vt;
            let spin = -wy; // the paper's sign: negative in the rolling sense
            let slip = vx - r * wy;
            let angle = (slip / vz).atan().to_degrees();
            et_pts.push((deg, et));
            w_pts.push((deg, spin));
            a_pts.push((deg, angle));
            if vt >= MARGIN * sliding_threshold(mu, e, vn) {
                let e_run = vz / vn;
                let et_cf = 1.0 - mu * (1.0 + e_run) / th.tan();
                let w_cf = -2.5 * mu * (1.0 + e_run) * vn / r;
                worst_slide = worst_slide
                    .max((et - et_cf).abs())
                    .max((spin - w_cf).abs() * r / vt);
            }
        }
        checks.push(Check::new(
            format!(
                "{}: sliding angles, largest |Δe_t|, |RΔω'|/v_t from the closed form",
                m.name
            ),
            "1",
            worst_slide,
            0.0,
            Band::Absolute(SLIDING_BAND),
            "rigid-body sliding limit (closed_form.rs)",
        ));
        if g == 0 {
            // The digitised curves are the oxide's (the alloy's lie within
            // 0.01 of them in the paper).
            let bands = [(0.03, "1"), (30.0, "rad/s"), (2.0, "degree")];
            for ((what, pts, published), (band, unit)) in [
                (
                    "e_t = v_t'/v_t",
                    &et_pts,
                    &digitised::T4_TANGENTIAL_RESTITUTION[..],
                ),
                ("ω'", &w_pts, &digitised::T4_SPIN[..]),
                ("rebound angle", &a_pts, &digitised::T4_REBOUND_ANGLE[..]),
            ]
            .into_iter()
            .zip(bands)
            {
                let (worst, n) = worst_against(pts, published);
                checks.push(Check::new(
                    format!("{}: largest |{what} − paper| over {n} angles", m.name),
                    unit,
                    worst,
                    0.0,
                    Band::Absolute(band),
                    "paper's curve, digitised by Kratos (benchmark4_graph*.dat)",
                ));
            }
        }
        et_curves.push(Curve::new(
            format!("ours: {}", m.name),
            et_pts,
            Style::Ours,
            g,
        ));
        w_curves.push(Curve::new(
            format!("ours: {}", m.name),
            w_pts,
            Style::Ours,
            g,
        ));
        a_curves.push(Curve::new(
            format!("ours: {}", m.name),
            a_pts,
            Style::Ours,
            g,
        ));
    }
    // The closed forms over the sliding range, with the target e.
    let th0 = (MARGIN * 3.5 * mu * (1.0 + e)).atan().to_degrees();
    let sl: Vec<f64> = (0..=40)
        .map(|k| th0 + (89.0 - th0) * k as f64 / 40.0)
        .collect();
    let t = |d: f64| d.to_radians();
    et_curves.push(Curve::new(
        "closed form (sliding)",
        sl.iter()
            .map(|&d| (d, 1.0 - mu * (1.0 + e) / t(d).tan()))
            .collect(),
        Style::ClosedForm,
        7,
    ));
    w_curves.push(Curve::new(
        "closed form (sliding)",
        sl.iter()
            .map(|&d| (d, -2.5 * mu * (1.0 + e) * v * t(d).cos() / r))
            .collect(),
        Style::ClosedForm,
        7,
    ));
    a_curves.push(Curve::new(
        "closed form (sliding)",
        sl.iter()
            .map(|&d| {
                (
                    d,
                    ((t(d).tan() - 3.5 * mu * (1.0 + e)) / e)
                        .atan()
                        .to_degrees(),
                )
            })
            .collect(),
        Style::ClosedForm,
        7,
    ));
    et_curves.push(Curve::new(
        "paper (digitised)",
        digitised::T4_TANGENTIAL_RESTITUTION.to_vec(),
        Style::Published,
        6,
    ));
    w_curves.push(Curve::new(
        "paper (digitised)",
        digitised::T4_SPIN.to_vec(),
        Style::Published,
        6,
    ));
    a_curves.push(Curve::new(
        "paper (digitised)",
        digitised::T4_REBOUND_ANGLE.to_vec(),
        Style::Published,
        6,
    ));
    let plot = |stem: &str, title: &str, y: &str, curves| Plot {
        stem: stem.into(),
        title: title.into(),
        x_label: "incident angle from the normal θ (degree)".into(),
        y_label: y.into(),
        curves,
    };
    Ok(Outcome {
        name: "chung-ooi-4",
        title: "Oblique impact on a rigid plane: constant speed, varying incident angle",
        source: SOURCE,
        parameters: vec![
            describe(&oxide),
            describe(&alloy),
            format!("R = {r} m, {v} m/s at θ = 5°–85° from the normal, no spin; μ = {mu}, e = {e} (Yade Test4.py; Kratos Benchmark4: 3.9 m/s, R = 2.5 mm)"),
            format!("rigid plane; Hertz + Tsuji damping (e exact), Mindlin spring; Δt = T_c/{}", steps_per_contact(quick)),
        ],
        notes: vec![
            "e_t is the centre's tangential restitution v_t'/v_t, as in the paper's figure and Kratos's script; the rebound angle is the contact point's, atan((v_t' − R ω')/v_n').".into(),
            "Bands against the digitised curve: 0.03 in e_t, 30 rad/s in ω' (5 % of its range), 2° in the angle: the paper's codes spread by about this much in the sticking regime (θ < 30°), where the result depends on the tangential law.".into(),
        ],
        checks,
        plots: vec![
            plot("chung-ooi-4-et", "Test 4: tangential restitution", "v_t'/v_t (1)", et_curves),
            plot("chung-ooi-4-spin", "Test 4: rebound spin", "ω' (rad/s, negative: rolling sense)", w_curves),
            plot("chung-ooi-4-angle", "Test 4: rebound angle of the contact point", "rebound angle (degree)", a_curves),
        ],
        seconds: 0.0,
    })
}

/// Test 5 against LAMMPS (same equations, `peer::LAMMPS_T5_STEEL`): the
/// two set-ups differ where LAMMPS's differs from ours, its torque arm
/// R − δ/2 (`pair_style granular`'s `dist_to_contact`; ours R) and its
/// elastic target (the overlap 2^0.4 times ours on the rigid plane, the
/// same k_t/k_n). The same equations integrated apart
/// (`scripts/chung_ooi_5_integrate.py`) in the two set-ups differ by up
/// to 0.0154 (at ψ₁ = 6, near the sliding threshold, the curve's steepest
/// point) and reproduce LAMMPS's numbers to 3e-4 and ours to 1e-4; 0.02
/// is that difference plus 0.0046 for the rounding of the table (5e-5)
/// and the quick runs' Δt = T_c/200 (quick: 0.0075 measured at ψ₁ = 1.0
/// and 4.0).
const LAMMPS_T5_BAND: f64 = 0.02;

pub(super) fn test5(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let steel = named("steel", 2.0e11, 0.30, 7800.0, ASSUMED);
    let poly = named("polyethylene", 1.0e9, 0.40, 1400.0, ASSUMED);
    let (r, vn, mu, e) = (1e-5, 5.0, 0.3, 1.0);
    let xs: Vec<f64> = if quick {
        // Three of the digitised (and LAMMPS) abscissae: sticking, near
        // the minimum, sliding.
        [3, 10, 13]
            .iter()
            .map(|&k| digitised::T5_RECOIL_STEEL[k].0)
            .collect()
    } else {
        digitised::T5_RECOIL_STEEL.iter().map(|p| p.0).collect()
    };
    let mut checks = Vec::new();
    let (mut c1, mut c2) = (Vec::new(), Vec::new());
    let materials: Vec<Named> = if quick {
        vec![steel]
    } else {
        vec![steel, poly]
    };
    for (g, m) in materials.iter().enumerate() {
        let (mut p1, mut p2) = (Vec::new(), Vec::new());
        let mut worst_slide = 0.0f64;
        for &x in &xs {
            progress(&format!("chung-ooi-5: {} at v_t/(μ v_n) = {x:.3}", m.name));
            let vt = x * mu * vn;
            let (vx, vz, wy) = on_plane(m, r, vn, vt, 0.0, e, mu, quick)?;
            let recoil = (vx - r * wy) / (mu * vz);
            let spin = -r * wy / (mu * vn);
            p1.push((x, recoil));
            p2.push((x, spin));
            if vt >= MARGIN * sliding_threshold(mu, e, vn) {
                let e_run = vz / vn;
                let cf1 = (x - 3.5 * (1.0 + e_run)) / e_run;
                let cf2 = -2.5 * (1.0 + e_run);
                worst_slide = worst_slide
                    .max((recoil - cf1).abs())
                    .max((spin - cf2).abs());
            }
        }
        if !quick || g == 0 {
            checks.push(Check::new(
                format!(
                    "{}: sliding, largest |Δψ₂|, |Δ(Rω'/μv_n)| from the closed form",
                    m.name
                ),
                "1",
                worst_slide,
                0.0,
                Band::Absolute(SLIDING_BAND),
                "rigid-body sliding limit (closed_form.rs)",
            ));
        }
        if g == 0 {
            for (what, pts, published, band) in [
                ("v_cp'/(μ v_n')", &p1, &digitised::T5_RECOIL_STEEL[..], 0.3),
                ("R ω'/(μ v_n)", &p2, &digitised::T5_SPIN_STEEL[..], 0.3),
            ] {
                let (worst, n) = worst_against(pts, published);
                checks.push(Check::new(
                    format!("{}: largest |{what} − paper| over {n} points", m.name),
                    "1",
                    worst,
                    0.0,
                    Band::Absolute(band),
                    "paper's curve, digitised by Kratos (benchmark5_graph*.dat)",
                ));
            }
            // The same model in LAMMPS, at the same abscissae.
            let (mut worst, mut n) = (0.0f64, 0);
            for &(x, psi2, spin) in &LAMMPS_T5_STEEL {
                let ours = p1.iter().zip(&p2).find(|(a, _)| a.0 == x);
                if let Some((a, b)) = ours {
                    worst = worst.max((a.1 - psi2).abs()).max((b.1 - spin).abs());
                    n += 1;
                }
            }
            checks.push(Check::new(
                format!(
                    "{}: largest |Δψ₂|, |Δ(Rω'/μv_n)| from LAMMPS over {n} points",
                    m.name
                ),
                "1",
                worst,
                0.0,
                Band::Absolute(LAMMPS_T5_BAND),
                "LAMMPS pair_style granular, tangential mindlin (peer.rs)",
            ));
        }
        c1.push(Curve::new(format!("ours: {}", m.name), p1, Style::Ours, g));
        c2.push(Curve::new(format!("ours: {}", m.name), p2, Style::Ours, g));
    }
    let x0 = MARGIN * 3.5 * (1.0 + e);
    c1.push(Curve::new(
        "closed form (sliding)",
        vec![(x0, x0 - 7.0), (14.0, 7.0)],
        Style::ClosedForm,
        7,
    ));
    c2.push(Curve::new(
        "closed form (sliding)",
        vec![(x0, -5.0), (20.0, -5.0)],
        Style::ClosedForm,
        7,
    ));
    c1.push(Curve::new(
        "paper: steel (digitised)",
        digitised::T5_RECOIL_STEEL.to_vec(),
        Style::Published,
        6,
    ));
    c2.push(Curve::new(
        "paper: steel (digitised)",
        digitised::T5_SPIN_STEEL.to_vec(),
        Style::Published,
        6,
    ));
    let x_label = "incident slip ψ₁ = v_t/(μ v_n) (1)".to_string();
    Ok(Outcome {
        name: "chung-ooi-5",
        title: "Oblique impact on a rigid plane: constant normal, varying tangential velocity",
        source: SOURCE,
        parameters: vec![
            describe(&steel),
            describe(&poly),
            format!("R = {r} m, v_n = {vn} m/s, μ = {mu}, elastic (e = 1), no spin; v_t from ψ₁ (Kratos Benchmark5: R = 1e-5 m, v_n = 5 m/s, μ = 0.3; e = 1 from the digitised sliding branch ψ₂ = ψ₁ − 7)"),
            format!("rigid plane; Hertz elastic, Mindlin spring; Δt = T_c/{}", steps_per_contact(quick)),
        ],
        notes: vec![
            "The normalised results depend only on ν (and e, μ): E, ρ, R and v_n scale out of the Hertz–Mindlin equations. The ν of steel (0.30) and polyethylene (0.40) are assumed, not taken from the paper.".into(),
            "Band 0.3 against the digitised curve (5 % of the ψ₂ range −3…6).".into(),
            "FAIL below the sliding threshold, investigated: not a bug, the tangential law. The sliding branch matches the closed form to round-off. In the sticking range ours keeps the sign of the contact point's velocity up to ψ₁ ≈ 1.7 (ψ₂ = +0.66 at ψ₁ = 1.01) where the digitised curve reverses it from the start (−0.75). LAMMPS's pair_style granular with the same model (hertz/material, tangential mindlin; scripts/lammps_chung_ooi_5.py) agrees with ours within the two set-ups' known difference (the LAMMPS check above), and so does a separate integration of the same equations (scripts/chung_ooi_5_integrate.py: ψ₂ = +0.6605 at ψ₁ = 1.01, ours +0.6605); LAMMPS's incremental variant (mindlin/force) keeps the sign too (+0.50 at ψ₁ = 1.01). The paper's own Test 4, which ours passes, agrees with ours and not with its Test 5: its rebound angles at 5°–25° (ψ₁ = tan θ/μ = 0.95, 1.92, 2.91, 3.96, 5.07; ν = 0.23, e = 0.98) give ψ₂ = tan(angle)/μ = +0.71, −0.30, −1.05, −1.44, −1.44; ours at ψ₁ = 1.01, 2.0, 2.99, 4.01, 5.0: +0.66, −0.28, −1.00, −1.40, −1.44. The same separate integration with k_t halved gives the digitised Test 5 curve within 0.11 up to ψ₁ = 2.35 (ψ₂ = −0.71, −1.00, −1.31, −1.64, −1.92 against −0.75, −1.00, −1.27, −1.53, −1.81; the spin within about 0.1): the codes behind that figure had a tangential stiffness about half of Mindlin's 8 G* a relative to the normal one (a Mindlin–Deresiewicz micro-slip law softens the spring so), or the figure shows another case; the paper itself could not be read to tell. LAMMPS's fix wall/gran with the same keywords reverses (ψ₂ = −0.79 at ψ₁ = 1.01) while its sphere pair does not: the wall's constants are not the pair's. fix_wall_gran.cpp's constructor (GRANULAR package before the GranularModel rewrite) sets hertz/material's k/a to (4/3) E/(2(1 − ν)) and mindlin NULL's k_t/a to (E/4)(2 − ν)(1 + ν) (read in the source; with the installed 29 Sep 2021 build the same run with these constants given explicitly ends in the same digits), against the pair's (4/3) E/(2(1 − ν²)) and 8 G* = 2E/((2 − ν)(1 + ν)) for like materials: k_t/k_n is 0.47 of Mindlin's at ν = 0.3 ((2 − ν)²(1 + ν)/8), and the separate integration with the wall's constants gives −0.7916, LAMMPS's number. The wall is the halved tangential stiffness above, not a different history. Later LAMMPS (the GranularModel rewrite, gran_sub_mod.cpp's mix_stiffnessE_wall and mix_stiffnessG_wall) gives the wall a like material's E/(2(1 − ν²)) and E/(4(2 − ν)(1 + ν)).".into(),
        ],
        checks,
        plots: vec![
            Plot {
                stem: "chung-ooi-5-recoil".into(),
                title: "Test 5: recoil of the contact point".into(),
                x_label: x_label.clone(),
                y_label: "ψ₂ = v_cp'/(μ v_n') (1)".into(),
                curves: c1,
            },
            Plot {
                stem: "chung-ooi-5-spin".into(),
                title: "Test 5: rebound spin".into(),
                x_label,
                y_label: "R ω'/(μ v_n) (1, negative: rolling sense)".into(),
                curves: c2,
            },
        ],
        seconds: 0.0,
    })
}

/// Tests 6 and 8: a sphere spinning so that its contact point moves at
/// v_cp = v_n tan θ (centre at rest tangentially), on the plane or on a
/// second sphere; returns per θ (x₁ = 3.5 μ (1+e) v_n/v_cp, β = −v_cp'/v_cp,
/// x₂ = v_cp/v_n, y₂ = v_cp'/v_n'), the worst sliding deviation and (two
/// spheres) the worst relative error of the linear momentum.
#[allow(clippy::type_complexity, clippy::too_many_arguments)]
fn spinning(
    m: &Named,
    target: Option<&Named>,
    r: f64,
    vn: f64,
    mu: f64,
    e: f64,
    quick: bool,
    progress: &dyn Fn(&str),
    name: &str,
) -> Result<(Vec<(f64, f64)>, Vec<(f64, f64)>, f64, f64), SceneError> {
    let (mut b1, mut b2) = (Vec::new(), Vec::new());
    let mut worst = 0.0f64;
    let mut momentum = 0.0f64;
    for deg in angles(quick) {
        progress(&format!("{name}: {} at {deg}°", m.name));
        let vcp = vn * deg.to_radians().tan();
        // Contact-point slip relative to the target, along +z for the sphere
        // pair (sphere 1 on −x moving +x) and +x on the plane.
        let (slip_after, vn_after) = match target {
            None => {
                let (vx, vz, wy) = on_plane(m, r, vn, 0.0, -vcp / r, e, mu, quick)?;
                (vx - r * wy, vz)
            }
            Some(t) => {
                let r2 = 2.0 * r;
                let h = hertz_impact(body(m, r), body(t, r2), vn);
                let dt = HERTZ_CONTACT_TIME_FACTOR * h.max_overlap / vn / steps_per_contact(quick);
                // Sphere 1 at −x; contact point at +R x̂: ω_y ŷ × R x̂ = −R ω_y ẑ,
                // so ω_y = −v_cp/R gives the contact point +v_cp along z.
                let out = Impact {
                    ball: Ball {
                        material: m.material,
                        radius: r,
                        velocity: [vn, 0.0, 0.0],
                        spin: [0.0, -vcp / r, 0.0],
                    },
                    target: Target::Ball(Ball {
                        material: t.material,
                        radius: r2,
                        velocity: [0.0; 3],
                        spin: [0.0; 3],
                    }),
                    contact: contact(e),
                    friction: Some(mu),
                    dt,
                    approach_speed: vn,
                    contact_time: h.duration,
                }
                .run()?;
                let [v1, v2] = out.velocity;
                let [w1, w2] = out.spin;
                // Contact-point velocities: body 1 at +R₁x̂, body 2 at −R₂x̂.
                let s = (v1[2] - r * w1[1]) - (v2[2] + r2 * w2[1]);
                // Linear momentum along x and z is conserved exactly.
                let (m1, m2) = (m.material.sphere_mass(r), t.material.sphere_mass(r2));
                momentum = momentum
                    .max(((m1 * v1[0] + m2 * v2[0]) / (m1 * vn) - 1.0).abs())
                    .max((m1 * v1[2] + m2 * v2[2]).abs() / (m1 * vn));
                (s, v2[0] - v1[0])
            }
        };
        let x1 = 3.5 * mu * (1.0 + e) * vn / vcp;
        b1.push((x1, -slip_after / vcp));
        b2.push((vcp / vn, slip_after / vn_after));
        if vcp >= MARGIN * sliding_threshold(mu, e, vn) {
            let e_run = vn_after / vn;
            let cf = vcp - sliding_threshold(mu, e_run, vn);
            worst = worst.max((slip_after - cf).abs() / vcp);
        }
    }
    Ok((b1, b2, worst, momentum))
}

/// Test 6 against LAMMPS (`peer::LAMMPS_T6_ALLOY`) at the angles where
/// the two set-ups' differences are computed small. LAMMPS's set-up
/// differs from ours by its elastic target and torque arm R − δ/2 (as in
/// Test 5) and by its order of the Coulomb cap with a dashpot (it caps
/// spring plus dashpot and solves the spring back from the capped force;
/// ours cuts the spring alone first). The same equations integrated apart
/// in both set-ups (`scripts/chung_ooi_6_integrate.py`) reproduce ours to
/// 1e-4 (compared up to θ = 20°) and LAMMPS's table to 2e-4 up to 20° and
/// from 50° on (0.04 apart at 25°–45°, not resolved), and differ from each
/// other by at most 3e-4 up to θ = 20° (x₁ ≥ 5.8: sticking but for the
/// contact's ends, the range of the failure against the paper) and by up
/// to 0.24 in β from θ = 25° on, where the cap acts and the two orders
/// part. Full runs: 1e-3
/// is that 3e-4 and 5e-5 of the table's rounding, with a margin of three
/// (measured 3.7e-4). Quick runs (Δt = T_c/200): their first-order error
/// adds 4.5e-3 at θ = 10° (β −0.0422 against −0.0378 at T_c/20,000), so
/// 1e-2.
fn lammps_t6_band(quick: bool) -> f64 {
    if quick {
        1e-2
    } else {
        1e-3
    }
}
/// The largest incident angle (degree) of the LAMMPS check.
const LAMMPS_T6_MAX_DEG: f64 = 20.0;

pub(super) fn test6(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let alloy = named("aluminium alloy", 7.0e10, 0.33, 2700.0, YADE4);
    let nylon = named("nylon", 2.5e9, 0.40, 1000.0, ASSUMED);
    let (r, vn, mu, e) = (0.1, 0.2, 0.4, 0.5);
    let mut checks = Vec::new();
    let (mut c1, mut c2) = (Vec::new(), Vec::new());
    let materials: Vec<Named> = if quick {
        vec![alloy]
    } else {
        vec![alloy, nylon]
    };
    for (g, m) in materials.iter().enumerate() {
        let (b1, b2, worst, _) = spinning(m, None, r, vn, mu, e, quick, progress, "chung-ooi-6")?;
        checks.push(Check::new(
            format!(
                "{}: sliding, largest |Δv_cp'|/v_cp from the closed form",
                m.name
            ),
            "1",
            worst,
            0.0,
            Band::Absolute(SLIDING_BAND),
            "rigid-body sliding limit (closed_form.rs)",
        ));
        if g == 0 {
            // The same model in LAMMPS, over the sticking angles.
            let (mut worst, mut n) = (0.0f64, 0);
            for ((deg, a), b) in angles(quick).into_iter().zip(&b1).zip(&b2) {
                let row = LAMMPS_T6_ALLOY.iter().find(|r| r.0 == deg);
                if let Some(&(_, beta, recoil)) = row.filter(|_| deg <= LAMMPS_T6_MAX_DEG) {
                    worst = worst
                        .max((a.1 - beta).abs())
                        .max((b.1 - recoil).abs() / recoil.abs().max(1.0));
                    n += 1;
                }
            }
            checks.push(Check::new(
                format!(
                    "{}: largest |Δβ|, |Δ(v_cp'/v_n')| from LAMMPS over {n} sticking angles (θ ≤ {LAMMPS_T6_MAX_DEG}°)",
                    m.name
                ),
                "1",
                worst,
                0.0,
                Band::Absolute(lammps_t6_band(quick)),
                "LAMMPS pair_style granular, tsuji + tangential mindlin (peer.rs)",
            ));
            for (what, pts, published, band) in [
                ("β = −v_cp'/v_cp", &b1, &digitised::T6_BETA_ALLOY[..], 0.05),
                ("v_cp'/v_n'", &b2, &digitised::T6_RECOIL_ALLOY[..], 0.15),
            ] {
                let (worst, n) = worst_against(pts, published);
                checks.push(Check::new(
                    format!("{}: largest |{what} − paper| over {n} points", m.name),
                    "1",
                    worst,
                    0.0,
                    Band::Absolute(band),
                    "paper's curve, digitised by Kratos (benchmark6_graph*.dat)",
                ));
            }
        }
        c1.push(Curve::new(format!("ours: {}", m.name), b1, Style::Ours, g));
        c2.push(Curve::new(format!("ours: {}", m.name), b2, Style::Ours, g));
    }
    let lim = 3.5 * mu * (1.0 + e);
    c1.push(Curve::new(
        "closed form (sliding)",
        vec![(0.0, -1.0), (1.0 / MARGIN, 1.0 / MARGIN - 1.0)],
        Style::ClosedForm,
        7,
    ));
    c2.push(Curve::new(
        "closed form (sliding)",
        vec![
            (MARGIN * lim, (MARGIN * lim - lim) / e),
            (12.0, (12.0 - lim) / e),
        ],
        Style::ClosedForm,
        7,
    ));
    let x1 = |deg: f64| lim / deg.to_radians().tan();
    c1.push(Curve::new(
        "LAMMPS, same model: Al alloy (peer.rs)",
        LAMMPS_T6_ALLOY.iter().map(|r| (x1(r.0), r.1)).collect(),
        Style::Peer,
        2,
    ));
    c2.push(Curve::new(
        "LAMMPS, same model: Al alloy (peer.rs)",
        LAMMPS_T6_ALLOY
            .iter()
            .map(|r| (r.0.to_radians().tan(), r.2))
            .collect(),
        Style::Peer,
        2,
    ));
    c1.push(Curve::new(
        "paper: Al alloy (digitised)",
        digitised::T6_BETA_ALLOY.to_vec(),
        Style::Published,
        6,
    ));
    c2.push(Curve::new(
        "paper: Al alloy (digitised)",
        digitised::T6_RECOIL_ALLOY.to_vec(),
        Style::Published,
        6,
    ));
    Ok(Outcome {
        name: "chung-ooi-6",
        title: "Impact of a spinning sphere on a rigid plane",
        source: SOURCE,
        parameters: vec![
            describe(&alloy),
            describe(&nylon),
            format!("R = {r} m, v_n = {vn} m/s, μ = {mu}, e = {e}; centre at rest tangentially, spin ω = −v_cp/R with v_cp = v_n tan θ, θ = 5°–85° (Kratos Benchmark6)"),
            format!("rigid plane; Hertz + Tsuji damping (e exact), Mindlin spring; Δt = T_c/{}", steps_per_contact(quick)),
        ],
        notes: vec![
            "Bands against the digitised curves: 0.05 in β (5 % of its range) and 0.15 in the recoil tangent (the digitised curve's kink at v_cp/v_n ≈ 2 makes linear interpolation uncertain there).".into(),
            "The normalised results depend on ν, e and μ only; nylon's E and ρ are assumed.".into(),
            "FAIL in β for small incident slip (x₁ = 3.5 μ (1 + e) v_n/v_cp > 3), investigated: the model, not a bug, and not Test 5's cause. The sliding side matches the closed form to round-off and the paper within 0.02. In the sticking range ours tends to β = −0.040 (θ = 5°, x₁ = 24) where the paper's curve reaches −0.34. LAMMPS's pair_style granular with the same model (hertz/material, damping tsuji with limit_damping at our α = 0.5708, tangential mindlin with the dashpot at the normal damping ratio; scripts/lammps_chung_ooi_6.py) gives −0.0402 there (ours −0.0404) and agrees within 3.7e-4 up to θ = 20° (the LAMMPS check above); the same equations integrated apart (scripts/chung_ooi_6_integrate.py) give −0.0404 in our set-up and −0.0402 in LAMMPS's. From θ = 25° on LAMMPS parts from ours, by up to 0.24 in β at 60°–65° (its points in the figures), and the separate integration gives the same split, to within 0.04 (at 25°–45°; to 2e-4 elsewhere), from the order of the Coulomb cap alone: LAMMPS caps spring plus dashpot and solves the spring back from the capped force, which at the contact's onset, where the dashpot exceeds the small limit, sets the spring against the slip; its sliding branch then misses the rigid-body closed form (β = −0.839 against −0.816 at 85°), ours does not. Test 5's explanation does not carry over: the same equations with k_t halved give β = +0.23 at θ = 5° (paper −0.34), and no factor on k_t from 0.1 to 3 gets below −0.09 there (0.1: +0.20, 0.25: +0.38, 0.5: +0.23, 1: −0.04, 1.5: −0.09, 2: −0.05, 3: +0.01); without the tangential dashpot β = −0.19 at 5° and +0.05 at 10°. While a contact sticks its tangential equations are linear in v_cp, so β cannot depend on the incident slip: ours stays within −0.040…−0.030 from x₁ = 24 to 5.8, where the paper's curve halves (−0.34 to −0.17). The codes behind the figure ran a tangential law that is not linear in the slip at small slip (Mindlin–Deresiewicz's micro-slip is one) or another damping; the paper itself could not be read to tell. Converged in Δt (T_c/4000 and T_c/20,000 agree to 1e-4).".into(),
        ],
        checks,
        plots: vec![
            Plot {
                stem: "chung-ooi-6-beta".into(),
                title: "Test 6: tangential restitution of the contact point".into(),
                x_label: "3.5 μ (1 + e) v_n/v_cp (1)".into(),
                y_label: "β = −v_cp'/v_cp (1)".into(),
                curves: c1,
            },
            Plot {
                stem: "chung-ooi-6-recoil".into(),
                title: "Test 6: recoil against incidence of the contact point".into(),
                x_label: "tangent of the incident angle v_cp/v_n (1)".into(),
                y_label: "tangent of the recoil angle v_cp'/v_n' (1)".into(),
                curves: c2,
            },
        ],
        seconds: 0.0,
    })
}

pub(super) fn test7(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let alloy = named("aluminium alloy", 7.0e10, 0.33, 2700.0, YADE4);
    let copper = named("copper", 1.2e11, 0.35, 8900.0, ASSUMED);
    let (r, vn, mu, e) = (0.1, 0.2, 0.4, 0.5);
    let mut checks = Vec::new();
    let mut c1 = Vec::new();
    let materials: Vec<Named> = if quick {
        vec![alloy]
    } else {
        vec![alloy, copper]
    };
    for (g, m) in materials.iter().enumerate() {
        let (mut p1, mut p2) = (Vec::new(), Vec::new());
        let (mut worst_v, mut worst_w) = (0.0f64, 0.0f64);
        for deg in angles(quick) {
            progress(&format!("chung-ooi-7: {} at {deg}°", m.name));
            let w0 = vn / r * deg.to_radians().tan();
            let h = hertz_impact(body(m, r), body(m, r), 2.0 * vn);
            let dt =
                HERTZ_CONTACT_TIME_FACTOR * h.max_overlap / (2.0 * vn) / steps_per_contact(quick);
            let out = Impact {
                ball: Ball {
                    material: m.material,
                    radius: r,
                    velocity: [vn, 0.0, 0.0],
                    spin: [0.0, w0, 0.0],
                },
                target: Target::Ball(Ball {
                    material: m.material,
                    radius: r,
                    velocity: [-vn, 0.0, 0.0],
                    spin: [0.0, -w0, 0.0],
                }),
                contact: contact(e),
                friction: Some(mu),
                dt,
                approach_speed: 2.0 * vn,
                contact_time: h.duration,
            }
            .run()?;
            let vt = out.velocity[0][2];
            let w = out.spin[0][1];
            p1.push((w0, vt / vn));
            p2.push((w0, w / w0));
            worst_v = worst_v.max(vt.abs() / vn);
            worst_w = worst_w.max((w / w0 - 1.0).abs());
        }
        checks.push(Check::new(
            format!("{}: largest |v_t'|/v_n", m.name),
            "1",
            worst_v,
            0.0,
            Band::Absolute(1e-9),
            "symmetry: no slip, no tangential force",
        ));
        checks.push(Check::new(
            format!("{}: largest |ω'/ω − 1|", m.name),
            "1",
            worst_w,
            0.0,
            Band::Absolute(1e-9),
            "symmetry: no slip, no tangential force",
        ));
        c1.push(Curve::new(
            format!("ours: v_t'/v_n, {}", m.name),
            p1,
            Style::Ours,
            g,
        ));
        c1.push(Curve::new(
            format!("ours: ω'/ω, {}", m.name),
            p2,
            Style::Ours,
            g + 2,
        ));
    }
    let wmax = vn / r * 85f64.to_radians().tan();
    c1.push(Curve::new(
        "published: ω'/ω = 1",
        vec![(0.0, 1.0), (wmax, 1.0)],
        Style::ClosedForm,
        7,
    ));
    c1.push(Curve::new(
        "published: v_t' = 0",
        vec![(0.0, 0.0), (wmax, 0.0)],
        Style::ClosedForm,
        7,
    ));
    Ok(Outcome {
        name: "chung-ooi-7",
        title: "Impact of two identical spinning spheres",
        source: SOURCE,
        parameters: vec![
            describe(&alloy),
            describe(&copper),
            format!("R = {r} m, each at {vn} m/s towards the other, spins +ω and −ω about the same axis, ω = (v_n/R) tan θ, θ = 5°–85°; μ = {mu}, e = {e} (Kratos Benchmark7: ±0.2 m/s, R = 0.1 m, spins ±ω, μ = 0.4; e = 0.5 assumed as in Tests 6 and 8)"),
            format!("Hertz + Tsuji damping (e exact), Mindlin spring; Δt = T_c/{}", steps_per_contact(quick)),
        ],
        notes: vec![
            "In this configuration the contact points of the two spheres move together: no slip, so the tangential velocity after is 0 and the spins unchanged (Kratos's benchmark7_graph{1,2}.dat: 0 and the identity). The band is round-off.".into(),
            "Whether the paper's Test 7 uses this sense of the spins (rather than equal spins, which slide) was not verified against the paper itself.".into(),
        ],
        checks,
        plots: vec![Plot {
            stem: "chung-ooi-7".into(),
            title: "Test 7: sphere 1 after the impact, against its initial spin".into(),
            x_label: "initial spin ω (rad/s)".into(),
            y_label: "v_t'/v_n and ω'/ω (1)".into(),
            curves: c1,
        }],
        seconds: 0.0,
    })
}

pub(super) fn test8(quick: bool, progress: &dyn Fn(&str)) -> Result<Outcome, SceneError> {
    let alloy = named("aluminium alloy", 7.0e10, 0.33, 2700.0, YADE4);
    let (r, vn, mu, e) = (0.1, 0.2, 0.4, 0.5);
    let (b1, b2, worst, momentum) = spinning(
        &alloy,
        Some(&alloy),
        r,
        vn,
        mu,
        e,
        quick,
        progress,
        "chung-ooi-8",
    )?;
    let (p1, p2, _, _) = spinning(
        &alloy,
        None,
        r,
        vn,
        mu,
        e,
        quick,
        progress,
        "chung-ooi-8 (plane)",
    )?;
    let lim = 3.5 * mu * (1.0 + e);
    // Like Test 6 point by point: for two spheres of one material the
    // dimensionless contact equations are the plane's (module doc of
    // Test 8's notes), so β and the recoil agree up to the turning normal.
    let same = b1
        .iter()
        .zip(&p1)
        .chain(b2.iter().zip(&p2))
        .map(|(a, b)| (a.1 - b.1).abs() / b.1.abs().max(1.0))
        .fold(0.0f64, f64::max);
    let checks = vec![
        Check::new(
            "sliding, largest |Δv_cp'|/v_cp from the closed form",
            "1",
            worst,
            0.0,
            Band::Absolute(TURNING_BAND),
            "rigid-body sliding limit for two spheres (closed_form.rs)",
        ),
        Check::new(
            "largest |sphere − plane| in β and v_cp'/v_n' (relative beyond 1)",
            "1",
            same,
            0.0,
            // Quick (T_c/200): each run's own first-order integration error
            // in the sticking regime (about 1e-3, Test 4's e_t moving by
            // 7e-5 from T_c/2000 to T_c/20,000) adds to the turn; measured
            // 3.2e-3.
            Band::Absolute(if quick { 5e-3 } else { TURNING_BAND }),
            "Test 6 run here: the same dimensionless equations",
        ),
        Check::new(
            "largest relative error of the linear momentum",
            "1",
            momentum,
            0.0,
            Band::Absolute(1e-12),
            "conservation (equal and opposite contact forces; round-off)",
        ),
    ];
    Ok(Outcome {
        name: "chung-ooi-8",
        title: "Impact of a spinning sphere on a different sphere",
        source: SOURCE,
        parameters: vec![
            describe(&alloy),
            format!("sphere 1: R = {r} m, {vn} m/s, spinning so that its contact point moves at v_n tan θ, θ = 5°–85° (Kratos Benchmark8: R = 0.1 m, v_n = 0.2 m/s, μ = 0.4, e = 0.5); sphere 2: R = {} m of the same material, free, at rest (assumed: the paper's second sphere was not found in a source)", 2.0 * r),
            format!("Hertz + Tsuji damping (e exact), Mindlin spring; Δt = T_c/{}", steps_per_contact(quick)),
        ],
        notes: vec![
            "The sliding limit of two free spheres equals the sphere–plane one (closed_form.rs: Δs = −(7/2) μ (1 + e) v_n for any masses and radii). More: for two spheres of one material the whole dimensionless problem is the rigid plane's, since the tangential-to-normal mass ratio is 2/7 for both (m_t = 1/Σ(1/m + R²/I) = m*/3.5) and G*/E* is the same ((1 − ν)/(2(2 − ν)) · … for like materials and for a rigid plane), so Test 8's curves must equal Test 6's everywhere, up to the turning line of centres. Kratos's digitised Test 8 \"case A\" lies on Test 6 up to 3.5 μ (1 + e) v_n/v_cp ≈ 6, consistent with this.".into(),
            "The second sphere's size and material in the paper were not found in a source; R₂ = 2R of the same alloy is our choice, which the equality above makes immaterial for like materials.".into(),
        ],
        checks,
        plots: vec![
            Plot {
                stem: "chung-ooi-8-beta".into(),
                title: "Test 8: tangential restitution of the contact point".into(),
                x_label: "3.5 μ (1 + e) v_n/v_cp (1)".into(),
                y_label: "β = −v_cp'/v_cp (1)".into(),
                curves: vec![
                    Curve::new("ours: on a sphere R₂ = 2R", b1, Style::Ours, 0),
                    Curve::new("ours: on the rigid plane (Test 6)", p1, Style::Ours, 1),
                    Curve::new("closed form (sliding)", vec![(0.0, -1.0), (1.0 / MARGIN, 1.0 / MARGIN - 1.0)], Style::ClosedForm, 7),
                ],
            },
            Plot {
                stem: "chung-ooi-8-recoil".into(),
                title: "Test 8: recoil against incidence of the contact point".into(),
                x_label: "tangent of the incident angle v_cp/v_n (1)".into(),
                y_label: "tangent of the recoil angle v_cp'/v_n' (1)".into(),
                curves: vec![
                    Curve::new("ours: on a sphere R₂ = 2R", b2, Style::Ours, 0),
                    Curve::new("ours: on the rigid plane (Test 6)", p2, Style::Ours, 1),
                    Curve::new("closed form (sliding)", vec![(MARGIN * lim, (MARGIN * lim - lim) / e), (12.0, (12.0 - lim) / e)], Style::ClosedForm, 7),
                ],
            },
        ],
        seconds: 0.0,
    })
}
