//! `dembound recommend`: the smallest boundary ζ (or r) that keeps h_max,
//! T_c or a_max within a tolerance of the rigid half-space, or the
//! deviations at a given (r, ζ).

use super::lists;
use super::{CliError, CliResult};
use crate::output::format::sig;
use crate::scenario_file::ScenarioArgs;
use anyhow::{anyhow, bail, Result};
use clap::Args;
use comfy_table::{presets, CellAlignment, Table};
use dembound_core::contact::ContactLawKind;
use dembound_core::study::recommend::{
    deviations, smallest, Deviations, Limit, Outcome, RecommendError,
};
use dembound_core::study::{Axis, Quantity};
use serde::Serialize;
use std::io::Write;

#[derive(Debug, Args)]
pub struct RecommendArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Largest allowed deviation |q(r, ζ)/q(∞, ∞) − 1|, a fraction (0.01) or a percentage (1%)
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub tolerance: Option<String>,

    /// Contact laws (default: linear,hertz)
    #[arg(long, value_name = "LIST")]
    pub law: Option<String>,

    /// Quantity: max_overlap (h_max), duration (T_c) or max_acceleration (a_max); default all three
    #[arg(long, value_name = "Q")]
    pub quantity: Option<String>,

    /// Boundary radius ratio r (`inf` allowed): with --tolerance, the smallest ζ for this r
    #[arg(long = "r", value_name = "R", allow_hyphen_values = true)]
    pub r: Option<String>,

    /// Boundary modulus ratio ζ (`inf` allowed): with --tolerance, the smallest r for this ζ
    #[arg(long = "zeta", value_name = "Z", allow_hyphen_values = true)]
    pub zeta: Option<String>,

    /// Print one JSON object to stdout instead of the table
    #[arg(long)]
    pub json: bool,
}

/// `0.01` or `1%`.
pub(crate) fn tolerance(text: &str) -> Result<f64> {
    let t = text.trim();
    let (num, scale) = match t.strip_suffix('%') {
        Some(n) => (n.trim(), 0.01),
        None => (t, 1.0),
    };
    let x = num.parse::<f64>().ok().map(|x| x * scale);
    match x {
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => bail!(
            "invalid value for `--tolerance`: `{t}` (allowed: finite and > 0, a fraction such as 0.01 or a percentage such as 1%)"
        ),
    }
}

fn quantities(text: Option<&str>) -> Result<Vec<Quantity>> {
    match text {
        None => Ok(Quantity::ALL.to_vec()),
        Some(t) => t
            .split(',')
            .map(|q| {
                Quantity::parse(q).ok_or_else(|| {
                    anyhow!(
                        "invalid value for `--quantity`: `{}` (allowed: max_overlap (h_max), duration (T_c), max_acceleration (a_max))",
                        q.trim()
                    )
                })
            })
            .collect(),
    }
}

#[derive(Debug, Serialize)]
#[serde(untagged)]
enum Report {
    Limits { tolerance: f64, limits: Vec<Limit> },
    Deviations { deviations: Vec<Deviations> },
}

fn core_error(e: RecommendError) -> CliError {
    match e {
        RecommendError::Input(i) => CliError::input(anyhow!(
            "invalid value for `--{}`: {} (allowed: {})",
            i.field,
            i.value,
            i.allowed
        )),
        e => CliError::failed(e),
    }
}

pub fn run(args: &RecommendArgs) -> CliResult {
    let base = args.scenario.load().map_err(CliError::input)?.resolved();
    let laws = match &args.law {
        Some(l) => lists::laws_for("--law", l, "recommend").map_err(CliError::input)?,
        None => vec![ContactLawKind::Linear, ContactLawKind::Hertz],
    };
    let r = args
        .r
        .as_deref()
        .map(|t| lists::ratio("--r", t))
        .transpose()
        .map_err(CliError::input)?;
    let zeta = args
        .zeta
        .as_deref()
        .map(|t| lists::ratio("--zeta", t))
        .transpose()
        .map_err(CliError::input)?;
    let qs = quantities(args.quantity.as_deref()).map_err(CliError::input)?;
    let report = match (&args.tolerance, r, zeta) {
        (Some(t), r, z) => {
            let t = tolerance(t).map_err(CliError::input)?;
            let targets: Vec<(Axis, f64)> = match (r, z) {
                (Some(_), Some(_)) => {
                    return Err(CliError::input(anyhow!(
                        "with --tolerance give at most one of --r and --zeta (the other is solved for); \
                         without --tolerance, --r and --zeta report the deviations"
                    )))
                }
                (Some(r), None) => vec![(Axis::Modulus, r)],
                (None, Some(z)) => vec![(Axis::Radius, z)],
                (None, None) => vec![(Axis::Modulus, f64::INFINITY), (Axis::Radius, f64::INFINITY)],
            };
            let mut limits = Vec::new();
            for &law in &laws {
                for &q in &qs {
                    for &(axis, other) in &targets {
                        limits.push(smallest(&base, law, q, t, axis, other).map_err(core_error)?);
                    }
                }
            }
            Report::Limits { tolerance: t, limits }
        }
        (None, Some(r), Some(z)) => {
            let mut d = laws
                .iter()
                .map(|&law| deviations(&base, law, r, z))
                .collect::<Result<Vec<_>, _>>()
                .map_err(core_error)?;
            for x in &mut d {
                x.quantities.retain(|q| qs.contains(&q.quantity));
            }
            Report::Deviations { deviations: d }
        }
        (None, _, _) => {
            return Err(CliError::input(anyhow!(
                "give --tolerance T (with at most one of --r, --zeta) for limits, or both --r and --zeta for deviations"
            )))
        }
    };
    let mut stdout = std::io::stdout().lock();
    if args.json {
        let text = serde_json::to_string_pretty(&report).map_err(CliError::failed)?;
        writeln!(stdout, "{text}").map_err(CliError::failed)?;
    } else {
        match &report {
            Report::Limits { tolerance, limits } => {
                writeln!(stdout, "{}", limits_table(limits)).map_err(CliError::failed)?;
                writeln!(
                    stdout,
                    "tolerance T = {} % on |q(r, ζ)/q(∞, ∞) − 1|; limits from the exact model \
                     (Brent), checked by the integrator ({}, η = {}) at the limit",
                    sig(tolerance * 100.0, 4),
                    base.integration.scheme.name(),
                    base.integration
                        .eta
                        .map(|e| e.to_string())
                        .unwrap_or_else(|| "given Δt".into())
                )
                .map_err(CliError::failed)?;
                for l in limits {
                    if let Outcome::Unreachable { floor } = l.outcome {
                        writeln!(
                            stdout,
                            "{} {}: no {} satisfies T: {} = {} alone already gives {} %",
                            l.law.name(),
                            l.quantity.symbol(),
                            l.solved.symbol(),
                            l.solved.other().symbol(),
                            lists::show(l.other),
                            sig(floor * 100.0, 4)
                        )
                        .map_err(CliError::failed)?;
                    }
                }
            }
            Report::Deviations { deviations } => {
                writeln!(stdout, "{}", deviations_table(deviations)).map_err(CliError::failed)?;
                writeln!(stdout, "deviation = |q(r, ζ)/q(∞, ∞) − 1|, the integrator against its own rigid half-space run")
                    .map_err(CliError::failed)?;
            }
        }
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

fn pct(x: Option<f64>) -> String {
    x.map(|x| format!("{} %", sig(x * 100.0, 6)))
        .unwrap_or_else(|| "–".into())
}

fn value(x: Option<f64>) -> String {
    x.map(|x| sig(x, 8)).unwrap_or_else(|| "–".into())
}

fn limits_table(limits: &[Limit]) -> Table {
    let mut t = Table::new();
    t.load_preset(presets::UTF8_FULL_CONDENSED);
    t.set_header(vec![
        "law",
        "quantity",
        "given",
        "smallest",
        "exact deviation",
        "integrator deviation",
        "closed form, g = 0",
        "closed form with g",
    ]);
    for l in limits {
        let found = match l.outcome {
            Outcome::Found { value } => format!("{} = {}", l.solved.symbol(), sig(value, 8)),
            Outcome::Unreachable { floor } => format!("none ({} % already)", sig(floor * 100.0, 4)),
            Outcome::AnyValue => "any value".into(),
        };
        t.add_row(vec![
            l.law.name(),
            l.quantity.symbol().to_string(),
            format!("{} = {}", l.solved.other().symbol(), lists::show(l.other)),
            found,
            pct(l.exact_deviation),
            pct(l.simulated_deviation),
            value(l.gravity_free),
            value(l.closed_form),
        ]);
    }
    for i in 3..8 {
        if let Some(c) = t.column_mut(i) {
            c.set_cell_alignment(CellAlignment::Right);
        }
    }
    t
}

fn deviations_table(ds: &[Deviations]) -> Table {
    let mut t = Table::new();
    t.load_preset(presets::UTF8_FULL_CONDENSED);
    t.set_header(vec![
        "law",
        "r",
        "ζ",
        "quantity",
        "exact deviation",
        "integrator deviation",
    ]);
    for d in ds {
        for q in &d.quantities {
            t.add_row(vec![
                d.law.name(),
                lists::show(d.radius_ratio),
                lists::show(d.modulus_ratio),
                q.quantity.symbol().to_string(),
                pct(Some(q.exact)),
                pct(Some(q.simulated)),
            ]);
        }
    }
    for i in 4..6 {
        if let Some(c) = t.column_mut(i) {
            c.set_cell_alignment(CellAlignment::Right);
        }
    }
    t
}
