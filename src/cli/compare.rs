//! `dembound compare DIR`: reads the per-step trace an exported deck wrote
//! (DIR/trace.txt) and prints each contact's h_max, T_c, v_c, v_r and e
//! beside dembound's run of the same scenario (DIR/scenario.toml) and the
//! exact reference. A scene deck (DIR/scene.toml) goes to
//! [`super::compare_scene`].

use super::exact::exact_contacts;
use super::{CliError, CliResult};
use crate::output::format::sig;
use crate::output::table::{si_prefix, Cell, Column, Format, Table, Unit};
use crate::scenario_file;
use anyhow::anyhow;
use clap::Args;
use dembound_core::bounce::{simulate, ContactRecord};
use dembound_export::trace::{MeasuredContact, Trace};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The exported deck's directory (holding scenario.toml and the trace
    /// the run wrote), or the trace file itself
    #[arg(value_name = "DIR|TRACE")]
    pub path: PathBuf,

    /// The scenario, when it is not DIR/scenario.toml
    #[arg(long, value_name = "SCENARIO.toml")]
    pub scenario: Option<PathBuf>,

    /// Print one JSON object (per contact: the code's, dembound's and the
    /// exact values, SI, and the relative differences; for a scene deck
    /// every quantity's series, divergence and window means) instead of
    /// tables
    #[arg(long)]
    pub json: bool,

    /// Scene decks: write a figure per quantity (SVG and PNG) and one of
    /// the relative differences into this directory
    #[arg(long, value_name = "DIR")]
    pub figures: Option<PathBuf>,

    /// Scene decks: the late window (means, standard errors, verdicts,
    /// profiles, the discharge rate) starts at this time, s (default: the
    /// last third of the rows)
    #[arg(long, value_name = "SECONDS")]
    pub window_from: Option<f64>,
}

/// The compared quantities of one contact, SI.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Quantities {
    pub t_contact: f64,
    pub max_overlap: f64,
    pub duration: f64,
    pub impact_velocity: f64,
    pub rebound_velocity: f64,
    pub restitution: f64,
}

impl From<&MeasuredContact> for Quantities {
    fn from(c: &MeasuredContact) -> Self {
        Quantities {
            t_contact: c.t_contact,
            max_overlap: c.max_overlap,
            duration: c.duration,
            impact_velocity: c.impact_velocity,
            rebound_velocity: c.rebound_velocity,
            restitution: c.restitution,
        }
    }
}

impl From<&ContactRecord> for Quantities {
    fn from(c: &ContactRecord) -> Self {
        Quantities {
            t_contact: c.t_contact,
            max_overlap: c.max_overlap,
            duration: c.duration,
            impact_velocity: c.impact_velocity,
            rebound_velocity: c.rebound_velocity,
            restitution: c.restitution,
        }
    }
}

impl Quantities {
    /// value/reference − 1 of each (e: the difference e − e_ref).
    fn relative_to(&self, r: &Quantities) -> Quantities {
        let rel = |a: f64, b: f64| a / b - 1.0;
        Quantities {
            t_contact: rel(self.t_contact, r.t_contact),
            max_overlap: rel(self.max_overlap, r.max_overlap),
            duration: rel(self.duration, r.duration),
            impact_velocity: rel(self.impact_velocity, r.impact_velocity),
            rebound_velocity: rel(self.rebound_velocity, r.rebound_velocity),
            restitution: self.restitution - r.restitution,
        }
    }
}

#[derive(Debug, Serialize)]
pub struct ContactComparison {
    pub contact: usize,
    pub code: Quantities,
    pub dembound: Option<Quantities>,
    pub exact: Option<Quantities>,
    /// code/exact − 1 (restitution: e_code − e_exact).
    pub code_vs_exact: Option<Quantities>,
    /// dembound/exact − 1 (restitution: the difference).
    pub dembound_vs_exact: Option<Quantities>,
}

#[derive(Debug, Serialize)]
pub struct CompareReport {
    pub code: String,
    pub trace: PathBuf,
    pub contacts: Vec<ContactComparison>,
}

/// The code whose deck is in `dir`, from its input file's name.
fn code_in(dir: &Path) -> String {
    for (file, name) in [
        ("in.lammps", "LAMMPS"),
        ("in.liggghts", "LIGGGHTS"),
        ("bounce.py", "Yade"),
    ] {
        if dir.join(file).exists() {
            return name.into();
        }
    }
    "code".into()
}

pub fn run(args: &CompareArgs) -> CliResult {
    if args.scenario.is_none() && super::compare_scene::is_scene_deck(&args.path) {
        return super::compare_scene::run(args, &args.path);
    }
    let (dir, trace_path) = if args.path.is_dir() {
        (args.path.clone(), args.path.join("trace.txt"))
    } else {
        (
            args.path
                .parent()
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf),
            args.path.clone(),
        )
    };
    // The deck's code, named in every refusal ("code" when the directory
    // holds no deck input).
    let code = code_in(&dir);
    let scenario_path = args
        .scenario
        .clone()
        .unwrap_or_else(|| dir.join("scenario.toml"));
    let text = std::fs::read_to_string(&scenario_path).map_err(|e| {
        CliError::input(anyhow!(
            "cannot read the scenario `{}` of the {code} deck: {e} (give --scenario)",
            scenario_path.display()
        ))
    })?;
    let scenario = scenario_file::load(Some((&scenario_path, &text)), &[])
        .map_err(CliError::input)?
        .resolved();
    let trace_text = std::fs::read_to_string(&trace_path).map_err(|e| {
        CliError::input(anyhow!(
            "cannot read the trace `{}`: {e} (run the deck first: the {code} deck writes it)",
            trace_path.display()
        ))
    })?;
    let trace = Trace::parse(&trace_text).map_err(|e| {
        CliError::input(anyhow!(
            "trace `{}` of the {code} deck: {e}",
            trace_path.display()
        ))
    })?;
    let expected = dembound_export::fingerprint(&scenario);
    if let Some(found) = &trace.scenario {
        if *found != expected {
            return Err(CliError::input(anyhow!(
                "trace `{}` was written by a {code} deck of another scenario (fingerprint {found}, \
                 `{}` has {expected}): run the deck exported with this scenario again",
                trace_path.display(),
                scenario_path.display()
            )));
        }
    }
    let measured = trace.contacts().map_err(|e| {
        CliError::input(anyhow!(
            "trace `{}` of the {code} deck: {e}",
            trace_path.display()
        ))
    })?;
    let exact = exact_contacts(&scenario)?;
    let ours = simulate(&scenario, &mut ())
        .map_err(|e| CliError::failed(anyhow!("dembound's run failed: {e}")))?
        .contacts;
    let contacts: Vec<ContactComparison> = measured
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let code_q = Quantities::from(m);
            let ex = exact.get(i).map(Quantities::from);
            let de = ours.get(i).map(Quantities::from);
            ContactComparison {
                contact: i + 1,
                code: code_q,
                dembound: de,
                exact: ex,
                code_vs_exact: ex.map(|e| code_q.relative_to(&e)),
                dembound_vs_exact: ex.and_then(|e| de.map(|d| d.relative_to(&e))),
            }
        })
        .collect();
    let mut stdout = std::io::stdout().lock();
    if args.json {
        let report = CompareReport {
            code,
            trace: trace_path,
            contacts,
        };
        let text = serde_json::to_string_pretty(&report).map_err(CliError::failed)?;
        writeln!(stdout, "{text}").map_err(CliError::failed)?;
    } else {
        writeln!(
            stdout,
            "{code} (trace {}, {} contact{}) against dembound ({}, Δt as in the deck) and the \
             exact reference; relative differences value/exact − 1, for e the difference e − e_exact",
            trace_path.display(),
            contacts.len(),
            if contacts.len() == 1 { "" } else { "s" },
            scenario.integration.scheme.name(),
        )
        .map_err(CliError::failed)?;
        for c in &contacts {
            writeln!(stdout, "\ncontact {}:\n{}", c.contact, table(&code, c))
                .map_err(CliError::failed)?;
        }
    }
    stdout.flush().map_err(CliError::failed)?;
    Ok(())
}

fn table(code: &str, c: &ContactComparison) -> Table {
    let mut t = Table::new(vec![
        Column::text("quantity"),
        Column::text(code).right(),
        Column::text("dembound").right(),
        Column::text("exact").right(),
        Column::number(
            format!("{code}/exact − 1"),
            Unit::NONE,
            Format::SignedSci(2),
        ),
        Column::number("dembound/exact − 1", Unit::NONE, Format::SignedSci(2)),
    ]);
    type Get = fn(&Quantities) -> f64;
    let rows: [(&str, &str, Get); 6] = [
        ("t_c", "s", |q| q.t_contact),
        ("h_max", "m", |q| q.max_overlap),
        ("T_c", "s", |q| q.duration),
        ("v_c", "m/s", |q| q.impact_velocity),
        ("v_r", "m/s", |q| q.rebound_velocity),
        ("e", "", |q| q.restitution),
    ];
    for (name, unit, get) in rows {
        let values = [Some(&c.code), c.dembound.as_ref(), c.exact.as_ref()];
        let prefix = if unit == "m" || unit == "s" {
            si_prefix(values.iter().flatten().map(|q| get(q)))
        } else {
            si_prefix([1.0])
        };
        let show = |q: Option<&Quantities>| {
            q.map_or_else(
                || Cell::text("—"),
                |q| {
                    Cell::text(format!(
                        "{} {}{unit}",
                        sig(get(q) / prefix.factor, 9),
                        prefix.symbol
                    ))
                },
            )
        };
        t.push(vec![
            Cell::text(name),
            show(Some(&c.code)),
            show(c.dembound.as_ref()),
            show(c.exact.as_ref()),
            c.code_vs_exact.as_ref().map(get).into(),
            c.dembound_vs_exact.as_ref().map(get).into(),
        ]);
    }
    t
}
