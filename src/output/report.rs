//! Reports of a run: the terminal header and contact table, `contacts.csv`,
//! the JSON object and the resolved `scenario.toml`.

use anyhow::{anyhow, Result};
use dembound_core::bounce::{
    BodyVelocities, ContactRecord, Problem, RunOutcome, Scenario, StepRule,
};
use serde::Serialize;
use std::io::Write;

use super::format::sig;
use super::table::{Cell, Column, Format, Table, Unit};

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
    contacts_document(contacts, |c| Cell::from(c.steps))
}

/// The per-contact table of exact values: the layout of [`contacts_table`],
/// the steps column reads "exact" (nothing was integrated).
pub fn exact_contacts_table(contacts: &[ContactRecord]) -> Table {
    contacts_document(contacts, |_| Cell::text("exact"))
}

/// Every column of a contact, for the terminal and `contacts.csv` alike
/// (SI values; the terminal picks the prefixes). Some columns are only on
/// the terminal (e, E_diss, t_F=0), one only in the CSV (apex height).
fn contacts_document(
    contacts: &[ContactRecord],
    steps: impl Fn(&ContactRecord) -> Cell + 'static,
) -> Table {
    let two_body = contacts.iter().any(|c| c.bodies.is_some());
    // A non-attractive law's force returns to zero before the overlap does:
    // both ends are reported when they differ.
    let force_zero = contacts.iter().any(|c| c.t_force_zero.is_some());
    let time = |label: &str, key: &str| Column::quantity(label, Unit::SECOND, DIGITS).csv(key);
    let speed =
        |label: &str, key: &str| Column::quantity(label, Unit::METRE_PER_SECOND, DIGITS).csv(key);
    type Get = Box<dyn Fn(&ContactRecord) -> Cell>;
    let mut columns: Vec<(Column, Get)> = vec![
        (
            Column::number("#", Unit::NONE, Format::Integer).csv("contact"),
            Box::new(|_| Cell::Empty),
        ),
        (time("t_c", "t_contact"), Box::new(|c| c.t_contact.into())),
        (
            time("t_mp", "t_max_overlap"),
            Box::new(|c| c.t_max_overlap.into()),
        ),
        (time("t_r", "t_rebound"), Box::new(|c| c.t_rebound.into())),
    ];
    if force_zero {
        columns.push((
            Column::quantity("t_F=0", Unit::SECOND, DIGITS),
            Box::new(|c| c.t_force_zero.map_or(Cell::text("–"), Cell::Number)),
        ));
    }
    columns.extend([
        (
            time("T_c", "duration"),
            Box::new(|c: &ContactRecord| c.duration.into()) as Get,
        ),
        (
            Column::quantity("h_max", Unit::METRE, DIGITS).csv("max_overlap"),
            Box::new(|c| c.max_overlap.into()),
        ),
        (
            Column::quantity("F_max", Unit::NEWTON, DIGITS).csv("max_force"),
            Box::new(|c| c.max_force.into()),
        ),
        (
            Column::quantity("a_max", Unit::METRE_PER_SECOND2, DIGITS).csv("max_acceleration"),
            Box::new(|c| c.max_acceleration.into()),
        ),
        (
            speed("v_c", "impact_velocity"),
            Box::new(|c| c.impact_velocity.into()),
        ),
        (
            speed("v_r", "rebound_velocity"),
            Box::new(|c| c.rebound_velocity.into()),
        ),
        (
            Column::quantity("e = v_r/|v_c|", Unit::ONE, DIGITS),
            Box::new(|c| c.restitution.into()),
        ),
        (
            Column::quantity("E_diss", Unit::JOULE, 3),
            Box::new(|c| c.energy_dissipated.into()),
        ),
        (
            Column::quantity("apex", Unit::METRE, DIGITS)
                .csv("apex_height")
                .csv_only(),
            Box::new(|c| c.apex_height.into()),
        ),
        (
            Column::number("steps", Unit::NONE, Format::Integer).csv("steps"),
            Box::new(steps),
        ),
    ]);
    if two_body {
        let body = |label: &str, key: &str, get: fn(&BodyVelocities) -> f64| -> (Column, Get) {
            (
                speed(label, key),
                Box::new(move |c: &ContactRecord| c.bodies.as_ref().map(get).into()),
            )
        };
        columns.extend([
            body("v_m before", "particle_velocity_before", |b| {
                b.particle_before
            }),
            body("v_m after", "particle_velocity_after", |b| b.particle_after),
            body("v_b before", "boundary_velocity_before", |b| {
                b.boundary_before
            }),
            body("v_b after", "boundary_velocity_after", |b| b.boundary_after),
        ]);
    }
    let (columns, getters): (Vec<Column>, Vec<Get>) = columns.into_iter().unzip();
    let mut table = Table::new(columns);
    for (i, c) in contacts.iter().enumerate() {
        let mut row: Vec<Cell> = getters.iter().map(|get| get(c)).collect();
        row[0] = (i + 1).into();
        table.push(row);
    }
    table
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

/// The table of relative errors against the exact reference, one row per
/// contact, the columns of [`contacts_table`].
pub fn relative_errors_table(errors: &[RelativeErrors]) -> Table {
    let error = |label: &str| Column::number(label, Unit::NONE, Format::SignedSci(ERROR_DIGITS));
    let mut table = Table::new(vec![
        Column::number("#", Unit::NONE, Format::Integer),
        error("t_c"),
        error("t_mp"),
        error("t_r"),
        error("T_c"),
        error("h_max"),
        error("F_max"),
        error("a_max"),
        error("v_c"),
        error("v_r"),
    ]);
    for (i, e) in errors.iter().enumerate() {
        table.push(vec![
            (i + 1).into(),
            e.t_contact.into(),
            e.t_max_overlap.into(),
            e.t_rebound.into(),
            e.duration.into(),
            e.max_overlap.into(),
            e.max_force.into(),
            e.max_acceleration.into(),
            e.impact_velocity.into(),
            e.rebound_velocity.into(),
        ]);
    }
    table
}

/// Writes `contacts.csv`: one row per contact, SI, units in the header.
/// With a free boundary four columns follow: each sphere's velocity
/// before and after the contact.
pub fn write_contacts_csv(contacts: &[ContactRecord], w: &mut dyn Write) -> Result<()> {
    contacts_table(contacts).write_csv(w)
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
