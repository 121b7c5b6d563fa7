//! `dembound wall-study` (issue 13): the paper's question in a
//! many-particle setting. For one particle material and a grid of boundary
//! walls (r, ζ, tiling), beside a plane of the particles' material and a
//! rigid plane: single impacts at random (seeded) points of the tiling,
//! normal and oblique, and a bed poured and settled on each floor. Thin:
//! the runs are `dembound_scene::wall_study`; this writes CSV, figures, the
//! side view of a bed and a Markdown report through [`AtomicDir`], all or
//! nothing.

mod part;
mod part_bed;
mod side_view;
mod verdicts;

use super::{CliError, CliResult};
use crate::output::files::AtomicDir;
use crate::plot::{Figure, Mark, Series};
use clap::Args;
use dembound_physics::contact::tangential::TangentialKind;
use dembound_physics::material::Material;
use dembound_scene::sources::tiling::Pattern;
use dembound_scene::wall_study::recommend::{self, mean, median, std_dev as std, FloorVerdict};
use dembound_scene::wall_study::{self, ChuteConfig, Floor, FloorResult, StudyConfig, Tolerances};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct WallStudyArgs {
    /// Output directory (CSV, figures, report.md); all or nothing
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Small and fast: 150 particles, 4 impacts per angle, r = 1 and the
    /// paper's r = 100 (not a wall), ζ = 100, square only (unless given),
    /// 0.05 s of settling after the pour
    #[arg(long)]
    pub quick: bool,
    /// Particles in the bed (default 1000; 150 with --quick; 0: no bed)
    #[arg(long)]
    pub particles: Option<usize>,
    /// Impacts per floor and angle (default 20; 4 with --quick)
    #[arg(long)]
    pub impacts: Option<usize>,
    /// Radius ratios r = R_b/R, for every tiling (default: the walls
    /// 0.5,1,2,2.4 square and 0.5,1,2,4,6 hexagonal; 1,100 with --quick)
    #[arg(long, value_delimiter = ',')]
    pub radius_ratios: Option<Vec<f64>>,
    /// Modulus ratios ζ = E_b/E (default 1,10,100; 100 with --quick)
    #[arg(long, value_delimiter = ',')]
    pub modulus_ratios: Option<Vec<f64>>,
    /// Tilings: square, hexagonal (default both; square with --quick)
    #[arg(long, value_delimiter = ',')]
    pub tilings: Option<Vec<String>>,
    /// Incidence angles from the normal, degrees (default 0,45)
    #[arg(long, value_delimiter = ',', default_value = "0,45")]
    pub angles: Vec<f64>,
    /// Impact speed, m/s
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Particle radius R, m
    #[arg(long, default_value_t = 0.5e-3)]
    pub radius: f64,
    /// Particle density, kg/m³
    #[arg(long, default_value_t = 1000.0)]
    pub density: f64,
    /// Particle Young's modulus, Pa
    #[arg(long, default_value_t = 1.0e7)]
    pub youngs_modulus: f64,
    /// Particle Poisson ratio
    #[arg(long, default_value_t = 0.3)]
    pub poisson_ratio: f64,
    /// Normal restitution (Hertz with Tsuji damping)
    #[arg(long, default_value_t = 0.5)]
    pub restitution: f64,
    /// Coulomb friction μ of every surface (the bed's side walls are frictionless)
    #[arg(long, default_value_t = 0.5)]
    pub friction: f64,
    /// Rolling friction μ_r
    #[arg(long, default_value_t = 0.0)]
    pub rolling_friction: f64,
    /// Tangential spring: mindlin or linear
    #[arg(long, default_value = "mindlin")]
    pub tangential: String,
    /// Δt = η × the particle–plane contact time at the impact speed
    #[arg(long, default_value_t = 0.05)]
    pub eta: f64,
    /// Bed settling time after the pour (the fall time is added), s
    /// (default 0.1; 0.05 with --quick; with --wall 0.25, 0.1 with --quick)
    #[arg(long)]
    pub settle_time: Option<f64>,
    /// μ of the floor's surface (the particle–floor pair takes √(μ μ_floor));
    /// default: --friction
    #[arg(long)]
    pub floor_friction: Option<f64>,
    /// Chute: inclination of the floor, degrees (above the bed's angle of repose)
    #[arg(long, default_value_t = 24.0)]
    pub chute_angle: f64,
    /// Chute: bed depth in particle diameters (default 5; 3 with --quick)
    #[arg(long)]
    pub chute_layers: Option<f64>,
    /// Chute: simulated time, s, the second half averaged (default 0.5;
    /// 0.15 with --quick; 0: no chute)
    #[arg(long)]
    pub chute_time: Option<f64>,
    /// Chute: floors whose periodic cell (whole tiling periods, at least
    /// 20 R × 12 R) needs more particles are not run
    #[arg(long, default_value_t = 3000)]
    pub chute_max_particles: usize,
    /// Recommendation: absolute tolerance on mean e_n and e_t, and on their
    /// spread (sd) beyond the plane's
    #[arg(long, default_value_t = Tolerances::default().restitution)]
    pub tol_restitution: f64,
    /// Recommendation: relative tolerance on the median contact time
    #[arg(long, default_value_t = Tolerances::default().contact_time)]
    pub tol_contact_time: f64,
    /// Recommendation: absolute tolerance on the packing fraction 0–2R
    #[arg(long, default_value_t = Tolerances::default().packing)]
    pub tol_packing: f64,
    /// Recommendation: relative tolerance on the floor pressure against N m g/A
    #[arg(long, default_value_t = Tolerances::default().pressure)]
    pub tol_pressure: f64,
    /// Recommendation: absolute tolerance on the floor-force fluctuation (sd/mean)
    #[arg(long, default_value_t = Tolerances::default().fluctuation)]
    pub tol_fluctuation: f64,
    /// Recommendation: absolute tolerance on the chute's slip / mean velocity
    #[arg(long, default_value_t = Tolerances::default().slip)]
    pub tol_slip: f64,
    /// The user's part instead of the plane: an STL or OBJ file (m),
    /// `square:SIDE` or `cylinder:RADIUS,HEIGHT` (as `particle-wall`);
    /// impacts at random points of it, mesh wall against particle walls
    /// (no bed, no chute yet)
    #[arg(long, value_name = "SURFACE")]
    pub wall: Option<String>,
    /// With --wall: the mesh wall's material, `steel`, `glass` or
    /// `E,NU[,RHO]` (Pa, 1, kg/m³); ζ scales its E (default: the particles')
    #[arg(long, value_name = "MATERIAL", allow_hyphen_values = true)]
    pub reference_material: Option<String>,
    /// With --wall: absolute tolerance on the mean rebound angle, degrees
    #[arg(long, default_value_t = 2.0)]
    pub tol_angle: f64,
    /// With --wall: the particles are behind the triangles' normals (a
    /// part whose normals point away from its inside, e.g. hopper.stl)
    #[arg(long)]
    pub flip: bool,
    /// With --wall: relative tolerance on the bed height, the packing at
    /// the wall and the discharge rate against the mesh wall, `0.03` or
    /// `3%` (default 3%)
    #[arg(long, value_name = "T")]
    pub tolerance: Option<String>,
    /// With --wall: discharge time after the opening of a part with an
    /// outlet, s (default 0.3; 0.15 with --quick)
    #[arg(long)]
    pub discharge_time: Option<f64>,
    /// With --wall: the discharge rate is taken from this long after the
    /// opening, s (default 0.05; 0.06 with --quick)
    #[arg(long)]
    pub discharge_skip: Option<f64>,
    /// With --wall: random points of the packing at the wall (default
    /// 200000; 20000 with --quick)
    #[arg(long)]
    pub packing_points: Option<usize>,
    /// Seed of the impact points and the bed's insertion
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// No progress lines
    #[arg(long, short)]
    pub quiet: bool,
}

fn input(key: &str, value: impl std::fmt::Display, allowed: &str) -> CliError {
    CliError::input(anyhow::anyhow!("{key} = {value}: allowed {allowed}"))
}

/// The default grid's radius ratios: walls only. Square: r ≤ 2.414 (a
/// particle passes between touching spheres beyond), hexagonal r ≤ 6.464;
/// each from r = 0.5 (boundary spheres smaller than the particles: the
/// fine end) through 1 and 2 to the largest wall of the tiling short of
/// its limit (2.4, gap radius 0.994 R; 6, 0.928 R), with r = 4 between
/// (the largest hexagonal floor the periodic chute takes).
const SQUARE_RATIOS: [f64; 4] = [0.5, 1.0, 2.0, 2.4];
const HEXAGONAL_RATIOS: [f64; 5] = [0.5, 1.0, 2.0, 4.0, 6.0];

fn tolerances(a: &WallStudyArgs) -> CliResult<Tolerances> {
    for (key, v) in [
        ("--tol-restitution", a.tol_restitution),
        ("--tol-contact-time", a.tol_contact_time),
        ("--tol-packing", a.tol_packing),
        ("--tol-pressure", a.tol_pressure),
        ("--tol-fluctuation", a.tol_fluctuation),
        ("--tol-slip", a.tol_slip),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(input(key, v, "finite and ≥ 0"));
        }
    }
    Ok(Tolerances {
        restitution: a.tol_restitution,
        contact_time: a.tol_contact_time,
        packing: a.tol_packing,
        pressure: a.tol_pressure,
        fluctuation: a.tol_fluctuation,
        slip: a.tol_slip,
    })
}

fn config(a: &WallStudyArgs) -> CliResult<StudyConfig> {
    let q = a.quick;
    let modulus_ratios = a.modulus_ratios.clone().unwrap_or(if q {
        vec![100.0]
    } else {
        vec![1.0, 10.0, 100.0]
    });
    let tilings = a.tilings.clone().unwrap_or(if q {
        vec!["square".into()]
    } else {
        vec!["square".into(), "hexagonal".into()]
    });
    let mut patterns = Vec::new();
    for t in &tilings {
        patterns.push(match t.as_str() {
            "square" => Pattern::Square,
            "hexagonal" => Pattern::Hexagonal,
            other => {
                return Err(input(
                    "--tilings",
                    format!("{other:?}"),
                    "\"square\", \"hexagonal\"",
                ))
            }
        });
    }
    let radius_ratios = |pattern: Pattern| -> Vec<f64> {
        match (&a.radius_ratios, q, pattern) {
            (Some(r), _, _) => r.clone(),
            (None, true, _) => vec![1.0, 100.0],
            (None, false, Pattern::Square) => SQUARE_RATIOS.to_vec(),
            (None, false, Pattern::Hexagonal) => HEXAGONAL_RATIOS.to_vec(),
        }
    };
    let tangential = TangentialKind::from_name(&a.tangential).ok_or_else(|| {
        input(
            "--tangential",
            format!("{:?}", a.tangential),
            "\"mindlin\", \"linear\"",
        )
    })?;
    if a.angles.is_empty() {
        return Err(input("--angles", "[]", "at least one angle"));
    }
    let mut floors = vec![Floor::Plane, Floor::Rigid];
    for &pattern in &patterns {
        for radius_ratio in radius_ratios(pattern) {
            for &modulus_ratio in &modulus_ratios {
                floors.push(Floor::Particles {
                    radius_ratio,
                    modulus_ratio,
                    pattern,
                });
            }
        }
    }
    if floors.len() > 64 {
        return Err(input(
            "--radius-ratios",
            format!("{} floors", floors.len()),
            "at most 62 (r, ζ, tiling) combinations",
        ));
    }
    Ok(StudyConfig {
        material: Material {
            density: a.density,
            youngs_modulus: a.youngs_modulus,
            poisson_ratio: a.poisson_ratio,
        },
        radius: a.radius,
        restitution: a.restitution,
        friction: a.friction,
        tangential,
        rolling_friction: a.rolling_friction,
        floors,
        impacts: a.impacts.unwrap_or(if q { 4 } else { 20 }),
        speed: a.speed,
        angles: a.angles.clone(),
        bed_particles: a.particles.unwrap_or(if q { 150 } else { 1000 }),
        eta: a.eta,
        settle_time: a.settle_time.unwrap_or(if q { 0.05 } else { 0.1 }),
        seed: a.seed,
        floor_friction: a.floor_friction,
        chute: {
            let duration = a.chute_time.unwrap_or(if q { 0.15 } else { 0.5 });
            (duration != 0.0).then(|| ChuteConfig {
                angle: a.chute_angle,
                layers: a.chute_layers.unwrap_or(if q { 3.0 } else { 5.0 }),
                min_cell: if q { [12.0, 8.0] } else { [20.0, 12.0] },
                duration,
                max_particles: a.chute_max_particles,
            })
        },
    })
}

/// The quantities compared with the plane, per floor.
struct Summary {
    label: String,
    /// (name with unit, value, spread)
    values: Vec<(String, f64, f64)>,
}

fn summarise(r: &FloorResult, angles: &[f64]) -> Summary {
    let mut values = Vec::new();
    for &a in angles {
        let at: Vec<_> = r.impacts.iter().filter(|i| i.angle == a).collect();
        let en: Vec<f64> = at.iter().map(|i| i.normal_restitution).collect();
        values.push((format!("e_n at {a}° (1)"), mean(&en), std(&en)));
        if a > 0.0 {
            let et: Vec<f64> = at.iter().map(|i| i.tangential_restitution).collect();
            values.push((format!("e_t at {a}° (1)"), mean(&et), std(&et)));
            let ra: Vec<f64> = at.iter().map(|i| i.rebound_angle).collect();
            values.push((format!("rebound angle at {a}° (deg)"), mean(&ra), std(&ra)));
        }
        let tc: Vec<f64> = at.iter().map(|i| i.contact_time * 1e6).collect();
        values.push((format!("contact time at {a}° (µs)"), mean(&tc), std(&tc)));
        // The median: a particle trapped in a hollow bounces for long and
        // drags the mean.
        values.push((
            format!("median contact time at {a}° (µs)"),
            median(&tc),
            0.0,
        ));
    }
    if let Some(b) = &r.bed {
        values.push(("bed height (mm)".into(), b.height * 1e3, 0.0));
        values.push(("packing fraction 0–2R (1)".into(), b.wall_packing, 0.0));
        values.push(("packing fraction 4R–8R (1)".into(), b.bulk_packing, 0.0));
        values.push(("floor pressure (Pa)".into(), b.floor_pressure, 0.0));
        values.push((
            "floor pressure fluctuation (1)".into(),
            b.pressure_fluctuation,
            0.0,
        ));
        values.push((
            "particles fallen through the floor (1)".into(),
            b.fell_through as f64,
            0.0,
        ));
        if !b.boundary_forces.is_empty() {
            values.push((
                "force per loaded boundary particle (µN)".into(),
                mean(&b.boundary_forces) * 1e6,
                std(&b.boundary_forces) * 1e6,
            ));
        }
    }
    if let Some(Ok(ch)) = &r.chute {
        values.push(("chute slip velocity (m/s)".into(), ch.slip_velocity, 0.0));
        let fit = ch.slip_fit;
        values.push((
            "chute extrapolated slip velocity (m/s)".into(),
            fit.map_or(f64::NAN, |f| f.slip_velocity),
            0.0,
        ));
        values.push((
            "chute slip length (mm)".into(),
            fit.map_or(f64::NAN, |f| f.slip_length * 1e3),
            0.0,
        ));
        values.push(("chute mean velocity (m/s)".into(), ch.mean_velocity, 0.0));
        values.push((
            "chute slip fraction, slip/mean velocity (1)".into(),
            ch.slip_velocity / ch.mean_velocity,
            0.0,
        ));
        values.push(("chute acceleration (m/s²)".into(), ch.acceleration, 0.0));
        values.push((
            "chute floor shear / N m g sin θ (1)".into(),
            ch.floor_shear_force / ch.weight_components[0],
            0.0,
        ));
    } else if r.chute.is_some() {
        for name in [
            "chute slip velocity (m/s)",
            "chute extrapolated slip velocity (m/s)",
            "chute slip length (mm)",
            "chute mean velocity (m/s)",
            "chute slip fraction, slip/mean velocity (1)",
            "chute acceleration (m/s²)",
            "chute floor shear / N m g sin θ (1)",
        ] {
            values.push((name.into(), f64::NAN, 0.0));
        }
    }
    Summary {
        label: r.floor.label(),
        values,
    }
}

pub fn run(args: &WallStudyArgs) -> CliResult {
    if let Some(surface) = &args.wall {
        return part::run(args, surface);
    }
    for (key, given) in [
        ("--reference-material", args.reference_material.is_some()),
        ("--flip", args.flip),
        ("--tolerance", args.tolerance.is_some()),
        ("--discharge-time", args.discharge_time.is_some()),
        ("--discharge-skip", args.discharge_skip.is_some()),
        ("--packing-points", args.packing_points.is_some()),
    ] {
        if given {
            return Err(input(
                key,
                "given without --wall",
                "only with --wall SURFACE",
            ));
        }
    }
    let c = config(args)?;
    let tolerances = tolerances(args)?;
    c.validate().map_err(CliError::input)?;
    let mut out = super::output_dir(&args.out, "wall-study")?;
    let quiet = args.quiet;
    let start = std::time::Instant::now();
    let results = wall_study::run(&c, |label| {
        if !quiet {
            eprintln!(
                "wall-study: {label} ({:.1} s)",
                start.elapsed().as_secs_f64()
            );
        }
    })
    .map_err(super::scene::scene_error)?;
    write_all(&mut out, &c, &results, &tolerances).map_err(CliError::failed)?;
    let files = out.commit().map_err(CliError::failed)?;
    println!(
        "wall-study: {} floors, {} files in {} ({:.1} s)",
        results.len(),
        files.len(),
        args.out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn write_all(
    out: &mut AtomicDir,
    c: &StudyConfig,
    results: &[FloorResult],
    tolerances: &Tolerances,
) -> anyhow::Result<()> {
    // impacts.csv
    out.write("impacts.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "floor",
            "angle_deg",
            "x_m",
            "y_m",
            "normal_restitution",
            "tangential_restitution",
            "rebound_angle_deg",
            "deflection",
            "contact_time_s",
            "contacts",
            "spin_rad_s",
        ])?;
        for r in results {
            for i in &r.impacts {
                csv.write_record([
                    r.floor.label(),
                    i.angle.to_string(),
                    format!("{:e}", i.point[0]),
                    format!("{:e}", i.point[1]),
                    defined(i.normal_restitution),
                    defined(i.tangential_restitution),
                    defined(i.rebound_angle),
                    defined(i.deflection),
                    defined(i.contact_time),
                    i.contacts.to_string(),
                    defined(i.spin),
                ])?;
            }
        }
        csv.flush()?;
        Ok(())
    })?;
    out.write("profile.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record(["floor", "z_m", "solid_fraction"])?;
        for r in results {
            if let Some(b) = &r.bed {
                for (z, phi) in &b.profile {
                    csv.write_record([r.floor.label(), format!("{z:e}"), format!("{phi:e}")])?;
                }
            }
        }
        csv.flush()?;
        Ok(())
    })?;
    out.write("boundary_forces.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record(["floor", "normal_force_N"])?;
        for r in results {
            if let Some(b) = &r.bed {
                for f in &b.boundary_forces {
                    csv.write_record([r.floor.label(), format!("{f:e}")])?;
                }
            }
        }
        csv.flush()?;
        Ok(())
    })?;
    let summaries: Vec<Summary> = results.iter().map(|r| summarise(r, &c.angles)).collect();
    out.write("summary.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record(["floor", "quantity", "mean", "spread_sd"])?;
        for s in &summaries {
            for (name, v, sd) in &s.values {
                csv.write_record([
                    s.label.clone(),
                    name.clone(),
                    format!("{v:e}"),
                    format!("{sd:e}"),
                ])?;
            }
        }
        csv.flush()?;
        Ok(())
    })?;
    // Figures.
    let palette = |k: usize| k % 10;
    // One series per incidence angle: `value` of each impact on each floor.
    let by_angle = |title: &str, y_label: &str, value: fn(&wall_study::Impact) -> f64| {
        let mut fig = Figure {
            title: title.into(),
            x_label: "floor (index in report.md)".into(),
            y_label: y_label.into(),
            ..Default::default()
        };
        for (k, &a) in c.angles.iter().enumerate() {
            let pts: Vec<(f64, f64)> = results
                .iter()
                .enumerate()
                .flat_map(|(f, r)| {
                    r.impacts
                        .iter()
                        .filter(move |i| i.angle == a)
                        .map(move |i| (f as f64, value(i)))
                })
                .collect();
            fig.series.push(Series::new(
                format!("θ = {a}°"),
                pts,
                Mark::Points,
                palette(k),
            ));
        }
        fig
    };
    if results.iter().any(|r| !r.impacts.is_empty()) {
        by_angle(
            "Normal restitution of single impacts, by floor",
            "effective normal restitution v_n'/v_n (1)",
            |i| i.normal_restitution,
        )
        .write_into(out, "restitution")?;
        by_angle(
            "Contact time of single impacts, by floor",
            "contact time (µs)",
            |i| i.contact_time * 1e6,
        )
        .write_into(out, "contact_time")?;
    }
    if results.iter().any(|r| r.bed.is_some()) {
        let mut prof = Figure {
            title: "Packing fraction near the floor".into(),
            x_label: "height above the floor's contact plane z/R (1)".into(),
            y_label: "solid fraction (1)".into(),
            legend_outside: true,
            ..Default::default()
        };
        for (k, r) in results.iter().enumerate() {
            if let Some(b) = &r.bed {
                let pts = b.profile.iter().map(|(z, p)| (z / c.radius, *p)).collect();
                prof.series
                    .push(Series::new(r.floor.label(), pts, Mark::Line, palette(k)));
            }
        }
        prof.write_into(out, "packing_profile")?;
        // The side view of the bed on the first floor of boundary
        // particles (else the plane).
        let pick = results
            .iter()
            .find(|r| matches!(r.floor, Floor::Particles { .. }) && r.bed.is_some())
            .or_else(|| results.iter().find(|r| r.bed.is_some()));
        if let Some(r) = pick {
            if let Some(b) = &r.bed {
                let (svg, png) = side_view::side_view(b, &r.floor.label())?;
                out.write("bed_side.svg", |w| Ok(w.write_all(svg.as_bytes())?))?;
                out.write("bed_side.png", |w| Ok(w.write_all(&png)?))?;
            }
        }
    }
    if results.iter().any(|r| matches!(r.chute, Some(Ok(_)))) {
        out.write("chute.csv", |w| {
            let mut csv = csv::Writer::from_writer(w);
            csv.write_record(["floor", "z_m", "vx_m_s", "samples"])?;
            for r in results {
                if let Some(Ok(ch)) = &r.chute {
                    for (z, v, k) in &ch.profile {
                        csv.write_record([
                            r.floor.label(),
                            format!("{z:e}"),
                            format!("{v:e}"),
                            k.to_string(),
                        ])?;
                    }
                }
            }
            csv.flush()?;
            Ok(())
        })?;
        let mut fig = Figure {
            title: "Chute: mean velocity profile over each floor".into(),
            x_label: "mean velocity along the flow v_x (m/s)".into(),
            y_label: "centre height above the floor's contact plane z/R (1)".into(),
            legend_outside: true,
            ..Default::default()
        };
        for (k, r) in results.iter().enumerate() {
            if let Some(Ok(ch)) = &r.chute {
                let pts = ch
                    .profile
                    .iter()
                    .map(|(z, v, _)| (*v, z / c.radius))
                    .collect();
                fig.series
                    .push(Series::new(r.floor.label(), pts, Mark::Line, palette(k)));
            }
        }
        fig.write_into(out, "chute_profile")?;
    }
    let verdicts = recommend::recommend(results, &c.angles, tolerances);
    out.write("recommendation.csv", |w| {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record([
            "floor",
            "wall",
            "quantity",
            "tolerance",
            "plane",
            "value",
            "within",
        ])?;
        for f in &verdicts {
            for v in &f.verdicts {
                csv.write_record([
                    f.floor.label(),
                    f.not_a_wall.is_none().to_string(),
                    v.quantity.clone(),
                    v.tolerance.clone(),
                    format!("{:e}", v.plane),
                    format!("{:e}", v.value),
                    match v.within {
                        Some(true) => "yes".into(),
                        Some(false) => "no".into(),
                        None => "not measured".to_string(),
                    },
                ])?;
            }
        }
        csv.flush()?;
        Ok(())
    })?;
    let report = report(c, results, &summaries, &verdicts, tolerances);
    out.write("report.md", |w| Ok(w.write_all(report.as_bytes())?))?;
    Ok(())
}

fn report(
    c: &StudyConfig,
    results: &[FloorResult],
    summaries: &[Summary],
    verdicts: &[FloorVerdict],
    tolerances: &Tolerances,
) -> String {
    let mut s = String::new();
    let m = &c.material;
    let _ = writeln!(s, "# Wall study: boundary particles against a plane\n");
    let _ = writeln!(
        s,
        "Particles: R = {} m, ρ = {} kg/m³, E = {} Pa, ν = {}; Hertz with Tsuji damping, e = {}; \
         {} tangential spring, μ = {}, μ_r = {}. Impacts at {} m/s, {} per floor and angle, at \
         random (seed {}) points of the tiling's cell; Δt = {:.4e} s (η = {} of the \
         particle–plane contact time {:.4e} s). Bed: {} particles poured into a box with \
         frictionless side walls and settled for {} s.\n",
        c.radius,
        m.density,
        m.youngs_modulus,
        m.poisson_ratio,
        c.restitution,
        c.tangential.row().name,
        c.friction,
        c.rolling_friction,
        c.speed,
        c.impacts,
        c.seed,
        c.dt(),
        c.eta,
        c.contact_time(),
        c.bed_particles,
        c.settle_time
    );
    let _ = writeln!(s, "## Floors\n");
    for (k, r) in results.iter().enumerate() {
        let _ = writeln!(s, "{k}. {}", r.floor.label());
    }
    compact_table(&mut s, c, results);
    let _ = writeln!(s, "\n## Results (mean ± standard deviation)\n");
    let Some(reference) = summaries.iter().find(|x| x.label == "plane") else {
        return s;
    };
    let _ = write!(s, "| quantity | plane |");
    for x in summaries.iter().filter(|x| x.label != "plane") {
        let _ = write!(s, " {} |", x.label);
    }
    let _ = writeln!(s);
    let _ = write!(s, "|---|---|");
    for _ in summaries.iter().filter(|x| x.label != "plane") {
        let _ = write!(s, "---|");
    }
    let _ = writeln!(s);
    for (name, v, sd) in &reference.values {
        let _ = write!(s, "| {name} | {} |", fmt(*v, *sd));
        for x in summaries.iter().filter(|x| x.label != "plane") {
            match x.values.iter().find(|(n, _, _)| n == name) {
                Some((_, v, sd)) => {
                    let _ = write!(s, " {} |", fmt(*v, *sd));
                }
                None => {
                    let _ = write!(s, " – |");
                }
            }
        }
        let _ = writeln!(s);
    }
    // No bed (`--particles 0`): no pressure, fluctuation or loads to
    // state (the weight per area would print as NaN Pa).
    let weight_pressure = results
        .iter()
        .find_map(|r| r.bed.as_ref().map(|b| b.weight_pressure));
    match weight_pressure {
        Some(w) => bed_loads_section(&mut s, w, results),
        None => {
            let _ = writeln!(
                s,
                "\nNo bed was poured (`--particles 0`): no floor pressure, fluctuation or \
                 boundary-particle loads.\n"
            );
        }
    }
    chute_section(&mut s, c, results);
    let _ = writeln!(
        s,
        "\nEffective restitutions are taken along the floor's normal (z) and the incidence \
         direction: on a bumpy floor a particle hitting the flank of a boundary sphere rebounds \
         sideways or down, so e_n may be negative and the rebound angle above 90°.\n"
    );
    verdicts::recommendation_section(&mut s, verdicts, tolerances);
    let _ = writeln!(
        s,
        "Files: impacts.csv (every impact), summary.csv, profile.csv (packing fraction in slabs of \
         R/4), boundary_forces.csv (N), restitution.svg/png, contact_time.svg/png, \
         packing_profile.svg/png, bed_side.svg/png (the bed drawn from its final state), \
         chute.csv and chute_profile.svg/png (the chute's velocity profiles), \
         recommendation.csv (every floor and quantity against the plane)."
    );
    s
}

/// The settled beds' floor pressure sentence and each floor's loaded
/// boundary particles (`weight_pressure`: N m g/A, Pa).
fn bed_loads_section(s: &mut String, weight_pressure: f64, results: &[FloorResult]) {
    let _ = writeln!(
        s,
        "\nThe floor pressure equals the weight per area ({weight_pressure:.6e} Pa) once a bed has \
         settled on any floor; its fluctuation over the last fifth of the run and the force per \
         boundary particle are what differ.\n"
    );
    for r in results {
        if let Some(b) = r.bed.as_ref().filter(|b| b.fell_through > 0) {
            let _ = writeln!(
                s,
                "**{}: {} of {} particles fell through the gaps between the touching boundary \
                 spheres** (wider than a particle for r > 2.414 square, r > 6.464 hexagonal): this \
                 floor is not a wall, and its floor pressure counts only the rest.\n",
                r.floor.label(),
                b.fell_through,
                b.particles
            );
        }
    }
    let _ = writeln!(
        s,
        "Normal force on each loaded boundary particle under the settled bed:\n"
    );
    for r in results {
        if let Some(b) = r.bed.as_ref().filter(|b| !b.boundary_forces.is_empty()) {
            let f = &b.boundary_forces;
            let max = f.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let _ = writeln!(
                s,
                "- {}: {} particles loaded, mean {} N, sd {} N, max {} N, sum {} N",
                r.floor.label(),
                f.len(),
                sig(mean(f)),
                sig(std(f)),
                sig(max),
                sig(f.iter().sum::<f64>())
            );
        }
    }
}

/// The chute's part of the report: setup, one row per floor, the reading.
fn chute_section(s: &mut String, c: &StudyConfig, results: &[FloorResult]) {
    let Some(cc) = &c.chute else {
        return;
    };
    let _ = writeln!(s, "\n## Chute flow: slip at the wall\n");
    let _ = writeln!(
        s,
        "A bed {} particle diameters deep flows down each floor inclined at θ = {}° (g = 9.81 \
         (sin θ, 0, −cos θ) m/s²), periodic along and across the flow in a cell of whole tiling \
         periods at least {} R × {} R, for {} s from a loose pour; the second half is averaged. \
         Slip velocity: the mean v_x of the first layer (centres below 1.5 R above the floor's \
         contact plane, hollows included). Steady: the bed's mean acceleration over the window \
         below 2 % of g sin θ. The floor's shear force against the bed's weight component \
         N m g sin θ: 1 in a steady flow (momentum balance); below 1 by acceleration/(g sin θ) \
         when the bed speeds up.\n",
        cc.layers, cc.angle, cc.min_cell[0], cc.min_cell[1], cc.duration
    );
    let _ = writeln!(
        s,
        "| floor | particles | cell (mm) | slip velocity (m/s) | mean velocity (m/s) | slip \
         fraction (1) | acceleration (m/s²) | steady | floor shear / N m g sin θ (1) | floor \
         normal / N m g cos θ (1) | bed height (mm) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for r in results {
        match &r.chute {
            Some(Ok(ch)) => {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} × {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    r.floor.label(),
                    ch.particles,
                    sig(ch.cell[0] * 1e3),
                    sig(ch.cell[1] * 1e3),
                    sig(ch.slip_velocity),
                    sig(ch.mean_velocity),
                    sig(ch.slip_velocity / ch.mean_velocity),
                    sig(ch.acceleration),
                    if ch.steady(0.02) { "yes" } else { "no" },
                    sig(ch.floor_shear_force / ch.weight_components[0]),
                    sig(ch.floor_normal_force / ch.weight_components[1]),
                    sig(ch.bed_height * 1e3),
                );
            }
            Some(Err(why)) => {
                let _ = writeln!(s, "| {} | not run: {why} |||||||||", r.floor.label());
            }
            None => {}
        }
    }
    let _ = writeln!(
        s,
        "\nA flat frictional floor cannot hold a sheared bed back: its first layer rolls, the \
         contact points sticking, and the bed keeps accelerating (no steady flow on a flat base, \
         Silbert et al., Phys. Rev. E 64, 051302, 2001). Boundary particles of radius ratio r \
         lock the first layer in their hollows, as long as r is small enough that a particle \
         cannot pass between them (touching spheres: r ≤ 2.414 square, r ≤ 6.464 hexagonal)."
    );
}

/// One row per floor, the plane first: the numbers the recommendation
/// compares, side by side.
fn compact_table(s: &mut String, c: &StudyConfig, results: &[FloorResult]) {
    let _ = writeln!(s, "\n## Each floor against the plane\n");
    let oblique = c.angles.iter().copied().find(|&a| a > 0.0);
    let normal = c.angles.first().copied().unwrap_or(0.0);
    let _ = write!(s, "| floor | e_n at {normal}° (mean ± sd) |");
    if let Some(a) = oblique {
        let _ = write!(s, " e_n at {a}° | e_t at {a}° |");
    }
    let _ = writeln!(
        s,
        " median contact time at {normal}° (µs) | packing 0–2R | floor pressure / N m g/A | \
         fluctuation | fell through | first-layer slip (m/s) | extrapolated slip (m/s) | slip \
         length (mm) | mean velocity (m/s) |"
    );
    let columns = 11 + if oblique.is_some() { 2 } else { 0 };
    let _ = writeln!(s, "|{}", "---|".repeat(columns));
    let stats = |r: &FloorResult, a: f64, f: fn(&wall_study::Impact) -> f64| {
        let v: Vec<f64> = r.impacts.iter().filter(|i| i.angle == a).map(f).collect();
        (mean(&v), std(&v), median(&v))
    };
    for r in results {
        let (en, sd, _) = stats(r, normal, |i| i.normal_restitution);
        let _ = write!(s, "| {} | {} |", r.floor.label(), fmt(en, sd));
        if let Some(a) = oblique {
            let (en, sd, _) = stats(r, a, |i| i.normal_restitution);
            let (et, sdt, _) = stats(r, a, |i| i.tangential_restitution);
            let _ = write!(s, " {} | {} |", fmt(en, sd), fmt(et, sdt));
        }
        let (_, _, tc) = stats(r, normal, |i| i.contact_time * 1e6);
        let _ = write!(s, " {} |", fmt(tc, 0.0));
        match &r.bed {
            Some(b) => {
                let _ = write!(
                    s,
                    " {} | {} | {} | {} |",
                    sig(b.wall_packing),
                    sig(b.floor_pressure / b.weight_pressure),
                    sig(b.pressure_fluctuation),
                    b.fell_through
                );
            }
            None => {
                let _ = write!(s, " – | – | – | – |");
            }
        }
        match &r.chute {
            Some(Ok(ch)) => {
                let fit = ch.slip_fit;
                let _ = writeln!(
                    s,
                    " {} | {} | {} | {} |",
                    sig(ch.slip_velocity),
                    fmt(fit.map_or(f64::NAN, |f| f.slip_velocity), 0.0),
                    fmt(fit.map_or(f64::NAN, |f| f.slip_length * 1e3), 0.0),
                    sig(ch.mean_velocity)
                );
            }
            Some(Err(_)) => {
                let _ = writeln!(s, " not run | | | |");
            }
            None => {
                let _ = writeln!(s, " – | – | – | – |");
            }
        }
    }
    let _ = writeln!(
        s,
        "\nImpacts: {} per angle at random points of the tiling's cell. Floor pressure against the \
         weight of all the bed's particles per area; fluctuation: sd/mean of the floor force over \
         the last fifth of the run. Slip: the chute's first layer (centres below 1.5 R), and the \
         line through the profile's slabs with mean centre 0 ≤ z ≤ min({} R, half the bed height) \
         extrapolated to the floor's contact plane (z = 0); slip length = that slip / the line's \
         shear rate (infinite: a block). Why a chute was not run: the chute section.",
        c.impacts,
        wall_study::chute::SLIP_FIT_TOP
    );
}

fn fmt(v: f64, sd: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    // A spread at round-off of the mean (identical impacts on a plane,
    // ~1e-16) is none.
    if sd > 1e-12 * v.abs() {
        format!("{} ± {}", sig(v), sig(sd))
    } else {
        sig(v)
    }
}

fn sig(v: f64) -> String {
    crate::output::format::sig(v, 4)
}

/// A value of impacts.csv: empty where it is undefined, never "NaN": e_t
/// at normal incidence (no tangential impact velocity to divide by), and
/// there a part study's rebound angle.
pub(super) fn defined(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        String::new()
    }
}
