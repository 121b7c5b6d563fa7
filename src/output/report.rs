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
    ) + &super::boundary::header_line(s)
        + &free_boundary_line(s)
}

/// With a free boundary: the masses and how gravity acts (empty otherwise).
fn free_boundary_line(s: &Scenario) -> String {
    let (Some(mb), Some(tb)) = (s.boundary_mass(), s.two_body()) else {
        return String::new();
    };
    format!(
        "free boundary: m_m = {} kg, m_b = {} kg, reduced mass m* = {} kg; \
         motion.gravity_on = \"{}\" (relative g = {} m/s²); velocities below are relative \
         (particle − boundary), each sphere's in the v_m, v_b columns\n",
        sig(tb.particle_mass, 6),
        sig(mb, 6),
        sig(s.reduced_mass(), 6),
        s.motion.gravity_on.name(),
        sig(s.relative_gravity(), 6),
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
    values_table(contacts, |c| c.steps.to_string())
}

/// The per-contact table of exact values: the layout of [`contacts_table`],
/// the steps column reads "exact" (nothing was integrated).
pub fn exact_contacts_table(contacts: &[ContactRecord]) -> Table {
    values_table(contacts, |_| "exact".to_string())
}

fn values_table(contacts: &[ContactRecord], steps: impl Fn(&ContactRecord) -> String) -> Table {
    let mut table = Table::new();
    table.load_preset(presets::UTF8_FULL_CONDENSED);
    let two_body = contacts.iter().any(|c| c.bodies.is_some());
    // A non-attractive law's force returns to zero before the overlap does:
    // both ends are reported when they differ.
    let force_zero = contacts.iter().any(|c| c.t_force_zero.is_some());
    let mut header = vec![
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
        "e = v_r/|v_c| (1)",
        "E_diss (J)",
        "steps",
    ];
    if force_zero {
        header.insert(4, "t_F=0 (ms)");
    }
    if two_body {
        header.extend([
            "v_m before (m/s)",
            "v_m after (m/s)",
            "v_b before (m/s)",
            "v_b after (m/s)",
        ]);
    }
    let columns = header.len();
    table.set_header(header);
    for (i, c) in contacts.iter().enumerate() {
        let mut row = vec![
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
            sig(c.restitution, DIGITS),
            sig(c.energy_dissipated, 3),
            steps(c),
        ];
        if force_zero {
            let t = c
                .t_force_zero
                .map_or("–".to_string(), |t| sig(t * 1e3, DIGITS));
            row.insert(4, t);
        }
        if let Some(b) = &c.bodies {
            row.extend(
                [
                    b.particle_before,
                    b.particle_after,
                    b.boundary_before,
                    b.boundary_after,
                ]
                .map(|v| sig(v, DIGITS)),
            );
        }
        table.add_row(row);
    }
    right_align(&mut table, columns);
    table
}

fn right_align(table: &mut Table, columns: usize) {
    for i in 0..columns {
        if let Some(column) = table.column_mut(i) {
            column.set_cell_alignment(CellAlignment::Right);
        }
    }
}

/// Relative errors of one contact against the exact reference, signed:
/// `value / exact − 1` (positive when the numerical magnitude is larger).
/// The keys are those of [`ContactRecord`] (`steps` left out).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RelativeErrors {
    pub t_contact: f64,
    pub t_max_overlap: f64,
    pub t_rebound: f64,
    pub duration: f64,
    pub max_overlap: f64,
    pub max_force: f64,
    pub max_acceleration: f64,
    pub impact_velocity: f64,
    pub rebound_velocity: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub apex_height: Option<f64>,
}

/// `value / exact − 1`; 0 when both are 0.
pub fn relative_error(value: f64, exact: f64) -> f64 {
    if value == exact {
        0.0
    } else {
        value / exact - 1.0
    }
}

impl RelativeErrors {
    pub fn new(c: &ContactRecord, e: &ContactRecord) -> Self {
        RelativeErrors {
            t_contact: relative_error(c.t_contact, e.t_contact),
            t_max_overlap: relative_error(c.t_max_overlap, e.t_max_overlap),
            t_rebound: relative_error(c.t_rebound, e.t_rebound),
            duration: relative_error(c.duration, e.duration),
            max_overlap: relative_error(c.max_overlap, e.max_overlap),
            max_force: relative_error(c.max_force, e.max_force),
            max_acceleration: relative_error(c.max_acceleration, e.max_acceleration),
            impact_velocity: relative_error(c.impact_velocity, e.impact_velocity),
            rebound_velocity: relative_error(c.rebound_velocity, e.rebound_velocity),
            apex_height: match (c.apex_height, e.apex_height) {
                (Some(a), Some(b)) => Some(relative_error(a, b)),
                _ => None,
            },
        }
    }

    /// The errors of every contact, pairing the i-th numerical contact with
    /// the i-th exact one.
    pub fn all(numerical: &[ContactRecord], exact: &[ContactRecord]) -> Vec<Self> {
        numerical
            .iter()
            .zip(exact)
            .map(|(c, e)| Self::new(c, e))
            .collect()
    }
}

/// Significant digits of relative errors in terminal tables.
pub const ERROR_DIGITS: usize = 3;

/// A relative error (fraction) for a table: scientific, signed.
pub fn error_cell(e: f64) -> String {
    if e == 0.0 {
        "0".into()
    } else if !e.is_finite() {
        e.to_string()
    } else {
        format!("{:+.*e}", ERROR_DIGITS - 1, e)
    }
}

/// The table of relative errors against the exact reference, one row per
/// contact, the columns of [`contacts_table`].
pub fn relative_errors_table(errors: &[RelativeErrors]) -> Table {
    let mut table = Table::new();
    table.load_preset(presets::UTF8_FULL_CONDENSED);
    table.set_header(vec![
        "#", "t_c", "t_mp", "t_r", "T_c", "h_max", "F_max", "a_max", "v_c", "v_r",
    ]);
    for (i, e) in errors.iter().enumerate() {
        table.add_row(vec![
            (i + 1).to_string(),
            error_cell(e.t_contact),
            error_cell(e.t_max_overlap),
            error_cell(e.t_rebound),
            error_cell(e.duration),
            error_cell(e.max_overlap),
            error_cell(e.max_force),
            error_cell(e.max_acceleration),
            error_cell(e.impact_velocity),
            error_cell(e.rebound_velocity),
        ]);
    }
    right_align(&mut table, 10);
    table
}

/// Writes `contacts.csv`: one row per contact, SI, units in the header.
/// With a free boundary four columns follow: each sphere's velocity
/// before and after the contact.
pub fn write_contacts_csv(contacts: &[ContactRecord], w: &mut dyn Write) -> Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    let two_body = contacts.iter().any(|c| c.bodies.is_some());
    let mut header = vec![
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
    ];
    if two_body {
        header.extend([
            "particle_velocity_before_m_s",
            "particle_velocity_after_m_s",
            "boundary_velocity_before_m_s",
            "boundary_velocity_after_m_s",
        ]);
    }
    csv.write_record(&header)?;
    for (i, c) in contacts.iter().enumerate() {
        let mut row = vec![
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
        ];
        if two_body {
            let b = c.bodies;
            row.extend(
                [
                    b.map(|b| b.particle_before),
                    b.map(|b| b.particle_after),
                    b.map(|b| b.boundary_before),
                    b.map(|b| b.boundary_after),
                ]
                .map(|v| v.map(exact).unwrap_or_default()),
            );
        }
        csv.write_record(&row)?;
    }
    csv.flush()?;
    Ok(())
}

/// The JSON object of `run --json` (SI).
#[derive(Debug, Serialize)]
pub struct RunReport<'a> {
    /// The resolved scenario, `boundary` with its SI values added.
    #[serde(serialize_with = "super::boundary::serialize_scenario")]
    pub scenario: &'a Scenario,
    pub contacts: &'a [ContactRecord],
    pub steps: u64,
    pub dt: f64,
    pub contact_time_estimate: f64,
    /// With `--compare-exact`: per contact, `value / exact − 1` of every field.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relative_errors: Option<Vec<RelativeErrors>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_estimate: Option<f64>,
    /// With `integration.tolerance`: the pilot runs' steps (not in `steps`)
    /// and the sum of both.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pilot_steps: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub total_steps: Option<u64>,
}

impl<'a> RunReport<'a> {
    pub fn new(scenario: &'a Scenario, outcome: &'a RunOutcome) -> Self {
        RunReport {
            scenario,
            contacts: &outcome.contacts,
            steps: outcome.steps,
            dt: outcome.dt,
            contact_time_estimate: outcome.contact_time_estimate,
            relative_errors: None,
            error_estimate: outcome.error_estimate,
            pilot_steps: outcome.pilot_steps,
            total_steps: outcome.pilot_steps.map(|_| outcome.total_steps()),
        }
    }
}

/// The resolved scenario as a TOML file that `dembound run FILE` reads back.
pub fn scenario_toml(s: &Scenario) -> Result<String> {
    let body = toml::to_string_pretty(s).map_err(|e| anyhow!("cannot write the scenario: {e}"))?;
    let b = &s.boundary;
    let radius = super::boundary::radius(s, b.radius_ratio);
    let modulus = super::boundary::youngs_modulus(s, b.modulus_ratio);
    Ok(format!(
        "# dembound scenario, every key written out (SI units).\n\
         # Re-run with: dembound run scenario.toml\n\
         # The boundary in SI: radius = {} m, youngs_modulus = {} Pa\n\
         # (radius_ratio × particle.radius, modulus_ratio × particle.youngs_modulus).\n\n{body}",
        super::format::exact(radius),
        super::format::exact(modulus)
    ))
}
