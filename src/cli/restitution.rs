//! `dembound restitution`: the effective restitution of the dissipative laws
//! on boundary particles (a sweep over r and ζ), and the reverse question
//! (`--target`): which e to enter for a given rebound on a given boundary
//! particle.

use super::lists;
use super::{CliError, CliResult};
use crate::output::boundary;
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
    required_restitution, restitution_sweep, CalibrationSite, DissipativeLaw, RequiredRestitution,
    RestitutionSpec, RestitutionStudy, DEFAULT_RATIOS, DEFAULT_TARGETS,
};
use dembound_core::Error;
use std::io::Write;
use std::path::PathBuf;

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
    fn calibrations(self) -> Vec<CalibrationSite> {
        match self {
            CalibrateArg::Wall => vec![CalibrationSite::Wall],
            CalibrateArg::Pair => vec![CalibrationSite::Pair],
            CalibrateArg::Both => CalibrationSite::ALL.to_vec(),
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

    /// Dissipative laws: viscous, tsuji, viscoelastic, walton-braun
    /// (comma-separated or repeated) [default: all four]
    #[arg(long, value_name = "LIST")]
    pub law: Vec<String>,

    /// Target restitutions set on the pair, 0 < e ≤ 1: `0.5,0.9`,
    /// `lin:0.3:0.9:4` [default: 0.5,0.9]
    #[arg(long = "e", value_name = "LIST", allow_hyphen_values = true)]
    pub targets: Vec<String>,

    /// Boundary radius ratios r = R_b/R_m: `1,10,100,inf`, `log:1:1000:7`,
    /// `lin:1:5:5` or a mix [default: 1,3,10,30,100,300,1000,inf]
    #[arg(long = "r", value_name = "LIST", allow_hyphen_values = true)]
    pub radius_ratios: Vec<String>,

    /// Boundary modulus ratios ζ = E_b/E_m (same syntax as --r)
    /// [default: 1,3,10,30,100,300,1000,inf]
    #[arg(long = "zeta", value_name = "LIST", allow_hyphen_values = true)]
    pub modulus_ratios: Vec<String>,

    /// Where the raw damping coefficient is calibrated for e: `wall` (on the
    /// rigid wall r = ζ = ∞, then reused on the boundary particle), `pair` (on
    /// each pair's own effective properties) or `both`
    /// [default: both for the sweep, wall with --target]
    #[arg(long, value_enum, value_name = "WHERE", hide_possible_values = true)]
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
    /// into DIR (created if missing; checked before computing; all files
    /// or none)
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// The parsed lists of the arguments (repeated flags joined).
struct Lists {
    laws: Vec<DissipativeLaw>,
    targets: Vec<f64>,
    radius_ratios: Vec<f64>,
    modulus_ratios: Vec<f64>,
}

fn lists_of(args: &RestitutionArgs) -> anyhow::Result<Lists> {
    let joined = |v: &Vec<String>| (!v.is_empty()).then(|| v.join(","));
    Ok(Lists {
        laws: match joined(&args.law) {
            Some(t) => lists::dissipative_laws("--law", &t)?,
            None => Vec::new(),
        },
        targets: match joined(&args.targets) {
            Some(t) => lists::restitutions("--e", &t)?,
            None => Vec::new(),
        },
        radius_ratios: match joined(&args.radius_ratios) {
            Some(t) => lists::ratios("--r", &t)?,
            None => Vec::new(),
        },
        modulus_ratios: match joined(&args.modulus_ratios) {
            Some(t) => lists::ratios("--zeta", &t)?,
            None => Vec::new(),
        },
    })
}

pub fn run(args: &RestitutionArgs) -> CliResult {
    let base = args.scenario.load().map_err(CliError::input)?.resolved();
    let lists = lists_of(args).map_err(CliError::input)?;
    match args.target {
        Some(target) => reverse(args, &lists, &base, target),
        None => sweep(args, &lists, &base),
    }
}

fn study_error(e: Error) -> CliError {
    match e {
        Error::Request(_) | Error::OutOfReach(_) | Error::Input { .. } => {
            CliError::input(anyhow!("{e}"))
        }
        // A point the step cannot resolve (Walton–Braun's unloading line
        // at a small e) is refused as `run` refuses it.
        Error::StudyRun { ref error, .. } if matches!(**error, Error::Input { .. }) => {
            CliError::input(anyhow!("{e}"))
        }
        e => CliError::failed(anyhow!("the study failed: {e}")),
    }
}

fn sweep(args: &RestitutionArgs, lists: &Lists, base: &Scenario) -> CliResult {
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
        laws: if lists.laws.is_empty() {
            DissipativeLaw::ALL.to_vec()
        } else {
            lists.laws.clone()
        },
        targets: or(&lists.targets, &DEFAULT_TARGETS),
        radius_ratios: or(&lists.radius_ratios, &DEFAULT_RATIOS),
        modulus_ratios: or(&lists.modulus_ratios, &DEFAULT_RATIOS),
        calibrations: args.calibrate.unwrap_or(CalibrateArg::Both).calibrations(),
    };
    let out = match &args.out {
        Some(dir) => Some(super::output_dir(dir, "restitution")?),
        None => None,
    };
    let study = restitution_sweep(base, &spec).map_err(study_error)?;
    let written = match out {
        Some(out) => Some(write_outputs(out, &study)?),
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

/// restitution.csv, restitution.md and the figures, all or none.
fn write_outputs(mut out: AtomicDir, study: &RestitutionStudy) -> CliResult<Vec<PathBuf>> {
    out.write("restitution.csv", |w| write_restitution_csv(study, w))
        .map_err(CliError::failed)?;
    let md = restitution_markdown(study);
    out.write("restitution.md", |w| Ok(w.write_all(md.as_bytes())?))
        .map_err(CliError::failed)?;
    restitution_figures(study, out.staging()).map_err(CliError::failed)?;
    out.commit().map_err(CliError::failed)
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

fn reverse(args: &RestitutionArgs, lists: &Lists, base: &Scenario, target: f64) -> CliResult {
    let law = single(&lists.laws, "--law", "dissipative law")?;
    let r = single(&lists.radius_ratios, "--r", "boundary radius ratio")?;
    let z = single(&lists.modulus_ratios, "--zeta", "boundary modulus ratio")?;
    if !lists.targets.is_empty() {
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
        // Each answer with the boundary in SI beside r and ζ.
        #[derive(serde::Serialize)]
        struct Answer<'a> {
            #[serde(flatten)]
            answer: &'a RequiredRestitution,
            #[serde(flatten)]
            si: boundary::SiBoundary,
        }
        let answers: Vec<Answer> = answers
            .iter()
            .map(|a| Answer {
                answer: a,
                si: boundary::SiBoundary::new(base, a.radius_ratio, a.modulus_ratio),
            })
            .collect();
        write!(stdout, "{}", super::json_text(&answers)?).map_err(CliError::failed)?;
    } else {
        let mapping = base.contact.calibration.unwrap_or_default();
        writeln!(
            stdout,
            "{} ({}) on the boundary particle r = {} ({}), ζ = {} ({}); wanted rebound E = {target} \
             (impact speed {} m/s)\ne → coefficient: contact.calibration = \"{}\", {}",
            law.name(),
            law.description(),
            ratio_text(r),
            boundary::radius_text(boundary::radius(base, r)),
            ratio_text(z),
            boundary::modulus_text(boundary::youngs_modulus(base, z)),
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
         simulated rebound with it: {:.9}\n  (entering E = {} itself {})",
        a.calibration.name(),
        a.calibration.description(),
        a.enter,
        law.coefficient_symbol(),
        sig(a.coefficient, 10),
        law.coefficient_unit(),
        a.achieved,
        a.target,
        match a.naive {
            Some(e) => format!("gives {e:.9}"),
            None => "is refused: the law cannot be calibrated for it or the step does not \
                     resolve it"
                .to_string(),
        },
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
        (_, CalibrationSite::Pair) => writeln!(
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
        (_, CalibrationSite::Wall) => writeln!(
            w,
            "  scenario: --set contact.law={} --set contact.damping={} --set contact.damping_coefficient={}",
            l.name(),
            d.name(),
            crate::output::format::exact(a.coefficient)
        ),
    }
}
