//! `dembound particle-wall SURFACE --radius R_b --out DIR`: boundary
//! particles covering a part (issue 29; the rules in
//! `dembound_scene::sources::mesh_tiling`), written for dembound, LAMMPS,
//! LIGGGHTS and Yade, with the largest hole and the bumpiness.

use super::particle_wall_choice::{self as choice, ChoiceArgs};
use super::particle_wall_report::{report_text, Measures, Size};
use super::{output_dir, CliError, CliResult};
use crate::output::boundary;
use crate::output::covering_picture;
use crate::output::format::sig;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use dembound_scene::io::vtk::{write_snapshot, Snapshot};
use dembound_scene::sources::mesh_tiling::measure::{bumpiness, holes, holes_sampled};
use dembound_scene::sources::mesh_tiling::slopes::bump_slopes;
use dembound_scene::sources::mesh_tiling::{
    cover, cover_file, shapes, Covering, CoveringOptions, Origin,
};
use dembound_scene::sources::tiling::Pattern;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TilingArg {
    Square,
    #[value(alias = "hexagonal")]
    Hex,
}

#[derive(Debug, Args)]
pub struct ParticleWallArgs {
    /// The surface: an STL or OBJ file (m), or `square:SIDE` (the square
    /// [0, SIDE]² at z = 0, normal +z) or `cylinder:RADIUS,HEIGHT` (closed,
    /// about the z axis from z = 0, 96 facets around)
    pub surface: String,

    /// Boundary-sphere radius R_b, m (or --tolerance chooses it); the
    /// report states its single-contact deviations
    #[arg(long, value_name = "R_B", allow_hyphen_values = true)]
    pub radius: Option<f64>,

    #[command(flatten)]
    pub choice: ChoiceArgs,

    /// The lattice of each flat face
    #[arg(long, value_enum, default_value = "square")]
    pub tiling: TilingArg,

    /// Centre distance of neighbouring spheres, m (default 2 R_b: touching)
    #[arg(long, value_name = "S")]
    pub spacing: Option<f64>,

    /// Smallest particle radius R_min, m: the report says whether it can
    /// pass the largest hole, and the bumpiness and friction it feels
    /// (default: with --tolerance the particle's radius R_m, which must
    /// not pass; with --radius R_b)
    #[arg(long, value_name = "R_MIN")]
    pub min_radius: Option<f64>,

    /// Put the spheres on the side the triangles' normals point to (the
    /// particles on the other side)
    #[arg(long)]
    pub flip: bool,

    /// Density written into the LAMMPS data file, kg/m³ (frozen atoms:
    /// their mass plays no part)
    #[arg(long, default_value_t = 2500.0)]
    pub density: f64,

    /// Directory for spheres.csv, spheres.data, spheres.vtp,
    /// yade_spheres.py, covering.png and report.md; all files or none
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

fn positive(key: &str, v: f64) -> CliResult<f64> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(CliError::input(anyhow!(
            "`{key}` = {v}: must be a finite length > 0 m"
        )))
    }
}

/// The built-in surfaces `square:SIDE` and `cylinder:R,H`.
pub(super) fn builtin(
    surface: &str,
) -> CliResult<Option<Vec<dembound_scene::walls::mesh::Triangle>>> {
    let Some((kind, values)) = surface.split_once(':') else {
        return Ok(None);
    };
    let numbers: Vec<f64> = values
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            CliError::input(anyhow!(
                "SURFACE `{surface}`: the values after `{kind}:` must be numbers (m)"
            ))
        })?;
    match (kind, numbers.as_slice()) {
        ("square", [side]) => Ok(Some(shapes::square(positive("square:SIDE", *side)?))),
        ("cylinder", [r, h]) => Ok(Some(shapes::cylinder(
            positive("cylinder:RADIUS", *r)?,
            positive("cylinder:HEIGHT", *h)?,
            96,
            1,
        ))),
        _ => Err(CliError::input(anyhow!(
            "SURFACE `{surface}`: expected an .stl or .obj file, `square:SIDE` or \
             `cylinder:RADIUS,HEIGHT` (m)"
        ))),
    }
}

/// R_b and how it came about: given (with its deviations) or chosen.
fn size(args: &ParticleWallArgs, q: &choice::Question) -> CliResult<(f64, Size)> {
    match (args.radius, q.tolerance) {
        (Some(_), Some(_)) => Err(CliError::input(anyhow!(
            "`--radius` and `--tolerance` both given: give one (R_b, or T to choose it)"
        ))),
        (None, None) => Err(CliError::input(anyhow!(
            "give `--radius R_B` (m) or `--tolerance T` (to choose R_b from the single-contact study)"
        ))),
        (Some(r_b), None) => {
            let r_b = positive("--radius", r_b)?;
            let deviations = choice::deviations(q, r_b / q.base.particle.radius)
                .map_err(|e| e.error().to_string());
            Ok((r_b, Size::Given { deviations }))
        }
        (None, Some(t)) => {
            let (r, limits) = choice::choose(q, t)?;
            let deviations = choice::deviations(q, r)?;
            Ok((
                r * q.base.particle.radius,
                Size::Chosen {
                    tolerance: t,
                    limits,
                    deviations,
                },
            ))
        }
    }
}

/// Hole sampling with --tolerance: fine enough that the bound (sampled +
/// h) decides leaks for R_min, h = min(s/8, R_min/16), but at most 2e7
/// samples' worth of area (the faces' area / h²).
fn hole_spacing(c: &Covering, min_radius: f64) -> f64 {
    let h = (c.options.spacing / 8.0).min(min_radius / 16.0);
    h.max((c.mesh.area / 2e7).sqrt())
}

/// The refusal when the chosen spheres leak: what would not leak, and the
/// deviations there.
fn leak_refusal(
    c: &Covering,
    hole: &dembound_scene::sources::mesh_tiling::measure::Holes,
    min_radius: f64,
    q: &choice::Question,
) -> CliError {
    let r_m = q.base.particle.radius;
    let r_b = c.options.radius;
    // A flat tiling of spacing k R_b leaves holes (w/R_b − 1) R_b, w the
    // window's circumradius: leak-free needs R_b < R_min/(w/R_b − 1).
    let per = dembound_scene::sources::mesh_tiling::window_circumradius(&c.options) / r_b - 1.0;
    let flat = if per > 0.0 {
        let r_leak = min_radius / per / r_m;
        let at = choice::deviations(q, r_leak)
            .map(|d| {
                format!(
                    "; there the largest deviation is {} %",
                    sig(choice::largest(&d) * 100.0, 4)
                )
            })
            .unwrap_or_default();
        format!(
            " A flat tiling of this spacing (s = {} R_b) is leak-free for R_min = {} m only \
             below r = {} (R_b = {} m){at}: raise `--tolerance` to that, or lower `--spacing`, or \
             give `--radius`.",
            sig(c.options.spacing / r_b, 4),
            boundary::si_text(min_radius),
            sig(r_leak, 5),
            boundary::si_text(r_leak * r_m)
        )
    } else {
        String::new()
    };
    CliError::input(anyhow!(
        "invalid value for `--tolerance`: the smallest spheres within it (r = {}, R_b = {} m) leave \
         holes up to {} m (found {} m), not below R_min = {} m: particles would pass the wall \
         (criterion: the largest hole's upper bound < R_min).{flat}",
        sig(r_b / r_m, 6),
        boundary::si_text(r_b),
        boundary::si_text(hole.hole_bound),
        boundary::si_text(hole.hole),
        boundary::si_text(min_radius),
    ))
}

pub fn run(args: &ParticleWallArgs) -> CliResult {
    let q = choice::question(&args.choice)?;
    let (radius, size) = size(args, &q)?;
    let chosen = matches!(size, Size::Chosen { .. });
    let spacing = positive("--spacing", args.spacing.unwrap_or(2.0 * radius))?;
    let default_min = if chosen {
        q.base.particle.radius
    } else {
        radius
    };
    let min_radius = positive("--min-radius", args.min_radius.unwrap_or(default_min))?;
    positive("--density", args.density).map_err(|_| {
        CliError::input(anyhow!(
            "`--density` = {}: must be a finite density > 0 kg/m³",
            args.density
        ))
    })?;
    let options = CoveringOptions {
        radius,
        spacing,
        pattern: match args.tiling {
            TilingArg::Square => Pattern::Square,
            TilingArg::Hex => Pattern::Hexagonal,
        },
        flip: args.flip,
    };
    let scene_error = super::scene::scene_error;
    let mut out = output_dir(&args.out, "particle-wall")?;
    let covering = match builtin(&args.surface)? {
        Some(soup) => cover(Path::new(&args.surface), &soup, &options),
        None => cover_file(Path::new(&args.surface), &options),
    }
    .map_err(scene_error)?;
    let hole = if chosen {
        holes_sampled(&covering, hole_spacing(&covering, min_radius))
    } else {
        holes(&covering)
    };
    if chosen && min_radius <= hole.hole_bound {
        return Err(leak_refusal(&covering, &hole, min_radius, &q));
    }
    let measures = Measures {
        holes: hole,
        bump: bumpiness(&covering, min_radius),
        slopes: bump_slopes(&covering, min_radius),
        min_radius,
    };
    let hole = measures.holes;

    out.write("spheres.csv", |w| {
        Ok(w.write_all(csv_text(&covering).as_bytes())?)
    })
    .map_err(CliError::failed)?;
    out.write("spheres.data", |w| {
        Ok(w.write_all(lammps_data(&covering, args.density).as_bytes())?)
    })
    .map_err(CliError::failed)?;
    out.write("spheres.vtp", |w| Ok(vtp(&covering, w)?))
        .map_err(CliError::failed)?;
    out.write("yade_spheres.py", |w| Ok(w.write_all(YADE.as_bytes())?))
        .map_err(CliError::failed)?;
    let png = out.path("covering.png").map_err(CliError::failed)?;
    let title = format!(
        "{} boundary spheres, R_b = {:e} m, on {}",
        covering.spheres.len(),
        radius,
        args.surface
    );
    covering_picture::write(&covering, &png, &title).map_err(CliError::failed)?;
    let report = report_text(args, &covering, &measures, &size, &q);
    out.write("report.md", |w| Ok(w.write_all(report.as_bytes())?))
        .map_err(CliError::failed)?;
    let written = out.commit().map_err(CliError::failed)?;
    let mut stdout = std::io::stdout().lock();
    if let Size::Chosen { tolerance, .. } = &size {
        writeln!(
            stdout,
            "chosen: r = {}, R_b = {} m (the smallest within {} % of the part's flat wall), \
             spheres of the part's material",
            sig(radius / q.base.particle.radius, 6),
            boundary::si_text(radius),
            sig(tolerance * 100.0, 4)
        )
        .map_err(CliError::failed)?;
    }
    writeln!(
        stdout,
        "{} boundary spheres of radius {:e} m; largest hole {:.4e} m ({:.3} R_b, ≤ {:.4e} m)",
        covering.spheres.len(),
        radius,
        hole.hole,
        hole.hole / radius,
        hole.hole_bound
    )
    .map_err(CliError::failed)?;
    if min_radius <= hole.hole_bound {
        eprintln!(
            "warning: particles of radius {min_radius:e} m {} the largest hole (≤ {:.4e} m): \
             lower --spacing or --radius",
            if min_radius <= hole.hole {
                "pass through"
            } else {
                "may pass through"
            },
            hole.hole_bound
        );
    }
    for p in written {
        writeln!(stdout, "wrote {}", p.display()).map_err(CliError::failed)?;
    }
    Ok(())
}

/// `x,y,z,radius` (m), shortest round-trip decimals: what
/// `[[particles]] csv = …` reads.
pub(super) fn csv_text(c: &Covering) -> String {
    let mut s = String::from("x,y,z,radius\n");
    for b in &c.spheres {
        let p = b.position;
        let _ = writeln!(s, "{:?},{:?},{:?},{:?}", p[0], p[1], p[2], b.radius);
    }
    s
}

/// A LAMMPS data file, `atom_style sphere`, one atom type.
fn lammps_data(c: &Covering, density: f64) -> String {
    let r = c.options.radius;
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for b in &c.spheres {
        for k in 0..3 {
            lo[k] = lo[k].min(b.position[k] - 2.0 * r);
            hi[k] = hi[k].max(b.position[k] + 2.0 * r);
        }
    }
    if c.spheres.is_empty() {
        (lo, hi) = ([-1.0; 3], [1.0; 3]);
    }
    let mut s = format!(
        "LAMMPS data file (atom_style sphere) written by `dembound particle-wall`: boundary spheres, \
         to be kept frozen\n\n{} atoms\n1 atom types\n\n{:?} {:?} xlo xhi\n{:?} {:?} ylo yhi\n\
         {:?} {:?} zlo zhi\n\nAtoms # sphere\n\n",
        c.spheres.len(),
        lo[0],
        hi[0],
        lo[1],
        hi[1],
        lo[2],
        hi[2]
    );
    for (i, b) in c.spheres.iter().enumerate() {
        let p = b.position;
        let _ = writeln!(
            s,
            "{} 1 {:?} {:?} {:?} {:?} {:?}",
            i + 1,
            2.0 * b.radius,
            density,
            p[0],
            p[1],
            p[2]
        );
    }
    s
}

fn vtp(c: &Covering, w: &mut dyn Write) -> std::io::Result<()> {
    let n = c.spheres.len();
    let positions: Vec<[f64; 3]> = c.spheres.iter().map(|s| s.position).collect();
    let radii: Vec<f64> = c.spheres.iter().map(|s| s.radius).collect();
    let zeros = vec![[0.0; 3]; n];
    let fixed = vec![true; n];
    // The `material` column holds what made each sphere: 0 face, 1 corner,
    // 2 edge, 3 fill.
    let made: Vec<usize> = c
        .origin
        .iter()
        .map(|o| match o {
            Origin::Face => 0,
            Origin::Corner => 1,
            Origin::Edge => 2,
            Origin::Fill => 3,
        })
        .collect();
    write_snapshot(
        w,
        &Snapshot {
            time: 0.0,
            step: 0,
            positions: &positions,
            radii: &radii,
            velocities: &zeros,
            forces: &zeros,
            fixed: &fixed,
            materials: &made,
            angular_velocities: &zeros,
        },
    )
}

/// Reads spheres.csv into Yade as fixed spheres.
const YADE: &str = "# Yade: the boundary spheres of `dembound particle-wall` as fixed bodies.\n\
# In a Yade script: exec(open('yade_spheres.py').read()); wall_ids = add_boundary_spheres(mat)\n\
import csv\n\n\
def add_boundary_spheres(material, path='spheres.csv'):\n\
    ids = []\n\
    with open(path) as f:\n\
        for row in csv.DictReader(f):\n\
            c = (float(row['x']), float(row['y']), float(row['z']))\n\
            ids.append(O.bodies.append(sphere(c, float(row['radius']), fixed=True, material=material)))\n\
    return ids\n";
