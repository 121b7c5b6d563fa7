//! `wall-study --wall SURFACE`: the bed and the flow on the part
//! (`dembound_scene::wall_study::part_bed`), each wall against the mesh
//! wall with a verdict per quantity against `--tolerance`: bed.csv,
//! discharge.csv, discharge.svg/png, scene_mesh_wall.toml and the
//! report's section.

use super::{input, WallStudyArgs};
use crate::cli::CliResult;
use crate::output::files::AtomicDir;
use crate::plot::{Figure, Mark, Series};
use dembound_scene::wall_study::part::{PartConfig, PartResults};
use dembound_scene::wall_study::part_bed::{
    PartBedConfig, BELOW_OUTLET_RADII, OUTLET_BOX_TOP_RADII, PLUG_DROP_RADII, PLUG_DROP_TIME,
    RATE_BATCHES,
};
use std::fmt::Write as _;

fn sig(v: f64) -> String {
    crate::output::format::sig(v, 4)
}

/// The part's file name without its directory (figure titles).
pub(super) fn short_name(name: &str) -> &str {
    std::path::Path::new(name)
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or(name)
}

/// The default tolerance of the bed and flow quantities (issue 29's 3 %).
pub const DEFAULT_TOLERANCE: f64 = 0.03;

/// `--tolerance`: a fraction or a percentage (as `recommend`'s).
pub(super) fn tolerance(a: &WallStudyArgs) -> CliResult<f64> {
    match &a.tolerance {
        None => Ok(DEFAULT_TOLERANCE),
        Some(t) => crate::cli::recommend::tolerance(t).map_err(crate::cli::CliError::input),
    }
}

/// The bed of the part study, `None` with `--particles 0`.
pub(super) fn bed_config(a: &WallStudyArgs) -> CliResult<Option<PartBedConfig>> {
    let q = a.quick;
    let particles = a.particles.unwrap_or(if q { 150 } else { 1000 });
    if particles == 0 {
        for (key, given) in [
            ("--discharge-time", a.discharge_time.is_some()),
            ("--discharge-skip", a.discharge_skip.is_some()),
            ("--packing-points", a.packing_points.is_some()),
        ] {
            if given {
                return Err(input(key, "given with --particles 0", "only with a bed"));
            }
        }
        return Ok(None);
    }
    let bed = PartBedConfig {
        particles,
        // Longer than the plane study's: a grain poured over a part falls
        // farther (from above its top) and lands faster.
        settle_time: a.settle_time.unwrap_or(if q { 0.1 } else { 0.25 }),
        // The first grains reach the outlet box (10 R below the outlet)
        // after √(20 R/g): 0.045 s for R = 1 mm; the rate is taken after.
        discharge_time: a.discharge_time.unwrap_or(if q { 0.15 } else { 0.3 }),
        skip: a.discharge_skip.unwrap_or(if q { 0.06 } else { 0.05 }),
        packing_points: a.packing_points.unwrap_or(if q { 20_000 } else { 200_000 }),
    };
    bed.validate().map_err(crate::cli::CliError::input)?;
    Ok(Some(bed))
}

/// One wall's bed quantity against the mesh wall's.
#[derive(Debug, Clone)]
pub(super) struct BedRow {
    pub wall: String,
    pub quantity: &'static str,
    pub value: f64,
    /// Standard error (NaN: none estimated).
    pub error: f64,
    /// v / v_mesh − 1 and its standard error.
    pub deviation: f64,
    pub deviation_error: f64,
    pub within: bool,
    /// The verdict stands: |d| is more than two standard errors from T.
    pub resolved: Option<bool>,
}

/// (name with unit, value, standard error) of each measured quantity.
fn quantities(b: &dembound_scene::wall_study::part_bed::PartBed) -> Vec<(&'static str, f64, f64)> {
    let mut q = vec![
        ("bed height (mm)", b.height * 1e3, f64::NAN),
        (
            "packing at the wall (1)",
            b.wall_packing,
            b.wall_packing_error,
        ),
    ];
    if let Some((rate, se)) = b.rate {
        q.push(("discharge rate (g/s)", rate * 1e3, se * 1e3));
    }
    q
}

/// Every wall's rows (the mesh wall's deviations are 0).
pub(super) fn rows(r: &PartResults, t: f64) -> Vec<BedRow> {
    let Some(mesh) = r.beds.first() else {
        return Vec::new();
    };
    let reference = quantities(mesh);
    let mut out = Vec::new();
    for (wall, bed) in r.walls.iter().zip(&r.beds) {
        for ((quantity, v, e), (_, v0, e0)) in quantities(bed).into_iter().zip(&reference) {
            let deviation = v / v0 - 1.0;
            let deviation_error = (v / v0).abs() * ((e / v).powi(2) + (e0 / v0).powi(2)).sqrt();
            let within = deviation.abs() <= t;
            let resolved = deviation_error
                .is_finite()
                .then(|| (deviation.abs() - t).abs() > 2.0 * deviation_error);
            out.push(BedRow {
                wall: wall.label.clone(),
                quantity,
                value: v,
                error: e,
                deviation,
                deviation_error,
                within,
                resolved,
            });
        }
    }
    out
}

/// Writes bed.csv, discharge.csv, discharge.svg/png and
/// scene_mesh_wall.toml; returns the report's section.
pub(super) fn write(
    out: &mut AtomicDir,
    c: &PartConfig,
    r: &PartResults,
    rows: &[BedRow],
    t: f64,
) -> anyhow::Result<String> {
    let (Some(bed), Some(region)) = (&c.bed, &r.region) else {
        return Ok(String::new());
    };
    out.write("bed.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "wall",
            "quantity",
            "value",
            "standard_error",
            "deviation_from_mesh",
            "deviation_standard_error",
            "within_tolerance",
            "verdict_resolved",
        ])?;
        for x in rows {
            csv.write_record([
                x.wall.clone(),
                x.quantity.to_string(),
                format!("{:e}", x.value),
                format!("{:e}", x.error),
                format!("{:e}", x.deviation),
                format!("{:e}", x.deviation_error),
                x.within.to_string(),
                x.resolved.map_or("not estimated".into(), |b| b.to_string()),
            ])?;
        }
        csv.flush()?;
        Ok(())
    })?;
    let outlet = region.outlet;
    if outlet.is_some() {
        out.write("discharge.csv", |w| {
            let mut csv = csv::Writer::from_writer(w);
            csv.write_record(["wall", "time_after_opening_s", "discharged_mass_kg"])?;
            for (wall, b) in r.walls.iter().zip(&r.beds) {
                for (time, mass) in &b.discharge {
                    csv.write_record([
                        wall.label.clone(),
                        format!("{time:e}"),
                        format!("{mass:e}"),
                    ])?;
                }
            }
            csv.flush()?;
            Ok(())
        })?;
        let mut fig = Figure {
            title: format!("Discharge through the outlet of {}", short_name(&c.name)),
            x_label: "time after the opening (s)".into(),
            y_label: "mass discharged (g)".into(),
            legend_outside: true,
            ..Default::default()
        };
        for (k, (wall, b)) in r.walls.iter().zip(&r.beds).enumerate() {
            let pts = b.discharge.iter().map(|(t, m)| (*t, m * 1e3)).collect();
            fig.series
                .push(Series::new(wall.label.clone(), pts, Mark::Line, k % 10));
        }
        fig.write_into(out, "discharge")?;
    }
    if let Some(toml) = &r.mesh_scene {
        out.write(
            "scene_mesh_wall.toml",
            |w| Ok(w.write_all(toml.as_bytes())?),
        )?;
    }
    let st = &c.study;
    let p = &region.pour;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## The bed{}\n",
        if outlet.is_some() {
            " and the discharge"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "{} spheres poured (gravity 9.81 m/s² along −z) from a loose random packing (solid \
         fraction 0.18, seed {}) in the box x {}–{} mm, y {}–{} mm, z {}–{} mm (the part's box in \
         x and y scaled by f = {} about its centre, the largest f whose corner columns lie inside \
         the part just below its top; from 2 R above the part's top), between four frictionless \
         side walls on the part's box, onto each wall; settled for the fall ({} s) and {} s more. \
         The same spheres and Δt for every wall.\n",
        p.count,
        st.seed,
        sig(p.lower[0] * 1e3),
        sig(p.upper[0] * 1e3),
        sig(p.lower[1] * 1e3),
        sig(p.upper[1] * 1e3),
        sig(p.lower[2] * 1e3),
        sig(p.upper[2] * 1e3),
        sig(region.box_fraction),
        sig(p.fall_time()),
        bed.settle_time
    );
    match outlet {
        Some(o) => {
            let _ = writeln!(
                s,
                "Outlet: {} open edges at the part's bottom z = {} mm, clear radius {} mm about \
                 ({}, {}) mm. A plug (a plane there, of the reference material) closes it while \
                 the bed settles, then drops {PLUG_DROP_RADII} R in {PLUG_DROP_TIME} s; an outlet box from \
                 {BELOW_OUTLET_RADII} R to {OUTLET_BOX_TOP_RADII} R below the outlet removes the discharged spheres. Discharge \
                 for {} s; the rate is the mass removed from {} s after the opening to the end \
                 over that time, ± the standard error of {RATE_BATCHES} batch rates. A covering keeps \
                 sites up to one spacing beyond an open rim: its spheres narrow the outlet \
                 (docs/particle-walls.md, the hopper).\n",
                o.edges,
                sig(o.z * 1e3),
                sig(o.radius * 1e3),
                sig(o.centre[0] * 1e3),
                sig(o.centre[1] * 1e3),
                bed.discharge_time,
                bed.skip
            );
        }
        None => {
            let _ = writeln!(
                s,
                "No outlet (no open edge at the part's bottom rises from it): no discharge.\n"
            );
        }
    }
    let _ = writeln!(
        s,
        "Bed height: the 95th percentile of the spheres' tops above the part's bottom. Packing \
         at the wall: the solid fraction in the shell within 2 R of the surface on the \
         particles' side, below the bed's top less 2 R, from {} seeded random points (± the \
         binomial standard error). Tolerance: each quantity within ± {} % of the mesh wall's; \
         'resolved' when the deviation is more than two standard errors from the tolerance \
         (the bed height carries no error estimate: one pour).\n",
        bed.packing_points,
        sig(100.0 * t)
    );
    let _ = writeln!(
        s,
        "| wall | quantity | value | deviation from the mesh wall | within ± {} % | resolved |",
        sig(100.0 * t)
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for x in rows {
        let value = if x.error.is_finite() {
            format!("{} ± {}", sig(x.value), sig(x.error))
        } else {
            sig(x.value)
        };
        let dev = if x.deviation_error.is_finite() {
            format!(
                "{:+.2} ± {:.2} %",
                100.0 * x.deviation,
                100.0 * x.deviation_error
            )
        } else {
            format!("{:+.2} %", 100.0 * x.deviation)
        };
        let _ = writeln!(
            s,
            "| {} | {} | {value} | {dev} | {} | {} |",
            x.wall,
            x.quantity,
            if x.within { "yes" } else { "no" },
            x.resolved.map_or("–", |b| if b { "yes" } else { "no" })
        );
    }
    let _ = writeln!(
        s,
        "\nWithin ± {} % of the mesh wall, per quantity:\n",
        sig(100.0 * t)
    );
    let mut names: Vec<&str> = rows.iter().map(|x| x.quantity).collect();
    names.dedup();
    names.sort();
    names.dedup();
    for q in names {
        let ok: Vec<&str> = rows
            .iter()
            .skip_while(|x| x.wall == "mesh wall")
            .filter(|x| x.quantity == q && x.within)
            .map(|x| x.wall.as_str())
            .collect();
        let _ = writeln!(
            s,
            "- {q}: {}",
            if ok.is_empty() {
                "none".to_string()
            } else {
                ok.join(", ")
            }
        );
    }
    let _ = writeln!(
        s,
        "\nParticles in each settled bed (and their mean speed at the {}): {}.{}\n",
        if outlet.is_some() { "opening" } else { "end" },
        r.walls
            .iter()
            .zip(&r.beds)
            .map(|(w, b)| format!("{} {} ({} m/s)", w.label, b.particles, sig(b.mean_speed)))
            .collect::<Vec<_>>()
            .join(", "),
        if r.mesh_scene.is_some() {
            " `scene_mesh_wall.toml`: the mesh wall's run as a `dembound scene` file (the same \
             spheres, walls, outlet and Δt)."
        } else {
            " (A built-in surface has no file: no scene file is written.)"
        }
    );
    Ok(s)
}
