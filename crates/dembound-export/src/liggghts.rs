//! LIGGGHTS deck (`pair_style gran`, `fix wall/gran … primitive`; checked
//! with Debian's LIGGGHTS 3.8.0).
//!
//! Mapping (docs/export-liggghts.md):
//! - Hertz: `model hertz` with per-type `youngsModulus` and `poissonsRatio`:
//!   LIGGGHTS mixes Y* = 1/((1 − ν_i²)/Y_i + (1 − ν_j²)/Y_j) and uses
//!   F = 4/3 Y* √(R* δ) δ, which is eq 6 and eq 4 exactly, so the boundary
//!   (sphere or wall) keeps its own material. `coefficientRestitution` 1
//!   makes its damping zero.
//! - linear and spring–dashpot: `model hooke/stiffness` with `kn` = E_eff
//!   R_eff and `gamman_abs` = c per type pair (`absolute_damping on`:
//!   F = k_n δ + c δ̇, no mass factor), `limitForce on` for dembound's clamp.
//!   (LIGGGHTS's `hooke` would derive k_n from a characteristic velocity and
//!   map e with the unclamped formula: not used.)
//! - Moduli above 1e9 Pa need `hard_particles yes`.

use crate::plan::{Boundary, Law, Plan};
use crate::{num, Error, Result};
use std::fmt::Write;

pub fn deck(plan: &Plan) -> Result<String> {
    let p = &plan.particle;
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
    if !e_b.is_finite() && matches!(plan.law, Law::Hertz { .. }) {
        return Err(Error::Export(
            "boundary.modulus_ratio = inf: LIGGGHTS needs a finite Young's modulus per type \
             (give e.g. boundary.modulus_ratio = 1e6: E_eff then differs by 1e-6)"
                .into(),
        ));
    }
    if matches!(plan.law, Law::Tsuji { .. } | Law::Viscoelastic { .. }) {
        return Err(Error::Export(
            "contact.damping = \"tsuji\" or \"viscoelastic\" with contact.law = \"hertz\" \
             cannot be exported to LIGGGHTS (exported to LAMMPS only so far)"
                .into(),
        ));
    }
    let mut d = String::new();
    for line in plan.provenance() {
        writeln!(d, "# {line}").ok();
    }
    let sphere = matches!(plan.boundary, Boundary::Sphere { .. });
    let r_b = match plan.boundary {
        Boundary::Sphere { radius, .. } => radius,
        Boundary::Plane { .. } => 0.0,
    };
    let half_width = 1.5 * r_b.max(p.radius) + p.radius;
    let zlo = if sphere {
        -1.5 * r_b - p.radius
    } else {
        -2.0 * p.radius
    };
    let rise = p.velocity.max(0.0).powi(2) / (2.0 * plan.particle_gravity().max(1e-300));
    let zhi = p.z + 2.0 * p.radius + rise.min(p.z.abs() + 1.0);
    writeln!(
        d,
        "\natom_style   granular\natom_modify  map array\nboundary     m m m\nnewton       off\n\
         communicate  single vel yes\nunits        si\n\
         hard_particles yes   # moduli above 1e9 Pa\n\
         region       box block {w0} {w1} {w0} {w1} {zlo} {zhi} units box\n\
         create_box   2 box\n\
         neighbor     {skin} bin\nneigh_modify delay 0",
        w0 = num(-half_width),
        w1 = num(half_width),
        zlo = num(zlo),
        zhi = num(zhi),
        skin = num(p.radius),
    )
    .ok();
    // Type 1 the particle, type 2 the boundary (sphere or wall).
    let e_b_written = if e_b.is_finite() { e_b } else { 1e300 };
    writeln!(
        d,
        "\n# Per-type materials: type 1 the particle, type 2 the boundary (its own modulus).\n\
         fix          m1 all property/global youngsModulus peratomtype {} {}\n\
         fix          m2 all property/global poissonsRatio peratomtype {} {}\n\
         fix          m3 all property/global coefficientRestitution peratomtypepair 2 1 1 1 1\n\
         fix          m4 all property/global coefficientFriction peratomtypepair 2 0 0 0 0",
        num(p.youngs_modulus),
        num(e_b_written),
        num(p.poisson_ratio),
        num(nu_b)
    )
    .ok();
    let model = match plan.law {
        Law::Hertz { .. } | Law::Tsuji { .. } | Law::Viscoelastic { .. } => {
            "model hertz tangential no_history".to_string()
        }
        Law::Linear { stiffness } | Law::Dashpot { stiffness, .. } => {
            let (c, clamp) = match plan.law {
                Law::Dashpot { damping, clamp, .. } => (damping, clamp),
                _ => (0.0, false),
            };
            let pair = |x: f64| format!("{x} {x} {x} {x}", x = num(x));
            writeln!(
                d,
                "# The pre-mixed pair stiffness k = E_eff R_eff and the absolute damping c (N s/m).\n\
                 fix          m5 all property/global kn peratomtypepair 2 {}\n\
                 fix          m6 all property/global kt peratomtypepair 2 {}\n\
                 fix          m7 all property/global gamman_abs peratomtypepair 2 {}\n\
                 fix          m8 all property/global gammat_abs peratomtypepair 2 {}",
                pair(stiffness),
                pair(0.0),
                pair(c),
                pair(0.0)
            )
            .ok();
            format!(
                "model hooke/stiffness tangential no_history absolute_damping on limitForce {}",
                if clamp { "on" } else { "off" }
            )
        }
    };
    writeln!(
        d,
        "\npair_style   gran {model}\npair_coeff   * *\ntimestep     {}\n\
         create_atoms 1 single 0 0 {} units box\n\
         set          atom 1 diameter {} density {}\n\
         group        particle id 1\n\
         velocity     particle set 0 0 {} units box",
        num(plan.dt),
        num(p.z),
        num(2.0 * p.radius),
        num(p.density),
        num(p.velocity)
    )
    .ok();
    let mut integrated = "particle";
    match plan.boundary {
        Boundary::Sphere {
            radius,
            density,
            fixed,
            velocity,
            ..
        } => {
            writeln!(
                d,
                "create_atoms 2 single 0 0 0 units box\n\
                 set          atom 2 diameter {} density {}\n\
                 group        boundary id 2",
                num(2.0 * radius),
                num(density)
            )
            .ok();
            if fixed {
                writeln!(d, "# the boundary sphere is frozen: never integrated").ok();
            } else {
                writeln!(
                    d,
                    "velocity     boundary set 0 0 {} units box",
                    num(velocity)
                )
                .ok();
                integrated = "all";
            }
        }
        Boundary::Plane { .. } => {
            writeln!(
                d,
                "# the plane z = 0 of type 2's material (R* = R_m)\n\
                 fix          wall all wall/gran {model} primitive type 2 zplane 0.0"
            )
            .ok();
        }
    }
    writeln!(d, "fix          integrate {integrated} nve/sphere").ok();
    crate::lammps::write_gravity(&mut d, plan, sphere);
    let g_p = plan.particle_gravity();
    let (h, v) = if sphere {
        (
            format!("{}-(z[1]-z[2])", num(plan.contact_distance())),
            "vz[1]-vz[2]",
        )
    } else {
        (format!("{}-z[1]", num(p.radius)), "vz[1]")
    };
    let f = if g_p > 0.0 {
        format!("fz[1]+{}", num(p.mass * g_p))
    } else {
        "fz[1]".into()
    };
    writeln!(
        d,
        "\n# trace: time (s), overlap (m), relative velocity (m/s), contact force on the particle (N)\n\
         variable     t equal step*dt\nvariable     h equal {h}\nvariable     v equal {v}\n\
         variable     f equal {f}\nthermo       100000"
    )
    .ok();
    let mut at = 0;
    for (i, w) in plan.windows.iter().enumerate() {
        if w.start > at {
            writeln!(d, "run          {}   # to step {}", w.start - at, w.start).ok();
        }
        let target = if i == 0 {
            format!(
                "file trace.txt title \"{}\"",
                crate::trace_title(&plan.scenario)
            )
        } else {
            "append trace.txt title none".to_string()
        };
        writeln!(
            d,
            "fix          trace all print 1 \"${{t}} ${{h}} ${{v}} ${{f}}\" {target} screen no\n\
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
