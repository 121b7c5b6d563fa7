//! Reports of a run: the terminal header and contact table, `contacts.csv`,
//! the JSON object and the resolved `scenario.toml`.

use anyhow::{anyhow, Result};
use comfy_table::{presets, CellAlignment, Table};
use dembound_core::bounce::{ContactRecord, Problem, RunOutcome, Scenario, StepRule};
use serde::Serialize;
use std::io::Write;

use super::format::{exact, sig};

/// Significant digits in terminal tables.
pub const DIGITS: usize = 9;

/// The lines printed before a run: law, scheme, stepping, Δt, steps and the
/// contact-time estimate.
pub fn header(s: &Scenario, problem: &Problem) -> String {
    let step = match s.step_rule() {
        StepRule::Fraction(eta) => format!("η = {eta} of the contact-time estimate"),
        StepRule::Fixed(_) => "given".to_string(),
        StepRule::Tolerance(tol) => format!(
            "η = {} chosen for a relative tolerance of {tol}, estimated error {}",
            sig(problem.dt / problem.contact_time_estimate, 3),
            sig(problem.error_estimate.unwrap_or(f64::NAN), 2)
        ),
    };
    format!(
        "contact law {}, scheme {}, {} stepping, {} contact{}\n\
         contact-time estimate T_c ≈ {} µs (at the first impact speed {} m/s)\n\
         Δt = {} ns ({step}), about {} steps expected\n",
        s.contact.law.name(),
        s.integration.scheme.name(),
        stepping_name(s),
        s.motion.contacts,
        if s.motion.contacts == 1 { "" } else { "s" },
        sig(problem.contact_time_estimate * 1e6, 6),
        sig(s.impact_speed(), 6),
        sig(problem.dt * 1e9, 6),
        sig(problem.expected_steps().round(), 3),
    )
}

pub fn stepping_name(s: &Scenario) -> &'static str {
    match s.integration.stepping {
        dembound_core::bounce::Stepping::Event => "event",
        dembound_core::bounce::Stepping::Fixed => "fixed",
    }
}

/// The per-contact table, units in the column headers.
pub fn contacts_table(contacts: &[ContactRecord]) -> Table {
    let mut table = Table::new();
    table.load_preset(presets::UTF8_FULL_CONDENSED);
    table.set_header(vec![
        "#",
        "t_c (ms)",
        "t_mp (ms)",
        "t_r (ms)",
        "T_c (µs)",
        "h_max (nm)",
        "F_max (N)",
        "a_max (m/s²)",
        "v_c (m/s)",
        "v_r (m/s)",
        "steps",
    ]);
    for (i, c) in contacts.iter().enumerate() {
        table.add_row(vec![
            (i + 1).to_string(),
            sig(c.t_contact * 1e3, DIGITS),
            sig(c.t_max_overlap * 1e3, DIGITS),
            sig(c.t_rebound * 1e3, DIGITS),
            sig(c.duration * 1e6, DIGITS),
            sig(c.max_overlap * 1e9, DIGITS),
            sig(c.max_force, DIGITS),
            sig(c.max_acceleration, DIGITS),
            sig(c.impact_velocity, DIGITS),
            sig(c.rebound_velocity, DIGITS),
            c.steps.to_string(),
        ]);
    }
    for i in 0..11 {
        if let Some(column) = table.column_mut(i) {
            column.set_cell_alignment(CellAlignment::Right);
        }
    }
    table
}

/// Writes `contacts.csv`: one row per contact, SI, units in the header.
pub fn write_contacts_csv(contacts: &[ContactRecord], w: &mut dyn Write) -> Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    csv.write_record([
        "contact",
        "t_contact_s",
        "t_max_overlap_s",
        "t_rebound_s",
        "duration_s",
        "max_overlap_m",
        "max_force_N",
        "max_acceleration_m_s2",
        "impact_velocity_m_s",
        "rebound_velocity_m_s",
        "apex_height_m",
        "steps",
    ])?;
    for (i, c) in contacts.iter().enumerate() {
        csv.write_record([
            (i + 1).to_string(),
            exact(c.t_contact),
            exact(c.t_max_overlap),
            exact(c.t_rebound),
            exact(c.duration),
            exact(c.max_overlap),
            exact(c.max_force),
            exact(c.max_acceleration),
            exact(c.impact_velocity),
            exact(c.rebound_velocity),
            c.apex_height.map(exact).unwrap_or_default(),
            c.steps.to_string(),
        ])?;
    }
    csv.flush()?;
    Ok(())
}

/// The JSON object of `run --json` (SI).
#[derive(Debug, Serialize)]
pub struct RunReport<'a> {
    pub scenario: &'a Scenario,
    pub contacts: &'a [ContactRecord],
    pub steps: u64,
    pub dt: f64,
    pub contact_time_estimate: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_estimate: Option<f64>,
}

impl<'a> RunReport<'a> {
    pub fn new(scenario: &'a Scenario, outcome: &'a RunOutcome) -> Self {
        RunReport {
            scenario,
            contacts: &outcome.contacts,
            steps: outcome.steps,
            dt: outcome.dt,
            contact_time_estimate: outcome.contact_time_estimate,
            error_estimate: outcome.error_estimate,
        }
    }
}

/// The resolved scenario as a TOML file that `dembound run FILE` reads back.
pub fn scenario_toml(s: &Scenario) -> Result<String> {
    let body = toml::to_string_pretty(s).map_err(|e| anyhow!("cannot write the scenario: {e}"))?;
    Ok(format!(
        "# dembound scenario, every key written out (SI units).\n\
         # Re-run with: dembound run scenario.toml\n\n{body}"
    ))
}
