//! `dembound restitution`: the effective restitution of the dissipative laws
//! on boundary particles (a sweep over r and ζ), and the reverse question
//! (`--target`): which e to enter for a given rebound on a given boundary
//! particle.

use super::{CliError, CliResult};
use crate::output::files::AtomicDir;
use crate::output::format::sig;
use crate::output::restitution::{
    ratio_text, restitution_figures, restitution_markdown, write_restitution_csv,
};
use crate::output::table::{Cell, Column, Table};
use crate::scenario_file::ScenarioArgs;
use anyhow::anyhow;
use clap::{Args, ValueEnum};
use dembound_core::bounce::Scenario;
use dembound_core::study::restitution::{
    required_restitution, restitution_sweep, Calibration, DissipativeLaw, RequiredRestitution,
    RestitutionError, RestitutionSpec, RestitutionStudy, DEFAULT_RATIOS, DEFAULT_TARGETS,
};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `--calibrate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CalibrateArg {
    /// Raw coefficient calibrated on the rigid wall r = ζ = ∞, reused on the pair
    Wall,
    /// Raw coefficient calibrated on each pair's own effective properties
    Pair,
    /// Both, side by side
    Both,
}

impl CalibrateArg {
    fn calibrations(self) -> Vec<Calibration> {
        match self {
            CalibrateArg::Wall => vec![Calibration::Wall],
            CalibrateArg::Pair => vec![Calibration::Pair],
            CalibrateArg::Both => Calibration::ALL.to_vec(),
        }
    }
}

#[derive(Debug, Args)]
pub struct RestitutionArgs {
    /// The base scenario: its particle, motion (drop), integration and
    /// contact.attractive are used; the contact law, restitution and
    /// boundary ratios are set by the study. The boundary must be fixed.
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Dissipative laws (comma-separated or repeated): viscous, tsuji,
    /// viscoelastic, walton-braun [default: all four]
    #[arg(long, value_name = "LAW", value_delimiter = ',', value_parser = parse_law)]
    pub law: Vec<DissipativeLaw>,

    /// Target restitutions set on the pair, 0 < e ≤ 1 [default: 0.5,0.9]
    #[arg(
        long = "e",
        value_name = "E",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub targets: Vec<f64>,

    /// Boundary radius ratios r = R_b/R_m (> 0 or inf)
    /// [default: 1,3,10,30,100,300,1000,inf]
    #[arg(long = "r", value_name = "R", value_delimiter = ',', value_parser = parse_ratio,
          allow_negative_numbers = true)]
    pub radius_ratios: Vec<f64>,

    /// Boundary modulus ratios ζ = E_b/E_m (> 0 or inf)
    /// [default: 1,3,10,30,100,300,1000,inf]
    #[arg(long = "zeta", value_name = "ZETA", value_delimiter = ',', value_parser = parse_ratio,
          allow_negative_numbers = true)]
    pub modulus_ratios: Vec<f64>,

    /// Where the raw damping coefficient is calibrated for e: on the rigid
    /// wall (then reused on the boundary particle), on each pair, or both
    /// [default: both for the sweep, wall with --target]
    #[arg(long, value_enum)]
    pub calibrate: Option<CalibrateArg>,

    /// The reverse question: the rebound E (0 < E < 1) wanted on the
    /// boundary particle given by --r and --zeta, for one --law; prints the
    /// e to enter and the raw coefficient
    #[arg(long, value_name = "E", allow_negative_numbers = true)]
    pub target: Option<f64>,

    /// With --target: print one JSON array of answers instead of text
    #[arg(long)]
    pub json: bool,

    /// Write restitution.csv, restitution.md and the figures (SVG + PNG)
    /// into DIR (created if missing)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

fn parse_law(s: &str) -> Result<DissipativeLaw, String> {
    DissipativeLaw::parse(s).ok_or_else(|| {
        format!("unknown law `{s}` (expected viscous, tsuji, viscoelastic or walton-braun)")
    })
}

fn parse_ratio(s: &str) -> Result<f64, String> {
    let t = s.trim();
    let x = if t.eq_ignore_ascii_case("inf") || t.eq_ignore_ascii_case("infinity") {
        f64::INFINITY
    } else {
        t.parse::<f64>()
            .map_err(|_| format!("`{s}` is not a number or inf"))?
    };
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("`{s}`: a ratio must be > 0 (or inf)"))
    }
}

pub fn run(args: &RestitutionArgs) -> CliResult {
    let base = args.scenario.load().map_err(CliError::input)?.resolved();
    match args.target {
        Some(target) => reverse(args, &base, target),
        None => sweep(args, &base),
    }
}

fn study_error(e: RestitutionError) -> CliError {
    match e {
        RestitutionError::Input(_) | RestitutionError::OutOfReach(_) => {
            CliError::input(anyhow!("{e}"))
        }
        e @ RestitutionError::Simulation { .. } => {
            CliError::failed(anyhow!("the study failed: {e}"))
        }
    }
}

fn sweep(args: &RestitutionArgs, base: &Scenario) -> CliResult {
    if args.json {
        return Err(CliError::input(anyhow!(
            "--json applies to the reverse question (--target); the sweep writes CSV with --out"
        )));
    }
    let or = |given: &Vec<f64>, default: &[f64]| {
        if given.is_empty() {
            default.to_vec()
        } else {
            given.clone()
        }
    };
    let spec = RestitutionSpec {
        laws: if args.law.is_empty() {
            DissipativeLaw::ALL.to_vec()
        } else {
            args.law.clone()
        },
        targets: or(&args.targets, &DEFAULT_TARGETS),
        radius_ratios: or(&args.radius_ratios, &DEFAULT_RATIOS),
        modulus_ratios: or(&args.modulus_ratios, &DEFAULT_RATIOS),
        calibrations: args.calibrate.unwrap_or(CalibrateArg::Both).calibrations(),
    };
    let study = restitution_sweep(base, &spec).map_err(study_error)?;
    let written = match &args.out {
        Some(dir) => Some(write_outputs(dir, &study)?),
        None => None,
    };
    let mut stdout = std::io::stdout().lock();
    let mut text = String::new();
    text.push_str("Effective restitution v_r/|v_c| of one drop on boundary particles.\n");
    for c in &spec.calibrations {
        text.push_str(&format!("  {}: {}\n", c.name(), c.description()));
    }
    let mapping = base.contact.calibration.unwrap_or_default();
    text.push_str(&format!(
        "  e → coefficient: contact.calibration = \"{}\", {}\n",
        mapping.name(),
        mapping.description()
    ));
    writeln!(stdout, "{text}{}", summary_table(&study)).map_err(CliError::failed)?;
    match written {
        Some(paths) => {
            for p in paths {
                writeln!(stdout, "wrote {}", p.display()).map_err(CliError::failed)?;
            }
        }
        None => writeln!(
            stdout,
            "(diagonal r = ζ only, or the first r and ζ when none coincide; --out DIR writes the full grid, tables and figures)"
        )
        .map_err(CliError::failed)?,
    }
    stdout.flush().map_err(CliError::failed)
}

/// Effective restitution per law, calibration and target, on the
/// diagonal r = ζ (or along the r list at the first ζ when no value is in both).
fn summary_table(study: &RestitutionStudy) -> Table {
    let spec = &study.spec;
    let mut cols: Vec<(f64, f64)> = spec
        .radius_ratios
        .iter()
        .filter(|r| spec.modulus_ratios.contains(r))
        .map(|&r| (r, r))
        .collect();
    if cols.is_empty() {
        cols = spec
            .radius_ratios
            .iter()
            .map(|&r| (r, spec.modulus_ratios[0]))
            .collect();
    }
    let mut columns = vec![
        Column::text("law"),
        Column::text("calibration"),
        Column::text("e").right(),
    ];
    columns.extend(cols.iter().map(|&(r, z)| {
        Column::text(if r == z {
            format!("r = ζ = {}", ratio_text(r))
        } else {
            format!("r = {}, ζ = {}", ratio_text(r), ratio_text(z))
        })
        .right()
    }));
    let mut table = Table::new(columns).with_keys(3);
    for &law in &spec.laws {
        for &cal in &spec.calibrations {
            for &e in &spec.targets {
                let mut row = vec![
                    Cell::text(law.name()),
                    Cell::text(cal.name()),
                    Cell::text(e.to_string()),
                ];
                row.extend(cols.iter().map(|&(r, z)| {
                    Cell::Text(
                        study
                            .point(law, cal, e, r, z)
                            .map(|p| format!("{:.6}", p.restitution()))
                            .unwrap_or_default(),
                    )
                }));
                table.push(row);
            }
        }
    }
    table
}

/// restitution.csv and restitution.md (staged, renamed together) and the
/// figures; on failure nothing of it is left.
fn write_outputs(dir: &Path, study: &RestitutionStudy) -> CliResult<Vec<PathBuf>> {
    let mut out = AtomicDir::create(dir).map_err(CliError::failed)?;
    out.write("restitution.csv", |w| write_restitution_csv(study, w))
        .map_err(CliError::failed)?;
    let md = restitution_markdown(study);
    out.write("restitution.md", |w| Ok(w.write_all(md.as_bytes())?))
        .map_err(CliError::failed)?;
    let figures = match restitution_figures(study, dir) {
        Ok(paths) => paths,
        Err(e) => {
            // Figures already written go too: a failed command leaves nothing.
            for path in figure_paths_in(dir) {
                let _ = std::fs::remove_file(path);
            }
            return Err(CliError::failed(e));
        }
    };
    let mut written = out.commit().map_err(CliError::failed)?;
    written.extend(figures);
    Ok(written)
}

fn figure_paths_in(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
                    name.starts_with("restitution_")
                        && (name.ends_with(".svg") || name.ends_with(".png"))
                })
                .collect()
        })
        .unwrap_or_default()
}

fn single<T: Copy>(values: &[T], flag: &str, what: &str) -> CliResult<T> {
    match values {
        [one] => Ok(*one),
        [] => Err(CliError::input(anyhow!(
            "--target needs {flag} (exactly one {what})"
        ))),
        _ => Err(CliError::input(anyhow!(
            "--target takes exactly one {flag} ({what}), got {}",
            values.len()
        ))),
    }
}

fn reverse(args: &RestitutionArgs, base: &Scenario, target: f64) -> CliResult {
    let law = single(&args.law, "--law", "dissipative law")?;
    let r = single(&args.radius_ratios, "--r", "boundary radius ratio")?;
    let z = single(&args.modulus_ratios, "--zeta", "boundary modulus ratio")?;
    if !args.targets.is_empty() {
        return Err(CliError::input(anyhow!(
            "--e sets targets of the sweep; with --target the answer is the e to enter"
        )));
    }
    if args.out.is_some() {
        return Err(CliError::input(anyhow!(
            "--out applies to the sweep, not to --target"
        )));
    }
    let calibrations = args.calibrate.unwrap_or(CalibrateArg::Wall).calibrations();
    let answers = calibrations
        .iter()
        .map(|&cal| required_restitution(base, law, cal, target, r, z))
        .collect::<Result<Vec<_>, _>>()
        .map_err(study_error)?;
    let mut stdout = std::io::stdout().lock();
    if args.json {
        let text = serde_json::to_string_pretty(&answers).map_err(CliError::failed)?;
        writeln!(stdout, "{text}").map_err(CliError::failed)?;
    } else {
        let mapping = base.contact.calibration.unwrap_or_default();
        writeln!(
            stdout,
            "{} ({}) on the boundary particle r = {}, ζ = {}; wanted rebound E = {target} \
             (impact speed {} m/s)\ne → coefficient: contact.calibration = \"{}\", {}",
            law.name(),
            law.description(),
            ratio_text(r),
            ratio_text(z),
            sig(base.impact_speed(), 6),
            mapping.name(),
            mapping.description()
        )
        .map_err(CliError::failed)?;
        for a in &answers {
            write_answer(&mut stdout, base, a).map_err(CliError::failed)?;
        }
    }
    stdout.flush().map_err(CliError::failed)
}

fn write_answer(
    w: &mut dyn Write,
    base: &Scenario,
    a: &RequiredRestitution,
) -> std::io::Result<()> {
    let law = a.law;
    writeln!(
        w,
        "\n{} calibration ({}):\n  enter e = {:.9}\n  raw coefficient {} = {} {}\n  \
         simulated rebound with it: {:.9}\n  (entering E = {} itself gives {:.9})",
        a.calibration.name(),
        a.calibration.description(),
        a.enter,
        law.coefficient_symbol(),
        sig(a.coefficient, 10),
        law.coefficient_unit(),
        a.achieved,
        a.target,
        a.naive,
    )?;
    let (l, d) = law.contact();
    match (law, a.calibration) {
        (DissipativeLaw::WaltonBraun, _) => {
            // k₂ = k₁/e² with the pair's own k₁ is the same law.
            let mut pair = *base;
            pair.boundary.radius_ratio = a.radius_ratio;
            pair.boundary.modulus_ratio = a.modulus_ratio;
            let k1 = pair.pair().power_law_stiffness(1.0);
            writeln!(
                w,
                "  scenario: --set contact.law=walton-braun --set contact.restitution={:.9} \
                 (the same k₂ with the pair's own k₁)",
                (k1 / a.coefficient).sqrt()
            )
        }
        (_, Calibration::Pair) => writeln!(
            w,
            "  scenario: --set contact.law={} --set contact.damping={} --set contact.restitution={:.9}{}",
            l.name(),
            d.name(),
            a.enter,
            match base.contact.calibration {
                Some(c) => format!(" --set contact.calibration={}", c.name()),
                None => String::new(),
            }
        ),
        (_, Calibration::Wall) => writeln!(
            w,
            "  scenario: --set contact.law={} --set contact.damping={} --set contact.damping_coefficient={}",
            l.name(),
            d.name(),
            crate::output::format::exact(a.coefficient)
        ),
    }
}
