//! `particle-wall`'s report.md: the surface, the size of the spheres
//! (chosen from the single-contact study, or given, with its deviations),
//! count and memory, the largest hole, the bumpiness and the friction the
//! bumps add, and how to use the files in each code.

use super::particle_wall::ParticleWallArgs;
use super::particle_wall_choice::Question;
use crate::output::boundary;
use crate::output::format::sig;
use dembound_core::study::recommend::{Deviations, Limit, Outcome};
use dembound_scene::sources::mesh_tiling::measure::Holes;
use dembound_scene::sources::mesh_tiling::slopes::BumpSlopes;
use dembound_scene::sources::mesh_tiling::{Covering, Origin};
use std::fmt::Write as _;

/// What was measured on the covering.
pub(super) struct Measures {
    pub holes: Holes,
    /// (bumpiness, samples used).
    pub bump: Option<(f64, usize)>,
    pub slopes: Option<BumpSlopes>,
    /// R_min, m.
    pub min_radius: f64,
}

/// How R_b came about.
pub(super) enum Size {
    /// `--radius`: the deviations of that size (or why they could not be
    /// computed).
    Given {
        deviations: Result<Vec<Deviations>, String>,
    },
    /// `--tolerance`: the limits of every (law, quantity) and the
    /// deviations at the chosen r.
    Chosen {
        tolerance: f64,
        limits: Vec<Limit>,
        deviations: Vec<Deviations>,
    },
}

fn pct(x: Option<f64>) -> String {
    x.map(|x| format!("{} %", sig(x * 100.0, 4)))
        .unwrap_or_else(|| "–".into())
}

/// The particle, the part's material and the speed, one paragraph.
fn context(q: &Question) -> String {
    let b = &q.base;
    let p = &b.particle;
    let zeta = q.modulus_ratio();
    format!(
        "Particle: R_m = {} m, E_m = {} Pa, ν_m = {}, ρ = {} kg/m³, hitting at {} m/s. Part \
         (the real wall, and the spheres' material): E_b = {} Pa (ζ = E_b/E_m = {}), ν_b = {}. \
         Reference: a flat wall of the part's material (`recommend --reference half-space`), \
         one contact, gravity {} m/s².\n\n",
        boundary::si_text(p.radius),
        boundary::si_text(p.youngs_modulus),
        p.poisson_ratio,
        boundary::si_text(p.density),
        sig(b.impact_speed(), 6),
        boundary::si_text(boundary::youngs_modulus(b, zeta)),
        boundary::si_text(zeta),
        b.boundary.poisson_ratio.unwrap_or(p.poisson_ratio),
        b.motion.gravity
    )
}

fn deviations_rows(s: &mut String, ds: &[Deviations]) {
    let _ = writeln!(
        s,
        "| law | quantity | deviation, exact model | deviation, integrator |\n|---|---|---|---|"
    );
    for d in ds {
        for x in &d.quantities {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                d.law.name(),
                x.quantity.symbol(),
                pct(Some(x.exact)),
                pct(Some(x.simulated))
            );
        }
    }
    s.push('\n');
}

/// The size section: chosen (limits, deviations) or given (deviations).
fn size_text(c: &Covering, size: &Size, q: &Question) -> String {
    let r_b = c.options.radius;
    let r = r_b / q.base.particle.radius;
    let mut s = String::new();
    match size {
        Size::Chosen {
            tolerance,
            limits,
            deviations,
        } => {
            let _ = writeln!(s, "## Choice of R_b\n");
            s.push_str(&context(q));
            let _ = writeln!(
                s,
                "Tolerance T = {} % on |q(r, ζ)/q(∞, ζ) − 1| for each quantity below; the smallest \
                 r = R_b/R_m of each (exact model, Brent; `recommend`'s search), and the choice, \
                 the largest: **r = {}, R_b = {} m**, spheres of the part's material \
                 (ζ = {}).\n",
                sig(tolerance * 100.0, 4),
                sig(r, 6),
                boundary::si_text(r_b),
                boundary::si_text(q.modulus_ratio())
            );
            let _ = writeln!(
                s,
                "| law | quantity | smallest r | R_b (m) |\n|---|---|---|---|"
            );
            for l in limits {
                let (value, rb) = match l.outcome {
                    Outcome::Found { value } => (
                        sig(value, 6),
                        boundary::si_text(value * q.base.particle.radius),
                    ),
                    Outcome::AnyValue => ("any".into(), "–".into()),
                    Outcome::Unreachable { .. } => ("none".into(), "–".into()),
                };
                let _ = writeln!(
                    s,
                    "| {} | {} | {value} | {rb} |",
                    l.law.name(),
                    l.quantity.symbol()
                );
            }
            let _ = writeln!(
                s,
                "\nPredicted single-contact deviations at the chosen r:\n"
            );
            deviations_rows(&mut s, deviations);
        }
        Size::Given { deviations } => {
            let _ = writeln!(s, "## Single-contact deviations of R_b\n");
            match deviations {
                Ok(ds) => {
                    s.push_str(&context(q));
                    let _ = writeln!(
                        s,
                        "R_b = {} m given: r = R_b/R_m = {}; spheres of the part's material. \
                         Deviations |q(r, ζ)/q(∞, ζ) − 1| (`--tolerance T` chooses the smallest R_b \
                         within T):\n",
                        boundary::si_text(r_b),
                        sig(r, 6)
                    );
                    deviations_rows(&mut s, ds);
                }
                Err(why) => {
                    let _ = writeln!(s, "Not computed: {why}.\n");
                }
            }
        }
    }
    let _ = writeln!(
        s,
        "In a dembound scene: `[[wall]] boundary_particles = {{ mesh = \"…\", radius_ratio = {}, \
         modulus_ratio = 1, tiling = \"{}\", reference_radius = {:e} }}` with `material` the part's \
         (E_b = modulus_ratio × its E).\n",
        sig(r, 6),
        match c.options.pattern {
            dembound_scene::sources::tiling::Pattern::Square => "square",
            dembound_scene::sources::tiling::Pattern::Hexagonal => "hexagonal",
        },
        q.base.particle.radius
    );
    s
}

/// The friction the bumps add (`mesh_tiling::slopes`).
fn friction_text(m: &Measures) -> String {
    let mut s = String::from("## Friction added by the bumps\n\n");
    match m.slopes {
        Some(b) if m.min_radius > m.holes.hole_bound => {
            let _ = writeln!(
                s,
                "A frictionless particle of radius {:e} m pressed on the wall by a load N and pushed \
                 along it by F_t moves its centre over the spheres' domes; where that surface rises at \
                 slope tan θ it climbs only if F_t ≥ N tan θ, so the bumps act as a friction \
                 coefficient a flat wall does not have. At the deepest hollow ({} spheres meet at \
                 ({:.4e}, {:.4e}, {:.4e}) m): **μ_exit = {:.4}** (the easiest way out, toward the \
                 saddle between two spheres: the least friction the bumps add to sliding from rest) \
                 and μ_max = {:.4} (the steepest slope, toward a sphere's top). A flat touching \
                 tiling with R_min = R_b gives μ_exit = 1/√2 = 0.707 (square) and 1/√8 = 0.354 \
                 (hexagonal). With a contact friction μ_c the two combine as slopes: \
                 tan(θ + arctan μ_c) = (μ_exit + μ_c)/(1 − μ_exit μ_c) out of the hollow \
                 (`mesh_tiling::slopes` derives these).\n",
                m.min_radius, b.domes, b.at[0], b.at[1], b.at[2], b.exit, b.steepest
            );
        }
        Some(_) => {
            let _ = writeln!(
                s,
                "Not stated: particles of radius {:e} m may pass the holes (see above), so they rest \
                 in no hollow.\n",
                m.min_radius
            );
        }
        None => {
            let _ = writeln!(
                s,
                "No face is wide enough (R_b + R_min + s around a point) to find a hollow away from \
                 edges.\n"
            );
        }
    }
    s
}

pub(super) fn report_text(
    args: &ParticleWallArgs,
    c: &Covering,
    m: &Measures,
    size: &Size,
    q: &Question,
) -> String {
    let (h, bump, min_radius) = (&m.holes, m.bump, m.min_radius);
    let r = c.options.radius;
    let count = c.spheres.len();
    let by = |o: Origin| c.origin.iter().filter(|x| **x == o).count();
    let mesh = &c.mesh;
    let mut s = String::new();
    let _ = writeln!(s, "# Boundary particles on `{}`\n", args.surface);
    let _ = writeln!(
        s,
        "Surface: {} triangles, {} flat patches, area {:.6e} m², box [{:.4e}, {:.4e}, {:.4e}] – \
         [{:.4e}, {:.4e}, {:.4e}] m.\n",
        mesh.triangles.len(),
        mesh.patch_count(),
        mesh.area,
        mesh.lo[0],
        mesh.lo[1],
        mesh.lo[2],
        mesh.hi[0],
        mesh.hi[1],
        mesh.hi[2]
    );
    let _ = writeln!(
        s,
        "Tiling: {:?} lattice on every flat patch, R_b = {:e} m, spacing s = {:e} m ({:.3} R_b); \
         spheres on the {} side of the triangles' normals, tops on the surface, none crossing it.\n",
        c.options.pattern,
        r,
        c.options.spacing,
        c.options.spacing / r,
        if c.options.flip { "same" } else { "opposite" }
    );
    s.push_str(&size_text(c, size, q));
    let _ = writeln!(s, "## Count and memory\n");
    let _ = writeln!(
        s,
        "| spheres | on faces | at corners | along edges | filling holes | dropped: crossing the surface | dropped: near duplicate |\n|---|---|---|---|---|---|---|\n| {count} | {} | {} | {} | {} | {} | {} |\n",
        by(Origin::Face),
        by(Origin::Corner),
        by(Origin::Edge),
        by(Origin::Fill),
        c.dropped_crossing,
        c.dropped_duplicate
    );
    // A wall's spheres are listed.
    let listed = dembound_scene::io::memory::SphereCount {
        listed: count as u64,
        lattice: 0,
    };
    let bytes = dembound_scene::io::memory::estimate(listed, false);
    let _ = writeln!(
        s,
        "Memory in a dembound scene: about {:.3} MB ({} B per sphere, Verlet without friction; \
         {} B with Gear5 or friction); spheres.csv {:.3} MB.\n",
        bytes as f64 / 1e6,
        dembound_scene::io::memory::BYTES_PER_SPHERE,
        dembound_scene::io::memory::BYTES_PER_SPHERE_GEAR5_OR_FRICTION,
        super::particle_wall::csv_text(c).len() as f64 / 1e6
    );
    let _ = writeln!(s, "## Largest hole\n");
    let verdict = if min_radius > h.hole_bound {
        format!("particles of radius R_min = {min_radius:e} m cannot pass: the wall is leak-free for them")
    } else if min_radius > h.hole {
        format!(
            "particles of radius R_min = {min_radius:e} m may pass (R_min is between the sampled hole \
             and its bound): lower the spacing or the radius to be sure"
        )
    } else {
        format!(
            "**particles of radius R_min = {min_radius:e} m pass through the wall**: lower the spacing \
             or the radius"
        )
    };
    let _ = writeln!(
        s,
        "The largest particle that can pass between the boundary spheres has radius {:.6e} m \
         ({:.4} R_b), found at ({:.4e}, {:.4e}, {:.4e}) m; at most {:.6e} m ({:.4} R_b). So {verdict}.\n\n\
         How it is measured: a particle passing through the wall must cross the surface of the \
         sphere centres (the part's surface offset inward by R_b); where it crosses, it touches no \
         boundary sphere only if every centre is R_b + ρ away. The largest hole is the largest \
         distance from a point of that surface to its nearest centre, minus R_b, sampled every \
         {:.3e} m ({} samples); adding the sample spacing bounds it from above. A flat touching \
         tiling gives (√2 − 1) R_b = 0.414 R_b (square) and (2/√3 − 1) R_b = 0.155 R_b (hexagonal).\n",
        h.hole,
        h.hole / r,
        h.at[0],
        h.at[1],
        h.at[2],
        h.hole_bound,
        h.hole_bound / r,
        h.spacing,
        h.samples
    );
    let _ = writeln!(s, "## Bumpiness\n");
    match bump {
        Some((b, used)) => {
            let _ = writeln!(
                s,
                "A particle of radius {min_radius:e} m rolling on a face rises and falls by {b:.6e} m \
                 ({:.4} of its radius) between the tops of the spheres and the hollows between them \
                 (the resting height of its centre above the surface, sampled at {used} face points \
                 away from edges; sampled every {:.3e} m, so at most that much below the true value).\n",
                b / min_radius,
                c.options.spacing / 8.0
            );
        }
        None => {
            let _ = writeln!(
                s,
                "No face is wide enough (R_b + R_min + s around a point) to measure it away from edges.\n"
            );
        }
    }
    s.push_str(&friction_text(m));
    let _ = writeln!(
        s,
        "## How to use the files\n\n\
         - **dembound**: `[[particles]]` `csv = \"spheres.csv\"`, `material = \"…\"`, `fixed = true` \
         (the spheres as fixed particles of that material).\n\
         - **LAMMPS / LIGGGHTS**: `read_data spheres.data` (atom_style sphere, type 1 = boundary \
         spheres; with more types, `read_data … add append offset` or edit the type column); keep \
         them frozen: integrate only the other atoms (`group mobile subtract all wall`, `fix 1 \
         mobile nve/sphere`) and `neigh_modify exclude type 1 1`. The density column ({} kg/m³) \
         plays no part for frozen atoms.\n\
         - **Yade**: `exec(open('yade_spheres.py').read())`, then `add_boundary_spheres(material)` \
         adds the spheres of spheres.csv as fixed bodies.\n\
         - **ParaView**: spheres.vtp (points with `radius`; `material` = 0 face, 1 corner, 2 edge, 3 fill): \
         Glyph, sphere, scale by `radius`, factor 2.\n\
         - covering.png: the spheres seen obliquely (faces blue, corners red, edges orange, fill green).\n",
        args.density
    );
    s
}
