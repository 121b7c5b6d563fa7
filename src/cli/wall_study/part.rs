//! `dembound wall-study --wall SURFACE`: the study on the user's part
//! (`dembound_scene::wall_study::part`): impacts at random points of the
//! part against its mesh wall (of `--reference-material`) and against
//! particle coverings (r, ζ, tiling), the deviations per quantity and which
//! coverings stay within the tolerances; then the bed and the flow
//! ([`super::part_bed`]). Writes impacts.csv, summary.csv, part.png, the
//! bed's files and report.md through [`AtomicDir`], all or nothing.

use super::{config, input, tolerances, WallStudyArgs};
use crate::cli::particle_wall::builtin;
use crate::cli::{CliError, CliResult};
use crate::output::covering_picture;
use crate::output::files::AtomicDir;
use dembound_physics::material::Material;
use dembound_scene::wall_study::part::{self, CoveringSpec, PartConfig, PartResults};
use dembound_scene::wall_study::recommend::{mean, median, std_dev};
use dembound_scene::wall_study::{Floor, Tolerances};
use std::fmt::Write as _;
use std::path::Path;

/// A named reference material: (name, E Pa, ν, ρ kg/m³, source).
pub const NAMED: [(&str, f64, f64, f64, &str); 2] = [
    (
        "steel",
        207e9,
        0.30,
        7850.0,
        "plain carbon steel (1020): Callister & Rethwisch, Materials Science and Engineering, \
         Appendix B, Tables B.1–B.3",
    ),
    (
        "glass",
        69e9,
        0.23,
        2500.0,
        "soda-lime glass: Callister & Rethwisch, Materials Science and Engineering, Appendix B, \
         Tables B.1–B.3",
    ),
];

/// `steel`, `glass` or `E,NU[,RHO]`; ρ defaults to the particles'.
pub fn reference_material(text: &str, particles: &Material) -> CliResult<(Material, String)> {
    if let Some(&(name, e, nu, rho, source)) = NAMED.iter().find(|n| n.0 == text) {
        let m = Material {
            density: rho,
            youngs_modulus: e,
            poisson_ratio: nu,
        };
        return Ok((
            m,
            format!("{name}: E = {e:e} Pa, ν = {nu}, ρ = {rho} kg/m³ ({source})"),
        ));
    }
    let allowed = "`steel`, `glass` or `E,NU[,RHO]` with E > 0 Pa, -1 < ν < 0.5, ρ > 0 kg/m³";
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| input("--reference-material", format!("{text:?}"), allowed))?;
    let (e, nu, rho) = match v.as_slice() {
        [e, nu] => (*e, *nu, particles.density),
        [e, nu, rho] => (*e, *nu, *rho),
        _ => return Err(input("--reference-material", format!("{text:?}"), allowed)),
    };
    if !(e > 0.0 && e.is_finite() && nu > -1.0 && nu < 0.5 && rho > 0.0 && rho.is_finite()) {
        return Err(input("--reference-material", format!("{text:?}"), allowed));
    }
    let m = Material {
        density: rho,
        youngs_modulus: e,
        poisson_ratio: nu,
    };
    Ok((
        m,
        format!("E = {e:e} Pa, ν = {nu}, ρ = {rho} kg/m³ (given)"),
    ))
}

fn part_config(a: &WallStudyArgs, surface: &str) -> CliResult<(PartConfig, String)> {
    let mut study = config(a)?;
    let (reference, reference_text) = match &a.reference_material {
        Some(t) => reference_material(t, &study.material)?,
        None => (study.material, "the particles' own material".to_string()),
    };
    // A part is covered per (r, tiling): default r = 0.5, 1, 2.
    let radius_ratios = a.radius_ratios.clone().unwrap_or(if a.quick {
        vec![1.0]
    } else {
        vec![0.5, 1.0, 2.0]
    });
    let mut patterns = Vec::new();
    let mut zetas = Vec::new();
    for f in &study.floors {
        if let Floor::Particles {
            pattern,
            modulus_ratio,
            ..
        } = *f
        {
            if !patterns.contains(&pattern) {
                patterns.push(pattern);
            }
            if !zetas.contains(&modulus_ratio) {
                zetas.push(modulus_ratio);
            }
        }
    }
    let mut coverings = Vec::new();
    for &pattern in &patterns {
        for &radius_ratio in &radius_ratios {
            for &modulus_ratio in &zetas {
                coverings.push(CoveringSpec {
                    radius_ratio,
                    modulus_ratio,
                    pattern,
                });
            }
        }
    }
    if coverings.len() > 62 {
        return Err(input(
            "--radius-ratios",
            format!("{} coverings", coverings.len()),
            "at most 62 (r, ζ, tiling) combinations",
        ));
    }
    if !(a.tol_angle.is_finite() && a.tol_angle >= 0.0) {
        return Err(input("--tol-angle", a.tol_angle, "finite and ≥ 0 degrees"));
    }
    study.floors.clear();
    study.chute = None;
    study.bed_particles = 0;
    let triangles = match builtin(surface)? {
        Some(t) => t,
        None => dembound_scene::walls::mesh::read::read_triangles(Path::new(surface))
            .map_err(|e| CliError::input(anyhow::anyhow!("--wall `{surface}`: {e}")))?,
    };
    let c = PartConfig {
        study,
        triangles,
        flip: a.flip,
        name: surface.to_string(),
        reference,
        coverings,
        bed: super::part_bed::bed_config(a)?,
    };
    c.validate().map_err(CliError::input)?;
    c.bed_region().map_err(CliError::input)?;
    Ok((c, reference_text))
}

/// One compared quantity: name (with unit), per-impact value, tolerance,
/// whether the tolerance is relative.
struct Quantity {
    name: String,
    angle: f64,
    value: fn(&part::PartImpact) -> f64,
    median: bool,
    tolerance: f64,
    relative: bool,
}

fn quantities(angles: &[f64], t: &Tolerances, tol_angle: f64) -> Vec<Quantity> {
    let mut q = Vec::new();
    for &a in angles {
        q.push(Quantity {
            name: format!("e_n at {a}° (1)"),
            angle: a,
            value: |i| i.normal_restitution,
            median: false,
            tolerance: t.restitution,
            relative: false,
        });
        q.push(Quantity {
            name: format!("rebound speed |v'|/|v| at {a}° (1)"),
            angle: a,
            value: |i| i.speed_ratio,
            median: false,
            tolerance: t.restitution,
            relative: false,
        });
        if a > 0.0 {
            q.push(Quantity {
                name: format!("e_t at {a}° (1)"),
                angle: a,
                value: |i| i.tangential_restitution,
                median: false,
                tolerance: t.restitution,
                relative: false,
            });
            q.push(Quantity {
                name: format!("rebound angle at {a}° (deg)"),
                angle: a,
                value: |i| i.rebound_angle,
                median: false,
                tolerance: tol_angle,
                relative: false,
            });
        }
        q.push(Quantity {
            name: format!("median contact time at {a}° (µs)"),
            angle: a,
            value: |i| i.contact_time * 1e6,
            median: true,
            tolerance: t.contact_time,
            relative: true,
        });
        q.push(Quantity {
            name: format!("spin at {a}° (rad/s, not judged)"),
            angle: a,
            value: |i| i.spin,
            median: false,
            tolerance: f64::INFINITY,
            relative: false,
        });
    }
    q
}

/// (value, spread) of `q` on one wall.
fn measure(q: &Quantity, w: &part::PartWallResult) -> (f64, f64) {
    let v: Vec<f64> = w
        .impacts
        .iter()
        .filter(|i| i.at.angle == q.angle)
        .map(q.value)
        .collect();
    if q.median {
        (median(&v), 0.0)
    } else {
        (mean(&v), std_dev(&v))
    }
}

/// Deviation of `value` from the mesh wall's `reference` (relative for
/// relative quantities) and whether it is within the tolerance.
fn deviation(q: &Quantity, value: f64, reference: f64) -> (f64, bool) {
    let d = if q.relative {
        (value - reference) / reference
    } else {
        value - reference
    };
    (d, d.abs() <= q.tolerance)
}

pub fn run(args: &WallStudyArgs, surface: &str) -> CliResult {
    let (c, reference_text) = part_config(args, surface)?;
    let tol = tolerances(args)?;
    let bed_tolerance = super::part_bed::tolerance(args)?;
    let mut out = crate::cli::output_dir(&args.out, "wall-study")?;
    let start = std::time::Instant::now();
    let quiet = args.quiet;
    let results = part::run(&c, |label| {
        if !quiet {
            eprintln!(
                "wall-study --wall: {label} ({:.1} s)",
                start.elapsed().as_secs_f64()
            );
        }
    })
    .map_err(crate::cli::scene::scene_error)?;
    let qs = quantities(&c.study.angles, &tol, args.tol_angle);
    let bed_rows = super::part_bed::rows(&results, bed_tolerance);
    let judged = Judged {
        impacts: &qs,
        bed: &bed_rows,
        bed_tolerance,
    };
    write_all(&mut out, &c, &results, &judged, &reference_text, args).map_err(CliError::failed)?;
    let files = out.commit().map_err(CliError::failed)?;
    println!(
        "wall-study: part `{surface}`, mesh wall and {} coverings, {} files in {} ({:.1} s)",
        results.walls.len() - 1,
        files.len(),
        args.out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// What the verdicts judge: the impacts' quantities and the bed's rows.
struct Judged<'a> {
    impacts: &'a [Quantity],
    bed: &'a [super::part_bed::BedRow],
    bed_tolerance: f64,
}

fn write_all(
    out: &mut AtomicDir,
    c: &PartConfig,
    r: &PartResults,
    judged: &Judged,
    reference_text: &str,
    args: &WallStudyArgs,
) -> anyhow::Result<()> {
    let qs = judged.impacts;
    let bed_section = super::part_bed::write(out, c, r, judged.bed, judged.bed_tolerance)?;
    out.write("impacts.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "wall",
            "angle_deg",
            "x_m",
            "y_m",
            "z_m",
            "nx",
            "ny",
            "nz",
            "normal_restitution",
            "tangential_restitution",
            "speed_ratio",
            "rebound_angle_deg",
            "deflection",
            "contact_time_s",
            "contacts",
            "spin_rad_s",
        ])?;
        for wall in &r.walls {
            for i in &wall.impacts {
                let mut row = vec![wall.label.clone(), i.at.angle.to_string()];
                row.extend(i.at.point.iter().map(|x| format!("{x:e}")));
                row.extend(i.at.normal.iter().map(|x| format!("{x:e}")));
                for x in [
                    i.normal_restitution,
                    i.tangential_restitution,
                    i.speed_ratio,
                    i.rebound_angle,
                    i.deflection,
                    i.contact_time,
                ] {
                    row.push(super::defined(x));
                }
                row.push(i.contacts.to_string());
                row.push(super::defined(i.spin));
                csv.write_record(&row)?;
            }
        }
        csv.flush()?;
        Ok(())
    })?;
    let mesh = &r.walls[0];
    // summary.csv and the table: per wall and quantity.
    let mut table = String::new();
    let mut rows = Vec::new();
    for wall in &r.walls {
        for q in qs {
            let (v, sd) = measure(q, wall);
            let (reference, _) = measure(q, mesh);
            let (d, within) = deviation(q, v, reference);
            rows.push((wall.label.clone(), q.name.clone(), v, sd, d, within));
        }
    }
    out.write("summary.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "wall",
            "quantity",
            "value",
            "sd",
            "deviation_from_mesh",
            "within_tolerance",
        ])?;
        for (wall, q, v, sd, d, within) in &rows {
            csv.write_record([
                wall.clone(),
                q.clone(),
                format!("{v:e}"),
                format!("{sd:e}"),
                format!("{d:e}"),
                within.to_string(),
            ])?;
        }
        csv.flush()?;
        Ok(())
    })?;
    let marks: Vec<[f64; 3]> = mesh.impacts.iter().map(|i| i.at.point).collect();
    if let Some(cov) = r.coverings.first() {
        let png = out.path("part.png")?;
        covering_picture::write_marked(
            cov,
            &png,
            &format!(
                "{}: covering r = {} ({} spheres) and {} impact points (red)",
                super::part_bed::short_name(&c.name),
                c.coverings[0].radius_ratio,
                cov.spheres.len(),
                marks.len()
            ),
            &marks,
        )?;
    }
    let st = &c.study;
    let _ = writeln!(
        table,
        "| wall | boundary spheres | {} |",
        qs.iter()
            .map(|q| q.name.as_str())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let _ = writeln!(table, "|---|---|{}", "---|".repeat(qs.len()));
    for wall in &r.walls {
        let _ = write!(table, "| {} | {} |", wall.label, wall.spheres);
        for q in qs {
            let (v, _) = measure(q, wall);
            let (reference, _) = measure(q, mesh);
            let (d, within) = deviation(q, v, reference);
            if wall.covering.is_none() {
                let _ = write!(table, " {v:.4} |");
            } else {
                let unit = if q.relative { " (rel.)" } else { "" };
                let mark = if q.tolerance.is_infinite() {
                    ""
                } else if within {
                    " ✓"
                } else {
                    " ✗"
                };
                let _ = write!(table, " {v:.4} ({d:+.4}{unit}){mark} |");
            }
        }
        let _ = writeln!(table);
    }
    let mut rec = String::new();
    for q in qs.iter().filter(|q| q.tolerance.is_finite()) {
        let (reference, _) = measure(q, mesh);
        let ok: Vec<String> = r.walls[1..]
            .iter()
            .filter(|w| deviation(q, measure(q, w).0, reference).1)
            .map(|w| w.label.clone())
            .collect();
        let tol = if q.relative {
            format!("± {} %", q.tolerance * 100.0)
        } else {
            format!("± {}", q.tolerance)
        };
        let _ = writeln!(
            rec,
            "- {} (tolerance {tol}): {}",
            q.name,
            if ok.is_empty() {
                "none".to_string()
            } else {
                ok.join(", ")
            }
        );
    }
    // The largest r within every judged quantity: the fewest spheres.
    let all_ok: Vec<&part::PartWallResult> = r.walls[1..]
        .iter()
        .filter(|w| {
            qs.iter()
                .filter(|q| q.tolerance.is_finite())
                .all(|q| deviation(q, measure(q, w).0, measure(q, mesh).0).1)
                && judged
                    .bed
                    .iter()
                    .filter(|x| x.wall == w.label)
                    .all(|x| x.within)
        })
        .collect();
    let best = all_ok
        .iter()
        .filter_map(|w| w.covering.map(|s| (s, w.spheres)))
        .min_by(|a, b| {
            a.1.cmp(&b.1)
                .then(a.0.modulus_ratio.total_cmp(&b.0.modulus_ratio))
        });
    let mut text = String::new();
    let _ = writeln!(text, "# wall-study on a part: `{}`\n", c.name);
    let _ = writeln!(
        text,
        "Particles: R = {} m, E = {:e} Pa, ν = {}, ρ = {} kg/m³; Hertz with Tsuji damping e = {}, \
         μ = {}, μ_r = {}. Impact speed {} m/s, {} impacts per angle at angles {:?}° from the local \
         face normal, at points uniform over the part's area (seed {}); the same points and \
         directions on every wall. Δt = {} s (η = {} × the shortest flat-wall Hertz contact time).\n",
        st.radius, st.material.youngs_modulus, st.material.poisson_ratio, st.material.density,
        st.restitution, st.friction, st.rolling_friction, st.speed, st.impacts, st.angles, st.seed,
        crate::output::format::sig(r.dt, 4), st.eta
    );
    let _ = writeln!(
        text,
        "Mesh wall (the reference): {reference_text}. Boundary spheres: R_b = r R, touching \
         (spacing 2 R_b), the reference material with E_b = ζ × E_reference (ζ relative to the \
         reference, not to the particles).\n"
    );
    let _ = writeln!(
        text,
        "Not run on a part: the chute (`--chute-*` have no effect with `--wall`) and the wall \
         load under the bed.{}\n",
        if c.bed.is_none() {
            " No bed (`--particles 0`)."
        } else {
            ""
        }
    );
    let _ = writeln!(
        text,
        "## Impacts (mean; median for contact times; deviation from the mesh wall in brackets)\n"
    );
    text.push_str(&table);
    let _ = writeln!(text, "\n## Coverings within the tolerance, per quantity\n");
    text.push_str(&rec);
    let _ = writeln!(text);
    text.push_str(&bed_section);
    let _ = writeln!(
        text,
        "\nRecommendation: {}\n",
        match best {
            Some((s, n)) => format!(
                "{} ({n} boundary spheres), the covering with the fewest spheres within every judged quantity (impacts{}).",
                s.label(),
                if c.bed.is_some() { ", bed and flow" } else { "" }
            ),
            None => "no covering studied stays within every judged quantity.".to_string(),
        }
    );
    let _ = writeln!(
        text,
        "`part.png`: the part covered with r = {} and the impact points (red crosses). \
         `impacts.csv`: each impact; `summary.csv`: the table. Seed {}, {} impacts: the means \
         carry a sampling error (sd / √n) that the tolerances do not account for.",
        c.coverings.first().map_or(f64::NAN, |s| s.radius_ratio),
        args.seed,
        st.impacts
    );
    out.write("report.md", |w| Ok(w.write_all(text.as_bytes())?))?;
    Ok(())
}
