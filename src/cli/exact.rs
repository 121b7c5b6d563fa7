//! `dembound exact`: the exact per-contact values of a scenario, with the
//! paper's estimates (eqs 26–30) beside the exact contact time and overlap.

use super::{warnings, CliError, CliResult};
use crate::output::format::sig;
use crate::output::report::{self, relative_error, DIGITS};
use crate::output::table::{Cell, Column, Format, Table, Unit};
use crate::scenario_file::ScenarioArgs;
use anyhow::anyhow;
use clap::Args;
use dembound_core::bounce::{ContactRecord, Scenario};
use dembound_core::contact::ContactLawKind;
use dembound_core::exact::{self, paper};
use dembound_core::Error;
use serde::Serialize;
use std::io::Write;

#[derive(Debug, Args)]
pub struct ExactArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,

    /// Print one JSON object (scenario, contacts, paper_estimates; SI) to
    /// stdout instead of the tables
    #[arg(long)]
    pub json: bool,
}

/// What the reference of `s` is: the elastic laws' exact solution, or for
/// a dissipative contact the closed form or adaptive integration of its own
/// law (never the elastic law: `contact.damping` is not ignored).
pub fn reference_source(s: &Scenario) -> String {
    use dembound_core::contact::DampingKind;
    let law = s.contact.law.name();
    match (s.contact.law, s.contact.damping) {
        (ContactLawKind::WaltonBraun, _) => {
            format!("contact law {law}, closed form with gravity")
        }
        (_, DampingKind::Viscous) => format!(
            "contact law {law} with viscous damping (spring–dashpot), closed form with gravity"
        ),
        (_, DampingKind::Tsuji | DampingKind::Viscoelastic) => format!(
            "contact law {law} with {} damping, adaptive Dormand–Prince integration of the \
             contact (relative tolerance 1e-13 per step)",
            s.contact.damping.name()
        ),
        _ => format!("contact law {law}"),
    }
}

/// Exact per-contact values of a validated scenario. A scenario the exact
/// reference rejects is bad input (exit 2); a failed quadrature or root
/// search exits 1.
pub fn exact_contacts(s: &Scenario) -> CliResult<Vec<ContactRecord>> {
    exact::scenario_contacts(s).map_err(exact_error)
}

pub(crate) fn exact_error(e: Error) -> CliError {
    match e {
        Error::Numerical(_) => {
            CliError::failed(anyhow!("the exact reference could not be computed: {e}"))
        }
        e => CliError::input(anyhow!("no exact reference for this scenario: {e}")),
    }
}

/// One of the paper's estimates, evaluated for the scenario's pair and
/// impact speed, beside the exact value of the law it is written for.
#[derive(Debug, Clone, Serialize)]
pub struct PaperEstimate {
    /// e.g. "26 as printed".
    pub equation: &'static str,
    /// The estimated field: `duration` (T_c) or `max_overlap` (h_max).
    pub quantity: &'static str,
    /// The law the formula is written for (`linear` or `hertz`).
    pub law: &'static str,
    /// The estimate, SI; `None` where the formula has no value (reason in `note`).
    pub value: Option<f64>,
    /// The exact value of `law` for this pair and impact speed (with gravity), SI.
    pub exact: f64,
    /// `value / exact − 1`.
    pub relative_difference: Option<f64>,
    pub note: String,
}

/// Eqs 26 (as printed and corrected), 27, 28, 29 for the linear law and
/// eq 30 for Hertz, all with the scenario's pair, gravity and impact speed.
pub fn paper_estimates(s: &Scenario) -> CliResult<Vec<PaperEstimate>> {
    let v = s.impact_speed();
    let g = s.motion.gravity;
    let shape = |law: ContactLawKind| {
        let mut t = *s;
        t.contact.law = law;
        exact::contact_shape(&exact::problem(&t), v).map_err(exact_error)
    };
    let linear = shape(ContactLawKind::Linear)?;
    let hertz = shape(ContactLawKind::Hertz)?;
    let p2_linear = exact::problem(&{
        let mut t = *s;
        t.contact.law = ContactLawKind::Linear;
        t
    })
    .p_squared;
    let p2_hertz = exact::problem(&{
        let mut t = *s;
        t.contact.law = ContactLawKind::Hertz;
        t
    })
    .p_squared;

    let make = |equation, quantity, law, value: Result<f64, Error>, exact: f64, note: &str| {
        let (value, note) = match value {
            Ok(x) => (Some(x), note.to_string()),
            Err(e) => (None, format!("no value: {e}")),
        };
        PaperEstimate {
            equation,
            quantity,
            law,
            value,
            exact,
            relative_difference: value.map(|x| relative_error(x, exact)),
            note,
        }
    };
    Ok(vec![
        make(
            "26 as printed",
            "duration",
            "linear",
            paper::eq26_as_printed(p2_linear, g, v),
            linear.duration,
            "2/p·arctan(|v_c| p/g): the wrong arctan branch, shorter than π/p (ERRATA 6)",
        ),
        make(
            "26 corrected",
            "duration",
            "linear",
            paper::eq26_corrected(p2_linear, g, v),
            linear.duration,
            "(π + 2 arctan(g/(|v_c| p)))/p: exact (ERRATA 6)",
        ),
        make(
            "27",
            "duration",
            "linear",
            paper::eq27(p2_linear),
            linear.duration,
            "π/p: gravity-free",
        ),
        make(
            "28 as printed",
            "max_overlap",
            "linear",
            paper::eq28_as_printed(p2_linear, g, v),
            linear.max_overlap,
            "(√(v_c² p² − g²) + g)/p²: −g² where +g² belongs (ERRATA 6)",
        ),
        make(
            "29",
            "max_overlap",
            "linear",
            paper::eq29(p2_linear, v),
            linear.max_overlap,
            "|v_c|/p: gravity-free",
        ),
        make(
            "30 (Brilliantov)",
            "duration",
            "hertz",
            paper::eq30_brilliantov(p2_hertz, v),
            hertz.duration,
            "2.94 (m_eff/k)^(2/5) |v_c|^(−1/5), gravity-free; the paper's 4.29 µs \
             is not reproducible (ERRATA 9)",
        ),
    ])
}

/// The JSON object of `exact --json`: the keys of `run --json` that have a
/// meaning without integration, plus the paper's estimates.
#[derive(Debug, Serialize)]
pub struct ExactReport<'a> {
    #[serde(serialize_with = "crate::output::boundary::serialize_scenario")]
    pub scenario: &'a Scenario,
    pub contacts: &'a [ContactRecord],
    pub paper_estimates: &'a [PaperEstimate],
    pub notes: Vec<&'static str>,
}

fn estimates_table(estimates: &[PaperEstimate]) -> Table {
    // One quantity per row: each value carries its unit in the cell.
    let mut table = Table::new(vec![
        Column::text("eq"),
        Column::text("quantity"),
        Column::text("law"),
        Column::text("estimate").right(),
        Column::text("exact (with gravity)").right(),
        Column::number(
            "estimate/exact − 1",
            Unit::NONE,
            Format::SignedSci(report::ERROR_DIGITS),
        ),
    ]);
    for e in estimates {
        let (scale, unit, name) = match e.quantity {
            "duration" => (1e6, "µs", "T_c"),
            _ => (1e9, "nm", "h_max"),
        };
        table.push(vec![
            Cell::text(e.equation),
            Cell::text(name),
            Cell::text(e.law),
            e.value
                .map(|x| Cell::text(format!("{} {unit}", sig(x * scale, DIGITS))))
                .unwrap_or_else(|| Cell::text("—")),
            Cell::text(format!("{} {unit}", sig(e.exact * scale, DIGITS))),
            e.relative_difference
                .map_or_else(|| Cell::text("—"), Cell::Number),
        ]);
    }
    table
}

fn estimate_notes(estimates: &[PaperEstimate]) -> String {
    estimates
        .iter()
        .map(|e| format!("  eq {}: {}\n", e.equation, e.note))
        .collect()
}

pub fn run(args: &ExactArgs) -> CliResult {
    let scenario = args.scenario.load().map_err(CliError::input)?.resolved();
    warnings::print(&warnings::inputs(&scenario));
    let contacts = exact_contacts(&scenario)?;
    warnings::print(&warnings::contacts(&scenario, &contacts));
    let estimates = paper_estimates(&scenario)?;
    let mut stdout = std::io::stdout().lock();
    if args.json {
        let report = ExactReport {
            scenario: &scenario,
            contacts: &contacts,
            paper_estimates: &estimates,
            notes: vec![paper::BRILLIANTOV_NOT_REPRODUCIBLE],
        };
        write!(stdout, "{}", super::json_text(&report)?).map_err(CliError::failed)?;
    } else {
        writeln!(
            stdout,
            "exact reference: {}, {} contact{}, impact speed {} m/s\n{}\n\n\
             The paper's estimates for this pair and impact speed (eqs 26–29 are \
             written for the linear law, eq 30 for Hertz):\n{}\n{}{}",
            reference_source(&scenario),
            scenario.motion.contacts,
            if scenario.motion.contacts == 1 {
                ""
            } else {
                "s"
            },
            sig(scenario.impact_speed(), DIGITS),
            report::exact_contacts_table(&contacts),
            estimates_table(&estimates),
            estimate_notes(&estimates),
            paper::BRILLIANTOV_NOT_REPRODUCIBLE,
        )
        .map_err(CliError::failed)?;
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}
