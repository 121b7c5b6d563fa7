//! `dembound particle-wall SURFACE --radius R_b --out DIR`: boundary
//! particles covering a part (issue 29; the rules in
//! `dembound_scene::sources::mesh_tiling`), written for dembound, LAMMPS,
//! LIGGGHTS and Yade, with the largest hole and the bumpiness.

use super::{output_dir, CliError, CliResult};
use crate::output::covering_picture;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use dembound_scene::io::vtk::{write_snapshot, Snapshot};
use dembound_scene::sources::mesh_tiling::measure::{bumpiness, holes, Holes};
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

    /// Boundary-sphere radius R_b, m
    #[arg(long, value_name = "R_B")]
    pub radius: f64,

    /// The lattice of each flat face
    #[arg(long, value_enum, default_value = "square")]
    pub tiling: TilingArg,

    /// Centre distance of neighbouring spheres, m (default 2 R_b: touching)
    #[arg(long, value_name = "S")]
    pub spacing: Option<f64>,

    /// Smallest particle radius R_min, m: the report says whether it can
    /// pass the largest hole, and the bumpiness it feels (default R_b)
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
fn builtin(surface: &str) -> CliResult<Option<Vec<dembound_scene::walls::mesh::Triangle>>> {
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

pub fn run(args: &ParticleWallArgs) -> CliResult {
    let radius = positive("--radius", args.radius)?;
    let spacing = positive("--spacing", args.spacing.unwrap_or(2.0 * radius))?;
    let min_radius = positive("--min-radius", args.min_radius.unwrap_or(radius))?;
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
    let scene_error = |e: dembound_scene::SceneError| {
        if e.is_input() {
            CliError::input(e)
        } else {
            CliError::failed(e)
        }
    };
    let mut out = output_dir(&args.out, "particle-wall")?;
    let covering = match builtin(&args.surface)? {
        Some(soup) => cover(Path::new(&args.surface), &soup, &options),
        None => cover_file(Path::new(&args.surface), &options),
    }
    .map_err(scene_error)?;
    let hole = holes(&covering);
    let bump = bumpiness(&covering, min_radius);

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
    let report = report_text(args, &covering, &hole, bump, min_radius);
    out.write("report.md", |w| Ok(w.write_all(report.as_bytes())?))
        .map_err(CliError::failed)?;
    let written = out.commit().map_err(CliError::failed)?;
    let mut stdout = std::io::stdout().lock();
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
fn csv_text(c: &Covering) -> String {
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

fn report_text(
    args: &ParticleWallArgs,
    c: &Covering,
    h: &Holes,
    bump: Option<(f64, usize)>,
    min_radius: f64,
) -> String {
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
    let bytes = dembound_scene::io::memory::estimate(count as u64, false);
    let _ = writeln!(
        s,
        "Memory in a dembound scene: about {:.3} MB ({} B per sphere, Verlet without friction; \
         {} B with Gear5 or friction); spheres.csv {:.3} MB.\n",
        bytes as f64 / 1e6,
        dembound_scene::io::memory::BYTES_PER_SPHERE,
        dembound_scene::io::memory::BYTES_PER_SPHERE_GEAR5_OR_FRICTION,
        csv_text(c).len() as f64 / 1e6
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
                h.spacing
            );
        }
        None => {
            let _ = writeln!(
                s,
                "No face is wide enough (R_b + R_min + s around a point) to measure it away from edges.\n"
            );
        }
    }
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
