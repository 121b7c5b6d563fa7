//! Reports of the validation study (the paper's Tables 1–2 against the exact
//! reference) and of the convergence study: terminal tables, Markdown, CSV,
//! the verdicts and the convergence figures (the verdicts and orders are
//! computed in [`dembound_core::study::validation`]).
//!
//! `tables_markdown`, `convergence_markdown` and `convergence_figures` are
//! shared with other commands (the `paper` report).

use super::format::{exact, sig};
use super::table::{Cell, Column, Format, Table, Unit};
use crate::plot::{Figure, Mark, Series};
use anyhow::Result;
use dembound_core::bounce::Stepping;
use dembound_core::contact::ContactLawKind;
use dembound_core::integrate::Scheme;
use dembound_core::study::validation::{
    orders, series, verdicts, ConvergencePoint, StepBasis, ValidationTable, Verdict, LAWS,
    QUANTITIES,
};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Short names of the four quantities, in the order of [`QUANTITIES`].
pub const LABELS: [&str; 4] = ["t_r", "h_max", "a_max", "v_r"];

/// The SI unit of each quantity (the tables choose the prefix).
const UNITS: [Unit; 4] = [
    Unit::SECOND,
    Unit::METRE,
    Unit::METRE_PER_SECOND2,
    Unit::METRE_PER_SECOND,
];

/// Significant digits of values in the tables.
const VALUE_DIGITS: usize = 9;

/// η as a fraction, `1/50`.
pub fn eta_label(eta: f64) -> String {
    let n = 1.0 / eta;
    if (n - n.round()).abs() < 1e-9 * n {
        format!("1/{}", n.round())
    } else {
        sig(eta, 3)
    }
}

fn stepping_name(s: Stepping) -> &'static str {
    match s {
        Stepping::Event => "event",
        Stepping::Fixed => "fixed",
    }
}

fn scheme_label(s: Scheme) -> &'static str {
    match s {
        Scheme::Gear5 => "Gear5",
        Scheme::Verlet => "Verlet",
    }
}

/// The law's registry name (with its exponent for a power law), Hertz's
/// capitalised as a person's name.
fn law_label(law: ContactLawKind) -> String {
    match law.name() {
        name if name == "hertz" => "Hertz".into(),
        name => name,
    }
}

fn table_number(law: ContactLawKind) -> &'static str {
    match law {
        ContactLawKind::Linear => "Table 1",
        ContactLawKind::Hertz => "Table 2",
        _ => "Table",
    }
}

/// A relative error (fraction) as a percentage with 3 significant digits.
fn percent(e: f64) -> String {
    sig(e * 100.0, 3)
}

fn text_columns(names: &[&str]) -> Vec<Column> {
    names.iter().map(|n| Column::text(*n)).collect()
}

/// The numerical rows of a table (the exact row first).
fn numerical_grid(t: &ValidationTable) -> Table {
    let mut columns = text_columns(&["row", "Δt from"]);
    columns.push(Column::text("η").right());
    columns.extend(text_columns(&["scheme", "stepping"]));
    columns.push(Column::quantity("Δt", Unit::SECOND, 5));
    columns.push(Column::number("steps", Unit::NONE, Format::Integer));
    for (q, label) in LABELS.iter().enumerate() {
        columns.push(Column::quantity(*label, UNITS[q], VALUE_DIGITS));
        columns.push(Column::quantity(format!("δ {label}"), Unit::PERCENT, 3));
    }
    let mut table = Table::new(columns).with_keys(5);
    let mut exact_row = vec![Cell::text("exact")];
    exact_row.resize(7, Cell::Empty);
    for q in 0..4 {
        exact_row.push(t.exact[q].into());
        exact_row.push(Cell::Empty);
    }
    table.push(exact_row);
    for r in &t.rows {
        let mut row = vec![
            Cell::text("dembound"),
            Cell::text(match r.basis {
                StepBasis::Paper => "paper T_c",
                StepBasis::Exact => "exact T_c",
            }),
            Cell::text(eta_label(r.eta)),
            Cell::text(scheme_label(r.scheme)),
            Cell::text(stepping_name(r.stepping)),
            r.dt.into(),
            r.steps.into(),
        ];
        for q in 0..4 {
            row.push(r.values[q].into());
            row.push((r.errors[q] * 100.0).into());
        }
        table.push(row);
    }
    table
}

fn four(x: [f64; 4], f: impl Fn(f64) -> String) -> String {
    x.iter().map(|&v| f(v)).collect::<Vec<_>>().join(", ")
}

/// The paper's printed rows, in SI.
fn paper_grid(t: &ValidationTable) -> Table {
    let mut columns = vec![
        Column::text("paper row"),
        Column::quantity("Δt", Unit::SECOND, 4),
    ];
    for q in 0..4 {
        columns.push(Column::quantity(LABELS[q], UNITS[q], 4));
    }
    columns.push(Column::text("printed δ (%): t_r, h_max, a_max, v_r").right());
    columns.push(Column::text("δ vs exact (%): t_r, h_max, a_max, v_r").right());
    let mut table = Table::new(columns);
    for r in &t.paper_rows {
        let mut row = vec![Cell::text(r.label), r.dt.into()];
        row.extend(r.values.iter().map(|&x| Cell::Number(x)));
        row.push(Cell::text(
            r.printed_delta_percent
                .map(|d| four(d, |x| x.to_string()))
                .unwrap_or_else(|| "—".into()),
        ));
        row.push(Cell::text(four(r.errors, percent)));
        table.push(row);
    }
    table
}

/// One line per law.
pub fn verdict_line(v: &Verdict) -> String {
    let detail = (0..4)
        .map(|q| {
            format!(
                "{} {} % vs {} % ({}){}",
                LABELS[q],
                percent(v.errors[q]),
                percent(v.best_paper_errors[q]),
                v.best_paper_rows[q],
                if v.better[q] { "" } else { " NOT better" }
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    format!(
        "verdict, {} law: dembound Gear5 event stepping at η = 1/50 (Δt = {} ns from the exact T_c) \
         is {} than every numerical row the paper printed, for {}: {detail}",
        law_label(v.law),
        sig(v.dt * 1e9, 5),
        if v.more_accurate {
            "more accurate"
        } else {
            "NOT more accurate"
        },
        if v.more_accurate {
            "every quantity"
        } else {
            "some quantities"
        },
    )
}

fn table_title(t: &ValidationTable) -> String {
    format!(
        "{} — {} law, 2nd contact: exact reference, dembound runs and the paper's rows \
         (exact T_c = {} ns; the paper took Δt from T_c = {} ns)",
        table_number(t.law),
        law_label(t.law),
        sig(t.exact_contact_time * 1e9, 6),
        sig(t.paper_contact_time * 1e9, 4),
    )
}

const TABLE_NOTES: &str = "δ is the relative error against the exact reference of the same case \
(ERRATA 6, 8), in %, never against another numerical run. Δt = η T_c, with T_c the paper's \
(848.3 ns linear, 4.29 µs Hertz) or the exact contact time. Event stepping: exact flight, only the \
contacts integrated; fixed stepping: one Δt through the whole path, as the paper did. The paper's \
values are converted to SI with the corrected units (ERRATA 10); h_max is shown as the positive \
overlap.";

/// Tables 1–2 for the terminal, with notes and one verdict line per law.
pub fn tables_terminal(tables: &[ValidationTable]) -> String {
    let mut out = String::new();
    for t in tables {
        out.push_str(&format!("{}\n", table_title(t)));
        out.push_str(&numerical_grid(t).to_string());
        out.push('\n');
        out.push_str(&format!(
            "the paper's printed {} rows, in SI:\n",
            table_number(t.law)
        ));
        out.push_str(&paper_grid(t).to_string());
        out.push('\n');
        for r in &t.paper_rows {
            out.push_str(&format!("  {}: {}\n", r.label, r.note));
        }
        out.push('\n');
    }
    out.push_str(&format!("{TABLE_NOTES}\n"));
    out.push_str(&format!(
        "{}\n",
        dembound_core::exact::paper::BRILLIANTOV_NOT_REPRODUCIBLE
    ));
    for v in verdicts(tables) {
        out.push_str(&format!("{}\n", verdict_line(&v)));
    }
    out
}

/// Tables 1–2 in Markdown, with notes and verdicts.
pub fn tables_markdown(tables: &[ValidationTable]) -> String {
    let mut out = String::new();
    for t in tables {
        out.push_str(&format!("### {}\n\n", table_title(t)));
        out.push_str(&numerical_grid(t).markdown());
        out.push_str(&format!(
            "\nThe paper's printed {} rows, in SI:\n\n",
            table_number(t.law)
        ));
        out.push_str(&paper_grid(t).markdown());
        out.push('\n');
        for r in &t.paper_rows {
            out.push_str(&format!("- {}: {}\n", r.label, r.note));
        }
        out.push('\n');
    }
    out.push_str(&format!("{TABLE_NOTES}\n\n"));
    out.push_str(&format!(
        "{}\n\n",
        dembound_core::exact::paper::BRILLIANTOV_NOT_REPRODUCIBLE
    ));
    for v in verdicts(tables) {
        out.push_str(&format!("- {}\n", verdict_line(&v)));
    }
    out
}

fn errors_grid(points: &[ConvergencePoint], law: ContactLawKind) -> Table {
    let mut columns = text_columns(&["scheme", "stepping"]);
    columns.push(Column::text("η").right());
    columns.push(Column::number("steps", Unit::NONE, Format::Integer));
    for l in LABELS {
        columns.push(Column::number(
            format!("error {l}"),
            Unit::NONE,
            Format::Sci(3),
        ));
    }
    let mut table = Table::new(columns).with_keys(3);
    for (_, scheme, stepping, pts) in series(points).into_iter().filter(|s| s.0 == law) {
        for p in pts {
            let mut row = vec![
                Cell::text(scheme_label(scheme)),
                Cell::text(stepping_name(stepping)),
                Cell::text(eta_label(p.eta)),
                p.steps.into(),
            ];
            row.extend(p.errors.iter().map(|&e| Cell::Number(e)));
            table.push(row);
        }
    }
    table
}

fn orders_grid(points: &[ConvergencePoint]) -> Table {
    let mut columns = text_columns(&["law", "scheme", "stepping"]);
    for l in LABELS {
        columns.push(Column::number(
            format!("order {l}"),
            Unit::NONE,
            Format::Fixed(2),
        ));
    }
    let mut table = Table::new(columns).with_keys(3);
    for o in orders(points) {
        let mut row = vec![
            Cell::text(law_label(o.law)),
            Cell::text(scheme_label(o.scheme)),
            Cell::text(stepping_name(o.stepping)),
        ];
        row.extend(
            o.orders
                .as_array()
                .iter()
                .map(|x| x.map_or_else(|| Cell::text("—"), Cell::Number)),
        );
        table.push(row);
    }
    table
}

const CONVERGENCE_NOTES: &str = "Errors are relative to the exact reference, 2nd contact, Δt = η T_c \
with the exact T_c. The observed order is the least-squares slope of log(error) against log(η) over \
all points with error > 1e−12 (rounding and the reference's own accuracy dominate below), \
pre-asymptotic points at large η included. Read the fixed-stepping orders with care: over \
10⁷–10⁸ flight steps rounding accumulates, and the linear Gear5 fixed errors level off near \
1e−10–1e−9 for η ≤ 1/200, which pulls the fitted slope down (from η = 1/20 to 1/100 they fall at \
order ≈ 5, as in event stepping). For Hertz, h^(3/2) is not smooth at the onset and rebound \
(h'''' ∝ h^(−1/2)), which holds a uniform step (fixed stepping, the paper's way) near order 2.5; \
event stepping grades the mesh over the first and last quarter of the contact (τ ∝ j³), which \
restores Gear5's 5th order at about twice the steps.";

/// The convergence study for the terminal: errors per law, then the orders.
pub fn convergence_terminal(points: &[ConvergencePoint]) -> String {
    let mut out = String::new();
    for law in LAWS {
        if !points.iter().any(|p| p.law == law) {
            continue;
        }
        out.push_str(&format!(
            "convergence, {} law: relative error against the exact reference vs η\n",
            law_label(law)
        ));
        out.push_str(&errors_grid(points, law).to_string());
        out.push_str("\n\n");
    }
    out.push_str("observed orders of convergence (slope of log error vs log η):\n");
    out.push_str(&orders_grid(points).to_string());
    out.push_str(&format!("\n{CONVERGENCE_NOTES}\n"));
    out
}

/// The convergence study in Markdown: orders, then the errors per law.
pub fn convergence_markdown(points: &[ConvergencePoint]) -> String {
    let mut out = String::new();
    out.push_str("### Observed orders of convergence\n\n");
    out.push_str(&orders_grid(points).markdown());
    out.push_str(&format!("\n{CONVERGENCE_NOTES}\n"));
    for law in LAWS {
        if !points.iter().any(|p| p.law == law) {
            continue;
        }
        out.push_str(&format!(
            "\n### Relative errors, {} law\n\n",
            law_label(law)
        ));
        out.push_str(&errors_grid(points, law).markdown());
    }
    out
}

/// Quantities drawn in the convergence figures: h_max and t_r.
const FIGURE_QUANTITIES: [(usize, Mark); 2] = [(1, Mark::LinePoints), (0, Mark::Dashed)];

/// One log–log figure per law, `convergence_linear` and `convergence_hertz`
/// (SVG and PNG): the relative errors of h_max (solid, markers) and t_r
/// (dashed) against steps per contact 1/η, one colour per scheme and
/// stepping mode. Returns the paths written.
pub fn convergence_figures(points: &[ConvergencePoint], dir: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for law in LAWS {
        let all = series(points);
        let of_law: Vec<_> = all.iter().filter(|s| s.0 == law).collect();
        if of_law.is_empty() {
            continue;
        }
        let mut figure = Figure {
            title: format!(
                "Convergence, {} law (2nd contact, Δt = η·T_c)",
                law_label(law)
            ),
            x_label: "steps per contact, 1/η = T_c/Δt".into(),
            y_label: "relative error |value/exact − 1|".into(),
            x_log: true,
            y_log: true,
            series: Vec::new(),
            ..Default::default()
        };
        for (color, (_, scheme, stepping, pts)) in of_law.iter().enumerate() {
            for (q, mark) in FIGURE_QUANTITIES {
                figure.series.push(Series::new(
                    format!(
                        "{} {}: {}",
                        scheme_label(*scheme),
                        stepping_name(*stepping),
                        LABELS[q]
                    ),
                    pts.iter().map(|p| (1.0 / p.eta, p.errors[q])).collect(),
                    mark,
                    color,
                ));
            }
        }
        let name = match law {
            ContactLawKind::Linear => "convergence_linear".to_string(),
            ContactLawKind::Hertz => "convergence_hertz".to_string(),
            other => format!("convergence_{}", other.name().replace(' ', "_")),
        };
        written.extend(figure.write(&dir.join(name))?);
    }
    Ok(written)
}

/// `validation.csv`: every row of Tables 1–2 (exact, dembound, paper), SI.
pub fn write_validation_csv(tables: &[ValidationTable], w: &mut dyn Write) -> Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    csv.write_record([
        "law",
        "source",
        "label",
        "dt_basis",
        "eta",
        "scheme",
        "stepping",
        "dt_s",
        "steps",
        "t_rebound_s",
        "max_overlap_m",
        "max_acceleration_m_s2",
        "rebound_velocity_m_s",
        "rel_error_t_rebound",
        "rel_error_max_overlap",
        "rel_error_max_acceleration",
        "rel_error_rebound_velocity",
        "printed_delta_t_rebound_percent",
        "printed_delta_max_overlap_percent",
        "printed_delta_max_acceleration_percent",
        "printed_delta_rebound_velocity_percent",
        "note",
    ])?;
    for t in tables {
        let law = t.law.name();
        let mut record: Vec<String> = vec![
            law.clone(),
            "exact".into(),
            "exact".into(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
        ];
        record.extend(t.exact.iter().map(|&x| exact(x)));
        record.extend(std::iter::repeat_n(String::new(), 9));
        csv.write_record(&record)?;
        for r in &t.rows {
            let mut record: Vec<String> = vec![
                law.clone(),
                "dembound".into(),
                String::new(),
                match r.basis {
                    StepBasis::Paper => "paper".into(),
                    StepBasis::Exact => "exact".into(),
                },
                exact(r.eta),
                r.scheme.name().into(),
                stepping_name(r.stepping).into(),
                exact(r.dt),
                r.steps.to_string(),
            ];
            record.extend(r.values.iter().map(|&x| exact(x)));
            record.extend(r.errors.iter().map(|&x| exact(x)));
            record.extend(std::iter::repeat_n(String::new(), 5));
            csv.write_record(&record)?;
        }
        for r in &t.paper_rows {
            let mut record: Vec<String> = vec![
                law.clone(),
                "paper".into(),
                r.label.into(),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
                r.dt.map(exact).unwrap_or_default(),
                String::new(),
            ];
            record.extend(r.values.iter().map(|&x| exact(x)));
            record.extend(r.errors.iter().map(|&x| exact(x)));
            match r.printed_delta_percent {
                Some(d) => record.extend(d.iter().map(|&x| exact(x))),
                None => record.extend(std::iter::repeat_n(String::new(), 4)),
            }
            record.push(r.note.into());
            csv.write_record(&record)?;
        }
    }
    csv.flush()?;
    Ok(())
}

/// `convergence.csv`: one row per (law, scheme, stepping, η).
pub fn write_convergence_csv(points: &[ConvergencePoint], w: &mut dyn Write) -> Result<()> {
    let mut csv = csv::Writer::from_writer(w);
    let mut header = vec!["law", "scheme", "stepping", "eta", "steps"];
    let names: Vec<String> = QUANTITIES
        .iter()
        .map(|q| format!("rel_error_{q}"))
        .collect();
    header.extend(names.iter().map(String::as_str));
    csv.write_record(&header)?;
    for (law, scheme, stepping, pts) in series(points) {
        for p in pts {
            let mut record = vec![
                law.name(),
                scheme.name().to_string(),
                stepping_name(stepping).to_string(),
                exact(p.eta),
                p.steps.to_string(),
            ];
            record.extend(p.errors.iter().map(|&x| exact(x)));
            csv.write_record(&record)?;
        }
    }
    csv.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eta_labels() {
        assert_eq!(eta_label(0.02), "1/50");
        assert_eq!(eta_label(0.0005), "1/2000");
        assert_eq!(eta_label(0.3), "0.300");
    }
}
