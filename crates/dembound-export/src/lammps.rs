//! LAMMPS deck (`pair_style granular`, `fix wall/gran granular`; checked
//! with Debian's LAMMPS 20220106).
//!
//! Mapping (docs/export-lammps.md):
//! - Hertz: `hertz k_n 0` with k_n = E_eff, so that LAMMPS's
//!   F = k_n a δ, a = √(R δ), is dembound's E_eff √R_eff h^(3/2); R is
//!   LAMMPS's own R_i R_j/(R_i + R_j) (R_m for a plane wall).
//! - linear: `hooke k_n c damping velocity` with k_n = E_eff R_eff and
//!   F = k_n δ + c δ̇ (c absolute, N s/m); `limit_damping` is dembound's
//!   clamp F = max(F, 0).
//! - The pair (and the wall) get the pre-mixed E_eff of eq 6. Never
//!   `hertz/material` for a boundary of another material: a wall of
//!   `hertz/material E_b` is mixed as if the particle were E_b too, and the
//!   per-type auto-mixing of two `hertz/material` types is not eq 6 either
//!   ([`Pitfall`]).
//! - The boundary sphere is a type-2 atom that is not integrated and is
//!   under `fix freeze` (LAMMPS then uses the particle's mass alone in the
//!   damping, as dembound does).

use crate::plan::{Boundary, Law, Plan};
use crate::{num, Error, Pitfall, Result};
use std::fmt::Write;

/// The granular model arguments of the pre-mixed law.
/// LAMMPS's `damping tsuji` reads the coefficient as a restitution e and
/// turns it into α = 1.2728 − 4.2783 e + 11.087 e² − 22.348 e³ + 27.467 e⁴
/// − 18.022 e⁵ + 4.8218 e⁶ (pair_granular.cpp), then η = α √(m k_n a).
pub fn tsuji_alpha(e: f64) -> f64 {
    let c = [1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218];
    c.iter().rev().fold(0.0, |acc, k| acc * e + k)
}

/// The e to give LAMMPS's `damping tsuji` so that its α is `alpha`
/// (bisection on [0, 1], where the polynomial falls from 1.2728 to 0.0006).
pub(crate) fn tsuji_input(alpha: f64) -> Result<f64> {
    let (mut lo, mut hi) = (0.0, 1.0);
    if !(tsuji_alpha(hi)..=tsuji_alpha(lo)).contains(&alpha) {
        return Err(Error::Export(format!(
            "the Tsuji damping asks LAMMPS for alpha = {alpha}, outside what its polynomial in e \
             gives on [0, 1] ({} to {})",
            tsuji_alpha(hi),
            tsuji_alpha(lo)
        )));
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tsuji_alpha(mid) > alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

fn model(plan: &Plan) -> Result<String> {
    // The mass LAMMPS puts in its damping: the particle's against a frozen
    // atom or a wall, the reduced mass of two free atoms.
    let m = plan.reduced_mass;
    match plan.law {
        // F_damp = α √(m k_n a) δ̇ with k_n = E_eff, a = √(R δ): α = γ/(√(m E_eff) R^(1/4)).
        Law::Tsuji { damping, clamp, .. } => {
            let alpha =
                damping / ((m * plan.effective_modulus).sqrt() * plan.effective_radius.powf(0.25));
            let e = tsuji_input(alpha)?;
            Ok(format!(
                "hertz {} {} tangential linear_nohistory 0.0 0.0 damping tsuji{}",
                num(plan.effective_modulus),
                num(e),
                if clamp { " limit_damping" } else { "" }
            ))
        }
        // F_damp = η₀ a m δ̇ with a = √(R δ): η₀ = (3/2) A E_eff/m.
        Law::Viscoelastic { a, clamp, .. } => Ok(format!(
            "hertz {} {} tangential linear_nohistory 0.0 0.0 damping viscoelastic{}",
            num(plan.effective_modulus),
            num(1.5 * a * plan.effective_modulus / m),
            if clamp { " limit_damping" } else { "" }
        )),
        // LAMMPS multiplies by a = √(R δ) itself: k_n is E_eff, not E_eff √R_eff.
        Law::Hertz { .. } => Ok(format!(
            "hertz {} 0.0 tangential linear_nohistory 0.0 0.0 damping velocity",
            num(plan.effective_modulus)
        )),
        Law::Linear { stiffness } => Ok(format!(
            "hooke {} 0.0 tangential linear_nohistory 0.0 0.0 damping velocity",
            num(stiffness)
        )),
        Law::Dashpot {
            stiffness,
            damping,
            clamp,
        } => Ok(format!(
            "hooke {} {} tangential linear_nohistory 0.0 0.0 damping velocity{}",
            num(stiffness),
            num(damping),
            if clamp { " limit_damping" } else { "" }
        )),
    }
}

/// The LAMMPS input of `plan` (`pitfall`: a known-wrong variant).
pub fn deck(plan: &Plan, pitfall: Option<Pitfall>) -> Result<String> {
    let p = &plan.particle;
    let mut d = String::new();
    for line in plan.provenance() {
        writeln!(d, "# {line}").ok();
    }
    // Where the boundary is in this deck: a frozen or free atom, or a plane.
    let (sphere, plane_z) = match (plan.boundary, pitfall) {
        (Boundary::Sphere { .. }, Some(Pitfall::WallMaterial)) => {
            (None, Some(plan.contact_distance() - p.radius))
        }
        (b @ Boundary::Sphere { .. }, _) => (Some(b), None),
        (Boundary::Plane { .. }, Some(Pitfall::AutoMix)) => {
            return Err(Error::Export(
                "--pitfall auto-mix (a LAMMPS pitfall) needs a boundary sphere \
                 (boundary.radius_ratio finite)"
                    .into(),
            ))
        }
        (Boundary::Plane { .. }, _) => (None, Some(0.0)),
    };
    let (e_b, nu_b) = match plan.boundary {
        Boundary::Sphere {
            youngs_modulus,
            poisson_ratio,
            ..
        }
        | Boundary::Plane {
            youngs_modulus,
            poisson_ratio,
        } => (youngs_modulus, poisson_ratio),
    };
    if let Some(pf) = pitfall {
        writeln!(
            d,
            "#\n# !!! PITFALL DECK ({}): written wrong on purpose to show what this setting does.\n\
             # !!! Do not use it; the deck without --pitfall is the right one.",
            pf.name()
        )
        .ok();
        if pf == Pitfall::AutoMix && !e_b.is_finite() {
            return Err(Error::Export(
                "--pitfall auto-mix (a LAMMPS pitfall) needs a finite boundary modulus \
                 (boundary.modulus_ratio finite)"
                    .into(),
            ));
        }
    }
    let r_b = match sphere {
        Some(Boundary::Sphere { radius, .. }) => radius,
        _ => 0.0,
    };
    let half_width = 1.5 * r_b.max(p.radius) + p.radius;
    let zlo = match plane_z {
        Some(z) => z - 2.0 * p.radius,
        None => -1.5 * r_b - p.radius,
    };
    let rise = p.velocity.max(0.0).powi(2) / (2.0 * plan.particle_gravity().max(1e-300));
    let zhi = p.z + 2.0 * p.radius + rise.min(p.z.abs() + 1.0);
    let types = if sphere.is_some() { 2 } else { 1 };
    writeln!(
        d,
        "\nunits        si\natom_style   sphere\natom_modify  map array\n\
         boundary     m m m\nnewton       off\ncomm_modify  vel yes\n\
         region       box block {w0} {w1} {w0} {w1} {zlo} {zhi} units box\n\
         create_box   {types} box\n\
         create_atoms 1 single 0 0 {z} units box\n\
         set          atom 1 diameter {dm} density {rho}\n\
         group        particle id 1\n\
         velocity     particle set 0 0 {v} units box",
        w0 = num(-half_width),
        w1 = num(half_width),
        zlo = num(zlo),
        zhi = num(zhi),
        z = num(p.z),
        dm = num(2.0 * p.radius),
        rho = num(p.density),
        v = num(p.velocity),
    )
    .ok();
    let mut integrated = "particle";
    if let Some(Boundary::Sphere {
        radius,
        density,
        fixed,
        velocity,
        ..
    }) = sphere
    {
        writeln!(
            d,
            "create_atoms 2 single 0 0 0 units box\n\
             set          atom 2 diameter {} density {}\n\
             group        boundary id 2",
            num(2.0 * radius),
            num(density)
        )
        .ok();
        if !fixed {
            writeln!(
                d,
                "velocity     boundary set 0 0 {} units box",
                num(velocity)
            )
            .ok();
            integrated = "all";
        }
    }
    // The contact model.
    match (sphere, pitfall) {
        (Some(_), Some(Pitfall::AutoMix)) => {
            writeln!(
                d,
                "\n# PITFALL: each type its own hertz/material, the 1-2 pair left to LAMMPS's mixing\n\
                 pair_style   granular\n\
                 pair_coeff   1 1 hertz/material {} 0.0 {} tangential linear_nohistory 0.0 0.0 damping velocity\n\
                 pair_coeff   2 2 hertz/material {} 0.0 {} tangential linear_nohistory 0.0 0.0 damping velocity",
                num(p.youngs_modulus),
                num(p.poisson_ratio),
                num(e_b),
                num(nu_b)
            )
            .ok();
        }
        (Some(_), _) => {
            writeln!(
                d,
                "\n# The particle-boundary pair gets the pre-mixed E_eff (eq 6) as an explicit 1-2\n\
                 # coefficient; types 1-1 and 2-2 never meet (one atom each).\n\
                 pair_style   granular\n\
                 pair_coeff   * * {m}\n\
                 pair_coeff   1 2 {m}",
                m = model(plan)?
            )
            .ok();
        }
        (None, _) => {
            writeln!(d, "\npair_style   none").ok();
        }
    }
    if let Some(z) = plane_z {
        if pitfall == Some(Pitfall::WallMaterial) {
            writeln!(
                d,
                "# PITFALL: the boundary's own modulus E_b given to hertz/material: LAMMPS mixes the wall\n\
                 # as if the particle were E_b too.\n\
                 fix          wall particle wall/gran granular hertz/material {} 0.0 {} \
                 tangential linear_nohistory 0.0 0.0 damping velocity zplane {} NULL",
                num(e_b),
                num(nu_b),
                num(z)
            )
            .ok();
        } else {
            writeln!(
                d,
                "# A plane wall with the pre-mixed E_eff of the particle against the boundary's material\n\
                 # (R_eff = R_m). Not hertz/material: LAMMPS would mix the wall as the particle's material.\n\
                 fix          wall particle wall/gran granular {} zplane {} NULL",
                model(plan)?,
                num(z)
            )
            .ok();
        }
    }
    writeln!(
        d,
        "\nneighbor     {} nsq\nneigh_modify delay 0 every 1 check yes\n\
         fix          integrate {integrated} nve/sphere",
        num(p.radius)
    )
    .ok();
    if let Some(Boundary::Sphere { fixed: true, .. }) = sphere {
        writeln!(d, "fix          freeze boundary freeze").ok();
    }
    write_gravity(&mut d, plan, sphere.is_some());
    let g_p = plan.particle_gravity();
    writeln!(d, "timestep     {}", num(plan.dt)).ok();
    let (h, v) = match (sphere, plane_z) {
        (Some(_), _) => (
            format!("{}-(z[1]-z[2])", num(plan.contact_distance())),
            "vz[1]-vz[2]".to_string(),
        ),
        (None, Some(z)) => (
            format!("{}-(z[1]-{})", num(p.radius), num(z)),
            "vz[1]".to_string(),
        ),
        (None, None) => unreachable!("a deck has a boundary"),
    };
    let f = if g_p > 0.0 {
        format!("fz[1]+{}", num(p.mass * g_p))
    } else {
        "fz[1]".into()
    };
    writeln!(
        d,
        "\n# trace: overlap (m), relative velocity (m/s), contact force on the particle (N; fz\n\
         # minus its weight)\n\
         variable     h equal {h}\nvariable     v equal {v}\nvariable     f equal {f}\n\
         thermo       100000\nthermo_style custom step time v_h v_v"
    )
    .ok();
    let line = "\"$(time:%.17g) $(v_h:%.17g) $(v_v:%.17g) $(v_f:%.17g)\"";
    let mut at = 0;
    for (i, w) in plan.windows.iter().enumerate() {
        if w.start > at {
            writeln!(
                d,
                "run          {}   # to step {} (t = {} s), where the trace window opens",
                w.start - at,
                w.start,
                num(w.start as f64 * plan.dt)
            )
            .ok();
        }
        let target = if i == 0 {
            format!(
                "file trace.txt title \"{}\"",
                crate::trace_title(&plan.scenario)
            )
        } else {
            "append trace.txt".into()
        };
        writeln!(
            d,
            "fix          trace all print 1 {line} {target} screen no\n\
             run          {}   # window {}: every step to step {}\n\
             unfix        trace",
            w.end - w.start,
            i + 1,
            w.end
        )
        .ok();
        at = w.end;
    }
    Ok(d)
}

/// The gravity fixes of the particle group and, when the boundary is a
/// sphere that falls, of the boundary group (LAMMPS and LIGGGHTS share the
/// syntax).
pub(crate) fn write_gravity(d: &mut String, plan: &Plan, boundary_sphere: bool) {
    let g_p = plan.particle_gravity();
    if g_p > 0.0 {
        writeln!(
            d,
            "fix          gravity particle gravity {} vector 0 0 -1",
            num(g_p)
        )
        .ok();
    }
    let g_b = plan.boundary_gravity();
    if g_b > 0.0 && boundary_sphere {
        writeln!(
            d,
            "fix          gravity_b boundary gravity {} vector 0 0 -1",
            num(g_b)
        )
        .ok();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tsuji_polynomial_is_inverted() {
        // The polynomial falls monotonically on [0, 1] (1.2728 at e = 0,
        // 3e-4 at e = 1), so bisection returns the e that produced α.
        for e in [0.1, 0.5, 0.9] {
            let back = tsuji_input(tsuji_alpha(e)).expect("in range");
            assert!((back - e).abs() < 1e-12, "{e} -> {back}");
        }
        assert!(tsuji_input(2.0).is_err());
    }
}
