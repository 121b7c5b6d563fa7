//! Yade script (checked with Debian's Yade 2023.02a).
//!
//! Mapping (docs/export-yade.md):
//! - Hertz: `FrictMat` per body (E, ν, ρ, friction 0) with
//!   `Ip2_FrictMat_FrictMat_MindlinPhys` and `Law2_ScGeom_MindlinPhys_Mindlin`:
//!   k = 4/3 E* √R*, E* = Ea Eb/((1 − νa²) Eb + (1 − νb²) Ea), R* = Ra Rb/(Ra + Rb),
//!   F = k δ^(3/2): eq 6 and eq 4 exactly, each body its own material.
//! - linear and spring–dashpot: `ViscElMat` with explicit kn, cn on both
//!   bodies (Yade combines them harmonically, so each gets 2k and 2c);
//!   `Law2_ScGeom_ViscElPhys_Basic` always clamps F = max(F, 0).
//! - r = ∞: a fixed sphere of radius 1e6 R_m, not `utils.wall`: for a wall
//!   the Mindlin functor takes R* = R_m/2 (the wall has no radius and the
//!   sphere's is used twice), 15 % off in h_max and T_c.
//! - `NewtonIntegrator(damping=0)`: Yade's default Cundall damping of 0.2
//!   would take energy out of every step. Gravity is a permanent force on
//!   the particle (`O.forces.setPermF`), so a free boundary feels none
//!   unless `motion.gravity_on = "both"`.
//! - Yade's leapfrog stores the velocity half a step back: the initial
//!   velocity written is v₀ − a₀ Δt/2, so that the trajectory is dembound's,
//!   and the trace says its velocities are at t − Δt/2.

use crate::plan::{Boundary, Law, Plan};
use crate::{num, Error, Pitfall, Result};
use std::fmt::Write;

/// The radius ratio of the sphere that stands in for a plane.
pub const PLANE_RADIUS_RATIO: f64 = 1e6;

pub fn deck(plan: &Plan, pitfall: Option<Pitfall>) -> Result<String> {
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
            "boundary.modulus_ratio = inf: Yade's FrictMat needs a finite Young's modulus \
             (give e.g. boundary.modulus_ratio = 1e6: E_eff then differs by 1e-6)"
                .into(),
        ));
    }
    if let Law::Dashpot { clamp: false, .. } = plan.law {
        return Err(Error::Export(
            "contact.attractive = true: Yade's ViscElMat law always clamps the normal force at \
             zero; export with contact.attractive = false"
                .into(),
        ));
    }
    if matches!(plan.law, Law::Tsuji { .. } | Law::Viscoelastic { .. }) {
        return Err(Error::Export(
            "contact.damping = \"tsuji\" or \"viscoelastic\" with contact.law = \"hertz\" \
             cannot be exported to Yade (exported to LAMMPS only so far)"
                .into(),
        ));
    }
    let mut d = String::new();
    for line in plan.provenance() {
        writeln!(d, "# {line}").ok();
    }
    if let Some(pf) = pitfall {
        writeln!(
            d,
            "#\n# !!! PITFALL SCRIPT ({}): written wrong on purpose to show what this setting does.\n\
             # !!! Do not use it; the script without --pitfall is the right one.",
            pf.name()
        )
        .ok();
    }
    let yade_wall = pitfall == Some(Pitfall::YadeWall);
    if yade_wall && !matches!(plan.boundary, Boundary::Plane { .. }) {
        return Err(Error::Export(
            "--pitfall yade-wall (a Yade pitfall) needs boundary.radius_ratio = inf (a plane)"
                .into(),
        ));
    }
    let cundall = if pitfall == Some(Pitfall::CundallDamping) {
        "0.2"
    } else {
        "0.0"
    };
    writeln!(d, "#\n# Run: yade -n -x bounce.py\n").ok();
    let g_p = plan.particle_gravity();
    let g_b = plan.boundary_gravity();
    let (r_b, z_b, fixed, rho_b, v_b, plane) = match plan.boundary {
        Boundary::Sphere {
            radius,
            fixed,
            density,
            velocity,
            ..
        } => (radius, 0.0, fixed, density, velocity, false),
        Boundary::Plane { .. } => {
            let r = PLANE_RADIUS_RATIO * p.radius;
            (r, -r, true, p.density, 0.0, true)
        }
    };
    if plane {
        writeln!(
            d,
            "# r = inf: the plane z = 0 is the top of a fixed sphere of radius {} R_m (R* differs\n\
             # from R_m by 1e-6); Yade's utils.wall would give R* = R_m/2 with the Mindlin law.",
            num(PLANE_RADIUS_RATIO)
        )
        .ok();
    }
    let materials = match plan.law {
        Law::Hertz { .. } | Law::Tsuji { .. } | Law::Viscoelastic { .. } => format!(
            "mat_p = O.materials.append(FrictMat(young={}, poisson={}, density={}, frictionAngle=0.0))\n\
             mat_b = O.materials.append(FrictMat(young={}, poisson={}, density={}, frictionAngle=0.0))\n\
             physics = [Ip2_FrictMat_FrictMat_MindlinPhys()]\n\
             law = [Law2_ScGeom_MindlinPhys_Mindlin()]",
            num(p.youngs_modulus),
            num(p.poisson_ratio),
            num(p.density),
            num(e_b),
            num(nu_b),
            num(rho_b)
        ),
        Law::Linear { stiffness } | Law::Dashpot { stiffness, .. } => {
            let c = match plan.law {
                Law::Dashpot { damping, .. } => damping,
                _ => 0.0,
            };
            format!(
                "# Yade combines kn and cn of the two bodies harmonically: each gets 2k and 2c.\n\
                 k, c = {}, {}\n\
                 mat_p = O.materials.append(ViscElMat(kn=2*k, cn=2*c, ks=0.0, cs=0.0, density={}, frictionAngle=0.0))\n\
                 mat_b = O.materials.append(ViscElMat(kn=2*k, cn=2*c, ks=0.0, cs=0.0, density={}, frictionAngle=0.0))\n\
                 physics = [Ip2_ViscElMat_ViscElMat_ViscElPhys()]\n\
                 law = [Law2_ScGeom_ViscElPhys_Basic()]",
                num(stiffness),
                num(c),
                num(p.density),
                num(rho_b)
            )
        }
    };
    let windows: Vec<String> = plan
        .windows
        .iter()
        .map(|w| format!("({}, {})", w.start, w.end))
        .collect();
    writeln!(
        d,
        "{materials}\n\
         p = O.bodies.append(sphere((0, 0, {z_p}), {r_p}, material=mat_p))\n\
         {boundary_body}\n\
         O.dt = {dt}\n\
         O.engines = [\n\
         \x20   ForceResetter(),\n\
         \x20   InsertionSortCollider([Bo1_Sphere_Aabb(){bo_wall}]),\n\
         \x20   InteractionLoop([Ig2_Sphere_Sphere_ScGeom(){ig_wall}], physics, law),\n\
         \x20   # damping=0: Yade's default Cundall damping is 0.2\n\
         \x20   NewtonIntegrator(damping={cundall}, gravity=(0, 0, 0)),\n\
         \x20   PyRunner(command='record()', iterPeriod=1, dead=True, label='recorder'),\n\
         ]\n\
         m_p = O.bodies[p].state.mass\n\
         m_b = O.bodies[b].state.mass\n\
         g_p, g_b = {g_p}, {g_b}\n\
         # gravity as permanent forces: on the particle (and on a free boundary with gravity_on = both)\n\
         O.forces.setPermF(p, Vector3(0, 0, -m_p * g_p))\n\
         if g_b > 0 and not {fixed}:\n\
         \x20   O.forces.setPermF(b, Vector3(0, 0, -m_b * g_b))\n\
         # leapfrog: the stored velocity is v(-dt/2) = v0 - a0 dt/2\n\
         O.bodies[p].state.vel = Vector3(0, 0, {v_p} + g_p * O.dt / 2)\n\
         if not {fixed}:\n\
         \x20   O.bodies[b].state.vel = Vector3(0, 0, {v_b} + g_b * O.dt / 2)\n\
         \n\
         trace = open('trace.txt', 'w')\n\
         trace.write('{title}\\n')\n\
         trace.write('# velocity_time_offset_s = %r\\n' % (-O.dt / 2))\n\
         \n\
         def record():\n\
         \x20   # after the integrator: positions at (iter + 1) dt, velocities half a step before\n\
         \x20   sp, sb = O.bodies[p].state, O.bodies[b].state\n\
         \x20   h = {contact} - (sp.pos[2] - sb.pos[2]{plane_shift})\n\
         \x20   v = sp.vel[2] - sb.vel[2]\n\
         \x20   f = O.forces.f(p)[2] + m_p * g_p\n\
         \x20   trace.write('%r %r %r %r\\n' % ((O.iter + 1) * O.dt, h, v, f))\n\
         \n\
         at = 0\n\
         for start, end in [{windows}]:\n\
         \x20   if start > at:\n\
         \x20       O.run(start - at, True)\n\
         \x20   recorder.dead = False\n\
         \x20   O.run(end - start, True)\n\
         \x20   recorder.dead = True\n\
         \x20   at = end\n\
         trace.close()",
        z_p = num(p.z),
        r_p = num(p.radius),
        boundary_body = if yade_wall {
            "# PITFALL: utils.wall instead of a large sphere\n\
             b = O.bodies.append(utils.wall(0, axis=2, material=mat_b))"
                .to_string()
        } else {
            format!(
                "b = O.bodies.append(sphere((0, 0, {}), {}, material=mat_b, fixed={}))",
                num(z_b),
                num(r_b),
                if fixed { "True" } else { "False" }
            )
        },
        bo_wall = if yade_wall { ", Bo1_Wall_Aabb()" } else { "" },
        ig_wall = if yade_wall { ", Ig2_Wall_Sphere_ScGeom()" } else { "" },
        cundall = cundall,
        fixed = if fixed { "True" } else { "False" },
        dt = num(plan.dt),
        g_p = num(g_p),
        g_b = num(g_b),
        v_p = num(p.velocity),
        v_b = num(v_b),
        contact = num(plan.contact_distance()),
        plane_shift = if plane && !yade_wall {
            format!(" - {}", num(r_b))
        } else {
            String::new()
        },
        windows = windows.join(", "),
        title = crate::trace_title(&plan.scenario),
    )
    .ok();
    Ok(d)
}
